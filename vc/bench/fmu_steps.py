"""``vc bench --link fmu``: the machine's FMU under FMPy, step for step against the same unit in process.

The FMU of ``vc fmu export`` is :class:`fmu.unit.NcUnit` behind FMI 2.0.  FMPy's low-level API
loads the FMU's binary into this process.  The self-contained FMU (the default) runs the unit in
a worker process of its own Python runtime and the binary talks to it over a socket pair; the
lean FMU (``python=PythonRuntime.HOST``) calls back into this interpreter through pythonfmu.  The
benchmark drives the FMU and a bare ``NcUnit`` (no FMI in between) with the same workload through
the same timed loops, so the ratio of their rates is what FMI costs: FMPy's ctypes arrays, the
binary, and the round trip to the worker (or pythonfmu's C++ layer and its Python slave).  It
also measures the start-up of an instance (``fmi2Instantiate``: for the self-contained FMU the
worker's interpreter starting and loading the machine) and states the FMU's size and glibc floor.

Workload, at the communication step of a PLC master (the machine's PLC cycle: 10 ms = 5 IPO
cycles on the turn-mill).  No PLC runs, so the host writes what basic_machine's networks 1 to 4
would (drives on, measuring system 1, controller and pulse enable, 100 % overrides,
JOG mode) and jogs the machine's first linear axis with its traverse keys, reversing every
:data:`STROKE_S`; the other axes and spindles stand in position control.  Two ways:

* step: ``doStep`` only; the traverse keys are written when they change.  The host never
  writes ``PLC.signOfLife``, so the NC does not watch for a PLC;
* exchange: each step as a PLC master makes it: every input written (one ``setBoolean``, one
  ``setInteger``), every output read (one ``getBoolean``, ``getInteger``, ``getReal``), then
  ``doStep``.  ``PLC.signOfLife`` counts up every step, as a PLC's does every scan: each write
  changes a value, and the NC watches the host as its PLC (alarm 2000 would stop the axis).

In the middle of every stroke the jogged axis's velocity is read from its output; the lowest
of these readings shows that the NC moved the axis throughout.
"""

from __future__ import annotations

import contextlib
import math
import sys
import tempfile
import time
from collections.abc import Callable, Iterator, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from fmu.export import ExportResult, PythonRuntime, export_fmu
from fmu.unit import PLC_SIGN_OF_LIFE, Causality, Kind, NcUnit
from interfaces.errors import VcError
from vc.config.loader import load_machine
from vc.config.model import MachineConfig
from vc.simulation.lockstep import Simulation

STROKE_S = 2.0  # the traverse keys reverse after this long: 67 mm at the turn-mill's JOG velocity of 2000 mm/min
SETTLE_S = 0.1  # untimed, after power-on: the drives enable and the position control closes
SIGN_OF_LIFE_MODULUS = 0x10000  # the sign of life wraps like a PLC's 16-bit scan counter
MODE_GROUP = "MODEGROUP"
DRIVES_ON = "Drives.on"  # the plant's infeed contactor, where the machine has one


class FmuBenchmarkError(VcError):
    """The benchmark cannot run here; the message says why and what to do."""


@dataclass(frozen=True, slots=True)
class Port:
    """A variable of the unit as a host addresses it: by value reference, per FMI type."""

    name: str
    kind: Kind
    causality: Causality
    reference: int


@dataclass(frozen=True, slots=True)
class Host:
    """The calls of one way to drive the unit; the timed loops see nothing else.

    For the FMU these are FMPy's bound methods themselves, so the loops add no layer of their own.
    """

    set_booleans: Callable[[list[int], list[bool]], None]
    set_integers: Callable[[list[int], list[int]], None]
    set_reals: Callable[[list[int], list[float]], None]
    get_booleans: Callable[[list[int]], Sequence[object]]
    get_integers: Callable[[list[int]], Sequence[object]]
    get_reals: Callable[[list[int]], Sequence[float]]
    do_step: Callable[[float, float], object]


def communication_step_s(machine: MachineConfig) -> float:
    """The PLC cycle: how often a PLC master exchanges with the NC (``NcUnit.plc_cycle_s``)."""
    return machine.plc_cycle_ipo * Simulation.ipo_seconds(machine)


