"""``vc run -j N``: scenario files in worker processes, reported as the serial run reports them.

Each worker process loads the catalogue and each machine file once (not once per scenario),
then runs the scenario files it is given: it loads the file, runs it on a fresh target, writes
its traces and compares it with its golden trace, all as :func:`~vc.scenario.runner.run_scenarios`
does, and sends back a :class:`ScenarioOutcome`, a picklable result without the recorder.  The
parent puts the outcomes back in file order, so the console report, the JUnit file, the trace
names and the exit code are those of a serial run; only the wall times differ.

A worker that dies (killed, out of memory) breaks its pool: the scenarios that had not
finished run again in a new pool, and one whose worker dies a second time is reported as an
error.  Ctrl-C stops the workers and returns what ran.

Workers start by ``fork`` where the platform has it: they inherit the parent's loaded
catalogue and the imported modules, so a worker costs milliseconds, not an interpreter start.
"""

from __future__ import annotations

import multiprocessing
import os
import signal
import time as wallclock
import traceback
from collections.abc import Callable, Collection, Sequence
from concurrent.futures import FIRST_COMPLETED, Future, ProcessPoolExecutor, wait
from concurrent.futures.process import BrokenProcessPool
from dataclasses import dataclass, field
from pathlib import Path

from vc.config.model import MachineConfig
from vc.located_yaml import LocatedMap, Mark, SourceError
from vc.scenario.golden import GoldenCheck
from vc.scenario.loader import MachineLoader, default_machine_loader, load_scenario
from vc.scenario.model import Scenario
from vc.scenario.runner import Failure, RunObserver, ScenarioResult, SignalTrail, run_one, trace_names
from vc.scenario.target import ScenarioTarget


def default_jobs() -> int:
    """The cores this process may use."""
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except AttributeError:  # not on Linux
        return max(1, os.cpu_count() or 1)


@dataclass(frozen=True, slots=True)
class RunSettings:
    """What every worker needs to run a scenario file exactly as the serial run would."""

    known_programs: tuple[str, ...]
    make_target: Callable[[Scenario], ScenarioTarget]  # a module-level function: it travels by name
    trace_dir: str | None = None
    golden: str | None = None
    update_golden: bool = False


@dataclass(frozen=True, slots=True)
class ScenarioOutcome:
    """A :class:`ScenarioResult` as it crosses the process boundary: the failing step by its
    index in the scenario, no recorder (the traces are already written)."""

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

    @classmethod
    def of(cls, position: int, result: ScenarioResult) -> ScenarioOutcome:
        failure = result.failure
        common = dict(position=position, passed=result.passed, error=result.error,
                      simulated_s=result.simulated_s, wall_s=result.wall_s, cycles=result.cycles,
                      steps_done=result.steps_done, trace_files=tuple(result.trace_files))
        if failure is None:
            return cls(**common)  # type: ignore[arg-type]
        steps = result.scenario.steps
        index = next((i for i, step in enumerate(steps) if step is failure.step), None)
        return cls(kind=failure.kind, step_index=index, mark=failure.mark, message=failure.message,
                   cycle=failure.cycle, time_s=failure.time_s, history=failure.history,
                   **common)  # type: ignore[arg-type]

    def result_for(self, scenario: Scenario) -> ScenarioResult:
        failure = None
        if self.kind:
            step = scenario.steps[self.step_index] if self.step_index is not None else None
            failure = Failure(self.kind, step, self.mark or scenario.mark, self.message, self.cycle, self.time_s,
                              self.history)
        return ScenarioResult(scenario, self.passed, failure, self.error, self.simulated_s, self.wall_s,
                              self.cycles, self.steps_done, None, list(self.trace_files))


class _MachinesOfThisProcess:
    """A machine loader that keeps each machine file (without overrides) for the process's life:
    the worker checks each machine once, not once per scenario."""

    def __init__(self, loader: MachineLoader = default_machine_loader):
        self.loader = loader
        self.loaded: dict[str, MachineConfig] = {}

    def __call__(self, path: str, overrides: LocatedMap | None, overrides_file: str) -> MachineConfig:
        if overrides:
            return self.loader(path, overrides, overrides_file)
        if path not in self.loaded:
            self.loaded[path] = self.loader(path, overrides, overrides_file)
        return self.loaded[path]


