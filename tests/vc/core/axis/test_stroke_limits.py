"""Stored stroke limits 2 (G22 / G23) and 3 (vc/core/axis/stroke_limits.py), alone and on turn_mill's
inclined Y1 (theta -30 degrees, C = 1; seed 000 L264-291, L414-429).

X1, Y1, Z1 are absolute and referenced at power-on: X1 at 150, Y1 at 0, Z1 at 300.  The box of
``G22 X200 Y90 I100 J50`` is X 100 .. 200, Y 50 .. 90 (inside forbidden unless MD62810 = 1).
"""

from __future__ import annotations

import math

import pytest
from core_rig import Rig, machine

from vc.core.axis.stroke_limits import StrokeArea

COS = math.cos(math.radians(-30.0))
TAN = math.tan(math.radians(-30.0))
BOX = "G22 X200 Y90 I100 J50"


def test_an_inside_area_forbids_its_inside_only() -> None:
    area = StrokeArea(2, {"X1": (100.0, 200.0), "Y1": (50.0, 90.0)}, True)
    assert area.forbidden({"X1": 150.0, "Y1": 60.0})
    assert not area.forbidden({"X1": 150.0, "Y1": 50.0})  # on the boundary: allowed
    assert not area.forbidden({"X1": 250.0, "Y1": 60.0})
    # from (150, 0) along +Y: the box begins 50 ahead; from inside no room
    assert area.room({"X1": 150.0, "Y1": 0.0}, {"Y1": 1.0}) == (-math.inf, 50.0)
    assert area.room({"X1": 250.0, "Y1": 0.0}, {"Y1": 1.0}) == (-math.inf, math.inf)
    assert area.room({"X1": 150.0, "Y1": 60.0}, {"Y1": 1.0}) == (0.0, 0.0)


def test_an_outside_area_keeps_the_point_inside_its_box() -> None:
    area = StrokeArea(2, {"X1": (100.0, 200.0), "Y1": (50.0, 90.0)}, False)
    assert area.forbidden({"X1": 150.0, "Y1": 0.0})
    assert area.room({"X1": 150.0, "Y1": 60.0}, {"X1": 1.0, "Y1": 1.0}) == (-10.0, 30.0)


def _rig(ao2: int = 1, outside: int = 0, x1: str = "MD62811: 1", y1: str = "MD62811: 1") -> Rig:
    absolute = "MD30240: [4], MD34210: [2]"
    rig = Rig(machine(f"CHAN1: {{MD20700: 0, MD62802: [1, {ao2}, 1], MD62810: {outside}}}\n"
                      f"X1: {{{absolute}, {x1}}}\nZ1: {{{absolute}}}\nY1: {{{absolute}, {y1}}}"))
    rig.ready_mda()
    return rig


def _alarms(rig: Rig) -> list[tuple[int, str]]:
    return [(alarm.number, alarm.axis) for alarm in rig.nck.present_alarms()]


def _positions(rig: Rig) -> tuple[float, float]:
    return rig.axis("X1").setpoint, rig.axis("Y1").setpoint


@pytest.mark.parametrize(("ao2", "x1", "y1"), [
    # AO2 = 1: the box in Cartesian coordinates: stop at Y 50 = 57.735 on the slide, X1 150 + 50 x 0.57735
    (1, 150.0 - 50.0 * TAN, 50.0 / COS),
    # AO2 = 0: the box in machine coordinates: Y1 stops at 50 (Y 43.301), X1 150 + 43.301 x 0.57735 = 175
    (0, 175.0, 50.0),
])
def test_a_block_into_the_area_stops_on_its_boundary_with_alarm_502(ao2: int, x1: float, y1: float) -> None:
    rig = _rig(ao2)
    rig.mda(f"{BOX}\nG1 Y100 F1000")
    rig.step(5000)
    assert _positions(rig) == pytest.approx((x1, y1), abs=1e-9)
    assert rig.axis("Y1").command_velocity == 0.0
    assert _alarms(rig) == [(502, "Y1")]
    assert rig.get("CHAN1.basic.in.progStateRunning") == 0


