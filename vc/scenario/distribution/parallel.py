"""``vc run -j N``: scenarios in worker processes, reported as the serial run reports them.

Each worker process loads the catalogue and each machine file once (not once per scenario),
then runs the tasks it is given (:mod:`vc.scenario.distribution.tasks`: one scenario file, or one variant of
a matrix): it loads the scenario, runs it on a fresh target, writes its traces and compares it
with its golden trace, all as :func:`~vc.scenario.run.runner.run_scenarios` does, and sends back a
:class:`~vc.scenario.distribution.tasks.ScenarioOutcome`, a picklable result without the recorder.  The
parent puts the outcomes back in file order, so the console report, the JUnit file, the trace
names and the exit code are those of a serial run; only the wall times differ.

The parent gives each worker one task at a time over a pipe of its own, so it knows what every
worker holds.  A worker that dies (killed, out of memory) costs only the task it held: that task
runs again on a new worker, and is reported as an error when its worker dies a second time
(:data:`MAX_ATTEMPTS`); the others are not touched.  Each such re-run is named after the summary.
(A ``concurrent.futures`` pool cannot do this: a worker's death breaks the whole pool and fails
every task it had, running or not.)  Ctrl-C stops the workers and gives back what finished.

Workers start by ``fork`` where the platform has it: they inherit the parent's loaded
catalogue and the imported modules, so a worker costs milliseconds, not an interpreter start.
"""

from __future__ import annotations

import contextlib
import multiprocessing
import os
import signal
import socket
import traceback
from collections import deque
from collections.abc import Collection, Sequence
from dataclasses import dataclass, field
from multiprocessing.connection import Connection, wait

from vc.scenario.distribution.tasks import (
    InOrder,
    RunSettings,
    ScenarioOutcome,
    ScenarioTask,
    ScenarioWorker,
    rerun_lines,
)
from vc.scenario.language.model import Scenario
from vc.scenario.run.runner import RunInterrupted, RunObserver, ScenarioResult, trace_names

__all__ = ["MAX_ATTEMPTS", "MAX_WORKERS_PER_CORE", "ParallelRun", "RunSettings", "default_jobs", "jobs_for",
           "max_workers", "run_parallel"]

MAX_ATTEMPTS = 2  # a scenario whose worker died twice is reported, not tried a third time
MAX_WORKERS_PER_CORE = 4  # -j N and local:N: more processes than this only share the same cores
STOP_TIMEOUT_S = 10.0  # for a worker to end after it was told to


def default_jobs() -> int:
    """The cores this process may use."""
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except AttributeError:  # not on Linux
        return max(1, os.cpu_count() or 1)


def max_workers() -> int:
    """The most worker processes a run starts on this machine (``-j N``, ``--cluster local:N``)."""
    return MAX_WORKERS_PER_CORE * (os.cpu_count() or 1)


def process_context() -> multiprocessing.context.BaseContext:
    methods = multiprocessing.get_all_start_methods()
    return multiprocessing.get_context("fork" if "fork" in methods else "spawn")