# ---------------------------------------------------------------------------------- figures


@dataclass(frozen=True, slots=True)
class WorkloadFigures:
    """One workload on one host: ``steps`` communication steps of ``step_s`` in ``wall_s``."""

    steps: int
    step_s: float
    wall_s: float
    jog_velocity: float  # mm/min: the lowest reading of the jogged axis's velocity in the middle of a stroke

    @property
    def steps_per_s(self) -> float:
        return self.steps / self.wall_s

    @property
    def us_per_step(self) -> float:
        return self.wall_s / self.steps * 1e6

    @property
    def realtime_factor(self) -> float:
        """Simulated seconds per wall-clock second."""
        return self.steps * self.step_s / self.wall_s

    def line(self, host: str) -> str:
        return (f"  {host:<11} {self.steps_per_s:8.0f} steps/s, {self.us_per_step:7.1f} us per step,"
                f" {self.realtime_factor:6.1f}x real time; jog velocity {self.jog_velocity:.0f} mm/min")


def rate_ratio(fmu: WorkloadFigures, inprocess: WorkloadFigures) -> float:
    """FMU steps per second / in-process steps per second: below 1 by what FMI costs."""
    return fmu.steps_per_s / inprocess.steps_per_s


@dataclass(frozen=True, slots=True)
class ExchangeSize:
    """How many variables each batch call of the exchange carries."""

    set_booleans: int
    set_integers: int
    set_reals: int
    get_booleans: int
    get_integers: int
    get_reals: int

    def text(self) -> str:
        return (f"setBoolean {self.set_booleans}, setInteger {self.set_integers}, setReal {self.set_reals},"
                f" getBoolean {self.get_booleans},"
                f" getInteger {self.get_integers}, getReal {self.get_reals}")


@dataclass(frozen=True, slots=True)
class FmuBenchmarkResult:
    machine: str
    jog_axis: str
    export_s: float
    instantiate_s: float  # the first fmi2Instantiate of the benchmark
    fmu_bytes: int
    glibc: tuple[int, ...]
    ipo_cycles_per_step: int
    exchange_size: ExchangeSize
    fmu_step: WorkloadFigures
    inprocess_step: WorkloadFigures
    fmu_exchange: WorkloadFigures
    inprocess_exchange: WorkloadFigures

    @property
    def ratio(self) -> float:
        """FMU / in process, ``doStep`` only."""
        return rate_ratio(self.fmu_step, self.inprocess_step)

    @property
    def exchange_ratio(self) -> float:
        """FMU / in process, with the full exchange in every step."""
        return rate_ratio(self.fmu_exchange, self.inprocess_exchange)

    @property
    def jog_velocity(self) -> float:
        """The lowest of the workloads' jog velocities: each of them moved the axis at least this fast."""
        workloads = (self.fmu_step, self.inprocess_step, self.fmu_exchange, self.inprocess_exchange)
        return min(workload.jog_velocity for workload in workloads)

    def figures(self) -> dict[str, float | int]:
        """The figures as ``vc bench --link fmu`` prints them in its JSON line."""
        workloads = {"fmu": self.fmu_step, "inprocess": self.inprocess_step,
                     "fmu_exchange": self.fmu_exchange, "inprocess_exchange": self.inprocess_exchange}
        figures: dict[str, float | int] = {f"{name}_steps_per_s": round(workload.steps_per_s, 1)
                                           for name, workload in workloads.items()}
        figures["ratio"] = round(self.ratio, 3)
        figures["exchange_ratio"] = round(self.exchange_ratio, 3)
        figures.update({f"{name}_us_per_step": round(workload.us_per_step, 2) for name, workload in workloads.items()})
        figures.update({f"{name}_realtime_factor": round(workload.realtime_factor, 1)
                        for name, workload in workloads.items()})
        figures.update({
            "export_s": round(self.export_s, 3),
            "step_ms": round(self.fmu_step.step_s * 1000, 3),
            "ipo_cycles_per_step": self.ipo_cycles_per_step,
            "steps": self.fmu_step.steps,
            "jog_velocity": round(self.jog_velocity, 1),
            "instantiate_ms": round(self.instantiate_s * 1000, 1),
            "fmu_mb": round(self.fmu_bytes / 1e6, 2),
            "glibc": float(".".join(map(str, self.glibc[:2]))),
        })
        return figures


