"""The tailstock's part as the quill's fixed stop (vc/plant/tailstock.py): the scenarios' lathe, the
part's face at 120 mm, 50 kN/mm, 10 kN at full torque, the part slips above 8 kN, the sleeve
retracted at or behind 5 mm; the test moves the quill and is the PLC reading the sensors."""

from __future__ import annotations

from pathlib import Path

import pytest

from interfaces.image import ProcessImage
from vc.config.loader import load_machine
from vc.config.model import MachineConfig
from vc.plant.tailstock import PartState, Tailstock

LATHE = Path(__file__).resolve().parents[3] / "scenarios" / "fixed_stop" / "machines" / "lathe_tailstock.yaml"


@pytest.fixture(scope="module")
def lathe() -> MachineConfig:
    return load_machine(str(LATHE))


def _tailstock(config: MachineConfig) -> tuple[Tailstock, ProcessImage]:
    assert config.plant.tailstock is not None
    io = ProcessImage(config.plant_io.area_sizes())
    tailstock = Tailstock(config.plant.tailstock, config.plant_io)
    tailstock.write_sensors(io)
    return tailstock, io


def _sensor(config: MachineConfig, io: ProcessImage, name: str) -> int:
    return int(io.read(config.plant_io.resolve(f"Tailstock.{name}")))


def test_the_quill_is_free_before_the_face_and_held_by_its_force_behind_it(lathe: MachineConfig) -> None:
    tailstock, io = _tailstock(lathe)
    assert tailstock.axis == "W1" and _sensor(lathe, io, "retracted") == 1
    assert tailstock.hold(100.0, 110.0, 20.0) == 110.0 and tailstock.force == 0.0
    assert tailstock.hold(119.0, 125.0, 20.0) == pytest.approx(120.04)  # 2 kN / 50 kN/mm
    assert tailstock.force == pytest.approx(2000.0)
    tailstock.write_sensors(io)
    assert (_sensor(lathe, io, "retracted"), _sensor(lathe, io, "atPart")) == (0, 1)
    assert tailstock.hold(120.04, 125.0, 50.0) == pytest.approx(120.1)  # more torque: deeper
    assert tailstock.hold(120.1, 120.05, 0.0) == pytest.approx(120.0)  # no torque: the part pushes back
    assert tailstock.hold(120.0, 110.0, 50.0) == 110.0  # away from the part: free
    tailstock.write_sensors(io)
    assert _sensor(lathe, io, "atPart") == 0


def test_more_force_than_the_part_takes_loses_the_stop(lathe: MachineConfig) -> None:
    tailstock, _ = _tailstock(lathe)
    assert tailstock.hold(119.0, 121.0, 90.0) == 121.0  # 9 kN > 8 kN: the part slips
    assert tailstock.state is PartState.LOST and tailstock.hold(121.0, 130.0, 10.0) == 130.0
    tailstock.repair()
    assert tailstock.hold(119.0, 121.0, 10.0) == pytest.approx(120.02)


@pytest.mark.parametrize("fault", ["stop_lost", "no_part"])
def test_the_faults_take_the_stop_away_until_repaired(lathe: MachineConfig, fault: str) -> None:
    tailstock, io = _tailstock(lathe)
    tailstock.inject(fault)
    assert tailstock.hold(119.0, 125.0, 20.0) == 125.0
    tailstock.write_sensors(io)
    assert _sensor(lathe, io, "atPart") == 0
    tailstock.repair()
    assert tailstock.hold(119.0, 125.0, 20.0) == pytest.approx(120.04)
    with pytest.raises(KeyError, match="stop_lost, no_part"):
        tailstock.inject("broken_centre")
