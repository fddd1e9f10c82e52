"""One task = one scenario (or one variant of a matrix), for worker processes and cluster workers.

What travels to the worker is a :class:`ScenarioTask`: the scenario file (or campaign file) as
the client names it, the variant's position in its matrix, the name of its trace files and the
files it reads.  The worker loads just that variant (each machine file once per process), runs
it on a fresh target and sends back a :class:`ScenarioOutcome`: the result without the live
recorder, its failure's step by index, and, when the client asks for it, the recording as plain
data (:class:`~vc.scenario.run.trace.RecordedData`), from which the client writes traces, compares
golden traces and draws diagrams exactly as a run in its own process would.

:class:`InOrder` hands results to the console report in the scenarios' order, whatever order the
workers finish them in: the report, the JUnit file and the trace names equal the serial run's.

:class:`Identity` is what a worker must share with the client for a variant to give the same
trace everywhere: the harness's sources and the PLC program's.
"""

from __future__ import annotations

import hashlib
import importlib
import os
import socket
import time as wallclock
from collections import OrderedDict
from collections.abc import Callable, Iterable, Mapping, Sequence
from dataclasses import dataclass, field, replace
from functools import cache
from pathlib import Path

from vc.config.model import MachineConfig
from vc.located_yaml import LocatedMap, Mark, SourceError
from vc.scenario.language.loader import MachineLoader, default_machine_loader, load_scenario, machine_key
from vc.scenario.language.model import Scenario
from vc.scenario.language.target import ScenarioTarget
from vc.scenario.outputs.golden import GoldenCheck
from vc.scenario.outputs.timing import diagram_quantities
from vc.scenario.run.runner import Failure, RunObserver, ScenarioResult, SignalTrail, run_one
from vc.scenario.run.trace import RecordedData, Recording, recorded_quantities

SEND_NOTHING = ""  # the worker writes what there is to write; only the verdict comes back
SEND_DIAGRAM = "diagram"  # ... and, of a scenario's first variant and of every failure, what a diagram shows
SEND_ALL = "all"  # every recorded history: the client writes the traces and compares the golden traces


@dataclass(frozen=True, slots=True)
class RunSettings:
    """What every worker needs to run a scenario exactly as the serial run would."""

    known_programs: tuple[str, ...]
    make_target: Callable[[Scenario], ScenarioTarget]  # a module-level function: it travels by name
    trace_dir: str | None = None  # where the worker writes traces (None: it writes none)
    golden: str | None = None  # the golden traces the worker compares with (None: it compares none)
    update_golden: bool = False
    send_back: str = SEND_NOTHING

    @property
    def records_all(self) -> bool:
        """Whether a run records every signal and axis (for traces, golden traces or the report's
        diagrams), or only the names its scenario reads (nothing else would look at the rest)."""
        return self.trace_dir is not None or self.golden is not None or self.send_back != SEND_NOTHING


@dataclass(frozen=True, slots=True)
class ScenarioTask:
    position: int  # in the run's list of scenarios
    path: str  # the scenario or campaign file, as the client names it
    variant: int | None  # the variant's position in the file's matrix
    trace_name: str
    sources: tuple[str, ...] = ()  # the files the scenario reads, as the client names them

    @classmethod
    def of(cls, position: int, scenario: Scenario, trace_name: str) -> ScenarioTask:
        variant = scenario.variant
        return cls(position, variant.origin if variant is not None else scenario.path,
                   variant.index if variant is not None else None, trace_name, scenario.sources)