# ---------------------------------------------------------------------------------- the host in place of the PLC


class JogDriver:
    """What the host writes in place of the PLC, and which outputs it reads.

    The inputs are one value vector per FMI type, in the order of their value references: a
    PLC's output image, all zero after a restart except what basic_machine would set.  The
    exchange writes the whole vectors, as a PLC master writes its whole output image; the
    power-up writes only the enables and overrides.  Steps are counted from the first timed
    step, which comes after :attr:`settle_steps`.
    """

    def __init__(self, ports: Sequence[Port], machine: MachineConfig):
        def references(causality: Causality, kind: Kind) -> list[int]:
            return [port.reference for port in ports if port.causality is causality and port.kind is kind]

        by_name = {port.name: port.reference for port in ports}
        self.step_s = communication_step_s(machine)
        self.settle_steps = round(SETTLE_S / self.step_s)
        self.steps_per_stroke = max(1, round(STROKE_S / self.step_s))
        self.jog_axis = next(axis.name for axis in machine.axes if not axis.is_rotary)
        self.boolean_inputs = references(Causality.INPUT, Kind.BOOLEAN)
        self.integer_inputs = references(Causality.INPUT, Kind.INTEGER)
        self.real_inputs = references(Causality.INPUT, Kind.REAL)  # FC18's Pos and FRate of every axis
        self.boolean_outputs = references(Causality.OUTPUT, Kind.BOOLEAN)
        self.integer_outputs = references(Causality.OUTPUT, Kind.INTEGER)
        self.real_outputs = references(Causality.OUTPUT, Kind.REAL)
        self.boolean_values = [False] * len(self.boolean_inputs)
        self.integer_values = [0] * len(self.integer_inputs)
        self.real_values = [0.0] * len(self.real_inputs)
        boolean_slot = {reference: slot for slot, reference in enumerate(self.boolean_inputs)}
        integer_slot = {reference: slot for slot, reference in enumerate(self.integer_inputs)}

        switched_on = [f"{MODE_GROUP}.basic.out.jogMode"]
        if DRIVES_ON in by_name:
            switched_on.append(DRIVES_ON)
        at_100_percent = []
        for channel in machine.channels:
            switched_on += [f"{channel.name}.basic.out.pathFeedrateOvr",
                            f"{channel.name}.basic.out.pathRapidTraversOvr"]
            at_100_percent += [f"{channel.name}.basic.out.pathFeedrateOvrFactor",
                               f"{channel.name}.basic.out.pathRapidTraversOvrFactor"]
        for axis in machine.axes:
            switched_on += [f"{axis.name}.basic.out.enc1Activation", f"{axis.name}.basic.out.enableCtrl",
                            f"{axis.name}.drive.out.enablePulses", f"{axis.name}.basic.out.enableOvr"]
            at_100_percent.append(f"{axis.name}.basic.out.feedrateOvrFactor")
        self.switched_on = [by_name[name] for name in switched_on]
        self.at_100_percent = [by_name[name] for name in at_100_percent]
        for reference in self.switched_on:
            self.boolean_values[boolean_slot[reference]] = True
        for reference in self.at_100_percent:
            self.integer_values[integer_slot[reference]] = 100

        self.key_references = [by_name[f"{self.jog_axis}.basic.out.traversKeyPlus"],
                               by_name[f"{self.jog_axis}.basic.out.traversKeyMinus"]]
        self._key_slots = [boolean_slot[reference] for reference in self.key_references]
        self._sign_of_life_slot = integer_slot[by_name[PLC_SIGN_OF_LIFE]]
        self.velocity_reference = by_name[f"{self.jog_axis}.velocity"]
        self.velocity_slot = self.real_outputs.index(self.velocity_reference)

    def time_at(self, step: int) -> float:
        """The communication point of a timed step."""
        return (self.settle_steps + step) * self.step_s

    def reverses(self, step: int) -> bool:
        """Whether the traverse keys change at this step."""
        return step % self.steps_per_stroke == 0

    def samples_velocity(self, step: int) -> bool:
        """Whether the axis's velocity is read at this step: in the middle of a stroke, at full speed."""
        return step % self.steps_per_stroke == self.steps_per_stroke // 2

    def keys(self, step: int) -> list[bool]:
        """Plus and minus key: plus in the first stroke, minus in the next, and so on."""
        plus = (step // self.steps_per_stroke) % 2 == 0
        return [plus, not plus]

    def prepare(self, step: int) -> None:
        """The value vectors for this step: the traverse keys, and the sign of life one up."""
        plus, minus = self.keys(step)
        self.boolean_values[self._key_slots[0]] = plus
        self.boolean_values[self._key_slots[1]] = minus
        self.integer_values[self._sign_of_life_slot] = (step + 1) % SIGN_OF_LIFE_MODULUS

    @property
    def exchange_size(self) -> ExchangeSize:
        return ExchangeSize(len(self.boolean_inputs), len(self.integer_inputs), len(self.real_inputs),
                            len(self.boolean_outputs), len(self.integer_outputs), len(self.real_outputs))


def power_up(host: Host, driver: JogDriver) -> None:
    """Write the enables and overrides and let the machine settle, untimed."""
    host.set_booleans(driver.switched_on, [True] * len(driver.switched_on))
    host.set_integers(driver.at_100_percent, [100] * len(driver.at_100_percent))
    for step in range(driver.settle_steps):
        host.do_step(step * driver.step_s, driver.step_s)


# ---------------------------------------------------------------------------------- the timed loops


def time_steps(host: Host, driver: JogDriver, steps: int) -> WorkloadFigures:
    """``doStep`` only; the keys written at each reversal, the velocity read in the middle of each stroke."""
    do_step, set_booleans, get_reals = host.do_step, host.set_booleans, host.get_reals
    keys, velocity, step_s = driver.key_references, [driver.velocity_reference], driver.step_s
    lowest = math.inf
    began = time.perf_counter()
    for step in range(steps):
        if driver.reverses(step):
            set_booleans(keys, driver.keys(step))
        if driver.samples_velocity(step):
            lowest = min(lowest, abs(get_reals(velocity)[0]))
        do_step(driver.time_at(step), step_s)
    wall = time.perf_counter() - began
    if lowest == math.inf:  # a run shorter than half a stroke: the velocity at its end
        lowest = abs(get_reals(velocity)[0])
    return WorkloadFigures(steps, step_s, wall, lowest)


def time_exchanges(host: Host, driver: JogDriver, steps: int) -> WorkloadFigures:
    """Each step: every input written, every output read, one batch per type, then ``doStep``."""
    do_step, step_s = host.do_step, driver.step_s
    set_booleans, set_integers, set_reals = host.set_booleans, host.set_integers, host.set_reals
    get_booleans, get_integers, get_reals = host.get_booleans, host.get_integers, host.get_reals
    boolean_inputs, integer_inputs, real_inputs = driver.boolean_inputs, driver.integer_inputs, driver.real_inputs
    boolean_values, integer_values = driver.boolean_values, driver.integer_values  # prepare() changes them in place
    real_values = driver.real_values
    boolean_outputs, integer_outputs, real_outputs = driver.boolean_outputs, driver.integer_outputs, driver.real_outputs
    velocity_slot = driver.velocity_slot
    lowest = math.inf
    began = time.perf_counter()
    for step in range(steps):
        driver.prepare(step)
        set_booleans(boolean_inputs, boolean_values)
        set_integers(integer_inputs, integer_values)
        set_reals(real_inputs, real_values)
        get_booleans(boolean_outputs)
        get_integers(integer_outputs)
        reals = get_reals(real_outputs)
        if driver.samples_velocity(step):
            lowest = min(lowest, abs(reals[velocity_slot]))
        do_step(driver.time_at(step), step_s)
    wall = time.perf_counter() - began
    if lowest == math.inf:  # a run shorter than half a stroke: the velocity at its end
        lowest = abs(get_reals(real_outputs)[velocity_slot])
    return WorkloadFigures(steps, step_s, wall, lowest)


Workload = Callable[[Host, JogDriver, int], WorkloadFigures]


# ---------------------------------------------------------------------------------- the two hosts


@dataclass(frozen=True, slots=True)
class _Fmpy:
    """The parts of FMPy's low-level API the benchmark uses (FMPy has no type hints)."""

    read_model_description: Callable[..., Any]
    extract: Callable[..., Any]
    slave_class: Callable[..., Any]


def _fmpy() -> _Fmpy:
    try:
        from fmpy import extract, read_model_description
        from fmpy.fmi2 import FMU2Slave
    except ImportError:
        raise FmuBenchmarkError("the FMU benchmark runs the FMU under FMPy, which is not installed:"
                                " install the test extra (pip install -e '.[test]')") from None
    return _Fmpy(read_model_description, extract, FMU2Slave)


class FmuUnderFmpy:
    """The exported FMU, extracted once, as FMPy's low-level API sees it: its ports and fresh instances.

    A context manager: at the end it takes back what a lean FMU's binary (pythonfmu) did to this
    process (the extracted ``resources`` folder on ``sys.path``, the slave and its bundled code
    imported from there), since the folder is about to be deleted.
    """

    def __init__(self, fmpy: _Fmpy, fmu_path: Path, unzip_dir: Path):
        self._slave_class = fmpy.slave_class
        self._description = fmpy.read_model_description(str(fmu_path))
        self._unzip_dir = Path(fmpy.extract(str(fmu_path), unzipdir=str(unzip_dir)))
        self.ports = [Port(variable.name, Kind(variable.type), Causality(variable.causality),
                           variable.valueReference)
                      for variable in self._description.modelVariables]
        self.instantiate_s: list[float] = []  # each fmi2Instantiate, in order

    @contextlib.contextmanager
    def instance(self, name: str) -> Iterator[Host]:
        """An instance initialised at t = 0, freed (and its library unloaded) afterwards."""
        description = self._description
        slave = self._slave_class(guid=description.guid, unzipDirectory=str(self._unzip_dir),
                                  modelIdentifier=description.coSimulation.modelIdentifier, instanceName=name)
        began = time.perf_counter()
        slave.instantiate()
        self.instantiate_s.append(time.perf_counter() - began)
        try:
            slave.setupExperiment(startTime=0.0)
            slave.enterInitializationMode()
            slave.exitInitializationMode()
            yield Host(slave.setBoolean, slave.setInteger, slave.setReal, slave.getBoolean, slave.getInteger,
                       slave.getReal, slave.doStep)
            slave.terminate()
        finally:
            slave.freeInstance()

    def __enter__(self) -> FmuUnderFmpy:
        return self

    def __exit__(self, *exception: object) -> None:
        extracted = str(self._unzip_dir)
        sys.path[:] = [entry for entry in sys.path if not entry.startswith(extracted)]
        # only the modules imported from this FMU's folder: another FMU's instances may share the
        # bundle's name (same code, same digest) and keep theirs
        for name, module in list(sys.modules.items()):
            if (getattr(module, "__file__", None) or "").startswith(extracted):
                del sys.modules[name]


def inprocess_ports(unit: NcUnit) -> list[Port]:
    """The unit's variables; the value reference of each is its index, as in the FMU."""
    return [Port(variable.name, variable.kind, variable.causality, index)
            for index, variable in enumerate(unit.variables)]


def inprocess_host(unit: NcUnit) -> Host:
    """The unit driven directly: a batch is a loop over ``unit.set`` / ``unit.get``, as in the slave."""
    set_value, get_value = unit.set, unit.get

    def set_each(references: list[int], values: Sequence[float | int | bool]) -> None:
        for reference, value in zip(references, values, strict=True):
            set_value(reference, value)

    def get_each(references: list[int]) -> list[float]:
        return [get_value(reference) for reference in references]

    return Host(set_each, set_each, set_each, get_each, get_each, get_each, unit.step)


def _on_fmu(fmu: FmuUnderFmpy, machine: MachineConfig, workload: Workload, steps: int) -> WorkloadFigures:
    """``workload`` on a fresh instance of the FMU, after the untimed power-up."""
    with fmu.instance(f"{machine.name}_bench") as host:
        driver = JogDriver(fmu.ports, machine)
        power_up(host, driver)
        return workload(host, driver, steps)


def _in_process(machine_path: str, machine: MachineConfig, workload: Workload, steps: int) -> WorkloadFigures:
    """``workload`` on a fresh unit, through the FMU's life cycle, after the untimed power-up."""
    unit = NcUnit(machine_path)
    unit.setup(0.0)
    unit.initialize()
    host = inprocess_host(unit)
    driver = JogDriver(inprocess_ports(unit), machine)
    power_up(host, driver)
    return workload(host, driver, steps)


# ---------------------------------------------------------------------------------- the benchmark


def run_fmu_benchmark(machine_path: str, seconds: float = 20.0, say: Callable[[str], None] = print,
                      python: PythonRuntime = PythonRuntime.BUNDLED) -> FmuBenchmarkResult:
    """Export the FMU (self-contained, or lean for ``python=HOST``), then each workload for
    ``seconds`` simulated on the FMU and in process."""
    fmpy = _fmpy()  # before the export: without FMPy there is nothing to measure
    machine = load_machine(machine_path)
    step_s = communication_step_s(machine)
    steps = max(1, round(seconds / step_s))
    with tempfile.TemporaryDirectory(prefix="vc_fmu_bench_") as work_text:
        work = Path(work_text)
        began = time.perf_counter()
        exported = export_fmu(machine_path, str(work / f"{machine.name}.fmu"), python)
        export_s = time.perf_counter() - began
        fmu_bytes = exported.size  # the FMU file goes with the directory
        with FmuUnderFmpy(fmpy, exported.path, work / "extracted") as fmu:
            plan = JogDriver(fmu.ports, machine)
            say(f"machine {machine.name}: FMU exported in {export_s:.2f} s; communication step"
                f" {step_s * 1000:g} ms = {machine.plc_cycle_ipo} IPO cycles; {steps} steps"
                f" ({steps * step_s:g} s simulated) per workload")
            say(_describe(exported))
            say(f"host in place of the PLC: JOG {plan.jog_axis} back and forth every {STROKE_S:g} s, every"
                f" axis and spindle in position control")
            say("step: doStep only")
            fmu_step = _on_fmu(fmu, machine, time_steps, steps)
            say(fmu_step.line("FMU (FMPy)"))
            inprocess_step = _in_process(machine_path, machine, time_steps, steps)
            say(inprocess_step.line("in process"))
            say(f"  ratio FMU / in process {rate_ratio(fmu_step, inprocess_step):.3f}")
            say(f"exchange: per step one call per batch ({plan.exchange_size.text()}), then doStep")
            fmu_exchange = _on_fmu(fmu, machine, time_exchanges, steps)
            say(fmu_exchange.line("FMU (FMPy)"))
            inprocess_exchange = _in_process(machine_path, machine, time_exchanges, steps)
            say(inprocess_exchange.line("in process"))
            say(f"  ratio FMU / in process {rate_ratio(fmu_exchange, inprocess_exchange):.3f}")
            instantiate_s, *later = fmu.instantiate_s
            say(f"start-up: fmi2Instantiate {instantiate_s * 1000:.0f} ms (the first of {len(fmu.instantiate_s)};"
                f" the others {', '.join(f'{seconds * 1000:.0f}' for seconds in later)} ms)")
    return FmuBenchmarkResult(machine.name, plan.jog_axis, export_s, instantiate_s, fmu_bytes, exported.glibc,
                              machine.plc_cycle_ipo, plan.exchange_size, fmu_step, inprocess_step, fmu_exchange,
                              inprocess_exchange)


def _describe(exported: ExportResult) -> str:
    kind = "self-contained" if exported.python is PythonRuntime.BUNDLED else "lean (pythonfmu, this Python)"
    return (f"FMU: {kind}, {exported.size / 1e6:.1f} MB; its linux64 binaries need glibc >="
            f" {'.'.join(map(str, exported.glibc))}")
