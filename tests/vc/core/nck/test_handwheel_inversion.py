"""The handwheel's direction inverted by the PLC (vc/core/nck/handwheel_inversion.py): DB31.DBX7.0 /
67.0 of a machine axis, DB21.DBX15.0 / 43.0 of geometry axis 1, a change only at standstill; the
test is the PLC."""

from __future__ import annotations

import pytest
from core_rig import ABSOLUTE_X1, Rig, machine


def handwheel_rig() -> Rig:
    rig = Rig(machine(ABSOLUTE_X1))
    rig.enable_axes("X1")
    rig.select_mode("jog")
    rig.step(20)
    rig.set("X1.basic.out.handwheelSelection", 1)
    rig.set("X1.basic.out.inc1000", 1)  # 1 mm per detent
    rig.step(2)
    return rig


def test_a_machine_axis_with_the_handwheel_inverted_travels_the_other_way_and_the_nc_acknowledges_it() -> None:
    rig = handwheel_rig()
    x1 = rig.axis("X1")
    start = x1.setpoint
    assert rig.get("X1.basic.in.handwheelDirInverted") == 0
    rig.set("X1.basic.out.handwheelInvertDir", 1)
    rig.step(2)
    assert rig.get("X1.basic.in.handwheelDirInverted") == 1
    rig.sim.turn_handwheel(1, 5, 50)
    rig.step(600)
    assert x1.setpoint == pytest.approx(start - 5.0, abs=1e-9)


def test_a_change_while_the_axis_travels_the_handwheels_distance_waits_until_it_stands() -> None:
    rig = handwheel_rig()
    x1 = rig.axis("X1")
    start = x1.setpoint
    rig.sim.turn_handwheel(1, 10, 10)
    rig.step(20)
    rig.set("X1.basic.out.handwheelInvertDir", 1)
    rig.step(20)
    assert x1.handwheel_rest != 0.0 and rig.get("X1.basic.in.handwheelDirInverted") == 0
    rig.run_until(lambda: rig.get("X1.basic.in.handwheelDirInverted") == 1, 2000)
    assert x1.setpoint == pytest.approx(start + 10.0, abs=1e-9)  # the distance travelled the old way


def test_geometry_axis_1_has_its_own_inversion_db21_dbx15_0() -> None:
    rig = handwheel_rig()
    x1 = rig.axis("X1")
    rig.set("X1.basic.out.handwheelSelection", 0)
    rig.set("CHAN1.geoAxis1.out.handwheelSelection", 1)
    rig.set("CHAN1.geoAxis1.out.inc1000", 1)
    rig.set("CHAN1.geoAxis1.out.handwheelInvertDir", 1)
    rig.step(2)
    assert rig.get("CHAN1.geoAxis1.in.handwheelDirInverted") == 1
    assert rig.get("X1.basic.in.handwheelDirInverted") == 0
    start = x1.setpoint
    rig.sim.turn_handwheel(1, 3, 50)
    rig.step(600)
    travel = x1.setpoint - start
    assert travel < 0.0  # the other way (geometry X of turn_mill moves X1 with its inclined-axis factor)


def test_without_inversion_nothing_waits_and_nothing_is_read_again() -> None:
    rig = handwheel_rig()
    inversion = rig.nck.manual.handwheel_inversion
    assert not inversion.axes and not inversion.geometry_axis_1 and not inversion._waiting
