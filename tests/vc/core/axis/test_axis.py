"""Machine axis behaviour through the whole NC (JOG, limits, enables, status bits).

Turn-mill X1: MD32020 JOG_VELO 2000 mm/min = 33.333 mm/s, MD32010 JOG_VELO_RAPID 10000 mm/min,
MD32300 4 m/s^2 = 4000 mm/s^2 (8 mm/s per 2 ms cycle), MD32000 30 m/min = 500 mm/s,
MD36610 0.05 s (rapid stop 500 / 0.05 = 10000 mm/s^2), MD36010 0.01 mm, MD36000 0.04 mm,
software limits -5 / 305, hardware limit switches at -12 / 312, slide at 150 at power-on.

Most tests act as the PLC themselves (``plc=None``); the hardware limit switch test runs
the built-in basic_machine PLC so that the switch travels plant -> PLC -> DB31.DBX12.1.
"""

from __future__ import annotations

import pytest
from core_rig import ABSOLUTE_X1, DT, FIVE_AXIS, Rig, machine, with_start_position

JOG_V = 2000.0 / 60.0  # mm/s, MD32020
A = 4000.0  # mm/s^2, MD32300


def jog_rig(overrides: str = ABSOLUTE_X1) -> Rig:
    rig = Rig(machine(overrides))
    rig.enable_axes()
    rig.select_mode("jog")
    rig.step(3)
    assert rig.get("MODEGROUP.basic.in.jogModeActive") == 1
    return rig


def hold(rig: Rig, axis: str, key: str, cycles: int) -> None:
    rig.set(f"{axis}.basic.out.traversKey{key}", 1)
    rig.step(cycles)


# ------------------------------------------------------------------------------ power-on state


def test_power_on_status_of_a_referenced_axis_with_enables() -> None:
    rig = jog_rig()
    assert rig.get("X1.basic.in.enc1Synchronized") == 1  # 60.4: absolute, calibrated encoder
    assert rig.get("X1.basic.in.posCtrlActive") == 1  # 61.5
    assert rig.get("X1.basic.in.posCoarseReached") == 1  # 60.6
    assert rig.get("X1.basic.in.posFineReached") == 1  # 60.7
    assert rig.get("X1.basic.in.isStationary") == 1  # 61.4
    assert rig.get("X1.basic.in.followUpModeActive") == 0
    assert rig.get("Z1.basic.in.enc1Synchronized") == 0  # incremental encoder, not referenced


# ------------------------------------------------------------------------------ JOG velocity


@pytest.mark.parametrize(("override", "factor"), [(100, 1.0), (50, 0.5), (10, 0.1), (120, 1.2), (150, 1.2)])
def test_jog_velocity_is_md32020_times_the_axis_override(override: int, factor: float) -> None:
    # DB31.DBB0 binary, limited to MD12100 = 120 %: 150 % gives 1.2 * 33.333 = 40 mm/s.
    rig = jog_rig()
    rig.set("X1.basic.out.feedrateOvrFactor", override)
    hold(rig, "X1", "Plus", 50)  # the ramp ends after at most ceil(40 / 8) = 5 cycles
    before = rig.axis("X1").actual
    rig.step(100)
    # 100 cycles = 0.2 s at factor * 33.333 mm/s
    assert rig.axis("X1").actual - before == pytest.approx(factor * JOG_V * 0.2, abs=1e-6)
    assert rig.sim.axis_quantity("X1", "velocity") == pytest.approx(factor * 2000.0, abs=1e-6)


def test_jog_minus_moves_in_minus_direction_at_jog_velocity() -> None:
    rig = jog_rig()
    hold(rig, "X1", "Minus", 50)
    before = rig.axis("X1").actual
    rig.step(100)
    assert rig.axis("X1").actual - before == pytest.approx(-JOG_V * 0.2, abs=1e-6)


