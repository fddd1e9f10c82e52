"""Running checked scenarios against a simulation, through :class:`ScenarioTarget` only.

Steps run in order, each by its kind's runner in the table of step kinds
(:mod:`vc.scenario.language.steps.table`); this module is the run loop they act through.  Time passes
only in steps that take time (``press``, ``pulse``, ``turn``, ``wait``); everything else happens
between two IPO cycles.  After every cycle the runner
records the changes, checks the invariants (the first violation fails the scenario) and
watches the ``when`` events; the scenario's ``timeout`` bounds the simulated time.  A failed
step ends the scenario.

Who builds the simulation is the caller's business: :func:`run_scenarios` takes a factory
``make_target(scenario) -> ScenarioTarget`` (the harness), so this module never imports it.
"""

from __future__ import annotations

import hashlib
import re
import time as wallclock
import traceback
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Protocol

from interfaces.errors import VcError
from vc.located_yaml import Mark
from vc.scenario.language.durations import format_seconds
from vc.scenario.language.expressions import AlarmCall, EvaluationError, Evaluator, Expression, walk
from vc.scenario.language.model import EdgeKind, Event, ExpectAlarm, Invariant, Scenario, Step, WaitUntil
from vc.scenario.language.quantities import Quantity, QuantityKind, unit_of
from vc.scenario.language.steps.common import alarms_text
from vc.scenario.language.steps.table import STEPS
from vc.scenario.language.target import ScenarioTarget
from vc.scenario.language.values import format_value
from vc.scenario.run.trace import History, Recorder, Recording, write_traces
from vc.simulation.observables import StepRefused

HISTORY_CHANGES = 10  # changes per name in a failure report
HISTORY_WINDOW_S = 5.0  # ... within this much simulated time before the failure
PROGRESS_EVERY = 500  # cycles between two progress reports


@dataclass(frozen=True, slots=True)
class SignalTrail:
    """Recent values of one name before a failure: ``(seconds since start, value)``."""

    name: str
    address: str
    entries: tuple[tuple[float, float], ...]
    unit: str = ""  # of the values (SP1.velocity: rev/min)


@dataclass(frozen=True, slots=True)
class Failure:
    kind: str  # "step", "invariant", "timeout"
    step: Step | None  # the step that was running
    mark: Mark  # where to look: the failing step, or the violated invariant
    message: str  # what was expected and what was found
    cycle: int
    time_s: float
    history: tuple[SignalTrail, ...] = ()

    @property
    def where(self) -> str:
        """``step 4 (wait) at x.yaml:12:5``, ``invariant at x.yaml:6:5, during step 4 (wait, line 12)``,
        ``timeout during step 4 (wait) at x.yaml:12:5``."""
        step = self.step
        if self.kind == "invariant":
            during = f", during {step.label[:-1]}, line {step.mark.line})" if step is not None else ""
            return f"invariant at {self.mark}{during}"
        if step is None:
            return f"{self.kind} at {self.mark}"
        return f"{'timeout during ' if self.kind == 'timeout' else ''}{step.label} at {self.mark}"


@dataclass(slots=True)
class ScenarioResult:
    scenario: Scenario
    passed: bool
    failure: Failure | None = None
    error: str = ""  # a harness error (exception with traceback): the scenario could not run
    simulated_s: float = 0.0
    wall_s: float = 0.0
    cycles: int = 0
    steps_done: int = 0
    recorder: Recording | None = None  # the live recorder, or a recording sent back by a worker
    trace_files: list[str] = field(default_factory=list)
    step_cycles: tuple[int, ...] = ()  # the cycle each step began at (since the start), in step order

    @property
    def status(self) -> str:
        return "PASS" if self.passed else ("ERROR" if self.error else "FAIL")


class RunObserver(Protocol):
    """Told about progress (the console report implements it)."""

    def scenario_started(self, scenario: Scenario, position: int, total: int) -> None: ...

    def scenario_progress(self, scenario: Scenario, simulated_s: float) -> None: ...

    def scenario_finished(self, result: ScenarioResult) -> None: ...


