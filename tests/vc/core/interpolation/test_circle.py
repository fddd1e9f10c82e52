"""The arc of a G2 / G3 block in program coordinates (vc/core/interpolation/circle.py)."""

from __future__ import annotations

import math

import pytest
from core_rig import DT, MILL, Rig, machine

from vc.core.interpolation.circle import Arc, ArcTolerance, plan_arc

PLANE = ("X1", "Y1")
TOLERANCE = ArcTolerance()  # MD21000 = 0.01 mm, MD21010 = 0.001 as delivered


def _arc(counter_clockwise: bool, start: tuple[float, float], end: tuple[float, float],
         offset: tuple[float, float] | None = None, radius: float | None = None,
         linear: tuple[tuple[str, float, float, bool], ...] = ()) -> Arc:
    """``offset``: I J, the centre from the start point."""
    arc = plan_arc(counter_clockwise, PLANE, start, end, offset, radius, linear, TOLERANCE)
    assert isinstance(arc, Arc), arc
    return arc


def _on_circle(arc: Arc, centre: tuple[float, float], radius: float) -> float:
    """The largest distance of the arc's points from the circle."""
    return max(abs(math.hypot(point["X1"] - centre[0], point["Y1"] - centre[1]) - radius)
               for point in arc.points(200))


def test_g3_with_a_centre_turns_counter_clockwise_on_the_circle_to_the_end_point() -> None:
    # from (20, 0) about (0, 0) (I-20 J0) to (0, 20): a quarter counter-clockwise through (14.142, 14.142)
    arc = _arc(True, (20.0, 0.0), (0.0, 20.0), offset=(-20.0, 0.0))
    assert arc.sweep == pytest.approx(math.pi / 2)
    assert arc.length == pytest.approx(10.0 * math.pi)
    assert arc.point(0.5) == pytest.approx({"X1": 14.1421356, "Y1": 14.1421356})
    assert arc.point(1.0) == pytest.approx({"X1": 0.0, "Y1": 20.0})
    assert _on_circle(arc, (0.0, 0.0), 20.0) < 1e-12


def test_g2_with_the_same_words_goes_the_other_way_round() -> None:
    arc = _arc(False, (20.0, 0.0), (0.0, 20.0), offset=(-20.0, 0.0))
    assert arc.sweep == pytest.approx(-1.5 * math.pi)
    assert arc.point(1 / 3) == pytest.approx({"X1": 0.0, "Y1": -20.0})  # through the bottom
    assert arc.length == pytest.approx(30.0 * math.pi)


@pytest.mark.parametrize(("counter_clockwise", "radius", "centre", "sweep"), [
    (True, 20.0, (0.0, 0.0), 0.5 * math.pi),  # G3 R20: the short way, centre on the left of the chord
    (True, -20.0, (20.0, 20.0), 1.5 * math.pi),  # G3 R-20: the long way round the other centre
    (False, 20.0, (20.0, 20.0), -0.5 * math.pi),  # G2 R20: the short way clockwise
    (False, -20.0, (0.0, 0.0), -1.5 * math.pi),
])
def test_a_radius_chooses_the_centre_by_its_sign_and_the_direction(
        counter_clockwise: bool, radius: float, centre: tuple[float, float], sweep: float) -> None:
    arc = _arc(counter_clockwise, (20.0, 0.0), (0.0, 20.0), radius=radius)
    assert arc.centre == pytest.approx(centre)
    assert arc.sweep == pytest.approx(sweep)
    assert arc.point(1.0) == pytest.approx({"X1": 0.0, "Y1": 20.0})


def test_a_full_circle_with_a_centre_and_the_end_on_the_start() -> None:
    arc = _arc(False, (30.0, 0.0), (30.0, 0.0), offset=(-10.0, 0.0))
    assert arc.sweep == pytest.approx(-2.0 * math.pi)
    assert arc.length == pytest.approx(20.0 * math.pi)
    assert arc.point(0.25) == pytest.approx({"X1": 20.0, "Y1": -10.0})  # clockwise: down first


def test_a_full_circle_with_a_radius_is_refused() -> None:
    reason = plan_arc(True, PLANE, (30.0, 0.0), (30.0, 0.0), None, 10.0, (), TOLERANCE)
    assert reason == "full circle programmed with a radius"


def test_a_radius_shorter_than_half_the_chord_is_refused() -> None:
    reason = plan_arc(True, PLANE, (0.0, 0.0), (30.0, 0.0), None, 14.9, (), TOLERANCE)
    assert reason == "radius 14.9 too small for the end point"


def test_an_end_point_off_the_circle_within_md21000_moves_the_centre_onto_the_bisector() -> None:
    # start radius 20, end radius 20.008: within 0.01 mm; the path ends on the programmed point
    arc = _arc(True, (20.0, 0.0), (0.0, 20.008), offset=(-20.0, 0.0))
    assert arc.point(1.0) == pytest.approx({"X1": 0.0, "Y1": 20.008}, abs=1e-12)
    centre = arc.centre
    assert math.hypot(centre[0] - 20.0, centre[1]) == pytest.approx(math.hypot(centre[0], centre[1] - 20.008))
    assert math.hypot(*centre) < 0.01  # moved from the programmed (0, 0) by less than the difference