def test_jog_rapid_overlay_uses_md32010() -> None:
    rig = jog_rig()
    rig.set("X1.basic.out.enableRapidTravers", 1)
    hold(rig, "X1", "Plus", 50)  # 166.67 mm/s reached after ceil(166.67 / 8) = 21 cycles
    before = rig.axis("X1").actual
    rig.step(50)
    assert rig.axis("X1").actual - before == pytest.approx(10000.0 / 60.0 * 0.1, abs=1e-6)


def test_jog_acceleration_is_md32300() -> None:
    rig = jog_rig()
    rig.set("X1.basic.out.traversKeyPlus", 1)
    velocities = []
    for _ in range(6):
        rig.step()
        velocities.append(rig.axis("X1").command_velocity)
    # +8 mm/s per cycle up to 33.333 mm/s
    assert velocities == pytest.approx([8.0, 16.0, 24.0, 32.0, JOG_V, JOG_V])


def test_jog_from_the_panel_through_the_basic_machine_plc_with_the_override_switch() -> None:
    # Operator: JOG is the power-on mode; feed override switch at 50 % -> 16.667 mm/s.
    rig = Rig(machine(ABSOLUTE_X1), plc="basic_machine")
    rig.step(120)  # drives ready, enables
    rig.press("MCP.feedOverride", 50)
    rig.press("MCP.minus.X1")
    rig.step(50)
    axis = rig.axis("X1")
    before = axis.actual
    rig.step(100)
    assert axis.actual - before == pytest.approx(-0.5 * JOG_V * 0.2, abs=1e-6)
    rig.release("MCP.minus.X1")
    rig.step(50)
    assert axis.velocity == 0.0
    assert rig.get("X1.basic.in.isStationary") == 1


def test_both_traverse_keys_give_no_motion() -> None:
    rig = jog_rig()
    rig.set("X1.basic.out.traversKeyPlus", 1)
    rig.set("X1.basic.out.traversKeyMinus", 1)
    rig.step(100)
    assert rig.axis("X1").physical == 150.0
    assert rig.get("X1.basic.in.traversPlusCommandActive") == 0
    assert rig.get("X1.basic.in.traversMinusCommandActive") == 0


def test_axis_override_zero_holds_jog() -> None:
    rig = jog_rig()
    rig.set("X1.basic.out.feedrateOvrFactor", 0)
    hold(rig, "X1", "Plus", 100)
    assert rig.axis("X1").physical == 150.0


def test_traverse_keys_are_ignored_outside_jog() -> None:
    rig = jog_rig()
    rig.select_mode("mda")
    rig.step(2)
    hold(rig, "X1", "Plus", 100)
    assert rig.axis("X1").physical == 150.0


# ------------------------------------------------------------------------------ release and braking


def test_key_release_brakes_with_md32300() -> None:
    rig = jog_rig()
    hold(rig, "X1", "Plus", 50)
    axis = rig.axis("X1")
    released_at = axis.setpoint
    rig.set("X1.basic.out.traversKeyPlus", 0)
    velocities: list[float] = []
    while axis.command_velocity != 0.0 or not velocities:
        rig.step()
        velocities.append(axis.command_velocity)
        assert len(velocities) < 20
    # 33.333 -> 25.333 -> 17.333 -> 9.333 -> 1.333 -> 0 (8 mm/s per cycle = 4000 mm/s^2)
    assert velocities == pytest.approx([25.0 + 1 / 3, 17.0 + 1 / 3, 9.0 + 1 / 3, 1.0 + 1 / 3, 0.0])
    # Braking distance (25.333 + 17.333 + 9.333 + 1.333) * 0.002 = 0.106667 mm
    # (continuous: v^2 / 2a = 1111.1 / 8000 = 0.1389 mm, minus the discrete half steps)
    assert axis.setpoint - released_at == pytest.approx((53.0 + 1 / 3) * DT, abs=1e-9)


