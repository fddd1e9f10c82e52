"""``vc bench``: how fast the lockstep simulation runs on this machine.

Two workloads, each on a fresh simulation of the machine with a built-in PLC program; the
operator selects MDA and presses NC start on the panel, and again whenever the program ended:

* light (since the first version, unchanged so that its figures stay comparable): PLC
  ``basic_machine``, the first two geometry axes back and forth while the other axes and
  spindles stand;
* heavy: PLC ``spindle`` (its gear-stage report lets the NC turn a spindle with a gearbox;
  ``basic_machine`` reports no gear stage, so the NC waits for a gear change that never comes
  and the program stands in its first spindle block until alarm 65830), every axis and spindle
  moving, on turn_mill SP2 coupled to SP1.

The loads are in vc/bench/workloads.py.  Figures: the real-time factor (simulated
seconds per wall-clock second) and the cost of one IPO cycle in microseconds, for the whole
loop (NC + plant + PLC).  Every 100 IPO cycles the operator looks at the velocities and the
coupling: a run whose motion differs from its load's (an axis that should move stood, one
that should stand moved, the pair never coupled) or that raised an alarm fails instead of
giving a figure.
"""

from __future__ import annotations

import time
from collections.abc import Sequence
from dataclasses import dataclass, replace

from interfaces.errors import VcError
from vc.bench.workloads import Load, MotionPlan, motion_plan
from vc.config import md_dictionary as MD
from vc.config.loader import load_machine
from vc.config.model import MachineConfig
from vc.located_yaml import LocatedMap, load_text
from vc.simulation.lockstep import Simulation

LIGHT_PLC = "basic_machine"
HEAVY_PLC = "spindle"
MASTER_SPINDLE_PARAMETER = "master_spindle"  # of the PLC program spindle
OBSERVE_EVERY = 100  # IPO cycles between two looks at the motion
SETUP_TIMEOUT_S = 30.0  # simulated: the untimed setup program and first run must end within this


class BenchmarkError(VcError):
    """The workload did not do what it stands for: no figure."""


@dataclass(frozen=True, slots=True)
class BenchmarkResult:
    machine: str
    plan: MotionPlan
    plc: str
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


def benchmark_machine(machine_path: str, plc: str = LIGHT_PLC) -> MachineConfig:
    """The machine of the workload: NC start lock off, the program starts without referencing.

    The PLC program ``spindle`` gives the panel's spindle keys to the first spindle with a
    gearbox; on a machine without one it needs ``master_spindle`` in the machine file's ``plc:``
    section, and where that is missing the benchmark names the channel's master spindle
    (MD20090), on which the keys act in the NC as well."""
    first_channel = load_machine(machine_path).channels[0]
    machine = load_machine(machine_path, _overrides(first_channel.name), "<benchmark>")
    if plc != HEAVY_PLC or MASTER_SPINDLE_PARAMETER in machine.plc_parameters:
        return machine
    number = first_channel.md.int(MD.SPIND_DEF_MASTER_SPIND)
    master = next((axis.name for axis in machine.axes if axis.spindle_number == number), None)
    if master is None:
        return machine
    return replace(machine, plc_parameters={**machine.plc_parameters, MASTER_SPINDLE_PARAMETER: master})


