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


def run_benchmark(machine_path: str, simulated_seconds: float = 20.0) -> BenchmarkResult:
    first_channel = load_machine(machine_path).channels[0]
    machine = load_machine(machine_path, _overrides(first_channel.name), "<benchmark>")
    channel = machine.channels[0]
    axes = [name for name in channel.geometry_names if channel.axis_for_program_name(name)][:2]
    simulation = Simulation(machine, "basic_machine")
    simulation.load_mda(channel.name, _PROGRAM.format(a=axes[0], b=axes[1]))
    _press(simulation, "MCP.mda")
    cycles = round(simulated_seconds * 1_000_000 / simulation.ipo_cycle_us)
    start_cycle = simulation.cycle
    started = time.perf_counter()
    start_key = simulation.plant_io.resolve("MCP.ncStart")
    state_reset = simulation.catalog.resolve(f"{channel.name}.basic.in.stateReset")
    while simulation.cycle - start_cycle < cycles:
        if simulation.read(state_reset):
            simulation.write(start_key, 1)
            simulation.step(20)
            simulation.write(start_key, 0)
        simulation.step(100)
    wall = time.perf_counter() - started
    done = simulation.cycle - start_cycle
    return BenchmarkResult(machine.name, simulation.ipo_cycle_us, done * simulation.ipo_cycle_us / 1e6, wall, done)


def _press(simulation: Simulation, key: str) -> None:
    """The operator presses a panel key for 40 ms."""
    ref = simulation.plant_io.resolve(key)
    simulation.write(ref, 1)
    simulation.step(20)
    simulation.write(ref, 0)
    simulation.step(20)