def test_braking_distance_follows_md32300() -> None:
    # MD32300 = 2 m/s^2: 4 mm/s per cycle: 29.333, 25.333 .. 1.333 then 0: 9 cycles;
    # distance 0.002 * sum(33.333 - 4k, k = 1..8) = 0.002 * (8 * 33.333 - 4 * 36) = 0.245333 mm
    rig = jog_rig("CHAN1: {MD20700: 0}\nX1: {MD30240: [4], MD34210: [2], MD32300: [2.0, 2.0, 2.0, 2.0, 2.0]}")
    hold(rig, "X1", "Plus", 50)
    axis = rig.axis("X1")
    released_at = axis.setpoint
    rig.set("X1.basic.out.traversKeyPlus", 0)
    cycles = rig.run_until(lambda: axis.command_velocity == 0.0, 50)
    assert cycles == 9
    assert axis.setpoint - released_at == pytest.approx(0.002 * (8 * JOG_V - 4 * 36), abs=1e-6)


# ------------------------------------------------------------------------------ status bits


def test_traverse_command_bits_while_moving_and_exact_stop_bits_at_standstill() -> None:
    rig = jog_rig()
    hold(rig, "X1", "Plus", 20)
    moving_plus = {name: rig.get(f"X1.basic.in.{name}") for name in (
        "traversPlusCommandActive", "traversMinusCommandActive", "posCoarseReached", "posFineReached",
        "isStationary")}
    assert moving_plus == {"traversPlusCommandActive": 1, "traversMinusCommandActive": 0,
                           "posCoarseReached": 0, "posFineReached": 0, "isStationary": 0}
    rig.set("X1.basic.out.traversKeyPlus", 0)
    hold(rig, "X1", "Minus", 30)
    assert rig.get("X1.basic.in.traversMinusCommandActive") == 1  # 64.6
    assert rig.get("X1.basic.in.traversPlusCommandActive") == 0  # 64.7
    assert rig.get("CHAN1.basic.in.allAxesStationary") == 0  # 36.3
    rig.set("X1.basic.out.traversKeyMinus", 0)
    rig.step(100)
    at_rest = {name: rig.get(f"X1.basic.in.{name}") for name in (
        "traversPlusCommandActive", "traversMinusCommandActive", "posCoarseReached", "posFineReached",
        "isStationary")}
    assert at_rest == {"traversPlusCommandActive": 0, "traversMinusCommandActive": 0,
                       "posCoarseReached": 1, "posFineReached": 1, "isStationary": 1}
    assert rig.get("CHAN1.basic.in.allAxesStationary") == 1


def test_exact_stop_bits_are_set_only_within_their_windows() -> None:
    # 60.7 only while |actual - end| <= MD36010 (0.01), 60.6 while <= MD36000 (0.04): the windows
    # are measured from the position the axis stops at (seed 003 §13.8.8, L21204-21273).
    rig = jog_rig()
    hold(rig, "X1", "Plus", 40)
    axis = rig.axis("X1")
    rig.set("X1.basic.out.traversKeyPlus", 0)
    rig.run_until(lambda: axis.command_velocity == 0.0, 20)
    end = axis.setpoint
    for _ in range(100):
        rig.step()
        distance = abs(axis.actual - end)
        if rig.get("X1.basic.in.posFineReached"):
            assert distance <= 0.01
        if rig.get("X1.basic.in.posCoarseReached"):
            assert distance <= 0.04
    assert rig.get("X1.basic.in.posFineReached") == 1


# ------------------------------------------------------------------------------ software limit switches


def test_jog_stops_exactly_on_the_plus_software_limit_and_raises_10621() -> None:
    rig = jog_rig("CHAN1: {MD20700: 0}\nX1: {MD30240: [4], MD34210: [2], MD36110: 152.0}")
    axis = rig.axis("X1")
    hold(rig, "X1", "Plus", 200)  # 2 mm at 33.3 mm/s take 60 ms = 30 cycles
    assert axis.setpoint == 152.0
    assert axis.actual == pytest.approx(152.0, abs=1e-6)
    [alarm] = [a for a in rig.sim.alarms() if a.number == 10621]
    assert alarm.axis == "X1"
    assert "+" in alarm.text
    # The key is still held: the axis does not move on.
    rig.step(50)
    assert axis.setpoint == 152.0


