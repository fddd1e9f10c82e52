"""Channel: MDA program execution, block change, holds, NC start/stop/reset and program alarms.

The test is the PLC (``plc=None``): it gives the enables, selects MDA and writes NC start,
NC stop, reset, feed disable and the overrides itself.  X1, Z1 and Y1 have calibrated
absolute encoders (referenced at power-on, actual = physical): X1 at 150, Z1 at 300,
Y1 at 0; software limits X1 -5 / 305.  X1 and Z1: MD32300 4 m/s^2 = 4000 mm/s^2,
MD32000 30 m/min = 500 mm/s.  IPO cycle 2 ms.
"""

from __future__ import annotations

import math

import pytest
from core_rig import ABSOLUTE_X1, ABSOLUTE_XYZ, DT, Rig, machine

A = 4000.0  # mm/s^2


def mda_rig(overrides: str = ABSOLUTE_XYZ, feed: int = 100, rapid: int = 100) -> Rig:
    rig = Rig(machine(overrides))
    rig.ready_mda(feed=feed, rapid=rapid)
    return rig


def run_to_reset(rig: Rig, max_cycles: int = 3000) -> int:
    return rig.run_until(lambda: rig.get("CHAN1.basic.in.stateReset") == 1, max_cycles)


def g1_cycles(length: float, feed_mm_min: float, accel: float = A) -> float:
    """IPO cycles of a trapezoidal move: length / v + v / a (accelerate and brake at a)."""
    v = feed_mm_min / 60.0
    return (length / v + v / accel) / DT


# ------------------------------------------------------------------------------ G1 timing and end point


def test_g1_reaches_its_end_within_the_fine_window_in_the_time_the_feed_gives() -> None:
    rig = mda_rig()
    x1 = rig.axis("X1")
    rig.mda("G1 X160 F1000")
    cycles = 1 + run_to_reset(rig)  # mda() stepped the NC start cycle
    # 10 mm at F1000 = 16.667 mm/s: 10 / 16.667 + 16.667 / 4000 = 0.6 + 0.00417 s = 302.1 cycles,
    # then the exact stop fine window MD36010 = 0.01 mm (a few cycles of settling).
    expected = g1_cycles(10.0, 1000.0)
    assert expected == pytest.approx(302.08, abs=0.01)
    assert math.floor(expected) <= cycles <= math.ceil(expected) + 10
    assert abs(x1.actual - 160.0) <= 0.01
    assert x1.setpoint == 160.0
    assert rig.program_state() == {"progStateRunning": 0, "progStateWaiting": 0, "progStateStopped": 0,
                                   "progStateInterrupted": 0, "progStateAborted": 1, "stateActive": 0,
                                   "stateInterrupted": 0, "stateReset": 1}


def test_running_program_shows_35_0_and_35_5() -> None:
    rig = mda_rig()
    rig.mda("G1 X160 F1000")
    rig.step(10)
    state = rig.program_state()
    assert state["progStateRunning"] == 1 and state["stateActive"] == 1
    assert state["stateReset"] == 0 and state["progStateAborted"] == 0


def test_g1_velocity_is_f_times_the_feed_override() -> None:
    # F1000 at 50 %: 8.333 mm/s; 10 mm: 10 / 8.333 + 8.333 / 4000 = 1.2 + 0.00208 s = 601.04 cycles
    rig = mda_rig(feed=50)
    rig.mda("G1 X160 F1000")
    rig.step(100)
    assert rig.axis("X1").command_velocity == pytest.approx(1000.0 / 60.0 * 0.5)
    assert rig.sim.axis_quantity("X1", "velocity") == pytest.approx(500.0, abs=1e-6)  # mm/min
    cycles = 1 + 100 + run_to_reset(rig)
    expected = g1_cycles(10.0, 500.0)
    assert math.floor(expected) <= cycles <= math.ceil(expected) + 10


def test_feed_override_change_acts_at_once_on_the_running_block() -> None:
    rig = mda_rig()
    rig.mda("G1 X200 F1000")
    rig.step(50)
    rig.set("CHAN1.basic.out.pathFeedrateOvrFactor", 120)
    rig.step(20)  # 16.667 -> 20 mm/s takes one cycle
    assert rig.axis("X1").command_velocity == pytest.approx(20.0)


