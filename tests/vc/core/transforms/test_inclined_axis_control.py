"""The inclined-axis control of turn_mill on the NC core: Y1 inclined at -30 degrees to X1 (seed 000).

The test is the PLC.  X1, Y1 and Z1 are absolute and referenced at power-on:
X1 stands at 150, Y1 at 0, Z1 at 300 (machine = physical), so program and machine agree in Y
and in X at the start.
"""

from __future__ import annotations

import math

import pytest

from tests.vc.core.core_rig import Rig, machine, with_start_position
from vc.core.referencing.referencing import Source

TAN = math.tan(math.radians(-30.0))
COS = math.cos(math.radians(-30.0))
NOZAGC = "CHAN1.inclinedAxis.out.noOrthogonalCompensation"


def _machine_data(channel: str = "", y1: str = "") -> str:
    """X1, Y1, Z1 absolute and referenced at power-on, no NC start lock, plus the given data."""
    absolute = "MD30240: [4], MD34210: [2]"
    return (f"CHAN1: {{MD20700: 0{', ' + channel if channel else ''}}}\nX1: {{{absolute}}}\n"
            f"Z1: {{{absolute}}}\nY1: {{{absolute}{', ' + y1 if y1 else ''}}}")


def _rig(channel: str = "", y1: str = "") -> Rig:
    rig = Rig(machine(_machine_data(channel, y1)))
    rig.ready_mda()
    return rig


def _run(rig: Rig, text: str, max_cycles: int = 5000) -> None:
    rig.mda(text)
    rig.run_until(lambda: rig.get("CHAN1.basic.in.stateReset") == 1, max_cycles)
    rig.step(200)  # settled below the fine window: the display reads actual values


def _alarms(rig: Rig) -> list[int]:
    return [alarm.number for alarm in rig.nck.present_alarms()]


def test_g0_y_moves_the_inclined_slide_by_y_over_cos_and_compensates_x() -> None:
    rig = _rig()
    _run(rig, "G0 Y50")
    # Ya = 50 / cos(-30) = 57.735; Xa = 150 - 50 tan(-30) = 178.868 (seed 000 L11-20)
    assert rig.axis("Y1").setpoint == pytest.approx(50.0 / COS)
    assert rig.axis("X1").setpoint == pytest.approx(150.0 - 50.0 * TAN)
    assert rig.nck.program_position("X1") == pytest.approx(150.0, abs=1e-3)
    assert rig.nck.program_position("Y1") == pytest.approx(50.0, abs=1e-3)
    assert rig.nck.program_position("Z1") == pytest.approx(300.0, abs=1e-3)


def test_g1_feed_is_the_cartesian_path_velocity() -> None:
    rig = _rig()
    rig.mda("G1 Y50 F1000")
    rig.step(300)  # 1000 mm/min reached long before
    # F_ay = F / cos(theta), F_ax = -F tan(theta) (the component form, docs/kinematics.md 1.7)
    assert rig.axis("Y1").command_velocity == pytest.approx(1000.0 / 60.0 / COS)
    assert rig.axis("X1").command_velocity == pytest.approx(-1000.0 / 60.0 * TAN)


def test_incremental_words_count_in_program_coordinates() -> None:
    rig = _rig()
    _run(rig, "G91 G0 Y10")
    _run(rig, "G91 G0 Y10 X5")
    assert rig.nck.program_position("Y1") == pytest.approx(20.0, abs=1e-3)
    assert rig.nck.program_position("X1") == pytest.approx(155.0, abs=1e-3)
    assert rig.axis("X1").setpoint == pytest.approx(155.0 - 20.0 * TAN)