def _serve(connection: Connection, settings: RunSettings) -> None:
    """A worker process: run the tasks that come over ``connection`` until it is told to stop."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)  # Ctrl-C is the parent's to handle
    worker = ScenarioWorker(settings)
    while True:
        try:
            task = connection.recv()
        except EOFError:  # the parent is gone
            return
        if task is None:
            return
        outcome = worker.run(task)
        try:
            connection.send(outcome)
        except (OSError, ValueError):  # the parent is gone
            return
        except Exception:  # an outcome that cannot be pickled: what went wrong instead
            connection.send(ScenarioOutcome(task.position, False, error=traceback.format_exc(),
                                            worker=outcome.worker))


class _Worker:
    """A worker process, its end of the pipe and the task it holds."""

    def __init__(self, context: multiprocessing.context.BaseContext, settings: RunSettings):
        self.connection, theirs = context.Pipe()
        self.process = context.Process(target=_serve, args=(theirs, settings), daemon=True)  # type: ignore[attr-defined]
        self.process.start()
        theirs.close()
        self.name = f"{socket.gethostname()}:{self.process.pid}"  # as its outcomes name it
        self.position: int | None = None  # of the task it holds

    def give(self, task: ScenarioTask) -> bool:
        """Hand over ``task``; False when the worker is gone (it then holds nothing)."""
        try:
            self.connection.send(task)
        except OSError:
            return False
        self.position = task.position
        return True

    def outcome(self) -> ScenarioOutcome | None:
        """The outcome of the task it held, once its pipe or its process said something; None if it died."""
        try:
            if self.connection.poll():
                outcome: ScenarioOutcome = self.connection.recv()
                self.position = None
                return outcome
        except (EOFError, OSError):  # it died in the middle of sending
            pass
        return None

    def stop(self) -> None:
        with contextlib.suppress(OSError):
            self.connection.send(None)
        self.process.join(STOP_TIMEOUT_S)
        self.end()

    def end(self) -> None:
        if self.process.is_alive():
            self.process.terminate()
        self.process.join()
        self.connection.close()


@dataclass(slots=True)
class ParallelRun:
    results: list[ScenarioResult]
    lost: dict[int, list[str]] = field(default_factory=dict)  # position -> the workers that died holding it
    ran_on: dict[int, str] = field(default_factory=dict)  # position -> the worker that ran it

    def rerun_lines(self, scenarios: Sequence[Scenario]) -> list[str]:
        """A sentence per re-run: which scenario, which worker died, where it ran then."""
        return rerun_lines(scenarios, self.lost, self.ran_on)


def run_parallel(scenarios: Sequence[Scenario], settings: RunSettings, jobs: int, *,
                 observer: RunObserver | None = None) -> ParallelRun:
    """Run ``scenarios`` on ``jobs`` worker processes; results in the order of ``scenarios``.

    Raises :class:`~vc.scenario.run.runner.RunInterrupted` (a KeyboardInterrupt) with the results that
    finished after stopping the workers when the user presses Ctrl-C; they have gone to ``observer``.
    """
    names = trace_names(scenarios)
    in_order = InOrder(scenarios, observer)
    run = ParallelRun([])
    attempts = [0] * len(scenarios)
    waiting = deque(range(len(scenarios)))  # positions not yet handed to a worker
    context = process_context()
    workers: list[_Worker] = []
    try:
        while waiting or any(worker.position is not None for worker in workers):
            while waiting:
                idle = next((worker for worker in workers if worker.position is None), None)
                if idle is None and len(workers) >= jobs:
                    break
                if idle is None:
                    idle = _Worker(context, settings)
                    workers.append(idle)
                position = waiting[0]
                if not idle.give(ScenarioTask.of(position, scenarios[position], names[position])):
                    workers.remove(idle)  # it died idle: it held nothing
                    idle.end()
                    continue
                waiting.popleft()
                attempts[position] += 1
            busy = [worker for worker in workers if worker.position is not None]
            ready = set(wait([worker.connection for worker in busy] + [worker.process.sentinel for worker in busy]))
            for worker in busy:
                if worker.connection not in ready and worker.process.sentinel not in ready:
                    continue
                held = worker.position
                assert held is not None
                outcome = worker.outcome()
                if outcome is not None:
                    run.ran_on[held] = outcome.worker
                    in_order.put(held, outcome.result_for(scenarios[held]))
                    continue
                workers.remove(worker)  # it died holding this task, and only this one
                worker.end()
                run.lost.setdefault(held, []).append(worker.name)
                if attempts[held] < MAX_ATTEMPTS:
                    waiting.appendleft(held)
                else:
                    in_order.put(held, ScenarioResult(
                        scenarios[held], False, error=f"the worker process running this scenario died"
                                                      f" {attempts[held]} times (killed or out of memory)"))
    except KeyboardInterrupt:
        for worker in workers:
            worker.end()
        in_order.report_rest()
        raise RunInterrupted(in_order.finished()) from None
    for worker in workers:
        worker.stop()
    run.results = in_order.finished()
    return run


def jobs_for(requested: int | None, scenarios: Collection[Scenario]) -> int:
    """The workers a run uses: as asked (default: the cores), never more than the scenarios."""
    jobs = default_jobs() if requested is None else requested
    return max(1, min(jobs, len(scenarios)))