def test_jog_rapid_to_the_software_limit_never_passes_it() -> None:
    # 166.67 mm/s needs 166.67^2 / 8000 = 3.5 mm to stop: braking starts before the limit.
    rig = jog_rig("CHAN1: {MD20700: 0}\nX1: {MD30240: [4], MD34210: [2], MD36110: 160.0}")
    axis = rig.axis("X1")
    rig.set("X1.basic.out.enableRapidTravers", 1)
    rig.set("X1.basic.out.traversKeyPlus", 1)
    furthest = 0.0
    for _ in range(300):
        rig.step()
        furthest = max(furthest, axis.setpoint, axis.actual, axis.physical)
    assert axis.setpoint == 160.0
    assert furthest <= 160.0 + 1e-6
    assert 10621 in rig.alarm_numbers()


def test_10621_clears_when_the_axis_moves_away_from_the_limit() -> None:
    rig = jog_rig("CHAN1: {MD20700: 0}\nX1: {MD30240: [4], MD34210: [2], MD36110: 152.0}")
    hold(rig, "X1", "Plus", 200)
    rig.set("X1.basic.out.traversKeyPlus", 0)
    rig.step(10)
    assert 10621 in rig.alarm_numbers()  # still resting on the limit
    hold(rig, "X1", "Minus", 20)
    assert rig.axis("X1").setpoint < 152.0
    assert 10621 not in rig.alarm_numbers()


def test_jog_stops_exactly_on_the_minus_software_limit() -> None:
    rig = jog_rig("CHAN1: {MD20700: 0}\nX1: {MD30240: [4], MD34210: [2], MD36100: 148.5}")
    hold(rig, "X1", "Minus", 200)
    assert rig.axis("X1").setpoint == 148.5
    [alarm] = [a for a in rig.sim.alarms() if a.number == 10621]
    assert "-" in alarm.text


def test_unreferenced_axis_ignores_the_software_limits() -> None:
    # Incremental encoder: not referenced, actual value 0 at power-on; MD36110 = 2 is passed.
    rig = jog_rig("CHAN1: {MD20700: 0}\nX1: {MD36110: 2.0}")
    axis = rig.axis("X1")
    assert not axis.referenced
    hold(rig, "X1", "Plus", 200)  # ~6.5 mm
    assert axis.actual > 5.0
    assert 10621 not in rig.alarm_numbers()


# ------------------------------------------------------------------------------ hardware limit switches


def test_hardware_limit_switch_stops_the_axis_raises_21614_and_allows_only_moving_away() -> None:
    # X1 (not referenced: no software limit) starts 4 mm before the plus limit switch at 312.
    rig = Rig(with_start_position(machine(), "X1", 308.0), plc="basic_machine")
    axis = rig.axis("X1")
    rig.step(100)  # drives ready, enables
    rig.press("MCP.plus.X1")
    rig.run_until(lambda: 21614 in rig.alarm_numbers(), 1000)
    [alarm] = [a for a in rig.sim.alarms() if a.number == 21614]
    assert alarm.axis == "X1" and "+" in alarm.text
    assert rig.get("X1.basic.out.hwLimitSwitchPlus") == 1  # the PLC reports the opened NC contact
    rig.step(100)
    stop = axis.physical
    # From 33.3 mm/s with MD32300 the axis stops within 0.139 mm + the loop's lag (~0.07 mm) after
    # the NC saw the switch; the PLC needs up to two scans (20 ms = 0.67 mm) to pass it on.
    assert 312.0 < stop < 312.0 + 0.67 + 0.14 + 0.07 + 0.05
    assert axis.velocity == 0.0
    rig.step(100)
    assert axis.physical == stop  # key still held: the axis stays
    # Toward the switch: blocked, also after reset.
    rig.release("MCP.plus.X1")
    rig.tap("MCP.reset")
    assert 21614 not in rig.alarm_numbers()
    rig.press("MCP.plus.X1")
    rig.step(100)
    assert axis.physical == pytest.approx(stop, abs=1e-9)
    rig.release("MCP.plus.X1")
    # Away from it: possible.
    rig.press("MCP.minus.X1")
    rig.step(200)
    assert axis.physical < 312.0
    assert rig.io("X1.hwLimitPlus") == 1  # contact closed again


