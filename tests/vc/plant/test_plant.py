"""The plant: switches on the slides and the drive line-up, as the PLC's inputs see them.

Turn-mill X1: reference cam 280 .. 295, hardware limit switches at -12 / 312 (normally closed);
mill Z1: cam -25 .. -10, limits -512 / 12.  Drives.ready follows Drives.on after 100 ms.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import pytest

from interfaces.image import ProcessImage
from vc.config.loader import load_machine
from vc.config.model import MachineConfig
from vc.plant.plant import DRIVE_READY_DELAY_S, Plant

ROOT = Path(__file__).resolve().parents[3]
IPO_US = 2000


@dataclass
class Slide:
    physical: float
    velocity: float = 0.0


@pytest.fixture(scope="module")
def turn_mill() -> MachineConfig:
    return load_machine(str(ROOT / "scenarios" / "machines" / "turn_mill.yaml"))


@pytest.fixture(scope="module")
def mill() -> MachineConfig:
    return load_machine(str(ROOT / "scenarios" / "machines" / "mill_3axis.yaml"))


class Bench:
    """A plant with hand-positioned slides and its I/O image."""

    def __init__(self, config: MachineConfig):
        self.config = config
        self.slides = {axis.name: Slide(axis.sim.start_position) for axis in config.axes}
        self.plant = Plant(config, IPO_US, [self.slides[axis.name] for axis in config.axes])
        self.io = ProcessImage(config.plant_io.area_sizes())
        self.plant.power_on(self.io)

    def move(self, axis: str, position: float) -> None:
        self.slides[axis].physical = position
        self.plant.step(self.io)

    def read(self, name: str) -> int:
        return int(self.io.read(self.config.plant_io.resolve(name)))

    def write(self, name: str, value: int) -> None:
        self.io.write(self.config.plant_io.resolve(name), value)


# ------------------------------------------------------------------------------ power-on


def test_power_on_sets_switches_for_the_start_positions_and_the_panel(turn_mill: MachineConfig) -> None:
    bench = Bench(turn_mill)
    # X1 at 150: off the cam, both limit switches free (normally closed: 1)
    assert (bench.read("X1.refCam"), bench.read("X1.hwLimitMinus"), bench.read("X1.hwLimitPlus")) == (0, 1, 1)
    assert (bench.read("Y1.refCam"), bench.read("Y1.hwLimitMinus"), bench.read("Y1.hwLimitPlus")) == (0, 1, 1)
    # e-stop released (normally closed chain: 1), override switches at 100 %
    assert bench.read("EStop.chainOk") == 1
    assert bench.read("MCP.feedOverride") == 100
    assert bench.read("MCP.rapidOverride") == 100
    assert bench.read("MCP.spindleOverride") == 100
    # the operator's keys are not pressed
    assert bench.read("MCP.plus.X1") == 0 and bench.read("MCP.ncStart") == 0


def test_slide_starting_on_its_cam_reads_the_cam_at_power_on(turn_mill: MachineConfig) -> None:
    config = turn_mill
    bench = Bench(config)
    bench.slides["X1"].physical = 290.0
    bench.plant.power_on(bench.io)
    assert bench.read("X1.refCam") == 1


# ------------------------------------------------------------------------------ reference cam


@pytest.mark.parametrize(("position", "cam"), [
    (279.999, 0), (280.0, 1), (287.5, 1), (295.0, 1), (295.001, 0), (150.0, 0), (300.0, 0)])
def test_reference_cam_is_1_while_the_slide_stands_on_it(turn_mill: MachineConfig, position: float,
                                                         cam: int) -> None:
    bench = Bench(turn_mill)
    bench.move("X1", position)
    assert bench.read("X1.refCam") == cam


def test_cam_follows_the_slide_across_both_edges_in_both_directions(turn_mill: MachineConfig) -> None:
    bench = Bench(turn_mill)
    seen = []
    for position in [270.0 + 0.5 * k for k in range(61)] + [300.0 - 0.5 * k for k in range(61)]:
        bench.move("X1", position)
        seen.append(bench.read("X1.refCam"))
    # 270 .. 300 and back: on the cam for 280 .. 295 (31 samples each way)
    assert seen.count(1) == 62
    assert seen[:20] == [0] * 20 and seen[20:51] == [1] * 31 and seen[51:61] == [0] * 10


def test_cam_of_a_negative_range_on_the_mill(mill: MachineConfig) -> None:
    bench = Bench(mill)
    bench.move("Z1", -17.0)
    assert bench.read("Z1.refCam") == 1
    bench.move("Z1", -26.0)
    assert bench.read("Z1.refCam") == 0


# ------------------------------------------------------------------------------ hardware limit switches


@pytest.mark.parametrize(("position", "minus", "plus"), [
    (150.0, 1, 1), (311.999, 1, 1), (312.0, 1, 0), (315.0, 1, 0),
    (-11.999, 1, 1), (-12.0, 0, 1), (-20.0, 0, 1)])
def test_limit_switches_are_normally_closed_and_open_when_actuated(turn_mill: MachineConfig, position: float,
                                                                   minus: int, plus: int) -> None:
    bench = Bench(turn_mill)
    bench.move("X1", position)
    assert (bench.read("X1.hwLimitMinus"), bench.read("X1.hwLimitPlus")) == (minus, plus)


def test_limit_switch_closes_again_when_the_slide_leaves_it(turn_mill: MachineConfig) -> None:
    bench = Bench(turn_mill)
    bench.move("X1", 313.0)
    assert bench.read("X1.hwLimitPlus") == 0
    bench.move("X1", 311.0)
    assert bench.read("X1.hwLimitPlus") == 1


def test_each_axis_drives_only_its_own_switches(turn_mill: MachineConfig) -> None:
    bench = Bench(turn_mill)
    bench.move("Z1", 620.0)  # Z1 on its plus limit switch (615)
    assert bench.read("Z1.hwLimitPlus") == 0
    assert bench.read("X1.hwLimitPlus") == 1 and bench.read("Y1.hwLimitPlus") == 1


# ------------------------------------------------------------------------------ drive line-up


def test_drives_ready_follows_drives_on_after_100_ms(turn_mill: MachineConfig) -> None:
    bench = Bench(turn_mill)
    assert bench.read("Drives.ready") == 0  # the PLC has not switched the infeed on yet
    bench.write("Drives.on", 1)
    delay = round(DRIVE_READY_DELAY_S * 1_000_000 / IPO_US)
    assert delay == 50  # 100 ms / 2 ms
    for _ in range(delay - 1):
        bench.plant.step(bench.io)
        assert bench.read("Drives.ready") == 0
    bench.plant.step(bench.io)
    assert bench.read("Drives.ready") == 1


def test_drives_ready_drops_when_drives_on_is_removed(turn_mill: MachineConfig) -> None:
    bench = Bench(turn_mill)
    bench.write("Drives.on", 1)
    for _ in range(60):
        bench.plant.step(bench.io)
    bench.write("Drives.on", 0)
    bench.plant.step(bench.io)
    assert bench.read("Drives.ready") == 0
    # switching on again takes the full 100 ms once more
    bench.write("Drives.on", 1)
    for _ in range(49):
        bench.plant.step(bench.io)
    assert bench.read("Drives.ready") == 0
    bench.plant.step(bench.io)
    assert bench.read("Drives.ready") == 1


def test_a_short_drives_on_pulse_does_not_make_the_drives_ready(turn_mill: MachineConfig) -> None:
    bench = Bench(turn_mill)
    bench.write("Drives.on", 1)
    for _ in range(30):
        bench.plant.step(bench.io)
    bench.write("Drives.on", 0)
    for _ in range(30):
        bench.plant.step(bench.io)
    bench.write("Drives.on", 1)
    for _ in range(30):
        bench.plant.step(bench.io)
    assert bench.read("Drives.ready") == 0  # 30 + 30 cycles on, but never 50 in a row