def test_two_axis_g1_moves_both_axes_linearly_and_they_arrive_together() -> None:
    # X1 150 -> 160 and Z1 300 -> 310: path length sqrt(200) = 14.142 mm at F1000 = 16.667 mm/s;
    # each axis carries 1/sqrt(2) of the path, so the path may accelerate with 4000 * sqrt(2) mm/s^2:
    # 14.142 / 16.667 + 16.667 / 5656.9 = 0.84853 + 0.00295 s = 425.7 cycles.
    rig = mda_rig()
    x1, z1 = rig.axis("X1"), rig.axis("Z1")
    rig.mda("G1 X160 Z310 F1000")
    for _ in range(200):
        rig.step()
        assert x1.setpoint - 150.0 == pytest.approx(z1.setpoint - 300.0, abs=1e-9)
    cycles = 1 + 200 + run_to_reset(rig)
    expected = g1_cycles(math.sqrt(200.0), 1000.0, A * math.sqrt(2.0))
    assert math.floor(expected) <= cycles <= math.ceil(expected) + 10
    assert (x1.setpoint, z1.setpoint) == (160.0, 310.0)


def test_path_velocity_changes_by_at_most_md32300_per_cycle() -> None:
    # The axis acceleration limit MD32300 holds for starting and for braking at the end point:
    # 4000 mm/s^2 * 2 ms = 8 mm/s per cycle at most.
    rig = mda_rig()
    x1 = rig.axis("X1")
    rig.sim.load_mda("CHAN1", "G1 X160 F1000")
    rig.set("CHAN1.basic.out.ncStart", 1)
    previous = 0.0
    worst = 0.0
    for _ in range(400):
        rig.step()
        worst = max(worst, abs(x1.command_velocity - previous))
        previous = x1.command_velocity
    assert x1.setpoint == 160.0
    assert worst <= A * DT + 1e-9


def test_traverse_command_bits_follow_the_path_direction() -> None:
    rig = mda_rig()
    rig.mda("G1 X140 Z310 F1000")
    rig.step(50)
    assert rig.get("X1.basic.in.traversMinusCommandActive") == 1  # DB31.DBX64.6
    assert rig.get("X1.basic.in.traversPlusCommandActive") == 0
    assert rig.get("Z1.basic.in.traversPlusCommandActive") == 1  # DB32.DBX64.7
    assert rig.get("X1.basic.in.posFineReached") == 0
    run_to_reset(rig)
    assert rig.get("X1.basic.in.traversMinusCommandActive") == 0
    assert rig.get("Z1.basic.in.traversPlusCommandActive") == 0
    assert rig.get("X1.basic.in.posFineReached") == 1


# ------------------------------------------------------------------------------ holds


def test_feed_override_zero_holds_the_path_and_100_continues() -> None:
    rig = mda_rig()
    x1 = rig.axis("X1")
    rig.mda("G1 X160 F1000")
    rig.step(50)
    rig.set("CHAN1.basic.out.pathFeedrateOvrFactor", 0)
    rig.step(5)  # 16.7 mm/s brakes in 3 cycles
    held = x1.setpoint
    rig.step(100)
    assert x1.setpoint == held < 160.0
    assert x1.velocity == 0.0
    assert rig.get("CHAN1.basic.in.stateActive") == 1  # the program is still active
    rig.set("CHAN1.basic.out.pathFeedrateOvrFactor", 100)
    run_to_reset(rig)
    assert x1.setpoint == 160.0


def test_channel_feed_disable_holds_the_path_and_release_continues() -> None:
    rig = mda_rig()
    x1 = rig.axis("X1")
    rig.mda("G1 X160 F1000")
    rig.step(50)
    rig.set("CHAN1.basic.out.disableFeed", 1)  # DB21.DBX6.0
    rig.step(5)
    held = x1.setpoint
    rig.step(100)
    assert x1.setpoint == held < 160.0
    assert rig.get("CHAN1.basic.in.stateActive") == 1
    rig.set("CHAN1.basic.out.disableFeed", 0)
    run_to_reset(rig)
    assert x1.setpoint == 160.0