class RunInterrupted(KeyboardInterrupt):
    """The user pressed Ctrl-C: the run stopped, with the results of the scenarios that finished
    (in the scenarios' order), so that their report and JUnit file can still be written."""

    def __init__(self, results: list[ScenarioResult]):
        super().__init__()
        self.results = results


class _Stop(VcError):
    def __init__(self, failure: Failure):
        super().__init__(failure.message)
        self.failure = failure


class _Probe:
    """Compiled expressions read the target through this."""

    def __init__(self, target: ScenarioTarget, start_cycle: int, axis_values: dict[str, float] | None = None):
        self.target = target
        self.start_cycle = start_cycle
        self.axis_values = axis_values  # what the recorder read of the axes in this cycle (empty between cycles)

    def reader(self, quantity: Quantity) -> Evaluator:
        target = self.target
        if quantity.kind is QuantityKind.SIGNAL:
            assert quantity.ref is not None
            read, ref = target.read, quantity.ref
            return lambda: read(ref)
        if quantity.kind is QuantityKind.AXIS:
            axis_value, axis, name = target.axis_quantity, quantity.axis, quantity.quantity
            values, key = self.axis_values, quantity.name
            if values is None:
                return lambda: axis_value(axis, name)

            def read_axis() -> float:  # once per cycle: the recorder's reading, if it took one
                value = values.get(key)
                return axis_value(axis, name) if value is None else value
            return read_axis
        if quantity.kind is QuantityKind.MACHINE_DATUM:
            datum, instance, number, index = target.machine_datum, quantity.axis, int(quantity.quantity), quantity.index
            return lambda: datum(instance, number, index)
        if quantity.kind is QuantityKind.LINK:
            link_value, name = target.link_quantity, quantity.quantity
            return lambda: link_value(name)
        start, seconds_per_cycle = self.start_cycle, target.ipo_cycle_us / 1e6
        return lambda: (target.cycle - start) * seconds_per_cycle

    def alarm_present(self, number: int, place: str, text: str = "") -> bool:
        return any(alarm.number == number and (not place or place in (alarm.axis, alarm.channel))
                   and text in alarm.text for alarm in self.target.alarms())


@dataclass(slots=True)
class _Inputs:
    """What a condition on signals alone reads, as their recorded histories: it cannot change while
    they do not grow (a history grows with each change of its signal, a write between cycles too)."""

    histories: tuple[History, ...]
    seen: int = -1  # the histories' entries when the condition was last judged

    @classmethod
    def of(cls, condition: Expression, recording: Recording) -> _Inputs | None:
        """None for a condition that must be judged every cycle: one on an axis quantity, a machine
        datum, the time or an alarm (none of them recorded change by change)."""
        if any(isinstance(node, AlarmCall) for node in walk(condition.root)):
            return None
        histories = []
        for quantity in condition.names:
            history = recording.history(quantity) if quantity.kind is QuantityKind.SIGNAL else None
            if history is None:
                return None
            histories.append(history)
        return cls(tuple(histories))

    def changed(self) -> bool:
        """Whether an input changed since the last call (True on the first)."""
        seen = sum(len(history.cycles) for history in self.histories)
        if seen == self.seen:
            return False
        self.seen = seen
        return True


@dataclass(slots=True)
class _Invariant:
    invariant: Invariant
    evaluate: Evaluator
    inputs: _Inputs | None  # None: judged every cycle


@dataclass(slots=True)
class _WhenTracker:
    evaluate: Evaluator
    inputs: _Inputs | None = None  # None: judged every cycle
    holds: bool = False
    cycles: list[int] = field(default_factory=list)