class _Worker:
    """One worker process's state: the settings and the machines it has loaded."""

    def __init__(self, settings: RunSettings):
        self.settings = settings
        self.machines = _MachinesOfThisProcess()
        golden = settings.golden
        self.check = GoldenCheck(Path(golden), settings.update_golden) if golden is not None else None

    def run(self, position: int, path: str, trace_name: str) -> ScenarioOutcome:
        began = wallclock.perf_counter()
        try:
            scenario = load_scenario(path, self.settings.known_programs, machine_loader=self.machines)
        except SourceError as error:  # the file changed since the parent checked it
            return ScenarioOutcome(position, False, error=f"{path} could not be loaded again:\n{error}",
                                   wall_s=wallclock.perf_counter() - began)
        trace_dir = self.settings.trace_dir
        result = run_one(scenario, self.settings.make_target, trace_dir=Path(trace_dir) if trace_dir else None,
                         trace_name=trace_name, check=self.check)
        return ScenarioOutcome.of(position, result)


_worker: _Worker | None = None  # this worker process's state, set by its initializer


def _start_worker(settings: RunSettings) -> None:
    global _worker  # the process is the worker: its state lives as long as it does
    signal.signal(signal.SIGINT, signal.SIG_IGN)  # Ctrl-C is the parent's to handle
    _worker = _Worker(settings)


def _run_in_worker(position: int, path: str, trace_name: str) -> ScenarioOutcome:
    assert _worker is not None, "the worker's initializer did not run"
    return _worker.run(position, path, trace_name)


def _context() -> multiprocessing.context.BaseContext:
    methods = multiprocessing.get_all_start_methods()
    return multiprocessing.get_context("fork" if "fork" in methods else "spawn")


def run_parallel(scenarios: Sequence[Scenario], settings: RunSettings, jobs: int, *,
                 observer: RunObserver | None = None) -> list[ScenarioResult]:
    """Run ``scenarios`` on ``jobs`` worker processes; results in the order of ``scenarios``.

    Raises KeyboardInterrupt after stopping the workers when the user presses Ctrl-C; the
    results reported so far have gone to ``observer``.
    """
    names = trace_names(scenarios)
    total = len(scenarios)
    results: list[ScenarioResult | None] = [None] * total
    attempts = [0] * total
    waiting = list(range(total))  # positions not yet handed to a pool
    reported = 0
    if observer is not None:
        observer.scenario_started(scenarios[0], 0, total)
    while waiting:
        pool = ProcessPoolExecutor(max_workers=min(jobs, len(waiting)), mp_context=_context(),
                                   initializer=_start_worker, initargs=(settings,))
        try:
            pending: dict[Future[ScenarioOutcome], int] = {}
            for position in waiting:
                attempts[position] += 1
                pending[pool.submit(_run_in_worker, position, scenarios[position].path, names[position])] = position
            waiting = []
            while pending:
                done, _ = wait(pending, return_when=FIRST_COMPLETED)
                for future in done:
                    position = pending.pop(future)
                    result = _result_of(future, scenarios[position], attempts[position])
                    if result is None:
                        waiting.append(position)  # its worker died: once more, in a new pool
                    else:
                        results[position] = result
                while reported < total and results[reported] is not None:
                    finished = results[reported]
                    assert finished is not None
                    if observer is not None:
                        observer.scenario_finished(finished)
                    reported += 1
                    if observer is not None and reported < total:
                        observer.scenario_started(scenarios[reported], reported, total)
        except KeyboardInterrupt:
            _stop(pool)
            raise
        pool.shutdown(wait=True)
        waiting.sort()
    return [result for result in results if result is not None]


MAX_ATTEMPTS = 2  # a scenario whose worker died twice is reported, not tried a third time


def _result_of(future: Future[ScenarioOutcome], scenario: Scenario, attempt: int) -> ScenarioResult | None:
    """The scenario's result; None when its worker died and it may run once more."""
    try:
        return future.result().result_for(scenario)
    except BrokenProcessPool:
        # every scenario the pool still had fails so; only one of them killed it
        if attempt < MAX_ATTEMPTS:
            return None
        return ScenarioResult(scenario, False, error=f"the worker process running this scenario died"
                                                     f" {attempt} times (killed or out of memory)")
    except Exception:  # a result that could not cross the process boundary
        return ScenarioResult(scenario, False, error=traceback.format_exc())


def _stop(pool: ProcessPoolExecutor) -> None:
    """Cancel what has not started and end the workers now (they ignore SIGINT)."""
    # the executor has no public way to end running tasks before Python 3.14's terminate_workers()
    processes = list((getattr(pool, "_processes", None) or {}).values())
    pool.shutdown(wait=False, cancel_futures=True)
    for process in processes:
        process.terminate()


def jobs_for(requested: int | None, scenarios: Collection[Scenario]) -> int:
    """The workers a run uses: as asked (default: the cores), never more than the scenarios."""
    jobs = default_jobs() if requested is None else requested
    return max(1, min(jobs, len(scenarios)))
