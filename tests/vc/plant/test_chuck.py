"""The spindle chucks as the PLC sees them: valve solenoids (Q) in, end-position sensors (I) out;
the guard door.

Turn-mill SP1 and SP2: a 0.3 s stroke = 150 IPO cycles of 2 ms; SP1 clamped and SP2 open at
power-on; solenoids Q0.4 / Q0.5 (SP1.chuckClose / chuckRelease) and Q0.6 / Q0.7 (SP2), sensors
I9.4 / I9.5 (SP1.chuckClosed / chuckOpen) and I9.6 / I9.7 (SP2); the guard door switch I6.2
(Door.closed).  The hydraulics have pressure while the drive line-up is ready (Drives.ready,
100 ms after Drives.on).
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from pathlib import Path

import pytest

from interfaces.image import ProcessImage
from interfaces.plant_io import PlantIoMap
from vc.config.loader import load_machine
from vc.config.model import ChuckPlant, MachineConfig
from vc.plant.plant import DRIVE_READY_DELAY_S, Plant
from vc.simulation.lockstep import Simulation

ROOT = Path(__file__).resolve().parents[3]
IPO_US = 2000
STROKE = 150  # 0.3 s / 2 ms
READY = round(DRIVE_READY_DELAY_S * 1_000_000 / IPO_US)
CLAMPED, BETWEEN, OPEN = (1, 0), (0, 0), (0, 1)


@dataclass
class Spindle:
    physical: float = 0.0
    velocity: float = 0.0


@pytest.fixture(scope="module")
def turn_mill() -> MachineConfig:
    return load_machine(str(ROOT / "scenarios" / "machines" / "turn_mill.yaml"))


class ChuckBench:
    """The turn-mill plant with its drive line-up switched on; the test is the PLC."""

    def __init__(self, config: MachineConfig, chucks_clamped: dict[str, bool] | None = None):
        self.config = config
        self.plant = Plant(config, IPO_US, [Spindle() for _ in config.axes], None, chucks_clamped)
        self.io = ProcessImage(config.plant_io.area_sizes())
        self.plant.power_on(self.io)
        self.write("Drives.on", 1)
        self.run(READY)  # pressure from here on

    def read(self, name: str) -> int:
        return int(self.io.read(self.config.plant_io.resolve(name)))

    def write(self, name: str, value: int) -> None:
        self.io.write(self.config.plant_io.resolve(name), value)

    def valve(self, spindle: str, clamp: int, release: int) -> None:
        """The two solenoids as the PLC switches them."""
        self.write(f"{spindle}.chuckClose", clamp)
        self.write(f"{spindle}.chuckRelease", release)

    def sensors(self, spindle: str) -> tuple[int, int]:
        return self.read(f"{spindle}.chuckClosed"), self.read(f"{spindle}.chuckOpen")

    def run(self, cycles: int) -> None:
        for _ in range(cycles):
            self.plant.step(self.io)


# ------------------------------------------------------------------------------ configuration and power-on


def test_the_chucks_of_the_machine_file(turn_mill: MachineConfig) -> None:
    assert turn_mill.axis("SP1").plant.chuck == ChuckPlant(travel_time_s=0.3, closed_at_power_on=True)
    assert turn_mill.axis("SP2").plant.chuck == ChuckPlant(travel_time_s=0.3, closed_at_power_on=False)
    assert turn_mill.axis("SP3").plant.chuck is None  # the driven tool has no chuck


def test_power_on_reports_each_chuck_as_the_machine_file_says_and_the_door_closed(turn_mill: MachineConfig) -> None:
    plant = Plant(turn_mill, IPO_US, [Spindle() for _ in turn_mill.axes])
    io = ProcessImage(turn_mill.plant_io.area_sizes())
    plant.power_on(io)
    assert io.read(turn_mill.plant_io.resolve("SP1.chuckClosed")) == 1
    assert io.read(turn_mill.plant_io.resolve("SP1.chuckOpen")) == 0
    assert io.read(turn_mill.plant_io.resolve("SP2.chuckClosed")) == 0
    assert io.read(turn_mill.plant_io.resolve("SP2.chuckOpen")) == 1
    assert io.read(turn_mill.plant_io.resolve("Door.closed")) == 1  # the operator left the door closed
    assert plant.chucks_clamped() == {"SP1": True, "SP2": False}


def test_without_pressure_the_chuck_holds_whatever_the_valve_says(turn_mill: MachineConfig) -> None:
    plant = Plant(turn_mill, IPO_US, [Spindle() for _ in turn_mill.axes])
    io = ProcessImage(turn_mill.plant_io.area_sizes())
    plant.power_on(io)
    io.write(turn_mill.plant_io.resolve("SP1.chuckRelease"), 1)
    for _ in range(2 * STROKE):
        plant.step(io)
    assert plant.chucks_clamped() == {"SP1": True, "SP2": False}
    io.write(turn_mill.plant_io.resolve("Drives.on"), 1)
    for _ in range(READY - 1):
        plant.step(io)
    assert plant.chucks_clamped()["SP1"]  # Drives.ready comes in the next cycle
    plant.step(io)
    assert not plant.chucks_clamped()["SP1"]  # pressure and the unclamp solenoid: the chuck opens


@pytest.mark.parametrize(("clamp", "release"), [(0, 0), (1, 1)])
def test_neither_or_both_solenoids_the_chuck_holds(turn_mill: MachineConfig, clamp: int, release: int) -> None:
    # a PLC program that does not know the chucks leaves both at 0: the part stays where it is
    bench = ChuckBench(turn_mill)
    bench.valve("SP1", clamp, release)
    bench.valve("SP2", clamp, release)
    bench.run(2 * STROKE)
    assert bench.sensors("SP1") == CLAMPED
    assert bench.sensors("SP2") == OPEN


# ------------------------------------------------------------------------------ strokes


def test_clamping_takes_the_travel_time_and_the_sensors_show_the_end_positions(turn_mill: MachineConfig) -> None:
    bench = ChuckBench(turn_mill)
    assert bench.sensors("SP2") == OPEN
    bench.valve("SP2", 1, 0)
    bench.run(1)
    assert bench.sensors("SP2") == BETWEEN  # left the open end position at once
    bench.run(STROKE - 2)
    assert bench.sensors("SP2") == BETWEEN
    bench.run(1)
    assert bench.sensors("SP2") == CLAMPED
    bench.run(50)
    assert bench.sensors("SP2") == CLAMPED
    assert bench.sensors("SP1") == CLAMPED  # the other chuck is not touched


def test_unclamping_takes_the_travel_time(turn_mill: MachineConfig) -> None:
    bench = ChuckBench(turn_mill)
    bench.valve("SP1", 0, 1)
    bench.run(STROKE - 1)
    assert bench.sensors("SP1") == BETWEEN
    bench.run(1)
    assert bench.sensors("SP1") == OPEN


def test_a_reversed_valve_moves_back_from_where_the_piston_stands(turn_mill: MachineConfig) -> None:
    bench = ChuckBench(turn_mill)
    bench.valve("SP2", 1, 0)
    bench.run(40)
    bench.valve("SP2", 0, 1)
    bench.run(39)
    assert bench.sensors("SP2") == BETWEEN
    bench.run(1)
    assert bench.sensors("SP2") == OPEN


def test_losing_the_pressure_stops_the_stroke(turn_mill: MachineConfig) -> None:
    bench = ChuckBench(turn_mill)
    bench.valve("SP2", 1, 0)
    bench.run(100)
    bench.write("Drives.on", 0)  # e-stop: the line-up and the hydraulic pump go off
    bench.run(STROKE)
    assert bench.sensors("SP2") == BETWEEN
    bench.write("Drives.on", 1)
    bench.run(READY + 48)  # pressure again in the READY-th cycle: 100 + 49 cycles of stroke
    assert bench.sensors("SP2") == BETWEEN
    bench.run(1)
    assert bench.sensors("SP2") == CLAMPED


def test_kept_chuck_states_override_the_machine_file(turn_mill: MachineConfig) -> None:
    plant = Plant(turn_mill, IPO_US, [Spindle() for _ in turn_mill.axes], None, {"SP1": False, "SP2": True})
    io = ProcessImage(turn_mill.plant_io.area_sizes())
    plant.power_on(io)
    assert plant.chucks_clamped() == {"SP1": False, "SP2": True}
    assert io.read(turn_mill.plant_io.resolve("SP1.chuckOpen")) == 1
    assert io.read(turn_mill.plant_io.resolve("SP2.chuckClosed")) == 1


# ------------------------------------------------------------------------------ wiring


def test_a_chuck_without_its_open_sensor_reports_only_clamped(turn_mill: MachineConfig) -> None:
    entries = {str(point.address): point.name for point in turn_mill.plant_io.points if point.name != "SP2.chuckOpen"}
    config = dataclasses.replace(turn_mill, plant_io=PlantIoMap.from_mapping(entries, turn_mill.layout.axes))
    bench = ChuckBench(config)
    bench.io.areas["I"][9] |= 1 << 7  # whatever else drives I9.7 (not the plant)
    bench.valve("SP2", 1, 0)
    bench.run(STROKE)
    assert bench.read("SP2.chuckClosed") == 1
    assert bench.io.areas["I"][9] >> 7 & 1 == 1  # the unwired point kept what it had


def test_a_machine_without_chucks_has_none() -> None:
    config = load_machine(str(ROOT / "scenarios" / "machines" / "mill_3axis.yaml"))
    plant = Plant(config, IPO_US, [Spindle() for _ in config.axes])
    assert plant.chucks_clamped() == {}


# ------------------------------------------------------------------------------ in the simulation


def test_the_chucks_keep_their_part_over_a_power_cycle(turn_mill: MachineConfig) -> None:
    sim = Simulation(turn_mill, plc=None)
    sim.write(sim.plant_io.resolve("Drives.on"), 1)
    sim.write(sim.plant_io.resolve("SP2.chuckClose"), 1)
    sim.step(READY + STROKE)
    assert sim.plant.chucks_clamped() == {"SP1": True, "SP2": True}
    sim.write(sim.plant_io.resolve("SP1.chuckRelease"), 1)
    sim.step(STROKE)
    sim.power_cycle(1.0)
    assert sim.plant.chucks_clamped() == {"SP1": False, "SP2": True}
    assert sim.read(sim.plant_io.resolve("SP2.chuckClosed")) == 1
    assert sim.read(sim.plant_io.resolve("SP1.chuckOpen")) == 1
