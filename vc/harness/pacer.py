"""Real-time pacing: IPO cycles tied to the wall clock, on the event loop of the links.

Only this module sleeps.  ``wait_next_cycle`` returns at the start of the next IPO cycle; while
it waits, the link servers on the same asyncio loop answer their clients.  Plain
``asyncio.sleep`` oversleeps by up to a millisecond (the poller counts whole milliseconds), so
the pacer sleeps coarsely until shortly before the deadline and then spins on the loop
(``asyncio.sleep(0)``), still serving requests.  It stops serving half a millisecond before the
deadline and spins the rest outside the loop: a request handler that started late (pymodbus
needs 0.1 to 0.3 ms for one) would otherwise delay the cycle; a request that arrives in that
last half millisecond is answered in the next cycle.  The Modbus server bounds its work per pass
of the loop (:mod:`interfaces.links.modbus.server`), so a flood of requests cannot hold the loop
past that quiet time either.

The pacer keeps a fixed schedule (cycle n starts at t0 + n * period / speed).  It records the
error of every cycle's start against that schedule and counts overruns: cycles that started
more than one period late; after an overrun it re-anchors the schedule instead of rushing
through the missed cycles.  An overrun *caused by the links* is one whose wait served the links
for more than a period beyond the end of serving, computing all that time (the thread's CPU
time); the others: the NC's own step was late, or the operating system woke the process late or
took the CPU from it.  The statistics are histograms (:class:`Histogram`): fixed memory however long
the pacer runs.
"""

from __future__ import annotations

import asyncio
import time as wallclock
from dataclasses import dataclass, field

SPIN_BEFORE_S = 0.0012  # the coarse sleep ends this long before the end of serving
QUIET_BEFORE_S = 0.0005  # no request is served this long before a cycle starts


def percentile(values: list[float], share: float) -> float:
    if not values:
        return 0.0
    ordered = sorted(values)
    return ordered[min(len(ordered) - 1, int(share * len(ordered)))]


class Histogram:
    """Counts of durations in bins: 1 us wide up to 2 ms, 0.1 ms wide up to 200 ms, and the rest;
    a percentile is the upper edge of its bin, the maximum exact."""

    FINE_S, FINE_BINS = 1e-6, 2000
    COARSE_S, COARSE_BINS = 1e-4, 1980

    def __init__(self) -> None:
        self.bins = [0] * (self.FINE_BINS + self.COARSE_BINS + 1)
        self.count = 0
        self.max = 0.0

    def add(self, seconds: float) -> None:
        if seconds < self.FINE_S * self.FINE_BINS:
            index = max(0, int(seconds / self.FINE_S))
        else:
            coarse = int((seconds - self.FINE_S * self.FINE_BINS) / self.COARSE_S)
            index = self.FINE_BINS + min(coarse, self.COARSE_BINS)
        self.bins[index] += 1
        self.count += 1
        self.max = max(self.max, seconds)

    def percentile(self, share: float) -> float:
        """The smallest bin edge that ``share`` of the values do not exceed (0 without values)."""
        if not self.count:
            return 0.0
        wanted = min(self.count, int(share * self.count) + 1)
        seen = 0
        for index, number in enumerate(self.bins):
            seen += number
            if seen >= wanted:
                return min(self.max, self._upper_edge(index))
        return self.max

    def _upper_edge(self, index: int) -> float:
        if index < self.FINE_BINS:
            return (index + 1) * self.FINE_S
        if index < self.FINE_BINS + self.COARSE_BINS:
            return self.FINE_S * self.FINE_BINS + (index - self.FINE_BINS + 1) * self.COARSE_S
        return float("inf")  # the last bin: up to the maximum


@dataclass(frozen=True, slots=True)
class PacingStats:
    cycles: int
    overruns: int
    link_overruns: int  # of them: the links were served past the cycle's start
    error_median_ms: float  # start of a cycle minus its scheduled time
    error_p99_ms: float
    error_max_ms: float
    period_error_p99_ms: float  # |time between two cycle starts - the period|
    period_error_max_ms: float
    realtime_share: float  # periods run / wall time between the first and the last cycle's start

    def __str__(self) -> str:
        return (f"{self.cycles} cycles: period error p99 {self.period_error_p99_ms:.3f} ms, max"
                f" {self.period_error_max_ms:.3f} ms; start error median {self.error_median_ms:.3f} ms, p99"
                f" {self.error_p99_ms:.3f} ms; {self.overruns} overruns ({self.link_overruns} while serving the"
                f" links); NC at {100 * self.realtime_share:.1f} % of the schedule")