@dataclass(frozen=True, slots=True)
class ScenarioOutcome:
    """A :class:`ScenarioResult` as it crosses the process boundary: the failing step by its
    index in the scenario, the recording (if asked for) as plain data."""

    position: int
    passed: bool
    kind: str = ""  # the failure's kind; "" when it passed or the harness failed
    step_index: int | None = None
    mark: Mark | None = None
    message: str = ""
    cycle: int = 0
    time_s: float = 0.0
    history: tuple[SignalTrail, ...] = ()
    error: str = ""
    simulated_s: float = 0.0
    wall_s: float = 0.0
    cycles: int = 0
    steps_done: int = 0
    trace_files: tuple[str, ...] = field(default_factory=tuple)
    step_cycles: tuple[int, ...] = ()
    recording: RecordedData | None = None
    task_s: float = 0.0  # the whole task on the worker: loading the variant, the run, the traces
    worker: str = ""  # host and process that ran it

    @classmethod
    def of(cls, position: int, result: ScenarioResult, recording: RecordedData | None = None) -> ScenarioOutcome:
        failure = result.failure
        common = dict(position=position, passed=result.passed, error=result.error,
                      simulated_s=result.simulated_s, wall_s=result.wall_s, cycles=result.cycles,
                      steps_done=result.steps_done, trace_files=tuple(result.trace_files),
                      step_cycles=result.step_cycles, recording=recording, worker=_this_process())
        if failure is None:
            return cls(**common)  # type: ignore[arg-type]
        steps = result.scenario.steps
        index = next((i for i, step in enumerate(steps) if step is failure.step), None)
        return cls(kind=failure.kind, step_index=index, mark=failure.mark, message=failure.message,
                   cycle=failure.cycle, time_s=failure.time_s, history=failure.history,
                   **common)  # type: ignore[arg-type]

    def result_for(self, scenario: Scenario) -> ScenarioResult:
        """The result again, on the client's own scenario; the recording, if sent, as its recorder."""
        failure = None
        if self.kind:
            step = scenario.steps[self.step_index] if self.step_index is not None else None
            failure = Failure(self.kind, step, self.mark or scenario.mark, self.message, self.cycle, self.time_s,
                              self.history)
        recorder = None
        if self.recording is not None:
            quantities = recorded_quantities(scenario.catalog, scenario.machine.plant_io,
                                             (axis.name for axis in scenario.machine.axes), scenario.quantities)
            recorder = Recording.from_data(self.recording, quantities)
        return ScenarioResult(scenario, self.passed, failure, self.error, self.simulated_s, self.wall_s,
                              self.cycles, self.steps_done, recorder, list(self.trace_files), self.step_cycles)

    def translated(self, names: Mapping[str, str]) -> ScenarioOutcome:
        """The outcome with the worker's file names (``names``: worker -> client) as the client's."""
        if not names:
            return self
        ordered = sorted(names.items(), key=lambda item: -len(item[0]))

        def text(value: str) -> str:
            for here, there in ordered:
                value = value.replace(here, there)
            return value

        mark = self.mark
        if mark is not None and mark.file in names:
            mark = replace(mark, file=names[mark.file])
        return replace(self, mark=mark, message=text(self.message), error=text(self.error))


class _MachinesOfThisProcess:
    """A machine loader that keeps the machines it loaded for the process's life: the worker checks
    each machine file once, and each set of a matrix's overrides once (the most recent ones)."""

    KEPT_WITH_OVERRIDES = 32

    def __init__(self, loader: MachineLoader = default_machine_loader):
        self.loader = loader
        self.loaded: OrderedDict[tuple[str, str, object], MachineConfig] = OrderedDict()

    def __call__(self, path: str, overrides: LocatedMap | None, overrides_file: str) -> MachineConfig:
        key = machine_key(path, overrides, overrides_file)
        if key not in self.loaded:
            self.loaded[key] = self.loader(path, overrides, overrides_file)
            if overrides and sum(1 for kept in self.loaded if kept[2] is not None) > self.KEPT_WITH_OVERRIDES:
                oldest = next(kept for kept in self.loaded if kept[2] is not None)
                del self.loaded[oldest]
        self.loaded.move_to_end(key)
        return self.loaded[key]


class ScenarioWorker:
    """One worker process's state: the settings and the machines it has loaded."""

    def __init__(self, settings: RunSettings):
        self.settings = settings
        self.machines = _MachinesOfThisProcess()
        golden = settings.golden
        self.check = GoldenCheck(Path(golden), settings.update_golden) if golden is not None else None

    def run(self, task: ScenarioTask, locate: Callable[[str], str] | None = None) -> ScenarioOutcome:
        """Run the task; ``locate`` gives where a file the client names lies here (the task's
        files sent along, or a shared path), and the outcome names the client's files again."""
        began = wallclock.perf_counter()
        path = locate(task.path) if locate is not None else task.path
        names = {locate(source): source for source in (task.path, *task.sources)} if locate is not None else {}
        try:
            scenario = load_scenario(path, self.settings.known_programs, machine_loader=self.machines,
                                     variant=task.variant)
        except SourceError as error:  # the file changed since the client checked it
            return ScenarioOutcome(task.position, False, error=f"{path} could not be loaded again:\n{error}",
                                   wall_s=wallclock.perf_counter() - began, worker=_this_process()).translated(names)
        trace_dir = self.settings.trace_dir
        directory = Path(locate(trace_dir) if locate is not None else trace_dir) if trace_dir else None
        result = run_one(scenario, self.settings.make_target, trace_dir=directory, trace_name=task.trace_name,
                         check=self.check, record_all=self.settings.records_all)
        outcome = ScenarioOutcome.of(task.position, result, self.recording_of(result))
        return replace(outcome, task_s=wallclock.perf_counter() - began).translated(names)

    def recording_of(self, result: ScenarioResult) -> RecordedData | None:
        recording, wanted = result.recorder, self.settings.send_back
        if recording is None or wanted == SEND_NOTHING:
            return None
        if wanted == SEND_ALL:
            return recording.data()
        variant = result.scenario.variant
        if result.passed and variant is not None and not variant.first:
            return None  # the report draws a matrix's first variant and its failures
        return recording.data({quantity.name for quantity in diagram_quantities(result.scenario, recording)})