def test_hardware_limit_switch_blocks_jog_in_both_directions_until_reset() -> None:
    rig = Rig(with_start_position(machine(), "X1", 308.0), plc="basic_machine")
    axis = rig.axis("X1")
    rig.step(100)
    rig.press("MCP.plus.X1")
    rig.run_until(lambda: 21614 in rig.alarm_numbers(), 1000)
    rig.release("MCP.plus.X1")
    rig.step(100)
    stop = axis.physical
    rig.press("MCP.minus.X1")
    rig.step(100)
    assert axis.physical == stop  # alarm 21614 stops the axes of the channel until reset


# ------------------------------------------------------------------------------ feed stop in JOG


def test_axis_feed_stop_holds_jog_and_release_continues() -> None:
    rig = jog_rig()
    axis = rig.axis("X1")
    hold(rig, "X1", "Plus", 20)
    rig.set("X1.basic.out.feedStopSpindleStop", 1)  # DB31.DBX4.3
    rig.step(10)  # 33.3 mm/s stops within 5 cycles
    stopped = axis.setpoint
    rig.step(50)
    assert axis.setpoint == stopped
    rig.set("X1.basic.out.feedStopSpindleStop", 0)
    rig.step(50)
    assert axis.setpoint > stopped + 1.0


def test_channel_feed_disable_holds_jog() -> None:
    # DB21.DBX6.0 brings every axis of the channel to standstill in all modes (seed 003 L8937-8941).
    rig = jog_rig()
    axis = rig.axis("X1")
    rig.set("CHAN1.basic.out.disableFeed", 1)
    hold(rig, "X1", "Plus", 50)
    assert axis.physical == 150.0
    rig.set("CHAN1.basic.out.disableFeed", 0)
    rig.step(50)
    assert axis.physical > 150.5


# ------------------------------------------------------------------------------ controller enable


@pytest.mark.parametrize("follow_up", [0, 1])
def test_controller_enable_removed_during_motion_raises_21612_and_stops_the_axis(follow_up: int) -> None:
    rig = Rig(machine(ABSOLUTE_X1), plc="basic_machine")
    axis = rig.axis("X1")
    rig.step(100)
    rig.press("MCP.plus.X1")
    rig.step(100)
    assert axis.velocity == pytest.approx(JOG_V)
    if follow_up:
        rig.sim.force(rig.sim.catalog.resolve("X1.basic.out.followUpMode"), 1)
    rig.sim.force(rig.sim.catalog.resolve("X1.basic.out.enableCtrl"), 0)
    rig.step(1)
    assert 21612 in rig.alarm_numbers()
    # The drive brakes on the rapid-stop ramp MD32000 / MD36610 = 500 / 0.05 = 10000 mm/s^2:
    # 33.3 mm/s -> 0 within ceil(33.3 / 20) = 2 cycles; allow the PLC's 2 scans of delay.
    rig.step(12)
    assert axis.velocity == 0.0
    stop = axis.physical
    rig.step(100)
    assert axis.physical == stop
    assert rig.get("X1.basic.in.posCtrlActive") == 0  # 61.5
    assert rig.get("X1.basic.in.followUpModeActive") == follow_up  # 61.3 only if requested (DB31.DBX1.4)
    if follow_up:
        assert axis.setpoint == pytest.approx(axis.actual)  # the setpoint follows the actual value


def test_controller_enable_removed_at_standstill_raises_no_alarm() -> None:
    rig = jog_rig()
    rig.set("X1.basic.out.followUpMode", 1)
    rig.set("X1.basic.out.enableCtrl", 0)
    rig.step(10)
    assert rig.alarm_numbers() == []
    assert rig.get("X1.basic.in.followUpModeActive") == 1
    assert rig.get("X1.basic.in.posCtrlActive") == 0


def test_axis_without_enable_does_not_jog() -> None:
    rig = jog_rig()
    rig.set("X1.basic.out.enableCtrl", 0)
    hold(rig, "X1", "Plus", 50)
    assert rig.axis("X1").physical == 150.0


