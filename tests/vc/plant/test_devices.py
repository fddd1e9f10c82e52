"""The machine's devices as the PLC sees them (the test is the PLC): the turn-mill's turret and
coolant pump, the mill's tool magazine and changer arm.

Turn-mill: 8 stations, 0.15 s per station = 75 IPO cycles, lock pin 0.08 s = 40 cycles, coolant
pressure after 0.3 s = 150 cycles.  Mill: 12 pockets, 0.25 s per pocket = 125 cycles, arm 0.5 s =
250 cycles.  IPO cycle 2 ms.
"""

from __future__ import annotations

from pathlib import Path

import pytest

from interfaces.image import ProcessImage
from vc.config.loader import load_machine
from vc.config.model import MachineConfig
from vc.plant.coolant import Coolant
from vc.plant.tool_changer import ToolChanger
from vc.plant.turret import Turret

ROOT = Path(__file__).resolve().parents[3]
IPO_US = 2000
PIN, STATION, PRESSURE, POCKET, ARM = 40, 75, 150, 125, 250


@pytest.fixture(scope="module")
def turn_mill() -> MachineConfig:
    return load_machine(str(ROOT / "scenarios" / "machines" / "turn_mill.yaml"))


@pytest.fixture(scope="module")
def mill() -> MachineConfig:
    return load_machine(str(ROOT / "scenarios" / "machines" / "mill_3axis.yaml"))


class Bench:
    """One device with the machine's process image; the test switches its outputs."""

    def __init__(self, config: MachineConfig, device: Turret | Coolant | ToolChanger):
        self.config, self.device = config, device
        self.io = ProcessImage(config.plant_io.area_sizes())
        device.write_sensors(self.io)

    def read(self, name: str) -> int:
        return int(self.io.read(self.config.plant_io.resolve(name)))

    def write(self, name: str, value: int) -> None:
        self.io.write(self.config.plant_io.resolve(name), value)

    def run(self, cycles: int) -> None:
        for _ in range(cycles):
            self.device.step(self.io)

    def code(self, prefix: str, bits: int) -> int:
        return sum(self.read(f"{prefix}.code{1 << n}") << n for n in range(bits))


def _turret(config: MachineConfig, station: int | None = None) -> tuple[Bench, Turret]:
    assert config.plant.turret is not None
    turret = Turret(config.plant.turret, config.plant_io, IPO_US, station)
    return Bench(config, turret), turret


