"""Gantry axes (seed 003 chapter 12): the grouping of gantry_mill's X1 (leading) and X2 (following),
its coupling, referencing and synchronization run, the warning and trip limits, break-up, and the
groupings' absence on the other machines; the test is the PLC."""

from __future__ import annotations

import pytest
from core_rig import MILL, ROOT, Rig, machine

from vc.config import md_dictionary as MD
from vc.core.gantry.gantry import State

GANTRY_MILL = str(ROOT / "scenarios" / "machines" / "gantry_mill.yaml")
# Y1 and Z1 on calibrated absolute encoders: only the grouping references
ABSOLUTE_YZ = "Y1: {MD30240: [4], MD34210: [2]}\nZ1: {MD30240: [4], MD34210: [2]}\n"


def _rig(overrides: str = "") -> Rig:
    rig = Rig(machine(ABSOLUTE_YZ + overrides, GANTRY_MILL))
    rig.enable_axes()
    rig.channel_overrides()
    rig.select_mode("jog")
    rig.set("MODEGROUP.basic.out.refPoint", 1)
    rig.step(2)
    return rig


def _state(rig: Rig) -> State:
    return rig.nck.gantries.groupings[0].state


def _reference(rig: Rig) -> None:
    """JOG-REF: X1's key held until X1 is referenced (the cam is copied from the plant each cycle)."""
    rig.set("X1.basic.out.traversKeyPlus", 1)
    for _ in range(10_000):
        for axis in ("X1", "X2"):
            rig.set(f"{axis}.basic.out.refPointApproachCam", rig.io(f"{axis}.refCam"))
        rig.step()
        if rig.get("X1.basic.in.enc1Synchronized"):
            rig.set("X1.basic.out.traversKeyPlus", 0)
        if _state(rig) in (State.SYNCHRONIZED, State.WAITING_FOR_START):
            return
    raise AssertionError(f"the grouping did not finish referencing: {_state(rig)}")


def test_a_machine_without_md37100_has_no_grouping_and_runs_none() -> None:
    rig = Rig(machine("", MILL))
    assert rig.nck.gantries.groupings == [] and rig.nck.gantries.of == {}
    assert rig.get("X1.coupling.in.gantryActive") == 0 and rig.get("X1.coupling.in.gantryLeadingActive") == 0


def test_the_grouping_shows_its_axes_and_the_follower_takes_the_leading_axis_setpoint_in_jog() -> None:
    rig = _rig()
    grouping = rig.nck.gantries.groupings[0]
    assert grouping.leader.name == "X1" and [f.name for f in grouping.followers] == ["X2"]
    assert (rig.get("X1.coupling.in.gantryActive"), rig.get("X1.coupling.in.gantryLeadingActive")) == (1, 1)
    assert (rig.get("X2.coupling.in.gantryActive"), rig.get("X2.coupling.in.gantryLeadingActive")) == (1, 0)
    assert rig.get("Y1.coupling.in.gantryActive") == 0
    assert _state(rig) is State.NOT_REFERENCED
    rig.set("MODEGROUP.basic.out.refPoint", 0)
    x1, x2 = rig.axis("X1"), rig.axis("X2")
    offset = x2.setpoint - x1.setpoint
    rig.set("X1.basic.out.traversKeyMinus", 1)
    rig.step(200)
    assert x1.command_velocity < 0 and x2.command_velocity == x1.command_velocity
    assert x2.setpoint - x1.setpoint == pytest.approx(offset)
    rig.set("X1.basic.out.traversKeyMinus", 0)
    rig.step(300)
    # the follower's own key is ignored (L15570-15573)
    before = x2.actual
    rig.set("X2.basic.out.traversKeyPlus", 1)
    rig.step(200)
    assert x2.actual == before and rig.get("X2.basic.in.traversPlusCommandActive") == 0


def test_referencing_the_leading_axis_references_the_follower_then_synchronizes_within_the_warning_limit() -> None:
    rig = _rig()
    _reference(rig)
    rig.run_until(lambda: _state(rig) is State.SYNCHRONIZED, 2000)
    rig.step(200)
    x1, x2 = rig.axis("X1"), rig.axis("X2")
    assert x1.actual == pytest.approx(763.0, abs=1e-3) and x2.actual == pytest.approx(763.0, abs=1e-3)
    assert rig.get("X1.coupling.in.gantrySyncOk") == 1 and rig.get("X2.coupling.in.gantrySyncOk") == 0
    assert rig.nck.gantries.groupings[0].offsets == {"X2": 0.0}
    assert 10655 in rig.history_numbers() and 10654 not in rig.history_numbers()


def test_beyond_the_warning_limit_the_nc_waits_for_dbx29_4_in_ref() -> None:
    rig = _rig("X2: {sim: {start_position: 401.0}}")
    _reference(rig)
    assert _state(rig) is State.WAITING_FOR_START
    rig.step(2)
    assert rig.get("X1.coupling.in.gantrySyncRunReady") == 1 and rig.alarm_numbers() == [10654]
    rig.set("MODEGROUP.basic.out.refPoint", 0)  # not in REF: DBX29.4 does nothing (L14767-14779)
    rig.step(2)
    rig.pulse("X1.coupling.out.gantryStartSyncRun", 2)
    rig.step(2)
    assert _state(rig) is State.WAITING_FOR_START
    rig.set("MODEGROUP.basic.out.refPoint", 1)
    rig.step(2)
    rig.pulse("X1.coupling.out.gantryStartSyncRun", 2)
    assert _state(rig) is State.SYNC_RUN
    rig.run_until(lambda: rig.get("X1.coupling.in.gantrySyncOk") == 1, 2000)
    rig.step(200)
    assert rig.axis("X2").actual == pytest.approx(rig.axis("X1").actual, abs=1e-3)
    assert rig.get("X1.coupling.in.gantrySyncRunReady") == 0 and rig.alarm_numbers() == []