class Workload:
    """The operator of the benchmark: MDA, the program loaded, NC start again whenever it ended;
    and the witness of what moved."""

    def __init__(self, simulation: Simulation, load: Load = Load.TWO_AXES):
        self.simulation = simulation
        self.plan = plan = motion_plan(simulation.machine, load)
        self._start_key = simulation.plant_io.resolve("MCP.ncStart")
        self._state_reset = simulation.catalog.resolve(f"{plan.channel}.basic.in.stateReset")
        self._following = None if plan.pair is None else simulation.catalog.resolve(
            f"{plan.pair.following}.coupling.in.followingSpindleActive")
        self._alarms_before = len(simulation.alarm_history())
        if plan.setup:
            simulation.load_mda(plan.channel, plan.setup)
            _press(simulation, "MCP.mda")
            self._run_to_end("setup program", plan.setup)
            simulation.load_mda(plan.channel, plan.program)
            self._run_to_end("first run of the program", plan.program)
        else:
            if plan.program:
                simulation.load_mda(plan.channel, plan.program)
            _press(simulation, "MCP.mda")
        self._standing = list(plan.axes)
        self.moved: set[str] = set()  # the axes seen with a velocity
        self.coupled = False  # the following spindle of the plan's pair seen coupled

    def _run_to_end(self, what: str, program: str) -> None:
        """Untimed: NC start, and the loaded program runs until the channel is in reset again."""
        simulation = self.simulation
        _press(simulation, "MCP.ncStart")
        deadline = simulation.cycle + round(SETUP_TIMEOUT_S / simulation.ipo_cycle_s)
        while not simulation.read(self._state_reset):
            if simulation.cycle >= deadline:
                alarms = "".join(f"\nalarm {alarm}" for alarm in simulation.alarms())
                raise BenchmarkError(f"the {what} did not end within {SETUP_TIMEOUT_S:g} s:\n{program}{alarms}")
            simulation.step(10)

    def run(self, cycles: int) -> int:
        """At least ``cycles`` IPO cycles of the workload; returns how many ran."""
        simulation = self.simulation
        start_cycle = simulation.cycle
        restart = bool(self.plan.program)
        while simulation.cycle - start_cycle < cycles:
            if restart and simulation.read(self._state_reset):
                simulation.write(self._start_key, 1)
                simulation.step(20)
                simulation.write(self._start_key, 0)
            simulation.step(OBSERVE_EVERY)
            self._observe()
        return simulation.cycle - start_cycle

    def _observe(self) -> None:
        simulation = self.simulation
        for axis in self._standing:
            if simulation.axis_quantity(axis, "velocity") != 0.0:
                self.moved.add(axis)
        if self.moved:
            self._standing = [axis for axis in self._standing if axis not in self.moved]
        if self._following is not None and not self.coupled:
            self.coupled = bool(simulation.read(self._following))

    def problems(self) -> list[str]:
        """What differed from the plan: motion, coupling, alarms.  Empty: the figure stands."""
        plan = self.plan
        found = []
        still = [axis for axis in plan.moving if axis not in self.moved]
        if still:
            found.append(f"{', '.join(still)} never moved")
        extra = sorted(self.moved - set(plan.moving))
        if extra:
            found.append(f"{', '.join(extra)} moved, though {plan.load} moves only "
                         f"{', '.join(plan.moving) or 'nothing'}")
        if plan.pair is not None and not self.coupled:
            found.append(f"{plan.pair.following} was never coupled to {plan.pair.leading}"
                         f" ({plan.pair.following}.coupling.in.followingSpindleActive stayed 0)")
        found += [f"alarm {alarm}" for alarm in self.simulation.alarm_history()[self._alarms_before:]]
        return found


def run_benchmark(machine_path: str, simulated_seconds: float = 20.0, load: Load = Load.TWO_AXES,
                  plc: str = LIGHT_PLC) -> BenchmarkResult:
    """One workload, timed; BenchmarkError if its motion was not its load's."""
    machine = benchmark_machine(machine_path, plc)
    simulation = Simulation(machine, plc)
    workload = Workload(simulation, load)
    cycles = round(simulated_seconds * 1_000_000 / simulation.ipo_cycle_us)
    started = time.perf_counter()
    done = workload.run(cycles)
    wall = time.perf_counter() - started
    _check(machine.name, workload.plan, plc, workload.problems())
    return BenchmarkResult(machine.name, workload.plan, plc, simulation.ipo_cycle_us,
                           done * simulation.ipo_cycle_us / 1e6, wall, done)


def run_light_and_heavy(machine_path: str, simulated_seconds: float) -> tuple[BenchmarkResult, BenchmarkResult]:
    """The two workloads of ``vc bench``, one after the other."""
    return (run_benchmark(machine_path, simulated_seconds, Load.TWO_AXES, LIGHT_PLC),
            run_benchmark(machine_path, simulated_seconds, Load.EVERYTHING, HEAVY_PLC))


def _check(machine: str, plan: MotionPlan, plc: str, problems: Sequence[str]) -> None:
    if problems:
        raise BenchmarkError(f"workload {plan.describe()} on {machine} with PLC {plc}: " + "; ".join(problems))


def _press(simulation: Simulation, key: str) -> None:
    """The operator presses a panel key for 40 ms."""
    ref = simulation.plant_io.resolve(key)
    simulation.write(ref, 1)
    simulation.step(20)
    simulation.write(ref, 0)
    simulation.step(20)
