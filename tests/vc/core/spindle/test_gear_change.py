"""The gear stages of a spindle and their change dialog (seed 003 §13.4), the state machine alone.

:class:`GearChange` on turn_mill's SP1 (3 gear stages, MD35010 = 1: change with oscillation,
MD35400 = 60 rev/min); the test plays the spindle (standstill, position control, positioning)
and the PLC (the inputs), cycle by cycle.  The whole spindle with its gear change runs in
test_spindle.py.
"""

from __future__ import annotations

import pytest
from core_rig import machine, spindle_rig

from vc.config import md_dictionary as MD
from vc.core.alarms import AlarmList
from vc.core.nc_memory import NcMemory
from vc.core.program.commands import SpindleCommand
from vc.core.spindle.gear_change import (
    ALARM_NOT_ACKNOWLEDGED,
    ALARM_WRONG_GEAR,
    GearChange,
    GearOutcome,
    GearState,
    select_gear,
)
from vc.core.spindle.positioning import Positioning
from vc.core.spindle.signals import SpindleInputs

IPO = 0.002
WAIT_S = 0.1  # MD10192 of the test: 50 cycles


def gear_change(extra: str = "") -> tuple[GearChange, SpindleInputs, AlarmList]:
    rig = spindle_rig(extra)
    inputs, alarms = SpindleInputs(), AlarmList()
    return GearChange(rig.axis("SP1"), inputs, "CHAN1", IPO, 0, WAIT_S, NcMemory(), alarms), inputs, alarms


def numbers(alarms: AlarmList) -> list[int]:
    return [alarm.number for alarm in alarms]


@pytest.mark.parametrize(("speed_rpm", "current", "expected"), [
    (500.0, 1, None),  # inside gear 1's window [10, 800]: keep
    (1500.0, 1, 2),  # above 800: gear 2's window [700, 2000]
    (750.0, 2, None),  # the hysteresis: 750 lies in gear 2's window [700, 2000]
    (600.0, 2, 1),  # below 700: gear 1
    (3000.0, 1, 3),
    (9000.0, 1, 3),  # above every window: the highest gear
    (5.0, 2, 1),  # below gear 1's window: gear 1
    (0.0, 2, None),  # S0: no change while MD35120[1] > 0
])
def test_m40_chooses_the_gear_from_the_switching_thresholds(speed_rpm: float, current: int,
                                                            expected: int | None) -> None:
    md = machine().axis("SP1").md
    assert select_gear(md, speed_rpm, current) == expected


def test_s0_selects_gear_1_when_its_lower_threshold_is_0() -> None:
    md = machine("SP1: {MD35120: [0, 0, 700, 1800]}").axis("SP1").md
    assert select_gear(md, 0.0, 2) == 1


def test_a_block_asks_for_a_stage_only_when_it_differs_from_the_active_one() -> None:
    change, _, _ = gear_change()
    assert change.programmed(SpindleCommand(gear=41), suppressed=False) is None  # gear 1 is active
    assert change.programmed(SpindleCommand(gear=43), suppressed=False) == 3
    assert change.programmed(SpindleCommand(gear=40, speed=1500.0), suppressed=False) == 2
    assert change.programmed(SpindleCommand(speed=500.0), suppressed=True) is None
    assert change.programmed(SpindleCommand(speed=1500.0), suppressed=True) == 2
    assert change.suppressed_gear == 2 and change.state is None  # remembered, not started


def test_a_fixed_ratio_asks_for_no_stage() -> None:
    change, _, _ = gear_change("SP1: {MD35010: 0}")
    assert not change.changes_enabled
    assert change.programmed(SpindleCommand(gear=43), suppressed=False) is None


def test_the_dialog_from_the_request_to_the_reported_gear() -> None:
    change, inputs, alarms = gear_change()
    change.start(2, 0, stops_spindle=False)
    assert change.state is GearState.REQUESTED and change.outcome is GearOutcome.DIALOG and change.dialog_open
    assert change.cycle(1, alarms, False, False, None, 0) == 0.0  # braking
    assert change.state is GearState.REQUESTED and change.outcome is GearOutcome.NONE
    assert change.cycle(2, alarms, True, False, None, 0) == 0.0  # stationary, no oscillation enable
    assert change.state is GearState.AT_STANDSTILL
    inputs.oscillation_enable = True
    assert change.cycle(3, alarms, True, False, None, -1) == pytest.approx(60.0 * 6.0)  # against the last M4
    inputs.gear_reported, inputs.gear_done = 2, True
    assert change.cycle(4, alarms, True, False, None, -1) is None
    assert change.state is None and change.outcome is GearOutcome.CHANGED and not change.dialog_open
    assert change.gear == 2 and change.acknowledged_gear == 2 and numbers(alarms) == []


def test_another_gear_reported_raises_22010_and_becomes_active() -> None:
    change, inputs, alarms = gear_change()
    change.start(3, 0, stops_spindle=False)
    inputs.gear_reported, inputs.gear_done = 2, True
    change.cycle(1, alarms, False, False, None, 0)  # 16.3 is accepted while the spindle still brakes
    assert change.gear == 2 and numbers(alarms) == [ALARM_WRONG_GEAR]


def test_a_missing_acknowledgement_raises_its_alarm_once() -> None:
    change, _, alarms = gear_change()
    change.start(2, 0, stops_spindle=False)
    for cycle in range(1, 52):
        change.cycle(cycle, alarms, True, False, None, 0)
    assert numbers(alarms) == [ALARM_NOT_ACKNOWLEDGED]  # after MD10192 = 0.1 s
    for cycle in range(52, 60):
        change.cycle(cycle, alarms, True, False, None, 0)
    assert numbers(alarms) == [ALARM_NOT_ACKNOWLEDGED] and change.state is GearState.AT_STANDSTILL


def test_at_the_change_position_the_dialog_waits_for_md35310() -> None:
    change, _, alarms = gear_change("SP1: {MD35010: 2, MD35310: [0.01, 0.01, 0.01, 0.01, 0.01, 0.01]}")
    change.start(2, 0, stops_spindle=True)
    assert change.state is GearState.TO_POSITION and change.outcome is GearOutcome.TO_POSITION
    assert change.change_position() == change.gear_float(MD.GEAR_STEP_CHANGE_POSITION)
    positioning = Positioning("DC", change.change_position(), True, programmed=False)
    assert change.cycle(1, alarms, True, True, positioning, 0) is None
    assert change.state is GearState.TO_POSITION  # not there yet
    positioning.done = True
    change.cycle(2, alarms, True, True, positioning, 0)
    assert change.state is GearState.POSITION_DELAY and change.delay_cycles == 5
    for cycle in range(3, 7):
        change.cycle(cycle, alarms, True, True, positioning, 0)
    assert change.state is GearState.POSITION_DELAY
    change.cycle(7, alarms, True, True, positioning, 0)
    assert change.state is GearState.REQUESTED and change.outcome is GearOutcome.DIALOG
    assert change.cycle(8, alarms, True, True, positioning, 0) == 0.0  # standing in position control
    assert change.state is GearState.AT_STANDSTILL and change.stops_spindle


def test_a_reported_gear_is_taken_in_reset_state_once_it_stood() -> None:
    change, _, _ = gear_change()
    change.take_report(3)
    assert not change.settled
    taken = [change.accept_reported_gear() for _ in range(10)]
    assert taken == [False] * 9 + [True]  # it stood 10 cycles
    assert change.gear == 3 and change.acknowledged_gear == 3 and change.settled
    change.take_report(2)  # a new report starts the wait again
    assert not change.accept_reported_gear() and change.gear == 3