def test_axis_feed_stop_of_one_path_axis_holds_every_axis_of_the_block_on_the_contour() -> None:
    # DB31.DBX4.3 on a path axis stops all axes of the block (seed 003 L8966-8975); the contour is kept.
    rig = mda_rig()
    x1, z1 = rig.axis("X1"), rig.axis("Z1")
    rig.mda("G1 X170 Z320 F1000")
    rig.step(100)
    rig.set("Z1.basic.out.feedStopSpindleStop", 1)
    for _ in range(10):
        rig.step()
        assert x1.setpoint - 150.0 == pytest.approx(z1.setpoint - 300.0, abs=1e-9)
    held = (x1.setpoint, z1.setpoint)
    rig.step(100)
    assert (x1.setpoint, z1.setpoint) == held
    assert x1.velocity == 0.0 and z1.velocity == 0.0
    rig.set("Z1.basic.out.feedStopSpindleStop", 0)
    run_to_reset(rig)
    assert (x1.setpoint, z1.setpoint) == (170.0, 320.0)


def test_delete_distance_to_go_brakes_the_path_and_the_next_block_starts_where_it_stopped() -> None:
    rig = mda_rig()
    x1, z1 = rig.axis("X1"), rig.axis("Z1")
    z_start = z1.setpoint
    rig.mda("N10 G1 X160 F1000\nN20 G91 Z-10\nN30 M30")
    rig.step(50)
    rig.set("CHAN1.basic.out.deleteDistanceToGo", 1)  # DB21.DBX6.2, its rising edge
    rig.step(1)
    assert x1.command_velocity != 0.0  # braked on its ramp, not stopped at once
    rig.step(20)
    deleted_at = x1.setpoint
    assert x1.command_velocity == 0.0 and deleted_at != 160.0
    run_to_reset(rig)
    assert x1.setpoint == deleted_at  # the rest of N10 is deleted
    assert z1.setpoint == pytest.approx(z_start - 10.0)  # N20 ran (incremental from where it stood)


def test_delete_distance_to_go_held_at_1_acts_once_and_not_on_a_positioning_axis() -> None:
    rig = mda_rig()
    x1, z1 = rig.axis("X1"), rig.axis("Z1")
    rig.set("CHAN1.basic.out.deleteDistanceToGo", 1)  # 1 before the program starts: no edge in a block
    rig.mda("N10 POS[Z]=250 FA[Z]=2000\nN20 G1 X160 F1000\nN30 M30")
    run_to_reset(rig)
    assert z1.setpoint == 250.0 and x1.setpoint == 160.0
    rig.set("CHAN1.basic.out.deleteDistanceToGo", 0)
    rig.mda("N10 POS[Z]=300 FA[Z]=2000\nN20 M30")
    rig.step(50)
    rig.set("CHAN1.basic.out.deleteDistanceToGo", 1)  # seed 003 L12160-12164: not for positioning axes
    run_to_reset(rig)
    assert z1.setpoint == 300.0


def test_read_in_disable_keeps_the_next_block_from_starting() -> None:
    rig = mda_rig()
    x1 = rig.axis("X1")
    rig.set("CHAN1.basic.out.disableReadIn", 1)  # DB21.DBX6.1
    rig.mda("G1 X151 F3000\nX152")
    rig.step(300)
    assert x1.setpoint == 151.0
    rig.set("CHAN1.basic.out.disableReadIn", 0)
    run_to_reset(rig)
    assert x1.setpoint == 152.0


# ------------------------------------------------------------------------------ NC stop, NC start, reset


def test_nc_stop_brakes_on_the_path_and_nc_start_continues_to_the_end_point() -> None:
    rig = mda_rig()
    x1, z1 = rig.axis("X1"), rig.axis("Z1")
    rig.mda("G1 X170 Z320 F1000")
    rig.step(100)
    rig.pulse("CHAN1.basic.out.ncStop")
    for _ in range(10):
        rig.step()
        assert x1.setpoint - 150.0 == pytest.approx(z1.setpoint - 300.0, abs=1e-9)
    stopped = x1.setpoint
    rig.step(100)
    assert x1.setpoint == stopped < 170.0
    state = rig.program_state()
    assert state["progStateStopped"] == 1  # 35.2
    assert state["stateInterrupted"] == 1  # 35.6
    assert state["progStateRunning"] == 0 and state["stateActive"] == 0
    rig.pulse("CHAN1.basic.out.ncStart")
    rig.step(5)
    assert rig.program_state()["progStateRunning"] == 1
    run_to_reset(rig)
    assert (x1.setpoint, z1.setpoint) == (170.0, 320.0)