# ------------------------------------------------------------------------------ jerk filter and exact stop


@pytest.mark.parametrize("mode", [1, 2])
def test_exact_stop_fine_with_the_jerk_filter_is_measured_from_the_end_point(mode: int) -> None:
    # MD32400 = 1, MD32402 = mode, MD32410 = 16 ms.  The exact-stop windows are increments from the
    # programmed end point (seed 003 §13.8.8, L21204-21273): 60.7 may only show while
    # |actual - 160| <= MD36010 = 0.01 mm, and the block ends only then.
    rig = Rig(machine(f"CHAN1: {{MD20700: 0}}\nX1: {{MD30240: [4], MD34210: [2], MD32400: 1, MD32402: {mode},"
                      f" MD32410: 0.016}}"))
    rig.ready_mda("X1")
    axis = rig.axis("X1")
    rig.mda("G1 X160 F1000")
    worst = 0.0
    for _ in range(500):
        rig.step()
        if rig.get("X1.basic.in.posFineReached"):
            worst = max(worst, abs(axis.actual - 160.0))
        if rig.get("CHAN1.basic.in.stateReset"):
            break
    assert rig.get("CHAN1.basic.in.stateReset") == 1
    assert abs(axis.actual - 160.0) <= 0.01
    assert worst <= 0.01


def test_jerk_filter_moving_average_ends_the_block_about_the_filter_time_later() -> None:
    # Same block with and without MD32400: the end of the motion moves by MD32410 = 16 ms
    # (8 cycles, the moving average reaches the end 7 cycles later), plus a few cycles of settling.
    def block_cycles(overrides: str) -> int:
        rig = Rig(machine(overrides))
        rig.ready_mda("X1")
        rig.mda("G1 X160 F1000")
        return rig.run_until(lambda: rig.get("CHAN1.basic.in.stateReset") == 1, 1000)

    plain = block_cycles(ABSOLUTE_X1)
    filtered = block_cycles("CHAN1: {MD20700: 0}\nX1: {MD30240: [4], MD34210: [2], MD32400: 1, MD32402: 2,"
                            " MD32410: 0.016}")
    assert 7 - 2 <= filtered - plain <= 8 + 2


# ------------------------------------------------------------------------------ modulo rotary axis


def test_a_modulo_rotary_axis_shows_its_position_inside_the_modulo_range() -> None:
    # mill_5axis C1: MD30310 = 1, 0 .. 360; JOG at MD32020 = 5 rev/min = 30 deg/s from 350
    rig = Rig(machine("CHAN1: {MD20700: 0}\nC1: {sim: {start_position: 350.0}}", FIVE_AXIS))
    rig.enable_axes()
    rig.select_mode("jog")
    rig.step(3)
    c1 = rig.axis("C1")
    c1.synchronise(c1.encoder, c1.physical, 350.0)
    hold(rig, "C1", "Plus", 500)  # 1 s: 30 deg
    assert c1.actual > 360.0  # the NC counts on: one continuous move
    assert rig.sim.axis_quantity("C1", "position") == pytest.approx(c1.actual - 360.0)
    assert 0.0 <= rig.sim.axis_quantity("C1", "setpoint") < 360.0
    assert rig.sim.axis_quantity("C1", "physical") == pytest.approx(c1.physical)


def test_a_rotary_axis_without_modulo_shows_its_position_as_it_is() -> None:
    rig = Rig(machine("", FIVE_AXIS))
    a1 = rig.axis("A1")
    assert a1.modulo_range is None
    assert a1.shown(725.0) == 725.0
    assert rig.axis("C1").shown(-10.0) == pytest.approx(350.0)


# ------------------------------------------------------------------------------ encoder limit frequency