def test_nozagc_leaves_the_orthogonal_axis_and_the_display_keeps_the_program_position() -> None:
    rig = _rig()
    rig.set(NOZAGC, 1)
    _run(rig, "G0 Y50")
    assert rig.axis("X1").setpoint == pytest.approx(150.0)
    assert rig.axis("Y1").setpoint == pytest.approx(50.0 / COS)
    assert rig.nck.program_position("X1") == pytest.approx(150.0, abs=1e-3)
    rig.set(NOZAGC, 0)
    _run(rig, "G0 X160")  # the program X goes from 150 to 160: the slide by the same 10
    assert rig.axis("X1").setpoint == pytest.approx(160.0)


def test_an_inclined_move_with_nozagc_drops_the_orthogonal_reference() -> None:
    """Seed 000 L378: a manual reference return is mandatory afterwards."""
    rig = _rig()
    rig.set(NOZAGC, 1)
    _run(rig, "G0 X160")  # the orthogonal axis alone: nothing lost
    assert rig.axis("X1").referenced
    _run(rig, "G0 Y10")
    assert not rig.axis("X1").referenced and rig.axis("Y1").referenced
    assert rig.get("X1.basic.in.enc1Synchronized") == 0


def test_the_orthogonal_axis_keeps_its_software_limits_while_a_reference_return_is_due() -> None:
    """Only the program relation is lost: MD36110 = 305 of X1 still refuses a target beyond it."""
    rig = _rig()
    rig.set(NOZAGC, 1)
    _run(rig, "G0 Y10")
    assert not rig.axis("X1").referenced
    rig.mda("G0 X400")
    rig.step(200)
    assert _alarms(rig) == [10720]
    assert rig.axis("X1").setpoint == pytest.approx(150.0)


def test_g28_of_the_inclined_axis_with_nozagc_drops_the_orthogonal_reference() -> None:
    """Up to the intermediate point G28 is an ordinary move (L72-74): with NOZAGC = 1 uncompensated."""
    rig = _rig()
    _run(rig, "G0 Y50")  # compensated: X1 keeps its reference
    assert rig.axis("X1").referenced
    rig.set(NOZAGC, 1)
    _run(rig, "G28 Y0")
    assert rig.axis("Y1").setpoint == pytest.approx(-73.0)  # at its reference point MD34100
    assert not rig.axis("X1").referenced and rig.get("X1.basic.in.enc1Synchronized") == 0


def test_reset_of_a_nozagc_block_that_has_not_moved_keeps_the_orthogonal_reference() -> None:
    """G0 Y50 M42 S100 waits for the gear change the test (as PLC) never acknowledges."""
    rig = _rig()
    rig.set(NOZAGC, 1)
    rig.mda("N20 G0 Y50 M42 S100")
    rig.step(50)
    assert rig.axis("Y1").setpoint == 0.0 and rig.get("CHAN1.basic.in.stateReset") == 0
    rig.pulse("CHAN1.basic.out.reset")
    rig.step(5)
    assert rig.axis("X1").referenced
    rig.set(NOZAGC, 1)
    rig.mda("N20 G0 Y50")
    rig.step(20)  # on the way
    assert rig.axis("Y1").setpoint > 0.0
    rig.pulse("CHAN1.basic.out.reset")
    rig.step(5)
    assert not rig.axis("X1").referenced


def test_g53_targets_are_machine_positions_and_the_display_is_cartesian() -> None:
    rig = _rig()
    rig.set(NOZAGC, 1)  # G53 ignores it (seed 000 L158)
    _run(rig, "G53 Y50")
    assert rig.axis("X1").setpoint == pytest.approx(150.0)
    assert rig.axis("Y1").setpoint == pytest.approx(50.0)
    # Xp = 150 + 50 cos(-30) tan(-30) = 125, Yp = 43.301 (TV-IA-5 at X150)
    assert rig.nck.program_position("X1") == pytest.approx(125.0, abs=1e-3)
    assert rig.nck.program_position("Y1") == pytest.approx(50.0 * COS, abs=1e-3)