def _this_process() -> str:
    return f"{socket.gethostname()}:{os.getpid()}"


class InOrder:
    """Hands results to the observer in the scenarios' order, whatever order they finish in."""

    def __init__(self, scenarios: Sequence[Scenario], observer: RunObserver | None):
        self.scenarios = scenarios
        self.observer = observer
        self.results: list[ScenarioResult | None] = [None] * len(scenarios)
        self.reported = 0
        if observer is not None and scenarios:
            observer.scenario_started(scenarios[0], 0, len(scenarios))

    def put(self, position: int, result: ScenarioResult) -> None:
        self.results[position] = result
        total = len(self.scenarios)
        while self.reported < total and (finished := self.results[self.reported]) is not None:
            if self.observer is not None:
                self.observer.scenario_finished(finished)
            self.reported += 1
            if self.observer is not None and self.reported < total:
                self.observer.scenario_started(self.scenarios[self.reported], self.reported, total)

    def finished(self) -> list[ScenarioResult]:
        return [result for result in self.results if result is not None]

    def report_rest(self) -> None:
        """The run stops early: report the results that finished after a gap, in order (the report
        names every scenario that finished)."""
        if self.observer is None:
            return
        for result in self.results[self.reported:]:
            if result is not None:
                self.observer.scenario_finished(result)
        self.reported = len(self.results)


def rerun_lines(scenarios: Sequence[Scenario], lost: Mapping[int, Sequence[str]],
                ran_on: Mapping[int, str]) -> list[str]:
    """A sentence per scenario whose worker died while it held it: which workers, where it ran then
    (workers named as the run names them: ``host:pid`` for ``-j``, the Dask worker's address)."""
    return [f"{scenarios[position].name}: the worker {', '.join(workers)} died while it had this task; "
            + (f"it ran again on {ran_on[position]}" if position in ran_on else "it did not finish on any worker")
            for position, workers in sorted(lost.items())]


# ---------------------------------------------------------------------------------- identity


@dataclass(frozen=True, slots=True)
class Identity:
    """The code a variant's trace depends on: the harness's sources and each PLC program's."""

    harness: str
    programs: tuple[tuple[str, str], ...]

    def difference(self, other: Identity) -> str:
        """What differs from ``other`` (the client's), as a sentence; "" when nothing does."""
        if self.harness != other.harness:
            return (f"this worker runs other harness sources than the client (digest {self.harness[:12]} here,"
                    f" {other.harness[:12]} there): install the same vc-harness on every worker")
        mine = dict(self.programs)
        for name, digest in other.programs:
            if mine.get(name) != digest:
                here = mine.get(name, "missing")[:12]
                return (f"this worker's PLC program {name} differs from the client's ({here} here, {digest[:12]}"
                        " there)")
        return ""


HARNESS_PACKAGES = ("vc", "interfaces", "plc_stub")


def identity_of(programs: Iterable[str]) -> Identity:
    """This process's :class:`Identity` for the named PLC programs."""
    harness = hashlib.sha256("".join(_package_digest(package) for package in HARNESS_PACKAGES).encode())
    return Identity(harness.hexdigest(), tuple((name, _program_digest(name)) for name in sorted(set(programs))))


@cache
def _package_digest(package: str) -> str:
    """The digest of a package's Python sources (compiled or not, the sources decide what runs)."""
    digest = hashlib.sha256()
    root = Path(importlib.import_module(package).__file__ or "").parent
    for path in sorted(root.rglob("*.py")):
        digest.update(path.relative_to(root).as_posix().encode())
        digest.update(path.read_bytes())
    return digest.hexdigest()


@cache
def _program_digest(name: str) -> str:
    """A PLC program's identity: the sources of the package its factory comes from."""
    from interfaces.links.inprocess import plc_programs

    factory = plc_programs().get(name)
    if factory is None:
        return "missing"
    return _package_digest(str(getattr(factory, "__module__", "")).split(".")[0])
