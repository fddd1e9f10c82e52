"""``vc bench``: how fast the lockstep simulation runs on this machine.

Workload: the machine with the built-in PLC ``basic_machine``; the operator selects MDA
and presses NC start on the panel; the program moves the first two geometry axes back and
forth (G1 and G0 blocks with exact stop) over and over, while the other axes and spindles
stand.  Figures: the real-time factor (simulated seconds per wall-clock second) and the
cost of one IPO cycle in microseconds, for the whole loop (NC + plant + PLC).
"""

from __future__ import annotations

import time
from dataclasses import dataclass

from vc.config.loader import load_machine
from vc.config.model import MachineConfig
from vc.harness.simulation import Simulation
from vc.located_yaml import LocatedMap, load_text

_PROGRAM = """; benchmark: back and forth on two axes
G90 G1 F6000
{a}=40 {b}=-30
{a}=0 {b}=0
G0 {a}=25
G1 {a}=10 {b}=-10 F3000
G0 {a}=0 {b}=0
M30
"""


@dataclass(frozen=True, slots=True)
class BenchmarkResult:
    machine: str
    ipo_cycle_us: int
    simulated_s: float
    wall_s: float
    cycles: int

    @property
    def realtime_factor(self) -> float:
        return self.simulated_s / self.wall_s

    @property
    def us_per_cycle(self) -> float:
        return self.wall_s / self.cycles * 1e6


def _overrides(channel: str) -> LocatedMap:
    """The program starts without referencing: NC start lock off for the benchmark."""
    document, _ = load_text(f"{channel}: {{MD20700: 0}}", "<benchmark>")
    assert isinstance(document, LocatedMap)
    return document


def benchmark_machine(machine_path: str) -> MachineConfig:
    """The machine of the workload: NC start lock off, the program starts without referencing."""
    first_channel = load_machine(machine_path).channels[0]
    return load_machine(machine_path, _overrides(first_channel.name), "<benchmark>")


class Workload:
    """The operator of the benchmark: MDA, the program loaded, NC start again whenever it ended."""

    def __init__(self, simulation: Simulation):
        self.simulation = simulation
        channel = simulation.machine.channels[0]
        axes = [name for name in channel.geometry_names if channel.axis_for_program_name(name)][:2]
        simulation.load_mda(channel.name, _PROGRAM.format(a=axes[0], b=axes[1]))
        _press(simulation, "MCP.mda")
        self._start_key = simulation.plant_io.resolve("MCP.ncStart")
        self._state_reset = simulation.catalog.resolve(f"{channel.name}.basic.in.stateReset")

    def run(self, cycles: int) -> int:
        """At least ``cycles`` IPO cycles of the workload; returns how many ran."""
        simulation = self.simulation
        start_cycle = simulation.cycle
        while simulation.cycle - start_cycle < cycles:
            if simulation.read(self._state_reset):
                simulation.write(self._start_key, 1)
                simulation.step(20)
                simulation.write(self._start_key, 0)
            simulation.step(100)
        return simulation.cycle - start_cycle


def run_benchmark(machine_path: str, simulated_seconds: float = 20.0) -> BenchmarkResult:
    machine = benchmark_machine(machine_path)
    simulation = Simulation(machine, "basic_machine")
    workload = Workload(simulation)
    cycles = round(simulated_seconds * 1_000_000 / simulation.ipo_cycle_us)
    started = time.perf_counter()
    done = workload.run(cycles)
    wall = time.perf_counter() - started
    return BenchmarkResult(machine.name, simulation.ipo_cycle_us, done * simulation.ipo_cycle_us / 1e6, wall, done)


def _press(simulation: Simulation, key: str) -> None:
    """The operator presses a panel key for 40 ms."""
    ref = simulation.plant_io.resolve(key)
    simulation.write(ref, 1)
    simulation.step(20)
    simulation.write(ref, 0)
    simulation.step(20)
