"""The real-time pacer's schedule and statistics, and that its memory does not grow with the
cycles (no timing is asserted: the figures of a shared machine say nothing; `vc bench --link
modbus` and bench/robustness.py measure them)."""

from __future__ import annotations

import asyncio
import tracemalloc

import pytest

from vc.cli.main import main
from vc.harness.pacer import Histogram, PacingStats, RealtimePacer, percentile

pytestmark = pytest.mark.realtime


@pytest.mark.parametrize(("speed", "period"), [(1.0, 0.002), (2.0, 0.001), (0.5, 0.004), (None, 0.0)])
def test_the_speed_factor_scales_the_wall_clock_period(speed: float | None, period: float) -> None:
    loop = asyncio.new_event_loop()
    pacer = RealtimePacer(loop, 0.002, speed)
    assert pacer.period == pytest.approx(period)
    for _ in range(5):
        pacer.wait_next_cycle()
    assert pacer.cycles == (0 if speed is None else 5)  # as fast as possible keeps no schedule
    loop.close()


@pytest.mark.parametrize("speed", [1.0, 5.0, 100.0])
def test_every_cycle_serves_the_links_whatever_the_speed(speed: float) -> None:
    # a period shorter than the quiet time before a cycle (0.5 ms) must not starve the servers
    loop = asyncio.new_event_loop()
    pacer = RealtimePacer(loop, 0.002, speed)
    served = 0

    async def server() -> None:
        nonlocal served
        while True:
            served += 1
            await asyncio.sleep(0)

    task = loop.create_task(server())
    for _ in range(20):
        pacer.wait_next_cycle()
    assert served >= 20
    task.cancel()
    loop.run_until_complete(asyncio.sleep(0))
    loop.close()


def test_statistics_from_start_errors() -> None:
    loop = asyncio.new_event_loop()
    pacer = RealtimePacer(loop, 0.002)
    for cycle, error in enumerate([0.0, 0.0001, 0.0, 0.0003]):  # seconds late at each cycle's start
        pacer.record(cycle * 0.002 + error, error, overrun=False, link_caused=False)
    stats = pacer.take_window()
    assert isinstance(stats, PacingStats)
    assert stats.cycles == 4
    assert stats.error_max_ms == pytest.approx(0.3)
    assert stats.period_error_max_ms == pytest.approx(0.3)  # from 0 to 0.3 ms late between two cycles
    assert stats.realtime_share == pytest.approx(0.006 / 0.0063)
    pacer.record(0.0100, 0.0021, overrun=True, link_caused=True)
    pacer.record(0.0121, 0.0, overrun=False, link_caused=False)
    pacer.record(0.0150, 0.0025, overrun=True, link_caused=False)
    window = pacer.take_window()
    assert (window.cycles, window.overruns, window.link_overruns) == (3, 2, 1)
    total = pacer.stats()
    assert (total.cycles, total.overruns, total.link_overruns) == (7, 2, 1)
    assert "2 overruns (1 while serving the links)" in str(total)
    loop.close()


def test_histogram_percentiles_to_a_microsecond_below_two_milliseconds() -> None:
    histogram = Histogram()
    for value_us in range(1, 101):
        histogram.add(value_us * 1e-6 - 1e-7)
    histogram.add(0.050)  # a long one: 0.1 ms bins
    histogram.add(5.0)  # beyond the last bin
    assert histogram.count == 102
    assert histogram.percentile(0.5) == pytest.approx(52e-6)
    assert histogram.percentile(0.99) == pytest.approx(0.0501)
    assert histogram.percentile(1.0) == histogram.max == 5.0
    assert Histogram().percentile(0.99) == 0.0


def test_the_pacers_memory_does_not_grow_with_the_cycles() -> None:
    """It kept one float per cycle: 1.2 MB a minute at 2 ms, 1.7 GB a day of vc serve --realtime."""
    loop = asyncio.new_event_loop()
    pacer = RealtimePacer(loop, 0.002)
    for cycle in range(1000):
        pacer.record(cycle * 0.002, 1e-5 * (cycle % 7), overrun=False, link_caused=False)
    tracemalloc.start()
    before = tracemalloc.get_traced_memory()[0]
    for cycle in range(1000, 51000):
        pacer.record(cycle * 0.002, 1e-5 * (cycle % 7), overrun=cycle % 5000 == 0, link_caused=False)
        if cycle % 5000 == 0:
            pacer.take_window()
    grown = tracemalloc.get_traced_memory()[0] - before
    tracemalloc.stop()
    assert pacer.stats().cycles == 51000
    # a float a cycle would be 1.6 MB; the histograms of a window take about 65 kB, whatever it counts
    assert grown < 150_000, f"{grown} bytes more after 50000 cycles"
    loop.close()


def test_percentile_of_nothing_is_zero() -> None:
    assert percentile([], 0.99) == 0.0
    assert percentile([3.0, 1.0, 2.0], 0.5) == 2.0


@pytest.mark.parametrize("speed", ["0", "fast", "1000"])
def test_a_bad_speed_is_refused_with_its_reason(speed: str, capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["serve", "--realtime", "--speed", speed, "--duration", "0.01"]) == 2
    assert "--speed" in capsys.readouterr().err