def test_g28_of_the_inclined_axis_goes_via_the_intermediate_point_to_its_reference_point() -> None:
    rig = _rig(y1="MD34100: [0.0]")
    _run(rig, "G0 Y40")
    _run(rig, "G28 Y40")
    # ARF = 1: the leg to the reference point (Y 0) is Cartesian, X1 is back at 150
    assert rig.axis("Y1").setpoint == pytest.approx(0.0)
    assert rig.axis("X1").setpoint == pytest.approx(150.0)
    assert _alarms(rig) == []


def test_g28_with_arf_0_keeps_the_orthogonal_axis_on_the_last_leg() -> None:
    rig = _rig(channel="MD62803: 0", y1="MD34100: [0.0]")
    _run(rig, "G0 Y40")
    x_at_intermediate = rig.axis("X1").setpoint
    _run(rig, "G28 Y40")
    assert rig.axis("Y1").setpoint == pytest.approx(0.0)
    assert rig.axis("X1").setpoint == pytest.approx(x_at_intermediate)
    assert rig.nck.program_position("X1") == pytest.approx(150.0, abs=1e-3)  # the program X is kept


def test_g28_names_both_axes_alarm_65821() -> None:
    rig = _rig()
    rig.mda("G28 X150 Y0")
    rig.step(5)
    assert 65821 in _alarms(rig)


def test_g28_of_the_orthogonal_axis_while_the_inclined_is_not_at_its_reference_point_alarm_65820() -> None:
    rig = _rig()  # Y1 stands at 0, its reference point is -73
    rig.mda("G28 X150")
    rig.step(5)
    assert 65820 in _alarms(rig)


def test_g74_of_the_orthogonal_axis_needs_the_inclined_one_at_its_reference_point() -> None:
    rig = _rig()  # Y1 is referenced (absolute) but not at its reference point -73
    rig.mda("G74 X1=0")
    rig.step(5)
    assert 65820 in _alarms(rig)
    assert rig.axis("X1").command_velocity == 0.0


def test_cartesian_stroke_limit_is_checked_before_the_move() -> None:
    rig = _rig()
    _run(rig, "G0 Y100")  # 115.47 along the slide: inside the Cartesian +100
    assert _alarms(rig) == []
    rig.mda("G0 Y100.5")
    rig.step(5)
    assert 10720 in _alarms(rig)
    assert rig.axis("Y1").setpoint == pytest.approx(100.0 / COS)


def test_polygon_turning_cannot_run_with_inclined_axis_control() -> None:
    rig = _rig()
    rig.mda("G51.2 P2 Q6")
    rig.step(5)
    assert 65822 in _alarms(rig)


def test_jog_of_the_inclined_axis_carries_the_orthogonal_one_unless_nozagc() -> None:
    rig = _rig()
    rig.select_mode("jog")
    rig.step(2)
    rig.set("Y1.basic.out.traversKeyPlus", 1)
    rig.step(200)
    y1, x1 = rig.axis("Y1"), rig.axis("X1")
    # the JOG velocity is Cartesian: 1500 mm/min along Y = 1732.05 along the slide (L32, L313)
    assert y1.command_velocity == pytest.approx(1500.0 / 60.0 / COS)
    assert x1.setpoint - 150.0 == pytest.approx(0.5 * y1.setpoint)  # -C sin(-30) per unit of travel
    rig.set("Y1.basic.out.traversKeyPlus", 0)
    rig.run_until(lambda: y1.at_rest and x1.at_rest, 500)
    rig.set(NOZAGC, 1)
    x_before = x1.setpoint
    rig.set("Y1.basic.out.traversKeyPlus", 1)
    rig.step(100)
    assert x1.setpoint == x_before
    assert rig.nck.program_position("X1") == pytest.approx(150.0, abs=0.05)


def test_a_rotary_axis_in_the_pair_raises_65824_and_leaves_the_function_off() -> None:
    rig = Rig(machine(_machine_data(channel="MD62805: 4")))  # SP1 as the inclined axis
    assert 65824 in _alarms(rig)
    assert rig.nck.channels_by_name["CHAN1"].inclined is None
    # ... and its referencing order with it: X1 references without SP1 at a reference point
    rig.nck.referencing.start("X1", Source.G74, 0, rig.nck.cycle)
    assert 65820 not in _alarms(rig)