def test_above_the_encoder_limit_frequency_the_axis_loses_its_reference_and_raises_21610() -> None:
    # X1 motor encoder: 2048 lines on 10 mm = 204.8 periods/mm; MD36300 = 20 kHz: 97.66 mm/s limit
    rig = jog_rig("CHAN1: {MD20700: 0}\nX1: {MD30240: [4], MD34210: [2], MD36300: [20000.0]}")
    x1 = rig.axis("X1")
    assert x1.encoder.limit_velocity == pytest.approx(20000.0 / 204.8)
    hold(rig, "X1", "Plus", 100)  # JOG 33.3 mm/s
    assert x1.referenced and rig.alarm_numbers() == []
    rig.set("X1.basic.out.enableRapidTravers", 1)  # 166.7 mm/s
    rig.run_until(lambda: abs(x1.velocity) > 97.66, 200)
    rig.step(1)
    assert not x1.referenced
    assert rig.get("X1.basic.in.enc1FreqLimitExceeded") == 1
    assert rig.get("X1.basic.in.enc1Synchronized") == 0
    assert rig.alarm_numbers() == [21610]
    rig.set("X1.basic.out.traversKeyPlus", 0)
    rig.run_until(lambda: x1.velocity == 0.0, 500)
    assert rig.get("X1.basic.in.enc1FreqLimitExceeded") == 0  # below MD36302 = 99.9 % again


def test_a_linear_scale_counts_its_grid_periods() -> None:
    # X1 measuring system 2: a linear scale, MD31010 = 0.01 mm grid: 300 kHz x 0.01 mm = 3000 mm/s
    x1 = Rig(machine()).axis("X1")
    assert x1.encoders[1].limit_velocity == pytest.approx(3000.0)
    assert x1.encoders[1].resync_velocity == pytest.approx(3000.0 * 0.999)


# ------------------------------------------------------------------------------ DRF (seed 003 §16.13.3)


def drf_rig(drf: int = 1) -> Rig:
    """MDA, handwheel 1 on X1 with INC100 (0.1 mm per detent), DB21.DBX0.3 = ``drf``."""
    rig = Rig(machine(ABSOLUTE_X1))
    rig.ready_mda()
    rig.set("X1.basic.out.handwheelSelection", 1)
    rig.set("X1.basic.out.inc100", 1)
    rig.set("CHAN1.basic.out.handwheelOffsetDrf", drf)
    rig.step(2)
    return rig


def test_drf_offset_moves_the_axis_in_the_mcs_at_jog_velocity_times_md32090() -> None:
    rig = drf_rig()
    axis = rig.axis("X1")
    start = axis.setpoint
    assert rig.get("CHAN1.basic.in.handwheelOvrActive") == 1  # DB21.DBX33.3
    rig.nck.turn_handwheel(1, 20, 1)
    peak = 0.0
    for _ in range(200):
        rig.step()
        peak = max(peak, axis.command_velocity + axis.overlay_velocity)
    assert peak == pytest.approx(JOG_V * 0.5)  # MD32090 0.5
    assert axis.drf_offset == pytest.approx(2.0, abs=1e-9)
    assert axis.setpoint == start  # the interpolator's position is untouched
    assert axis.actual == pytest.approx(start + 2.0, abs=1e-4)


def test_drf_pulses_move_nothing_without_dbx0_3_or_in_jog() -> None:
    rig = drf_rig(drf=0)
    axis = rig.axis("X1")
    rig.nck.turn_handwheel(1, 20, 1)
    rig.step(100)
    assert axis.drf_offset == 0.0
    assert rig.get("CHAN1.basic.in.handwheelOvrActive") == 0
    rig.set("CHAN1.basic.out.handwheelOffsetDrf", 1)
    rig.select_mode("jog")
    rig.step(3)
    rig.nck.turn_handwheel(1, 20, 1)
    rig.step(100)
    assert axis.drf_offset == 0.0
    assert rig.get("CHAN1.basic.in.handwheelOvrActive") == 0


def test_feed_stop_brakes_the_drf_travel_and_drops_its_rest() -> None:
    rig = drf_rig()
    axis = rig.axis("X1")
    rig.nck.turn_handwheel(1, 20, 1)
    rig.step(20)
    rig.set("X1.basic.out.feedStopSpindleStop", 1)
    rig.step(100)
    assert 0.0 < axis.drf_offset < 1.0
    assert not axis.drf_moving