class _Run:
    def __init__(self, scenario: Scenario, target: ScenarioTarget, recorder: Recorder,
                 observer: RunObserver | None):
        self.scenario = scenario
        self.target = target
        self.recorder = recorder
        self.observer = observer
        self.ipo_cycle_us = target.ipo_cycle_us
        self.timeout_cycles = scenario.timeout.cycles(self.ipo_cycle_us)
        self.start_cycle = target.cycle
        self.probe = _Probe(target, self.start_cycle, recorder.axis_values)
        # conditions compiled once; one on signals alone is judged again only when a signal of it changed
        self.invariants = [_Invariant(invariant, invariant.condition.compile(self.probe),
                                      _Inputs.of(invariant.condition, recorder))
                           for invariant in scenario.invariants]
        self.when: dict[str, _WhenTracker] = {}
        for event in scenario.events:
            if event.kind is EdgeKind.WHEN and event.text not in self.when:
                assert event.condition is not None
                self.when[event.text] = _WhenTracker(event.condition.compile(self.probe),
                                                     _Inputs.of(event.condition, recorder))
        self.axis_values = recorder.axis_values if recorder.axis_values is not None else {}
        self.forced: set[str] = set()
        self.step: Step | None = None
        self.steps_done = 0

    @property
    def cycle(self) -> int:
        return self.target.cycle - self.start_cycle

    def seconds(self, cycle: int | None = None) -> float:
        return (self.cycle if cycle is None else cycle) * self.ipo_cycle_us / 1e6

    # -- time ------------------------------------------------------------------------------

    def begin(self) -> None:
        self.recorder.start()
        for tracker in self.when.values():
            if tracker.inputs is not None:
                tracker.inputs.changed()  # the recording's initial values: what this judgement read
            tracker.holds = bool(self.evaluate(tracker.evaluate, None))
            if tracker.holds:
                tracker.cycles.append(0)

    def advance(self, cycles: int | None, until: Evaluator | None = None,
                until_expression: Expression | None = None) -> bool:
        """Run ``cycles`` IPO cycles (None: no limit but the timeout), or until ``until`` holds.
        True if ``until`` became true."""
        done = 0
        while cycles is None or done < cycles:
            if self.cycle >= self.timeout_cycles:
                step = self.step
                waiting = ""
                if isinstance(step, WaitUntil):
                    waiting = f' while waiting for "{step.condition}"{self.now(step.quantities, ". Now: ")}'
                raise _Stop(self.failure(
                    "timeout", f"the scenario's timeout of {self.scenario.timeout} was reached{waiting}",
                    step.mark if step is not None else self.scenario.mark,
                    step.quantities if step is not None else ()))
            self.target.step(1)
            done += 1
            try:
                self.after_cycle()
                if until is not None and self.evaluate(until, until_expression):
                    return True
            finally:  # the steps between two cycles read the target itself
                self.axis_values.clear()
        return False

    def after_cycle(self) -> None:
        self.recorder.sample()
        cycle = self.cycle
        for judged in self.invariants:
            inputs = judged.inputs
            if inputs is not None and not inputs.changed():
                continue  # it held when they were as they are
            invariant = judged.invariant
            if not self.evaluate(judged.evaluate, invariant.condition):
                names = invariant.condition.names
                raise _Stop(self.failure(
                    "invariant",
                    f"invariant \"{invariant.condition}\" was violated at cycle {cycle}"
                    f" (t = {format_seconds(self.seconds())}){self.now(names, ': ')}",
                    invariant.mark, names))
        self.watch_when_events()
        if self.observer is not None and cycle % PROGRESS_EVERY == 0:
            self.observer.scenario_progress(self.scenario, self.seconds())

    def watch_when_events(self) -> None:
        cycle = self.cycle
        for tracker in self.when.values():
            inputs = tracker.inputs
            if inputs is not None and not inputs.changed():
                continue  # it holds, or not, as it did
            holds = bool(self.evaluate(tracker.evaluate, None))
            if holds and not tracker.holds:
                tracker.cycles.append(cycle)
            tracker.holds = holds

    def after_writes(self, written: Sequence[Quantity]) -> None:
        """The scenario wrote between two cycles: that belongs to the history of this cycle."""
        self.recorder.note_writes(written)
        self.watch_when_events()

    def evaluate(self, evaluator: Evaluator, expression: Expression | None) -> float:
        try:
            return evaluator()
        except EvaluationError as error:
            text = f" in \"{expression}\"" if expression is not None else ""
            step = self.step
            raise _Stop(self.failure("step", f"cannot evaluate{text}: {error}",
                                     step.mark if step is not None else self.scenario.mark,
                                     expression.names if expression is not None else ())) from None

    # -- reporting -------------------------------------------------------------------------

    def failure(self, kind: str, message: str, mark: Mark, names: Sequence[Quantity]) -> Failure:
        """The failure, its message followed by the alarms present (a cause the message may not name:
        a wait for a signal the NC never set because an alarm stopped it); the recent history of ``names``."""
        alarms = self.target.alarms()
        if alarms and not isinstance(self.step, ExpectAlarm):  # those list the alarms themselves
            message = f"{message}; alarms present: {alarms_text(alarms)}"
        trails = []
        for quantity in names:
            if quantity.kind is QuantityKind.TIME:
                continue
            entries = self.recorder.recent(quantity, HISTORY_CHANGES, HISTORY_WINDOW_S)
            trails.append(SignalTrail(quantity.name, quantity.address,
                                      tuple((self.seconds(cycle), value) for cycle, value in entries),
                                      unit_of(quantity, self.scenario.machine)))
        return Failure(kind, self.step, mark, message, self.cycle, self.seconds(), tuple(trails))

    def fail(self, step: Step, message: str, names: Sequence[Quantity] | None = None) -> _Stop:
        return _Stop(self.failure("step", message, step.mark, step.quantities if names is None else names))

    def read(self, quantity: Quantity) -> float:
        return self.probe.reader(quantity)()

    def shown(self, quantity: Quantity, value: float) -> str:
        return format_value(value, unit_of(quantity, self.scenario.machine))

    def now(self, names: Sequence[Quantity], lead: str) -> str:
        shown = [f"{q.name} = {self.shown(q, self.read(q))}" for q in names if q.kind is not QuantityKind.TIME]
        return lead + ", ".join(shown) if shown else ""

    # -- steps -----------------------------------------------------------------------------

    def run_step(self, step: Step) -> None:
        self.step = step
        try:
            self.act(step)
        except StepRefused as refusal:
            raise self.fail(step, str(refusal)) from None
        self.steps_done += 1

    def act(self, step: Step) -> None:
        kind = STEPS.get(step.kind)
        if kind is None:  # pragma: no cover - the loader builds only the table's kinds
            raise TypeError(f"unknown step {step!r}")
        kind.run(self, step)

    def occurrences(self, event: Event) -> list[int]:
        if event.kind is EdgeKind.WHEN:
            return self.when[event.text].cycles
        assert event.quantity is not None
        return self.recorder.occurrences(event.quantity, event.kind)

    def at(self, cycle: int) -> str:
        return format_seconds(self.seconds(cycle))