def test_an_end_point_off_the_circle_beyond_the_tolerance_is_refused() -> None:
    # 0.011 mm beyond the start radius 20: MD21000 allows 0.01, MD21010 0.001 x 20 = 0.02 would allow it
    assert isinstance(plan_arc(True, PLANE, (20.0, 0.0), (0.0, 20.011), (-20.0, 0.0), None, (),
                               ArcTolerance(0.01, 0.0)), str)
    assert isinstance(plan_arc(True, PLANE, (20.0, 0.0), (0.0, 20.011), (-20.0, 0.0), None, (), TOLERANCE), Arc)
    reason = plan_arc(True, PLANE, (20.0, 0.0), (0.0, 20.5), (-20.0, 0.0), None, (), TOLERANCE)
    assert reason == "radius at the end point 20.5000 differs from the start radius 20.0000"


def test_a_helix_moves_the_third_axis_with_the_angle_and_f_counts_its_travel() -> None:
    arc = _arc(True, (20.0, 0.0), (20.0, 0.0), offset=(-20.0, 0.0), linear=(("Z1", 0.0, -10.0, True),))
    assert arc.point(0.5) == pytest.approx({"X1": -20.0, "Y1": 0.0, "Z1": -5.0})
    assert arc.length == pytest.approx(math.hypot(40.0 * math.pi, 10.0))
    # an axis outside the geometry moves along but is not part of the path length
    other = _arc(True, (20.0, 0.0), (20.0, 0.0), offset=(-20.0, 0.0), linear=(("A1", 0.0, 90.0, False),))
    assert other.length == pytest.approx(40.0 * math.pi)


# ------------------------------------------------------------------------------ on the channel (mill_3axis)
# X1, Y1, Z1 absolute and referenced at power-on: they stand at 400, 250, -200; limits X1 -5 .. 805,
# Y1 -3 .. 503, Z1 -505 .. 5.

MILL_ABSOLUTE = ("CHAN1: {MD20700: 0}\nX1: {MD30240: [4], MD34210: [2]}\nY1: {MD30240: [4], MD34210: [2]}\n"
                 "Z1: {MD30240: [4], MD34210: [2]}")


def _mill(feed: int = 100) -> Rig:
    rig = Rig(machine(MILL_ABSOLUTE, MILL))
    rig.ready_mda(feed=feed)
    return rig


def _arc_cycles(rig: Rig, centre: tuple[float, float], radius: float) -> tuple[int, float, float]:
    """Cycles until the program ends, the largest distance of the X1 / Y1 setpoints from the circle
    and the largest path velocity (mm/s) on the way."""
    x1, y1 = rig.axis("X1"), rig.axis("Y1")
    cycles, off, fastest = 0, 0.0, 0.0
    while rig.get("CHAN1.basic.in.stateReset") != 1:
        rig.step()
        cycles += 1
        off = max(off, abs(math.hypot(x1.setpoint - centre[0], y1.setpoint - centre[1]) - radius))
        fastest = max(fastest, math.hypot(x1.command_velocity, y1.command_velocity))
        assert cycles < 20000
    return cycles, off, fastest


@pytest.mark.parametrize("override", [100, 50])
def test_a_full_circle_runs_on_the_circle_at_f_times_the_override(override: int) -> None:
    # G2 I-20 from (400, 250): centre (380, 250), 125.66 mm at 600 mm/min x override
    rig = _mill(feed=override)
    rig.mda("G2 I-20 F600")
    cycles, off, fastest = _arc_cycles(rig, (380.0, 250.0), 20.0)
    velocity = 10.0 * override / 100.0  # mm/s
    assert off < 1e-9
    assert fastest == pytest.approx(velocity, rel=1e-6)  # the chord of one cycle, a little shorter than the arc
    length = 40.0 * math.pi
    assert length / velocity / DT <= cycles <= length / velocity / DT + 60  # + the ramps and the exact stop
    assert (rig.axis("X1").setpoint, rig.axis("Y1").setpoint) == (400.0, 250.0)


def test_a_helix_ends_on_its_end_point_with_z_linear_in_the_angle() -> None:
    rig = _mill()
    x1, y1, z1 = rig.axis("X1"), rig.axis("Y1"), rig.axis("Z1")
    rig.mda("G17 G3 X380 Y270 Z-210 I-20 J0 F1200")  # a quarter, Z 10 mm down
    while rig.get("CHAN1.basic.in.stateReset") != 1:
        rig.step()
        angle = math.atan2(y1.setpoint - 250.0, x1.setpoint - 380.0)
        assert z1.setpoint == pytest.approx(-200.0 - 10.0 * angle / (math.pi / 2), abs=1e-9)
    assert (x1.setpoint, y1.setpoint, z1.setpoint) == (380.0, 270.0, -210.0)


def test_an_arc_beyond_a_software_limit_is_refused_before_it_moves() -> None:
    # end point (400, 250) inside, but the full circle about (400, 0) reaches Y1 -250: 10720 for Y1 minus
    rig = _mill()
    rig.mda("G2 J-250 F600")
    rig.step(5)
    assert rig.alarm_numbers() == [10720]
    assert rig.sim.alarms()[0].axis == "Y1"
    assert rig.axis("Y1").setpoint == 250.0


def test_an_end_point_off_the_circle_raises_14040() -> None:
    rig = _mill()
    rig.mda("G3 X380 Y271 I-20 J0 F600")
    rig.step(5)
    assert rig.alarm_numbers() == [14040]
    assert rig.axis("X1").setpoint == 400.0
