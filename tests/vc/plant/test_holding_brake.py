"""The holding brake of an axis's motor (vc/plant/holding_brake.py): the scenarios' vertical_axis
(Z1, 50 ms, sags at 600 mm/min); the test is the drive (its order, the contact it reads) and the axis."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import pytest

from vc.config.loader import load_machine
from vc.plant.holding_brake import HoldingBrake

VERTICAL = Path(__file__).resolve().parents[3] / "scenarios" / "drives" / "machines" / "vertical_axis.yaml"
CYCLE_US = 2000
SAG_PER_CYCLE = -600.0 / 60.0 * 0.002


@dataclass
class _Drive:
    release_ordered: bool = False
    contact: bool = False
    reports: int = 0

    def report(self, released: bool) -> None:
        self.reports += released != self.contact
        self.contact = released


@dataclass
class _Axis:
    servo_on: bool = True
    resting: bool = True


def _brake() -> tuple[HoldingBrake, _Drive, _Axis]:
    config = load_machine(str(VERTICAL)).plant.holding_brake
    assert config is not None and config.axis == "Z1"
    brake, drive, axis = HoldingBrake(config, CYCLE_US), _Drive(), _Axis()
    brake.fit(axis, drive)
    return brake, drive, axis


def _cycles_until_contact(brake: HoldingBrake, drive: _Drive, value: bool) -> int:
    for cycle in range(1, 200):
        brake.cycle()
        if drive.contact == value:
            return cycle
    raise AssertionError("the contact never changed")


def test_the_brake_releases_and_engages_in_its_switching_time_and_holds_until_released() -> None:
    brake, drive, _ = _brake()
    assert brake.hold(-200.0, -201.0, 100.0) == -200.0  # engaged: the drive cannot move the slide
    drive.release_ordered = True
    assert _cycles_until_contact(brake, drive, True) == 25
    assert brake.hold(-200.0, -201.0, 100.0) == -201.0
    drive.release_ordered = False
    brake.cycle()
    assert brake.hold(-200.0, -201.0, 100.0) == -201.0  # engaging: the linings do not hold yet
    assert _cycles_until_contact(brake, drive, False) == 24
    assert brake.hold(-200.0, -201.0, 100.0) == -200.0 and drive.reports == 2


def test_released_without_torque_the_weight_moves_the_slide_and_wakes_the_axis() -> None:
    brake, drive, axis = _brake()
    drive.release_ordered = True
    _cycles_until_contact(brake, drive, True)
    assert axis.resting  # the drive holds the weight: nothing to do for the axis
    axis.servo_on = False
    brake.cycle()
    assert not axis.resting
    assert brake.hold(-200.0, -200.0, 0.0) == pytest.approx(-200.0 + SAG_PER_CYCLE)
    assert brake.hold(-200.0, -200.0, 20.0) == -200.0  # any torque holds it [INF]


def test_a_brake_that_does_not_open_never_reports_released_until_repaired() -> None:
    brake, drive, _ = _brake()
    brake.inject("brake_not_opening")
    drive.release_ordered = True
    for _ in range(100):
        brake.cycle()
    assert not drive.contact and brake.hold(-200.0, -201.0, 100.0) == -200.0
    brake.repair()
    assert _cycles_until_contact(brake, drive, True) == 25


def test_a_brake_that_does_not_close_stays_released_until_repaired() -> None:
    brake, drive, _ = _brake()
    drive.release_ordered = True
    _cycles_until_contact(brake, drive, True)
    brake.inject("brake_not_closing")
    drive.release_ordered = False
    for _ in range(100):
        brake.cycle()
    assert drive.contact and brake.hold(-200.0, -200.0, 0.0) < -200.0
    brake.repair()
    assert _cycles_until_contact(brake, drive, False) == 25


def test_an_unknown_fault_is_refused() -> None:
    brake, _, _ = _brake()
    with pytest.raises(KeyError, match="brake_not_opening"):
        brake.inject("brake_worn")