# ---------------------------------------------------------------------------------- public


def run_scenario(scenario: Scenario, target: ScenarioTarget, recorder: Recorder | None = None,
                 observer: RunObserver | None = None, record_all: bool = True) -> ScenarioResult:
    """Run one scenario on a freshly created target; exceptions of the target propagate.

    ``record_all``: record every signal and axis of the machine (for traces, golden traces and
    diagrams); False records the scenario's own names only, all its steps, conditions and failure
    messages read (the result's recording then holds those alone)."""
    began = wallclock.perf_counter()
    if recorder is None:
        recorder = Recorder(target, record_all=record_all, axis_values={})
    recorder.watch(scenario.quantities)
    run = _Run(scenario, target, recorder, observer)
    failure = None
    step_cycles: list[int] = []
    try:
        run.begin()
        for step in scenario.steps:
            step_cycles.append(run.cycle)
            run.run_step(step)
    except _Stop as stop:
        failure = stop.failure
    return ScenarioResult(
        scenario=scenario, passed=failure is None, failure=failure, simulated_s=run.seconds(),
        wall_s=wallclock.perf_counter() - began, cycles=run.cycle, steps_done=run.steps_done,
        recorder=recorder, step_cycles=tuple(step_cycles),
    )


def run_scenarios(scenarios: Sequence[Scenario], make_target: Callable[[Scenario], ScenarioTarget], *,
                  observer: RunObserver | None = None,
                  trace_dir: str | Path | None = None,
                  check: Callable[[ScenarioResult], None] | None = None,
                  record_all: bool = True) -> list[ScenarioResult]:
    """Run each scenario on its own target from ``make_target``; write traces to ``trace_dir``.

    ``check`` looks at each result before it is reported and may turn a pass into a failure
    (the golden-trace comparison does).  An exception while building or running a target (a
    harness error, not a scenario failure) is reported as that scenario's ``error`` and the
    next scenario runs.  Ctrl-C raises :class:`RunInterrupted` with the results so far.
    ``record_all``: see :func:`run_scenario`; with traces or a check every scenario records all.
    """
    results: list[ScenarioResult] = []
    names = trace_names(scenarios)
    directory = Path(trace_dir) if trace_dir is not None else None
    try:
        for position, scenario in enumerate(scenarios):
            if observer is not None:
                observer.scenario_started(scenario, position, len(scenarios))
            result = run_one(scenario, make_target, observer=observer, trace_dir=directory,
                             trace_name=names[position], check=check, record_all=record_all)
            results.append(result)  # finished, even if Ctrl-C comes while it is reported
            if observer is not None:
                observer.scenario_finished(result)
    except KeyboardInterrupt:
        raise RunInterrupted(results) from None
    return results


