"""The clamp of the scenarios' rotary table (vc/plant/clamp.py): closed in 0.2 s by Clamp.close, it
holds C1's slide; its faults: it does not close, it gives way under a load of 600 deg/min.  The test
is the PLC writing the valve and reading the sensors."""

from __future__ import annotations

from pathlib import Path

import pytest

from interfaces.image import ProcessImage
from vc.config.loader import load_machine
from vc.config.model import MachineConfig
from vc.plant.clamp import AxisClamp

TABLE = Path(__file__).resolve().parents[3] / "scenarios" / "indexing_axes" / "machines" / "rotary_table.yaml"
IPO_US = 2000


@pytest.fixture(scope="module")
def table() -> MachineConfig:
    return load_machine(str(TABLE))


def _clamp(config: MachineConfig) -> tuple[AxisClamp, ProcessImage]:
    assert config.plant.clamp is not None
    io = ProcessImage(config.plant_io.area_sizes())
    clamp = AxisClamp(config.plant.clamp, config.plant_io, IPO_US)
    clamp.write_sensors(io)
    return clamp, io


def _sensors(config: MachineConfig, io: ProcessImage) -> tuple[int, int]:
    return (int(io.read(config.plant_io.resolve("Clamp.closed"))),
            int(io.read(config.plant_io.resolve("Clamp.opened"))))


def _valve(config: MachineConfig, io: ProcessImage, on: bool) -> None:
    io.write(config.plant_io.resolve("Clamp.close"), 1 if on else 0)


def test_it_closes_in_its_stroke_time_and_holds_the_slide(table: MachineConfig) -> None:
    clamp, io = _clamp(table)
    assert clamp.axis == "C1" and _sensors(table, io) == (0, 1) and clamp.hold(10.0, 12.0, 100.0) == 12.0
    _valve(table, io, True)
    moving = [clamp.step(io) for _ in range(100)]
    assert moving.index(False) == 99 and _sensors(table, io) == (1, 0)  # 0.2 s = 100 IPO cycles
    assert clamp.hold(10.0, 12.0, 100.0) == 10.0  # the drive cannot move it
    _valve(table, io, False)
    for _ in range(100):
        clamp.step(io)
    assert _sensors(table, io) == (0, 1)


def test_it_gives_way_under_the_load_and_the_load_pushes_the_slide(table: MachineConfig) -> None:
    clamp, io = _clamp(table)
    _valve(table, io, True)
    for _ in range(100):
        clamp.step(io)
    clamp.inject("clamp_opening")
    clamp.step(io)
    assert _sensors(table, io) == (0, 0)  # pushed off its closed end
    assert clamp.hold(10.0, 10.0, 100.0) == pytest.approx(10.02)  # 600 deg/min for 2 ms
    clamp.repair()
    clamp.step(io)
    assert _sensors(table, io) == (1, 0) and clamp.hold(10.0, 10.5, 100.0) == 10.0


def test_a_clamp_that_does_not_close_stays_open_until_repaired(table: MachineConfig) -> None:
    clamp, io = _clamp(table)
    clamp.inject("clamp_not_closing")
    _valve(table, io, True)
    for _ in range(200):
        clamp.step(io)
    assert _sensors(table, io) == (0, 1) and clamp.hold(10.0, 12.0, 100.0) == 12.0
    clamp.repair()
    for _ in range(100):
        clamp.step(io)
    assert _sensors(table, io) == (1, 0)
    with pytest.raises(KeyError, match="clamp_opening"):
        clamp.inject("clamp_lost")
