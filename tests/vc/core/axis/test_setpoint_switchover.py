"""Setpoint switchover (vc/core/axis/setpoint_switchover.py): X1 and Y1 of the scenarios'
setpoint_switchover machine share one drive (MD30110 = 1); the test is the PLC."""

from __future__ import annotations

from core_rig import ROOT, Rig, machine

from vc.core.axis.setpoint_switchover import Switchover

SHARED = str(ROOT / "scenarios" / "drives" / "machines" / "setpoint_switchover.yaml")
ACTIVE_X1, ACTIVE_Y1 = "X1.drive.in.driveCtrlActive", "Y1.drive.in.driveCtrlActive"


def _rig() -> Rig:
    rig = Rig(machine("CHAN1: {MD20700: 0}", SHARED))
    rig.ready_mda()
    rig.step(5)
    return rig


def test_at_power_on_the_first_axis_of_the_drive_has_its_control_and_the_other_follows() -> None:
    rig = _rig()
    (drive,) = rig.nck._parts.shared_drives
    assert [axis.name for axis in drive.axes] == ["X1", "Y1"] and drive.holder.name == "X1"
    assert (rig.get(ACTIVE_X1), rig.get(ACTIVE_Y1), rig.get("Z1.drive.in.driveCtrlActive")) == (1, 0, 0)
    assert rig.axis("X1").servo_on and not rig.axis("Y1").servo_on and rig.axis("Y1").follow_up
    assert rig.axis("Z1").drive_control and rig.nck._switching_drives == []


def test_one_request_passes_the_control_at_rest_in_the_next_cycle() -> None:
    rig = _rig()
    rig.set("Y1.drive.out.requestDriveCtrl", 1)
    rig.step(1)
    assert (rig.get(ACTIVE_X1), rig.get(ACTIVE_Y1)) == (0, 1)
    rig.step(1)
    assert rig.axis("Y1").servo_on and not rig.axis("X1").servo_on and rig.axis("X1").follow_up
    assert rig.nck._switching_drives == [] and rig.alarm_numbers() == []  # at rest again: nothing to tick


def test_several_requests_or_none_keep_the_control_where_it_is() -> None:
    rig = _rig()
    rig.set("X1.drive.out.requestDriveCtrl", 1)
    rig.set("Y1.drive.out.requestDriveCtrl", 1)
    rig.step(5)
    assert (rig.get(ACTIVE_X1), rig.get(ACTIVE_Y1)) == (1, 0)
    rig.set("X1.drive.out.requestDriveCtrl", 0)
    rig.set("Y1.drive.out.requestDriveCtrl", 0)
    rig.step(5)
    assert (rig.get(ACTIVE_X1), rig.get(ACTIVE_Y1)) == (1, 0)


def test_a_moving_axis_of_the_drive_delays_the_switchover_until_it_stands() -> None:
    rig = _rig()
    rig.mda("N10 G1 G91 X-20 F3000\nN20 M30")
    rig.step(50)
    rig.set("Y1.drive.out.requestDriveCtrl", 1)
    rig.step(50)
    (drive,) = rig.nck._parts.shared_drives
    assert drive.state is Switchover.REQUESTED and rig.get(ACTIVE_X1) == 1 and rig.axis("X1").velocity
    rig.run_until(lambda: rig.get(ACTIVE_Y1) == 1, 1000)
    assert abs(rig.axis("X1").actual + 20.0) < 0.01 and drive.state is Switchover.STEADY


def test_an_axis_without_the_control_holds_its_program_block() -> None:
    rig = _rig()
    rig.mda("N10 G1 G91 Y-10 F3000\nN20 M30")
    rig.step(300)
    assert rig.axis("Y1").actual == 0.0 and rig.get("CHAN1.basic.in.stateReset") == 0
    rig.set("Y1.drive.out.requestDriveCtrl", 1)
    rig.run_until(lambda: rig.get("CHAN1.basic.in.stateReset") == 1, 1000)
    assert abs(rig.axis("Y1").actual + 10.0) < 0.01