@dataclass(slots=True)
class _Window:
    """The statistics of a stretch of cycles."""

    errors: Histogram = field(default_factory=Histogram)
    periods: Histogram = field(default_factory=Histogram)
    overruns: int = 0
    link_overruns: int = 0
    first_start: float = 0.0
    last_start: float = 0.0

    def record(self, started: float, error: float, period_error: float | None, overrun: bool,
               link_caused: bool) -> None:
        if not self.errors.count:
            self.first_start = started
        self.last_start = started
        self.errors.add(error)
        if period_error is not None:
            self.periods.add(period_error)
        self.overruns += overrun
        self.link_overruns += overrun and link_caused

    def stats(self, period: float) -> PacingStats:
        cycles = self.errors.count
        wall = self.last_start - self.first_start
        share = (cycles - 1) * period / wall if cycles > 1 and wall > 0 else 1.0
        errors, periods = self.errors, self.periods
        return PacingStats(cycles, self.overruns, self.link_overruns, 1000 * errors.percentile(0.5),
                           1000 * errors.percentile(0.99), 1000 * errors.max, 1000 * periods.percentile(0.99),
                           1000 * periods.max, share)


class RealtimePacer:
    """Paces cycles of ``period_s`` at ``speed`` times real time (None: as fast as possible)."""

    def __init__(self, loop: asyncio.AbstractEventLoop, period_s: float, speed: float | None = 1.0):
        self.loop = loop
        self.speed = speed
        self.period = period_s / speed if speed else 0.0
        self._total = _Window()
        self._recent = _Window()
        self._last_error: float | None = None
        self._next: float | None = None

    @property
    def overruns(self) -> int:
        return self._total.overruns

    @property
    def cycles(self) -> int:
        """Cycles paced so far (none as fast as possible: no schedule is kept)."""
        return self._total.errors.count

    def wait_next_cycle(self) -> None:
        if not self.period:
            self.loop.run_until_complete(asyncio.sleep(0))  # as fast as possible, still serving the links
            return
        now = wallclock.perf_counter()
        if self._next is None:
            self._next = now
        deadline = self._next
        serve_until = max(now, deadline - QUIET_BEFORE_S)
        cpu = wallclock.thread_time()
        if now < serve_until:
            self.loop.run_until_complete(self._until(serve_until))
        else:
            # late, or a period shorter than the quiet time (high --speed): the links are still
            # served once per cycle, else a PLC never gets an answer
            self.loop.run_until_complete(asyncio.sleep(0))
        served_over = wallclock.perf_counter() - serve_until  # the loop beyond its end: its work, or the OS's
        working = wallclock.thread_time() - cpu >= served_over  # the process computed all that time
        while wallclock.perf_counter() < deadline:
            pass  # the last moments outside the loop: nothing can start late in them
        started = wallclock.perf_counter()
        error = started - deadline
        overrun = error > self.period
        self.record(started, error, overrun, link_caused=served_over > self.period and working)
        self._next = started + self.period if overrun else deadline + self.period

    def record(self, started: float, error: float, overrun: bool, link_caused: bool) -> None:
        """One cycle's start (wall clock), its error against the schedule, whether it overran and
        whether the links were served past its start."""
        period_error = None if self._last_error is None else abs(error - self._last_error)
        self._last_error = error
        for window in (self._total, self._recent):
            window.record(started, error, period_error, overrun, link_caused)

    @staticmethod
    async def _until(deadline: float) -> None:
        remaining = deadline - wallclock.perf_counter()
        if remaining > SPIN_BEFORE_S:
            await asyncio.sleep(remaining - SPIN_BEFORE_S)
        while wallclock.perf_counter() < deadline:
            await asyncio.sleep(0)

    def stats(self) -> PacingStats:
        """Every cycle since the start."""
        return self._total.stats(self.period)

    def take_window(self) -> PacingStats:
        """The cycles since the last call (or the start); the next window begins now."""
        stats = self._recent.stats(self.period)
        self._recent = _Window()
        return stats