def run_one(scenario: Scenario, make_target: Callable[[Scenario], ScenarioTarget], *,
            observer: RunObserver | None = None, trace_dir: Path | None = None, trace_name: str = "",
            check: Callable[[ScenarioResult], None] | None = None, record_all: bool = True) -> ScenarioResult:
    """One scenario of a run: on its own target, its traces written as ``trace_dir/trace_name.*``,
    then ``check`` (the golden comparison).  A harness error becomes the result's ``error``.
    ``record_all`` (see :func:`run_scenario`) is taken as True with traces or a check."""
    began = wallclock.perf_counter()
    record_all = record_all or trace_dir is not None or check is not None
    try:
        result = run_scenario(scenario, make_target(scenario), observer=observer, record_all=record_all)
    except Exception:
        result = ScenarioResult(scenario, passed=False, error=traceback.format_exc(),
                                wall_s=wallclock.perf_counter() - began)
    finish(result, trace_dir, trace_name, check)
    return result


def finish(result: ScenarioResult, trace_dir: Path | None, trace_name: str,
           check: Callable[[ScenarioResult], None] | None) -> None:
    """After the run: its traces written as ``trace_dir/trace_name.*`` (CSV, VCD, GTKWave save
    file with the scenario's own names), then ``check`` (the golden comparison).  Where the run
    happened, or where its recording was sent back to."""
    if trace_dir is not None and result.recorder is not None:
        machine = result.scenario.machine
        result.trace_files = write_traces(result.recorder, result.scenario.quantities, trace_dir, trace_name,
                                          result.scenario.name, lambda quantity: unit_of(quantity, machine))
    if check is not None:
        check(result)


def trace_names(scenarios: Sequence[Scenario]) -> list[str]:
    """A file name (without suffix) per scenario: :func:`file_stem`, numbered when stems repeat."""
    names: list[str] = []
    used: dict[str, int] = {}
    for scenario in scenarios:
        stem = file_stem(scenario)
        used[stem] = used.get(stem, 0) + 1
        names.append(stem if used[stem] == 1 else f"{stem}-{used[stem]}")
    return names


FILE_STEM_LIMIT = 200  # characters of a trace or golden file's name: file systems allow 255 bytes


def file_stem(scenario: Scenario) -> str:
    """The scenario file's stem, a variant's values in brackets after it: ``edges[X1.MD34050=1]``."""
    stem = re.sub(r"[^A-Za-z0-9_.-]+", "_", Path(scenario.path).stem) or "scenario"
    if scenario.variant is None:
        return stem
    arguments = re.sub(r"[^A-Za-z0-9_.,=+\-\[\]{}]+", "_", scenario.variant.arguments)
    name = f"{stem}[{arguments}]"
    if len(name) > FILE_STEM_LIMIT:  # still unique: the digest of the whole id
        digest = hashlib.sha1(scenario.variant.arguments.encode()).hexdigest()[:12]
        name = f"{name[:FILE_STEM_LIMIT - 15]}~{digest}]"
    return name
