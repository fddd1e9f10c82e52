"""The spindle gearbox as the PLC sees it: shift actuators (Q) in, stage sensors (I) out.

Turn-mill SP1: three stages, shift time 0.4 s = 200 IPO cycles of 2 ms while the motor turns,
stage 1 in mesh at power-on; sensors I9.0..I9.2 (gearEngaged1..3) and I9.3 (gearNeutral),
actuators Q0.1..Q0.3 (gearShift1..3).  The teeth mesh only while the motor turns at 1 rev/min
(6 deg/s) or faster, in either direction (seed 003 L19259-19325: the spindle oscillates).
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from pathlib import Path

import pytest

from interfaces.image import ProcessImage
from interfaces.plant_io import PlantIoMap
from vc.config.loader import load_machine
from vc.config.model import MachineConfig
from vc.located_yaml import LocatedMap
from vc.plant.gearbox import MESHING_SPEED_DEG_S
from vc.plant.plant import Plant
from vc.simulation.lockstep import Simulation

ROOT = Path(__file__).resolve().parents[3]
IPO_US = 2000
SHIFT_CYCLES = 200  # 0.4 s / 2 ms
TURNING = 60.0  # deg/s = 10 rev/min, a slow oscillation


@dataclass
class Motor:
    physical: float = 0.0
    velocity: float = 0.0


@pytest.fixture(scope="module")
def turn_mill() -> MachineConfig:
    return load_machine(str(ROOT / "scenarios" / "machines" / "turn_mill.yaml"))


class GearBench:
    """The turn-mill plant with every slide standing and the SP1 motor turned by hand."""

    def __init__(self, config: MachineConfig, gear_stages: dict[str, int] | None = None):
        self.config = config
        self.motors = {axis.name: Motor(axis.sim.start_position) for axis in config.axes}
        self.plant = Plant(config, IPO_US, [self.motors[axis.name] for axis in config.axes], gear_stages)
        self.io = ProcessImage(config.plant_io.area_sizes())
        self.plant.power_on(self.io)

    def sensors(self) -> tuple[int, int, int, int]:
        """gearEngaged1, gearEngaged2, gearEngaged3, gearNeutral."""
        names = ("SP1.gearEngaged1", "SP1.gearEngaged2", "SP1.gearEngaged3", "SP1.gearNeutral")
        first, second, third, neutral = (int(self.io.read(self.config.plant_io.resolve(name))) for name in names)
        return first, second, third, neutral

    def actuators(self, *stages: int) -> None:
        """Exactly these shift actuators on, the others off (what the PLC's outputs say)."""
        for stage in (1, 2, 3):
            self.io.write(self.config.plant_io.resolve(f"SP1.gearShift{stage}"), 1 if stage in stages else 0)

    def run(self, cycles: int, velocity: float = 0.0) -> None:
        self.motors["SP1"].velocity = velocity
        for _ in range(cycles):
            self.plant.step(self.io)


IN_STAGE_1 = (1, 0, 0, 0)
IN_STAGE_2 = (0, 1, 0, 0)
IN_STAGE_3 = (0, 0, 1, 0)
NEUTRAL = (0, 0, 0, 1)


# ------------------------------------------------------------------------------ power-on


def test_stage_of_the_machine_file_is_engaged_at_power_on(turn_mill: MachineConfig) -> None:
    bench = GearBench(turn_mill)
    assert bench.sensors() == IN_STAGE_1
    assert bench.plant.gear_stages() == {"SP1": 1}


def test_a_gearbox_may_be_in_neutral_or_keep_its_stage_at_power_on(turn_mill: MachineConfig) -> None:
    neutral = load_machine(turn_mill.source, LocatedMap({"SP1": {"plant": {"gearbox": {"engaged": 0}}}}))
    assert GearBench(neutral).sensors() == NEUTRAL
    assert GearBench(turn_mill, {"SP1": 3}).sensors() == IN_STAGE_3  # the stage kept over a power cycle


# ------------------------------------------------------------------------------ meshing


def test_shift_leaves_the_old_stage_at_once_and_meshes_after_the_shift_time_of_turning(
        turn_mill: MachineConfig) -> None:
    bench = GearBench(turn_mill)
    bench.actuators(2)
    bench.run(1, TURNING)
    assert bench.sensors() == NEUTRAL  # the sliding gear left stage 1 in the first cycle
    bench.run(SHIFT_CYCLES - 2, TURNING)
    assert bench.sensors() == NEUTRAL
    bench.run(1, TURNING)
    assert bench.sensors() == IN_STAGE_2  # 200 cycles = 0.4 s of turning
    bench.actuators()
    bench.run(10, TURNING)
    assert bench.sensors() == IN_STAGE_2  # the PLC switched the actuator off: the stage stays


def test_tooth_on_tooth_a_standing_motor_leaves_the_gearbox_in_neutral(turn_mill: MachineConfig) -> None:
    bench = GearBench(turn_mill)
    bench.actuators(3)
    bench.run(5 * SHIFT_CYCLES)
    assert bench.sensors() == NEUTRAL  # pushed for 2 s, but the teeth found no gap
    bench.run(SHIFT_CYCLES, TURNING)
    assert bench.sensors() == IN_STAGE_3  # the motor moves: they mesh


@pytest.mark.parametrize(("velocity", "meshes"), [
    (MESHING_SPEED_DEG_S, True), (-MESHING_SPEED_DEG_S, True), (-TURNING, True),
    (0.99 * MESHING_SPEED_DEG_S, False), (-0.99 * MESHING_SPEED_DEG_S, False)])
def test_meshing_needs_1_rev_per_min_in_either_direction(turn_mill: MachineConfig, velocity: float,
                                                         meshes: bool) -> None:
    bench = GearBench(turn_mill)
    bench.actuators(2)
    bench.run(SHIFT_CYCLES, velocity)
    assert bench.sensors() == (IN_STAGE_2 if meshes else NEUTRAL)


def test_turning_time_adds_up_over_the_reversals_of_an_oscillation(turn_mill: MachineConfig) -> None:
    bench = GearBench(turn_mill)
    bench.actuators(2)
    bench.run(80, TURNING)
    bench.run(30)  # reversing: the motor passes through standstill
    bench.run(80, -TURNING)
    bench.run(30)
    assert bench.sensors() == NEUTRAL  # 160 cycles turned
    bench.run(40, TURNING)
    assert bench.sensors() == IN_STAGE_2  # 200 cycles turned


# ------------------------------------------------------------------------------ actuators


def test_two_actuators_at_once_move_nothing(turn_mill: MachineConfig) -> None:
    bench = GearBench(turn_mill)
    bench.actuators(2, 3)
    bench.run(3 * SHIFT_CYCLES, TURNING)
    assert bench.sensors() == IN_STAGE_1  # the fork is pushed both ways: it stays in stage 1


def test_a_second_actuator_stalls_a_shift_in_progress(turn_mill: MachineConfig) -> None:
    bench = GearBench(turn_mill)
    bench.actuators(2)
    bench.run(150, TURNING)
    bench.actuators(2, 3)
    bench.run(3 * SHIFT_CYCLES, TURNING)
    assert bench.sensors() == NEUTRAL  # stalled in neutral
    bench.actuators(2)
    bench.run(50, TURNING)
    assert bench.sensors() == IN_STAGE_2  # and carries on where it stalled: 150 + 50


def test_actuator_released_before_the_stage_meshes_leaves_the_gearbox_in_neutral(
        turn_mill: MachineConfig) -> None:
    bench = GearBench(turn_mill)
    bench.actuators(3)
    bench.run(SHIFT_CYCLES - 1, TURNING)
    bench.actuators()
    bench.run(3 * SHIFT_CYCLES, TURNING)
    assert bench.sensors() == NEUTRAL
    assert bench.plant.gear_stages() == {"SP1": 0}
    bench.actuators(3)
    bench.run(SHIFT_CYCLES - 1, TURNING)
    assert bench.sensors() == NEUTRAL  # the turning before the release does not count
    bench.run(1, TURNING)
    assert bench.sensors() == IN_STAGE_3


def test_without_an_actuator_or_with_the_engaged_stage_s_actuator_the_stage_stays(
        turn_mill: MachineConfig) -> None:
    bench = GearBench(turn_mill)
    bench.run(3 * SHIFT_CYCLES, TURNING)
    assert bench.sensors() == IN_STAGE_1
    bench.actuators(1)
    bench.run(3 * SHIFT_CYCLES, TURNING)
    assert bench.sensors() == IN_STAGE_1


def test_another_stage_commanded_during_a_shift_starts_meshing_anew(turn_mill: MachineConfig) -> None:
    bench = GearBench(turn_mill)
    bench.actuators(2)
    bench.run(150, TURNING)
    bench.actuators(3)
    bench.run(SHIFT_CYCLES - 1, TURNING)
    assert bench.sensors() == NEUTRAL
    bench.run(1, TURNING)
    assert bench.sensors() == IN_STAGE_3


# ------------------------------------------------------------------------------ wiring


def test_the_plant_writes_only_the_sensors_that_are_wired(turn_mill: MachineConfig) -> None:
    entries = {str(point.address): point.name for point in turn_mill.plant_io.points
               if point.name not in ("SP1.gearNeutral", "SP1.gearEngaged3")}
    config = dataclasses.replace(turn_mill, plant_io=PlantIoMap.from_mapping(entries, turn_mill.layout.axes))
    bench = GearBench(config)
    i9 = bench.io.areas["I"]
    i9[9] |= 0b1100  # whatever else drives I9.2 and I9.3 (not the plant)
    bench.actuators(3)
    bench.run(SHIFT_CYCLES, TURNING)
    assert bench.plant.gear_stages() == {"SP1": 3}
    gear_bits = 0b1111  # I9.4..I9.7 are the chucks'
    assert i9[9] & gear_bits == 0b1100  # gearEngaged1 and 2 are 0; the unwired points kept what they had
    bench.actuators(1)
    bench.run(SHIFT_CYCLES, TURNING)
    assert i9[9] & gear_bits == 0b1101


def test_a_machine_without_a_gearbox_has_no_gear_sensors() -> None:
    config = load_machine(str(ROOT / "scenarios" / "machines" / "mill_5axis.yaml"))
    motors = [Motor(axis.sim.start_position) for axis in config.axes]
    plant = Plant(config, IPO_US, motors)
    io = ProcessImage(config.plant_io.area_sizes())
    plant.power_on(io)
    assert plant.gear_stages() == {}


# ------------------------------------------------------------------------------ in the simulation


def _sensors(sim: Simulation) -> tuple[int, ...]:
    names = ("SP1.gearEngaged1", "SP1.gearEngaged2", "SP1.gearEngaged3", "SP1.gearNeutral")
    return tuple(int(sim.read(sim.plant_io.resolve(name))) for name in names)


def test_a_gear_change_in_the_simulation_with_the_test_as_plc(turn_mill: MachineConfig) -> None:
    # No PLC: the servo of SP1 is off, so a hand on the chuck can turn it (the NC core does not
    # oscillate spindles yet); the test switches the actuators as the PLC would.
    sim = Simulation(turn_mill, plc=None)
    assert _sensors(sim) == IN_STAGE_1
    sim.write(sim.plant_io.resolve("SP1.gearShift2"), 1)
    sim.step(50)
    assert _sensors(sim) == NEUTRAL  # tooth on tooth: the spindle stands
    sim.move_by_hand("SP1", 10.0)  # rev/min
    sim.step(SHIFT_CYCLES // 2)
    assert _sensors(sim) == NEUTRAL
    sim.step(SHIFT_CYCLES // 2 + 5)  # + the cycles the slide needs to start turning
    assert _sensors(sim) == IN_STAGE_2
    sim.move_by_hand("SP1", 0.0)
    sim.write(sim.plant_io.resolve("SP1.gearShift2"), 0)
    sim.step(10)
    # a power cycle keeps the stage: the gearbox does not move while the machine is off
    sim.power_cycle()
    assert _sensors(sim) == IN_STAGE_2


def test_a_shift_the_power_cut_short_ends_in_neutral(turn_mill: MachineConfig) -> None:
    sim = Simulation(turn_mill, plc=None)
    sim.write(sim.plant_io.resolve("SP1.gearShift3"), 1)
    sim.move_by_hand("SP1", 10.0)
    sim.step(SHIFT_CYCLES // 2)
    sim.power_cycle()  # the actuator drops with the PLC's outputs
    assert _sensors(sim) == NEUTRAL
    sim.step(2 * SHIFT_CYCLES)
    assert _sensors(sim) == NEUTRAL