def test_reset_in_motion_brakes_on_the_path_and_aborts_the_program() -> None:
    rig = mda_rig()
    x1, z1 = rig.axis("X1"), rig.axis("Z1")
    rig.mda("G1 X170 Z320 F1000")
    rig.step(100)
    velocity = x1.command_velocity
    rig.pulse("CHAN1.basic.out.reset")
    # braking at 4000 * sqrt(2) mm/s^2 along the path: the axes keep their 1:1 ratio
    for _ in range(10):
        rig.step()
        assert x1.setpoint - 150.0 == pytest.approx(z1.setpoint - 300.0, abs=1e-9)
    assert x1.command_velocity == 0.0
    assert velocity > 10.0
    rig.step(50)
    stopped = x1.setpoint
    assert stopped < 170.0
    state = rig.program_state()
    assert state["progStateAborted"] == 1  # 35.4
    assert state["stateReset"] == 1  # 35.7
    assert state["progStateRunning"] == 0 and state["progStateStopped"] == 0
    rig.step(200)
    assert x1.setpoint == stopped  # the rest of the block is not executed


def test_reset_after_nc_stop_aborts_and_the_next_start_runs_the_program_from_its_start() -> None:
    rig = mda_rig()
    x1 = rig.axis("X1")
    rig.mda("G91 G1 X5 F3000\nX5")
    rig.step(20)
    rig.pulse("CHAN1.basic.out.ncStop")
    rig.step(20)
    rig.pulse("CHAN1.basic.out.reset")
    rig.step(5)
    assert rig.get("CHAN1.basic.in.stateReset") == 1
    start = x1.setpoint
    rig.pulse("CHAN1.basic.out.ncStart")
    run_to_reset(rig)
    assert x1.setpoint == pytest.approx(start + 10.0)


def test_m30_ends_the_program_in_reset_state() -> None:
    rig = mda_rig()
    x1 = rig.axis("X1")
    rig.mda("G1 X152 F1000\nM30\nG1 X160")
    run_to_reset(rig)
    rig.step(300)
    assert x1.setpoint == 152.0  # the block after M30 is never executed
    state = rig.program_state()
    assert state["stateReset"] == 1 and state["progStateAborted"] == 1


def test_m0_stops_the_program_and_nc_start_continues() -> None:
    rig = mda_rig()
    x1 = rig.axis("X1")
    rig.mda("G1 X151 F3000\nM0\nX152")
    rig.step(200)
    assert x1.setpoint == 151.0
    assert rig.program_state()["progStateStopped"] == 1
    rig.pulse("CHAN1.basic.out.ncStart")
    run_to_reset(rig)
    assert x1.setpoint == 152.0


def test_program_without_m30_ends_after_its_last_block() -> None:
    rig = mda_rig()
    rig.mda("G1 X151 F3000")
    run_to_reset(rig, 200)
    assert rig.axis("X1").setpoint == 151.0


# ------------------------------------------------------------------------------ G4, G91, G0


def test_g4_dwell_lasts_f_seconds() -> None:
    # G4 F0.5: 0.5 s = 250 IPO cycles (the program ends after its last block: no M30, whose
    # acknowledgement by the PLC would add to the time)
    rig = mda_rig()
    rig.mda("G4 F0.5")
    assert rig.get("CHAN1.basic.in.stateActive") == 1
    cycles = 1 + run_to_reset(rig)
    assert 250 <= cycles <= 252


def test_g4_between_two_moves_holds_the_axis_for_the_dwell_time() -> None:
    rig = mda_rig()
    x1 = rig.axis("X1")
    rig.mda("G1 X151 F3000\nG4 F0.2\nX152")
    rig.run_until(lambda: x1.setpoint == 151.0, 200)
    standing = rig.run_until(lambda: x1.setpoint > 151.0, 400)
    # 0.2 s = 100 cycles plus the exact stop fine at 151 before the dwell starts
    assert 100 <= standing <= 100 + 10
    run_to_reset(rig)
    assert x1.setpoint == 152.0


def test_feed_after_a_dwell_is_the_modal_feed_not_the_dwell_time() -> None:
    rig = mda_rig()
    x1 = rig.axis("X1")
    rig.mda("G1 X151 F1000\nG4 F0.1\nX152")
    rig.run_until(lambda: x1.setpoint > 151.0, 500)
    rig.step(20)
    assert x1.command_velocity == pytest.approx(1000.0 / 60.0)


def test_g91_incremental_moves_add_up() -> None:
    rig = mda_rig()
    rig.mda("G91 G1 X5 F3000\nX5\nX-2")
    run_to_reset(rig)
    assert rig.axis("X1").setpoint == pytest.approx(158.0)


