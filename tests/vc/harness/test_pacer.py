"""The real-time pacer's schedule and statistics (no timing is asserted: the figures of a shared
machine say nothing; `vc bench --link modbus` measures them)."""

from __future__ import annotations

import asyncio

import pytest

from vc.cli.main import main
from vc.harness.pacer import PacingStats, RealtimePacer, percentile

pytestmark = pytest.mark.realtime


@pytest.mark.parametrize(("speed", "period"), [(1.0, 0.002), (2.0, 0.001), (0.5, 0.004), (None, 0.0)])
def test_the_speed_factor_scales_the_wall_clock_period(speed: float | None, period: float) -> None:
    loop = asyncio.new_event_loop()
    pacer = RealtimePacer(loop, 0.002, speed)
    assert pacer.period == pytest.approx(period)
    for _ in range(5):
        pacer.wait_next_cycle()
    assert len(pacer.errors) == (0 if speed is None else 5)  # as fast as possible keeps no schedule
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
    pacer.errors = [0.0, 0.0001, 0.0, 0.0003]  # seconds late at each cycle's start
    stats = pacer.stats()
    assert isinstance(stats, PacingStats)
    assert stats.cycles == 4
    assert stats.error_max_ms == pytest.approx(0.3)
    assert stats.period_error_max_ms == pytest.approx(0.3)  # from 0 to 0.3 ms late between two cycles
    assert pacer.stats(since=3).cycles == 1
    loop.close()


def test_percentile_of_nothing_is_zero() -> None:
    assert percentile([], 0.99) == 0.0
    assert percentile([3.0, 1.0, 2.0], 0.5) == 2.0


@pytest.mark.parametrize("speed", ["0", "fast", "1000"])
def test_a_bad_speed_is_refused_with_its_reason(speed: str, capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["serve", "--realtime", "--speed", speed, "--duration", "0.01"]) == 2
    assert "--speed" in capsys.readouterr().err
