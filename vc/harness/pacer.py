"""Real-time pacing: IPO cycles tied to the wall clock, on the event loop of the links.

Only this module sleeps.  ``wait_next_cycle`` returns at the start of the next IPO cycle; while
it waits, the link servers on the same asyncio loop answer their clients.  Plain
``asyncio.sleep`` oversleeps by up to a millisecond (the poller counts whole milliseconds), so
the pacer sleeps coarsely until shortly before the deadline and then spins on the loop
(``asyncio.sleep(0)``), still serving requests.  It stops serving half a millisecond before the
deadline and spins the rest outside the loop: a request handler that started late (pymodbus
needs 0.1 to 0.3 ms for one) would otherwise delay the cycle; a request that arrives in that
last half millisecond is answered in the next cycle.

The pacer keeps a fixed schedule (cycle n starts at t0 + n * period / speed).  It records the
error of every cycle's start against that schedule and counts overruns: cycles that started
more than one period late; after an overrun it re-anchors the schedule instead of rushing
through the missed cycles.
"""

from __future__ import annotations

import asyncio
import itertools
import time as wallclock
from dataclasses import dataclass

SPIN_BEFORE_S = 0.0012  # the coarse sleep ends this long before the end of serving
QUIET_BEFORE_S = 0.0005  # no request is served this long before a cycle starts


@dataclass(frozen=True, slots=True)
class PacingStats:
    cycles: int
    overruns: int
    error_median_ms: float  # start of a cycle minus its scheduled time
    error_p99_ms: float
    error_max_ms: float
    period_error_p99_ms: float  # |time between two cycle starts - the period|
    period_error_max_ms: float

    def __str__(self) -> str:
        return (f"{self.cycles} cycles: period error p99 {self.period_error_p99_ms:.3f} ms, max"
                f" {self.period_error_max_ms:.3f} ms; start error median {self.error_median_ms:.3f} ms, p99"
                f" {self.error_p99_ms:.3f} ms; {self.overruns} overruns")


def percentile(values: list[float], share: float) -> float:
    if not values:
        return 0.0
    ordered = sorted(values)
    return ordered[min(len(ordered) - 1, int(share * len(ordered)))]


class RealtimePacer:
    """Paces cycles of ``period_s`` at ``speed`` times real time (None: as fast as possible)."""

    def __init__(self, loop: asyncio.AbstractEventLoop, period_s: float, speed: float | None = 1.0):
        self.loop = loop
        self.speed = speed
        self.period = period_s / speed if speed else 0.0
        self.errors: list[float] = []
        self.overruns = 0
        self._next: float | None = None

    def wait_next_cycle(self) -> None:
        if not self.period:
            self.loop.run_until_complete(asyncio.sleep(0))  # as fast as possible, still serving the links
            return
        now = wallclock.perf_counter()
        if self._next is None:
            self._next = now
        deadline = self._next
        if now < deadline - QUIET_BEFORE_S:
            self.loop.run_until_complete(self._until(deadline - QUIET_BEFORE_S))
        else:
            # late, or a period shorter than the quiet time (high --speed): the links are still
            # served once per cycle, else a PLC never gets an answer
            self.loop.run_until_complete(asyncio.sleep(0))
        while wallclock.perf_counter() < deadline:
            pass  # the last moments outside the loop: nothing can start late in them
        started = wallclock.perf_counter()
        error = started - deadline
        self.errors.append(error)
        if error > self.period:
            self.overruns += 1
            self._next = started + self.period
        else:
            self._next = deadline + self.period

    @staticmethod
    async def _until(deadline: float) -> None:
        remaining = deadline - wallclock.perf_counter()
        if remaining > SPIN_BEFORE_S:
            await asyncio.sleep(remaining - SPIN_BEFORE_S)
        while wallclock.perf_counter() < deadline:
            await asyncio.sleep(0)

    def stats(self, since: int = 0) -> PacingStats:
        errors = [error * 1000 for error in self.errors[since:]]
        periods = [abs(later - earlier) for earlier, later in itertools.pairwise(errors)]
        return PacingStats(len(errors), self.overruns, percentile(errors, 0.5), percentile(errors, 0.99),
                           max(errors, default=0.0), percentile(periods, 0.99), max(periods, default=0.0))