def test_g0_uses_md32000_times_the_rapid_override_and_ignores_the_feed_override() -> None:
    rig = mda_rig(rapid=50, feed=10)
    x1 = rig.axis("X1")
    rig.mda("G0 X300")
    # 500 mm/s * 50 % = 250 mm/s, reached after 250 / 8 = 32 cycles
    rig.step(60)
    assert x1.command_velocity == pytest.approx(250.0)
    rig.set("CHAN1.basic.out.pathFeedrateOvrFactor", 100)
    rig.step(5)
    assert x1.command_velocity == pytest.approx(250.0)
    rig.set("CHAN1.basic.out.pathRapidTraversOvrFactor", 100)
    rig.step(40)  # 250 -> 500 mm/s in 32 cycles
    assert x1.command_velocity == pytest.approx(500.0)
    run_to_reset(rig)
    assert x1.setpoint == 300.0


def test_g0_rapid_override_zero_holds_the_axis() -> None:
    rig = mda_rig(rapid=0)
    rig.mda("G0 X300")
    rig.step(100)
    assert rig.axis("X1").physical == 150.0
    assert rig.get("CHAN1.basic.in.stateActive") == 1


# ------------------------------------------------------------------------------ program alarms


def test_block_beyond_the_software_limit_raises_10720_before_moving() -> None:
    rig = mda_rig()
    x1 = rig.axis("X1")
    rig.mda("G1 X310 F1000")  # MD36110 = 305
    rig.step(100)
    assert 10720 in rig.alarm_numbers()
    assert x1.physical == 150.0
    assert rig.get("CHAN1.basic.in.alarmActive") == 1  # 36.6
    assert rig.get("CHAN1.basic.in.alarmWithStopActive") == 1  # 36.7
    assert rig.get("NC.basic.in.alarmActive") == 1  # DB10.DBX109.0
    assert rig.get("CHAN1.basic.in.progStateRunning") == 0


def test_10720_in_the_second_block_lets_the_first_block_finish() -> None:
    rig = mda_rig()
    x1 = rig.axis("X1")
    rig.mda("G1 X151 F3000\nG1 X400")
    rig.step(300)
    assert x1.setpoint == 151.0
    assert 10720 in rig.alarm_numbers()


def test_10720_is_cleared_by_reset_and_nc_start_is_refused_until_then() -> None:
    rig = mda_rig()
    x1 = rig.axis("X1")
    rig.mda("G1 X310 F1000")
    rig.step(10)
    rig.sim.load_mda("CHAN1", "G1 X151 F3000")
    rig.pulse("CHAN1.basic.out.ncStart")
    rig.step(100)
    assert x1.physical == 150.0
    rig.pulse("CHAN1.basic.out.reset")
    rig.step(2)
    assert rig.alarm_numbers() == []
    assert rig.get("CHAN1.basic.in.alarmActive") == 0
    rig.pulse("CHAN1.basic.out.ncStart")
    run_to_reset(rig)
    assert x1.setpoint == 151.0


@pytest.mark.parametrize(("text", "number"), [
    ("G1 X160", 10860),  # G1 without F (seed 003 L7841-7858)
    ("G1 X160 F1000 NOSUCHWORD", 12550),  # name not defined
    ("G1 X=", 12080),  # syntax error
    ("G1 X160 F1000 )", 12080),
])
def test_program_alarm_stops_the_program_before_the_block_moves(text: str, number: int) -> None:
    rig = mda_rig()
    rig.mda(text)
    rig.step(100)
    assert rig.alarm_numbers() == [number]
    assert rig.axis("X1").physical == 150.0
    assert rig.get("CHAN1.basic.in.progStateRunning") == 0
    assert rig.get("CHAN1.basic.in.alarmWithStopActive") == 1


def test_syntax_error_in_a_later_block_raises_12080_only_when_execution_reaches_it() -> None:
    rig = mda_rig()
    x1 = rig.axis("X1")
    rig.mda("G1 X160 F3000\nN20 X=")
    rig.step(20)  # 10 mm at 50 mm/s take 100 cycles
    assert rig.alarm_numbers() == []  # still moving in block 1
    rig.step(200)
    assert x1.setpoint == 160.0
    assert rig.alarm_numbers() == [12080]


