"""``vc run -j N``: scenarios in worker processes, reported as the serial run reports them.

Each worker process loads the catalogue and each machine file once (not once per scenario),
then runs the tasks it is given (:mod:`vc.scenario.tasks`: one scenario file, or one variant of
a matrix): it loads the scenario, runs it on a fresh target, writes its traces and compares it
with its golden trace, all as :func:`~vc.scenario.runner.run_scenarios` does, and sends back a
:class:`~vc.scenario.tasks.ScenarioOutcome`, a picklable result without the recorder.  The
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
import traceback
from collections.abc import Collection, Sequence
from concurrent.futures import FIRST_COMPLETED, Future, ProcessPoolExecutor, wait
from concurrent.futures.process import BrokenProcessPool

from vc.scenario.model import Scenario
from vc.scenario.runner import RunObserver, ScenarioResult, trace_names
from vc.scenario.tasks import InOrder, RunSettings, ScenarioOutcome, ScenarioTask, ScenarioWorker

__all__ = ["MAX_ATTEMPTS", "RunSettings", "default_jobs", "jobs_for", "run_parallel"]


def default_jobs() -> int:
    """The cores this process may use."""
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except AttributeError:  # not on Linux
        return max(1, os.cpu_count() or 1)


_worker: ScenarioWorker | None = None  # this worker process's state, set by its initializer


def _start_worker(settings: RunSettings) -> None:
    global _worker  # the process is the worker: its state lives as long as it does
    signal.signal(signal.SIGINT, signal.SIG_IGN)  # Ctrl-C is the parent's to handle
    _worker = ScenarioWorker(settings)


def _run_in_worker(task: ScenarioTask) -> ScenarioOutcome:
    assert _worker is not None, "the worker's initializer did not run"
    return _worker.run(task)


def process_context() -> multiprocessing.context.BaseContext:
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
    in_order = InOrder(scenarios, observer)
    attempts = [0] * total
    waiting = list(range(total))  # positions not yet handed to a pool
    while waiting:
        pool = ProcessPoolExecutor(max_workers=min(jobs, len(waiting)), mp_context=process_context(),
                                   initializer=_start_worker, initargs=(settings,))
        try:
            pending: dict[Future[ScenarioOutcome], int] = {}
            for position in waiting:
                attempts[position] += 1
                task = ScenarioTask.of(position, scenarios[position], names[position])
                pending[pool.submit(_run_in_worker, task)] = position
            waiting = []
            while pending:
                done, _ = wait(pending, return_when=FIRST_COMPLETED)
                for future in done:
                    position = pending.pop(future)
                    result = _result_of(future, scenarios[position], attempts[position])
                    if result is None:
                        waiting.append(position)  # its worker died: once more, in a new pool
                    else:
                        in_order.put(position, result)
        except KeyboardInterrupt:
            _stop(pool)
            raise
        pool.shutdown(wait=True)
        waiting.sort()
    return in_order.finished()


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