def test_warning_comes_and_goes_by_itself_and_the_trip_stops_the_grouping_until_reset() -> None:
    rig = _rig()
    _reference(rig)
    rig.run_until(lambda: _state(rig) is State.SYNCHRONIZED, 2000)
    x2 = rig.axis("X2")
    x2.disturbance_velocity = 1200.0 / 60.0  # 1.2 mm behind at Kv 16.7/s: beyond 0.5, within 2
    x2.resting = False
    rig.run_until(lambda: rig.get("X2.coupling.in.gantryWarningLimitExceeded") == 1, 500)
    assert rig.alarm_numbers() == [10652] and _state(rig) is State.SYNCHRONIZED
    x2.disturbance_velocity = 0.0
    x2.resting = False
    rig.run_until(lambda: rig.get("X2.coupling.in.gantryWarningLimitExceeded") == 0, 500)
    assert rig.alarm_numbers() == []
    x2.disturbance_velocity = 3000.0 / 60.0  # 3 mm: beyond MD37120 = 2
    x2.resting = False
    rig.run_until(lambda: 10653 in rig.alarm_numbers(), 500)
    assert _state(rig) is State.TRIPPED and rig.get("X2.coupling.in.gantryCutOffLimitExceeded") == 1
    assert rig.get("X1.coupling.in.gantrySyncOk") == 0
    rig.step(200)
    assert not rig.axis("X1").servo_on and not rig.axis("Y1").servo_on  # the mode group stops
    x2.disturbance_velocity = 0.0
    rig.pulse("CHAN1.basic.out.reset", 2)
    rig.step(10)
    assert 10653 not in rig.alarm_numbers() and _state(rig) is State.WAITING_FOR_START
    assert rig.get("X2.coupling.in.gantryCutOffLimitExceeded") == 0
    assert rig.get("X1.coupling.in.gantrySyncRunReady") == 1


def test_a_broken_up_grouping_moves_its_axes_alone_and_monitors_nothing() -> None:
    rig = _rig("X1: {MD37140: 1}")
    assert _state(rig) is State.BROKEN_UP
    rig.set("MODEGROUP.basic.out.refPoint", 0)
    rig.set("X1.basic.out.traversKeyMinus", 1)
    rig.step(1000)
    rig.set("X1.basic.out.traversKeyMinus", 0)
    rig.step(300)
    assert rig.axis("X2").physical == pytest.approx(400.3) and rig.axis("X1").physical < 390.0
    assert rig.alarm_numbers() == [] and rig.get("X2.coupling.in.gantryWarningLimitExceeded") == 0


def test_extended_monitoring_keeps_the_difference_in_md37135_and_brings_10653_back_at_reset() -> None:
    rig = _rig("X1: {MD37140: 1, MD37150: 1}")
    _reference_broken_up(rig)
    rig.set("MODEGROUP.basic.out.refPoint", 0)
    rig.set("X1.basic.out.traversKeyMinus", 1)
    rig.run_until(lambda: 10653 in rig.alarm_numbers(), 2000)
    kept = rig.nck.memory.view("X2", rig.axis("X2").config.md).float(MD.GANTRY_ACT_POS_TOL_ERROR)
    assert kept > 2.0
    rig.set("X1.basic.out.traversKeyMinus", 0)
    rig.pulse("CHAN1.basic.out.reset", 2)
    rig.step(10)
    assert 10653 in rig.alarm_numbers()  # MD37135 is not 0 (L14532-14547)


def _reference_broken_up(rig: Rig) -> None:
    """Each axis of a broken-up grouping is referenced on its own key."""
    for axis in ("X1", "X2"):
        rig.set(f"{axis}.basic.out.traversKeyPlus", 1)
        for _ in range(10_000):
            rig.set(f"{axis}.basic.out.refPointApproachCam", rig.io(f"{axis}.refCam"))
            rig.step()
            if rig.get(f"{axis}.basic.in.enc1Synchronized"):
                break
        rig.set(f"{axis}.basic.out.traversKeyPlus", 0)
        rig.step(50)


@pytest.mark.parametrize("disable_sync", [0, 1])
def test_follow_up_loses_the_synchronism_and_position_control_within_md36030_restores_it_unless_dbx29_5(
        disable_sync: int) -> None:
    rig = _rig()
    _reference(rig)
    rig.run_until(lambda: _state(rig) is State.SYNCHRONIZED, 2000)
    rig.step(200)
    rig.set("X1.coupling.out.gantryDisableSync", disable_sync)
    rig.set("X2.basic.out.followUpMode", 1)
    rig.set("X2.basic.out.enableCtrl", 0)
    rig.step(10)
    assert _state(rig) is State.WAITING_FOR_START and rig.get("X1.coupling.in.gantrySyncOk") == 0
    rig.set("X2.basic.out.enableCtrl", 1)
    rig.set("X2.basic.out.followUpMode", 0)
    rig.step(10)
    # 12.3.2 (L14906-14944): back in position control within the standstill tolerance
    assert rig.get("X1.coupling.in.gantrySyncOk") == 1 - disable_sync
    assert _state(rig) is (State.WAITING_FOR_START if disable_sync else State.SYNCHRONIZED)
