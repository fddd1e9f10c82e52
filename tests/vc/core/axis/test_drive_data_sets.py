"""The drive's data set changeover and integrator (vc/core/axis/drive_data_sets.py): DB31.DBX21.0-21.6
-> DBX93.0-93.6, the switchover time, the pulses of a motor changeover; turn_mill's X1 with an
absolute encoder; the test is the PLC."""

from __future__ import annotations

from core_rig import Rig, machine

from vc.core.axis.drive_data_sets import Changeover


def _rig() -> Rig:
    rig = Rig(machine("CHAN1: {MD20700: 0}\nX1: {MD30240: [4], MD34210: [2]}"))
    rig.ready_mda()
    return rig


def _cycles_until(rig: Rig, name: str, value: int) -> int:
    return rig.run_until(lambda: rig.get(name) == value, 50)


def test_a_drive_data_set_changes_over_in_its_switchover_time_while_the_drive_runs() -> None:
    rig = _rig()
    rig.set("X1.drive.out.driveDataSetSelection", 2)
    assert _cycles_until(rig, "X1.drive.in.driveDataSetNumber", 2) == 2  # 4 ms of 2 ms cycles
    assert rig.axis("X1").servo_on
    assert rig.axis("X1").data_sets.state is Changeover.STEADY
    assert rig.nck._changing_drives == []  # nothing left to tick: the drive at rest costs nothing


def test_a_motor_changeover_cancels_the_pulses_until_the_plc_confirms_the_motor() -> None:
    rig = _rig()
    x1 = rig.axis("X1")
    rig.set("X1.drive.out.motorDataSetSelection", 1)
    rig.step(1)
    assert x1.data_sets.state is Changeover.SWITCHING and not x1.drive_ready
    assert _cycles_until(rig, "X1.drive.in.motorDataSetNumber", 1) <= 2
    rig.step(20)
    assert x1.data_sets.state is Changeover.WAIT_MOTOR and not x1.servo_on and not x1.drive_ready
    rig.set("X1.drive.out.motorChangeoverDone", 1)
    rig.step(1)
    assert x1.data_sets.state is Changeover.STEADY and x1.servo_on
    assert rig.alarm_numbers() == []  # the axis stood still: no 21612


def test_a_plc_that_holds_the_confirmation_gets_the_pulses_back_with_the_new_motor() -> None:
    rig = _rig()
    rig.set("X1.drive.out.motorChangeoverDone", 1)
    rig.set("X1.drive.out.motorDataSetSelection", 3)
    assert _cycles_until(rig, "X1.drive.in.motorDataSetNumber", 3) == 2
    rig.step(1)
    assert rig.axis("X1").servo_on


def test_a_selection_changed_during_the_changeover_ends_it_with_the_latest_selection() -> None:
    rig = _rig()
    rig.set("X1.drive.out.driveDataSetSelection", 1)
    rig.step(1)
    rig.set("X1.drive.out.driveDataSetSelection", 5)
    seen = []
    for _ in range(6):
        rig.step(1)
        seen.append(rig.get("X1.drive.in.driveDataSetNumber"))
    assert seen == [5] * 6  # the changeover under way ends with what the PLC selects by then


def test_the_integrator_disable_is_answered_in_the_next_cycle() -> None:
    rig = _rig()
    rig.set("X1.drive.out.disableSpeedCtrlIntegrator", 1)
    assert _cycles_until(rig, "X1.drive.in.speedCtrlIntegratorDisabled", 1) == 1
    rig.set("X1.drive.out.disableSpeedCtrlIntegrator", 0)
    assert _cycles_until(rig, "X1.drive.in.speedCtrlIntegratorDisabled", 0) == 1


def test_a_motor_changeover_of_a_moving_axis_stops_it_with_21612() -> None:
    rig = _rig()
    rig.mda("N10 G1 G91 X-50 F3000\nN20 M30")
    rig.step(100)
    rig.set("X1.drive.out.motorDataSetSelection", 1)
    rig.step(5)
    assert 21612 in rig.alarm_numbers()