def test_nc_start_with_unreferenced_axes_and_md20700_raises_10203_and_nothing_moves() -> None:
    # The shipped turn-mill: MD20700 = 1, incremental encoders: nothing referenced after power-on.
    rig = Rig(machine())
    rig.ready_mda()
    rig.sim.load_mda("CHAN1", "G1 X10 Z10 F1000")
    rig.set("CHAN1.basic.out.ncStart", 1)
    for _ in range(100):
        rig.step()
        assert rig.get("CHAN1.basic.in.progStateRunning") == 0
    assert rig.alarm_numbers() == [10203]
    assert [a.physical for a in rig.nck.axes] == [a.config.sim.start_position for a in rig.nck.axes]
    assert rig.get("CHAN1.basic.in.stateReset") == 1
    assert rig.get("CHAN1.basic.in.allAxesReferenced") == 0  # DB21.DBX36.2


def test_nc_start_with_md20700_and_every_axis_referenced_runs() -> None:
    absolute = "{MD30240: [4], MD34210: [2]}"
    rig = mda_rig(f"X1: {absolute}\nZ1: {absolute}\nY1: {absolute}")
    assert rig.get("CHAN1.basic.in.allAxesReferenced") == 1
    rig.mda("G1 X151 F3000")
    run_to_reset(rig, 300)
    assert rig.alarm_numbers() == []
    assert rig.axis("X1").setpoint == 151.0


def test_nc_start_is_ignored_in_jog() -> None:
    rig = Rig(machine(ABSOLUTE_X1))
    rig.enable_axes()
    rig.channel_overrides()
    rig.select_mode("jog")
    rig.step(2)
    rig.mda("G1 X151 F3000")
    rig.step(100)
    assert rig.get("CHAN1.basic.in.stateReset") == 1
    assert rig.axis("X1").physical == 150.0


def test_nc_start_disable_refuses_the_start() -> None:
    rig = mda_rig()
    rig.set("CHAN1.basic.out.disableNcStart", 1)  # DB21.DBX7.0
    rig.mda("G1 X151 F3000")
    rig.step(100)
    assert rig.get("CHAN1.basic.in.stateReset") == 1
    assert rig.axis("X1").physical == 150.0


# ------------------------------------------------------------------------------ program jumps


def test_a_conditional_jump_goes_back_while_its_condition_holds() -> None:
    rig = mda_rig()
    rig.mda("N10 $AC_LIFTFAST=1\nAGAIN:\nN20 G91 G1 X1 F3000\nN30 IF $AC_LIFTFAST GOTOB AGAIN\nN40 G90 G0 X140\nM30")
    rig.run_until(lambda: rig.axis("X1").setpoint > 151.5, 3000)  # the first pass ran on into the jump
    assert rig.alarm_numbers() == []
    rig.channel.esr.liftfast = 0.0  # the next test of the condition falls through
    run_to_reset(rig)
    assert rig.axis("X1").setpoint == pytest.approx(140.0)
    assert rig.alarm_numbers() == []


def test_a_labelled_jump_block_jumps_to_its_own_label_while_the_condition_holds() -> None:
    rig = mda_rig()
    rig.mda("N10 $AC_LIFTFAST=1\nN20 G91\nMM: IF $AC_LIFTFAST GOTOB MM\nN40 G90 G1 X140.5 F3000\nM30")
    rig.step(50)
    assert rig.alarm_numbers() == [] and rig.channel.current_block.label == "line 3"  # loops on itself
    rig.channel.esr.liftfast = 0.0
    run_to_reset(rig)
    assert rig.axis("X1").setpoint == pytest.approx(140.5) and rig.alarm_numbers() == []


@pytest.mark.parametrize(("text", "alarm"), [
    ("N10 GOTOF NOWHERE\nM30", 14080),
    ("N10 IF $AC_NOTHING GOTOF END_1\nEND_1:\nM30", 12550),
    ("N10 IF ($AC_LIFTFAST GOTOF END_1\nEND_1:\nM30", 12080),
])
def test_bad_jumps_raise_the_control_alarm(text: str, alarm: int) -> None:
    rig = mda_rig()
    rig.mda(text)
    rig.step(5)
    assert rig.alarm_numbers() == [alarm]


def test_gotoc_goes_on_without_a_destination() -> None:
    rig = mda_rig()
    rig.mda("N10 GOTOC NOWHERE\nN20 G1 X160 F3000\nM30")
    run_to_reset(rig)
    assert rig.axis("X1").setpoint == pytest.approx(160.0) and rig.alarm_numbers() == []