def test_the_referencing_order_comes_from_the_active_control() -> None:
    rig = _rig()  # Y1 is referenced (absolute) but not at its reference point -73
    assert not rig.nck.referencing.start("X1", Source.G74, 0, rig.nck.cycle)
    assert 65820 in _alarms(rig)


def test_rigid_tapping_on_the_inclined_axis_is_refused_with_65822() -> None:
    rig = _rig()
    rig.mda("G331 Y-10 J2 S600")
    rig.run_until(lambda: bool(_alarms(rig)), 5000)
    assert 65822 in _alarms(rig)
    assert rig.nck.axes_by_name["Y1"].setpoint == 0.0  # nothing moved
    assert any("rigid tapping on the inclined axis Y1 (G331)" in str(alarm) for alarm in rig.nck.present_alarms())


def _jog(rig: Rig, key: str, cycles: int) -> None:
    rig.set(key, 1)
    rig.step(cycles)
    rig.set(key, 0)
    rig.step(50)


def test_jog_stops_on_the_cartesian_stroke_limit_with_aot_1() -> None:
    rig = _rig()
    rig.select_mode("jog")
    rig.step(2)
    y1, x1 = rig.axis("Y1"), rig.axis("X1")
    _jog(rig, "Y1.basic.out.traversKeyPlus", 4000)
    # program Y +100 = 115.470 along the slide (its machine limit 100 is passed); X1 carried by 0.5 per mm
    assert y1.setpoint == pytest.approx(100.0 / COS, abs=1e-9)
    assert x1.setpoint == pytest.approx(150.0 + 0.5 * 100.0 / COS, abs=1e-9)
    assert rig.nck.program_position("X1") == pytest.approx(150.0, abs=1e-3)
    assert [(alarm.number, alarm.axis) for alarm in rig.nck.present_alarms()] == [(10621, "Y1")]
    _jog(rig, "X1.basic.out.traversKeyMinus", 3000)
    # program X -5: Xa = -5 + C Ya sin(30) = 52.735
    assert x1.setpoint == pytest.approx(-5.0 - 100.0 * TAN, abs=1e-9)
    assert rig.nck.program_position("X1") == pytest.approx(-5.0, abs=1e-3)
    _jog(rig, "X1.basic.out.traversKeyMinus", 100)  # resting on the limit: the key does nothing
    assert x1.setpoint == pytest.approx(-5.0 - 100.0 * TAN, abs=1e-9)


def test_jog_stops_on_the_machine_stroke_limit_with_aot_0() -> None:
    rig = _rig(channel="MD62802: [0, 1, 1]")
    rig.select_mode("jog")
    rig.step(2)
    _jog(rig, "Y1.basic.out.traversKeyPlus", 4000)
    assert rig.axis("Y1").setpoint == pytest.approx(100.0, abs=1e-9)
    assert rig.axis("X1").setpoint == pytest.approx(200.0, abs=1e-9)


def test_jog_of_an_unreferenced_inclined_axis_stops_where_the_carried_axis_reaches_its_limit() -> None:
    """Y1 not referenced (no own limits), X1 absolute at 295: Y1+ carries X1 by 0.5 per mm up to
    its MD36110 = 305, so Y1 stops 20 mm on (shipped AOT = 1, [control])."""
    config = with_start_position(machine("CHAN1: {MD20700: 0}\nX1: {MD30240: [4], MD34210: [2]}"), "X1", 295.0)
    rig = Rig(config)
    rig.ready_mda()
    y1, x1 = rig.axis("Y1"), rig.axis("X1")
    assert x1.referenced and not y1.software_limits_active
    rig.select_mode("jog")
    rig.step(2)
    _jog(rig, "Y1.basic.out.traversKeyPlus", 3000)
    assert x1.setpoint == pytest.approx(305.0, abs=1e-9)
    assert y1.setpoint == pytest.approx(20.0, abs=1e-9)
    assert [(alarm.number, alarm.axis) for alarm in rig.nck.present_alarms()] == [(10621, "Y1")]


