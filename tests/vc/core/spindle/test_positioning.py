"""The motion of SPOS / SPOSA / M19 (seed 003 §13.2.5), the drive alone on turn_mill's SP1 at standstill.

The test gives the drive MD35300 with the override (``limit``) and MD35210 (``accel``) as the
spindle would; the whole spindle positions in test_spindle.py.
"""

from __future__ import annotations

import pytest
from core_rig import spindle_rig

from vc.core.axis.axis import MachineAxis
from vc.core.spindle.positioning import Positioning, PositioningDrive

IPO = 0.002
LIMIT = 100.0 * 6.0  # deg/s
ACCEL = 30.0 * 360.0  # deg/s^2


def standing_sp1() -> MachineAxis:
    return spindle_rig().axis("SP1")


def test_an_unsynchronised_spindle_searches_its_zero_mark_without_position_control() -> None:
    axis = standing_sp1()
    axis.encoder.referenced = False
    drive = PositioningDrive(axis, IPO)
    positioning = Positioning("ACN", 90.0, True)
    assert drive.step(positioning, LIMIT, ACCEL) == -LIMIT  # ACN: the negative direction, at MD35300
    assert drive.position_control is False and not drive.planned and positioning.direction == -1


def test_a_synchronised_spindle_plans_its_approach_in_position_control() -> None:
    axis = standing_sp1()
    axis.encoder.referenced = True
    drive = PositioningDrive(axis, IPO)
    positioning = Positioning("IC", 30.0, True)
    velocity = drive.step(positioning, LIMIT, ACCEL)
    assert drive.position_control is True and drive.planned
    assert positioning.target == pytest.approx(axis.setpoint + 30.0)
    assert velocity == pytest.approx(ACCEL * IPO)  # the first step of the planned ramp


def test_a_positioning_holds_the_block_until_it_stands_on_its_target() -> None:
    axis = standing_sp1()
    spos, sposa = Positioning("AC", 0.0, True), Positioning("AC", 0.0, False)
    assert spos.holds_block_end(axis) and not sposa.holds_block_end(axis)
    spos.done = True
    assert not spos.holds_block_end(axis) and spos.reached(axis)
    axis.encoder.referenced = True
    assert spos.in_position(axis)
    spos.programmed = False  # the approach to the gear-change position shows no 85.5
    assert not spos.in_position(axis)