def test_g23_switches_stroke_limit_2_off() -> None:
    rig = _rig()
    rig.mda(f"{BOX}\nG23\nG1 Y100 F1000")
    rig.step(5000)
    assert rig.axis("Y1").setpoint == pytest.approx(100.0 / COS)
    assert _alarms(rig) == []


def test_an_arc_stops_where_it_enters_the_area() -> None:
    # G3 about (150, 40) from (150, 0) to (110, 40): y = 40 + 40 sin(t) reaches the box's bottom Y 50
    # at sin(t) = 0.25, x = 150 + 40 x 0.968246 = 188.730 (inside X 100 .. 200): the arc stops there
    rig = _rig()
    rig.mda(f"{BOX}\nG3 X110 Y40 I0 J40 F1000")
    rig.step(5000)
    program_y = rig.axis("Y1").setpoint * COS
    program_x = rig.axis("X1").setpoint + program_y * TAN
    assert (program_x, program_y) == pytest.approx((150.0 + 40.0 * math.sqrt(1.0 - 1.0 / 16.0), 50.0), abs=1e-6)
    assert _alarms(rig) == [(502, "Y1")]


def test_a_block_starting_inside_the_area_is_refused_before_it_moves() -> None:
    rig = _rig()
    rig.mda("G1 Y60 F1000")
    rig.step(2000)
    rig.mda(f"{BOX}\nG1 Y80 F1000")
    rig.step(200)
    assert rig.axis("Y1").setpoint == pytest.approx(60.0 / COS)
    assert _alarms(rig) == [(502, "Y1")]


def test_an_outside_area_stops_a_block_that_leaves_the_box() -> None:
    # MD62810 = 1: the outside is forbidden; from (150, 60) G1 Y100 stops at Y 90
    rig = _rig(outside=1)
    rig.mda("G23\nG1 Y60 F1000")
    rig.step(2000)
    rig.mda(f"{BOX}\nG1 Y100 F1000")
    rig.step(2000)
    assert rig.axis("Y1").setpoint == pytest.approx(90.0 / COS, abs=1e-9)
    assert _alarms(rig) == [(502, "Y1")]


def test_stroke_limit_3_from_its_machine_data_alarm_505() -> None:
    # MD62814-62816 of Y1: inside Y -30 .. -10 forbidden, always checked; G1 Y-50 stops at Y -10
    rig = _rig(x1="MD62811: 0", y1="MD62814: 1, MD62815: -10, MD62816: -30")
    rig.mda("G1 Y-50 F1000")
    rig.step(3000)
    assert rig.axis("Y1").setpoint == pytest.approx(-10.0 / COS, abs=1e-9)
    assert _alarms(rig) == [(505, "Y1")]


@pytest.mark.parametrize(("ao2", "x1", "y1"), [(1, 150.0 - 50.0 * TAN, 50.0 / COS), (0, 175.0, 50.0)])
def test_jog_stops_on_the_boundary_and_the_key_against_it_raises_502(ao2: int, x1: float, y1: float) -> None:
    rig = _rig(ao2)
    rig.mda(BOX)
    rig.step(20)
    rig.select_mode("jog")
    rig.step(2)
    rig.set("Y1.basic.out.traversKeyPlus", 1)
    rig.step(4000)
    assert _positions(rig) == pytest.approx((x1, y1), abs=1e-9)
    assert (502, "Y1") in _alarms(rig)
    rig.set("Y1.basic.out.traversKeyPlus", 0)
    rig.pulse("CHAN1.basic.out.reset")
    rig.step(10)
    assert _alarms(rig) == []
    rig.set("Y1.basic.out.traversKeyMinus", 1)  # away from the area
    rig.step(200)
    assert rig.axis("Y1").setpoint < y1 - 1.0