def test_turret_unlock_index_lock(turn_mill: MachineConfig) -> None:
    bench, turret = _turret(turn_mill)
    assert (bench.read("Turret.locked"), bench.read("Turret.unlocked"), bench.code("Turret", 4)) == (1, 0, 1)
    bench.write("Turret.indexCw", 1)
    bench.run(STATION)
    assert turret.station == 1  # the engaged pin holds the disk
    bench.write("Turret.indexCw", 0)
    bench.write("Turret.unlock", 1)
    bench.run(PIN)
    assert (bench.read("Turret.locked"), bench.read("Turret.unlocked")) == (0, 1)
    bench.write("Turret.indexCcw", 1)  # 1 -> 8 the short way
    bench.run(STATION // 2)
    assert bench.code("Turret", 4) == 0  # between two stations
    bench.run(STATION - STATION // 2)
    assert bench.code("Turret", 4) == 8
    bench.write("Turret.indexCcw", 0)
    bench.write("Turret.unlock", 0)
    bench.run(PIN)
    assert (bench.read("Turret.locked"), bench.read("Turret.unlocked"), turret.station) == (1, 0, 8)


def test_turret_pin_rests_on_the_disk_between_two_stations(turn_mill: MachineConfig) -> None:
    bench, _ = _turret(turn_mill, station=3)
    bench.write("Turret.unlock", 1)
    bench.run(PIN)
    bench.write("Turret.indexCw", 1)
    bench.run(STATION // 2)
    bench.write("Turret.indexCw", 0)
    bench.write("Turret.unlock", 0)
    bench.run(2 * PIN)
    assert (bench.read("Turret.locked"), bench.read("Turret.unlocked"), bench.code("Turret", 4)) == (0, 0, 0)


@pytest.mark.parametrize(("fault", "locked", "unlocked", "station"), [
    ("turret_sensor_missing", 0, 0, 2), ("turret_lock_jammed", 0, 0, 2), ("turret_drive_stalled", 1, 0, 1)])
def test_turret_faults(turn_mill: MachineConfig, fault: str, locked: int, unlocked: int, station: int) -> None:
    bench, turret = _turret(turn_mill)
    turret.inject(fault)
    bench.write("Turret.unlock", 1)
    bench.run(PIN)
    bench.write("Turret.indexCw", 1)
    bench.run(STATION)
    bench.write("Turret.indexCw", 0)
    bench.write("Turret.unlock", 0)
    bench.run(PIN)
    if fault == "turret_sensor_missing":
        bench.write("Turret.unlock", 1)  # pulled again: the broken sensor never says so
        bench.run(PIN)
    assert (bench.read("Turret.locked"), bench.read("Turret.unlocked"), turret.station) == (locked, unlocked, station)
    turret.repair()
    bench.write("Turret.unlock", 0)
    bench.run(PIN)
    assert bench.read("Turret.locked") == 1


def test_coolant_pressure_builds_up_and_can_be_lost(turn_mill: MachineConfig) -> None:
    assert turn_mill.plant.coolant is not None
    coolant = Coolant(turn_mill.plant.coolant, turn_mill.plant_io, IPO_US)
    bench = Bench(turn_mill, coolant)
    bench.write("Coolant.pump", 1)
    bench.run(PRESSURE - 1)
    assert bench.read("Coolant.pressureOk") == 0
    bench.run(1)
    assert bench.read("Coolant.pressureOk") == 1
    coolant.inject("coolant_pressure_lost")
    bench.run(1)
    assert bench.read("Coolant.pressureOk") == 0
    coolant.repair()
    bench.run(1)
    assert bench.read("Coolant.pressureOk") == 1
    bench.write("Coolant.pump", 0)
    bench.run(1)
    assert bench.read("Coolant.pressureOk") == 0


def test_tool_changer_swaps_the_spindle_tool_with_the_pocket(mill: MachineConfig) -> None:
    assert mill.plant.tool_changer is not None
    changer = ToolChanger(mill.plant.tool_changer, mill.plant_io, IPO_US)
    bench = Bench(mill, changer)
    assert (bench.read("ToolArm.home"), bench.code("Magazine", 4)) == (1, 1)
    bench.write("Magazine.rotateCcw", 1)  # pocket 1 -> 12
    bench.run(POCKET)
    bench.write("Magazine.rotateCcw", 0)
    assert bench.code("Magazine", 4) == 12
    bench.write("ToolArm.toSpindle", 1)
    bench.run(ARM)
    assert (bench.read("ToolArm.atSpindle"), changer.spindle_tool, changer.tools[12]) == (1, 12, 0)
    bench.write("Magazine.rotateCw", 1)  # the magazine does not turn while the arm is out
    bench.run(POCKET)
    bench.write("Magazine.rotateCw", 0)
    assert bench.code("Magazine", 4) == 12
    bench.write("ToolArm.toSpindle", 0)
    bench.run(ARM)
    assert (bench.read("ToolArm.home"), changer.spindle_tool) == (1, 12)


def test_tool_changer_faults(mill: MachineConfig) -> None:
    assert mill.plant.tool_changer is not None
    changer = ToolChanger(mill.plant.tool_changer, mill.plant_io, IPO_US)
    bench = Bench(mill, changer)
    changer.inject("magazine_stalled")
    bench.write("Magazine.rotateCw", 1)
    bench.run(POCKET)
    bench.write("Magazine.rotateCw", 0)
    assert bench.code("Magazine", 4) == 1
    changer.inject("tool_arm_stuck")
    bench.write("ToolArm.toSpindle", 1)
    bench.run(ARM)
    assert (bench.read("ToolArm.home"), bench.read("ToolArm.atSpindle")) == (1, 0)
    changer.repair()
    bench.run(ARM)
    assert bench.read("ToolArm.atSpindle") == 1