def _arc_on_the_circle(rig: Rig, centre: tuple[float, float], radius: float, nozagc: bool = False) -> float:
    """Run the program to its end; the largest distance of the Cartesian point of the X1 / Y1
    setpoints from the circle, cycle by cycle (NOZAGC: X1 is not compensated, Xp = Xa)."""
    x1, y1 = rig.axis("X1"), rig.axis("Y1")
    off = 0.0
    for _ in range(20000):
        rig.step()
        yp = y1.setpoint * COS
        xp = x1.setpoint if nozagc else x1.setpoint + yp * TAN
        off = max(off, abs(math.hypot(xp - centre[0], yp - centre[1]) - radius))
        if rig.get("CHAN1.basic.in.stateReset") == 1:
            return off
    raise AssertionError("the program did not end")


def test_g3_is_interpolated_in_cartesian_coordinates_and_mapped_to_the_slides() -> None:
    # from X150 Y0 about (130, 0) to X130 Y20: every point on the Cartesian circle; at the end
    # Ya = 20 / cos(-30) = 23.094, Xa = 130 - 20 tan(-30) = 141.547 (seed 000 L11-20, L194-204)
    rig = _rig()
    rig.mda("G3 X130 Y20 I-20 J0 F600")
    assert _arc_on_the_circle(rig, (130.0, 0.0), 20.0) < 1e-9
    assert rig.axis("Y1").setpoint == pytest.approx(20.0 / COS, abs=1e-9)
    assert rig.axis("X1").setpoint == pytest.approx(130.0 - 20.0 * TAN, abs=1e-9)
    rig.step(200)  # settled: the display reads actual values
    assert rig.nck.program_position("X1") == pytest.approx(130.0, abs=1e-3)


def test_g2_with_nozagc_converts_only_the_inclined_component() -> None:
    # NOZAGC = 1: Xa = Xp, Ya = Yp / cos(theta); the display keeps the program X
    rig = _rig()
    rig.set(NOZAGC, 1)
    rig.step(2)
    rig.mda("G2 X130 Y-20 R20 F600")
    assert _arc_on_the_circle(rig, (130.0, 0.0), 20.0, nozagc=True) < 1e-9
    assert rig.axis("X1").setpoint == pytest.approx(130.0, abs=1e-9)
    assert rig.axis("Y1").setpoint == pytest.approx(-20.0 / COS, abs=1e-9)
    rig.step(200)
    assert rig.nck.program_position("X1") == pytest.approx(130.0, abs=1e-3)


def test_the_feed_of_an_arc_is_the_cartesian_path_velocity() -> None:
    rig = _rig()
    x1, y1 = rig.axis("X1"), rig.axis("Y1")
    rig.mda("G2 I-20 F600")
    rig.step(400)  # 10 mm/s reached long before
    # the Cartesian velocity of the slides: Vy = Vya cos(theta), Vx = Vxa + Vy tan(theta)
    vy = y1.command_velocity * COS
    vx = x1.command_velocity + vy * TAN
    assert math.hypot(vx, vy) == pytest.approx(10.0, rel=1e-6)


def test_an_arc_beyond_the_cartesian_stroke_limit_is_refused_before_it_moves() -> None:
    # AOT = 1: the circle about (150, 60) reaches Y 120, beyond Y1's Cartesian +100, although it ends
    # where it starts; the machine position 120 / cos(-30) ... never comes: 10720 for Y1, nothing moves
    rig = _rig()
    rig.mda("G2 J60 F600")
    rig.step(5)
    assert _alarms(rig) == [10720]
    assert rig.axis("Y1").setpoint == 0.0 and rig.axis("X1").setpoint == 150.0
