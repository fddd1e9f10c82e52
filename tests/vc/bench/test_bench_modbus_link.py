"""The Modbus link benchmarks, each run very briefly: structure and plausibility of the figures.

No speed targets here (the figures of one short run on a shared machine say nothing); the
targets are printed by ``vc bench --link modbus`` and recorded in bench/README.md.  Servers
and the PLC process listen on 127.0.0.1, ephemeral ports.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import pytest

from interfaces.links.modbus.codec import READ_LIMIT, WRITE_LIMIT, Table
from vc.bench import modbus_link
from vc.bench.modbus_link import (
    ExchangeClient,
    LinkBenchmark,
    ServerKind,
    ServerProcess,
    TableSizes,
    register_map_of,
    run_link_benchmark,
)
from vc.cli.main import main
from vc.config.loader import load_machine

ROOT = Path(__file__).resolve().parents[3]
TURN_MILL = str(ROOT / "scenarios" / "machines" / "turn_mill.yaml")
EXCHANGES = 20
LOCKSTEP_SECONDS = 1.0
REALTIME_SECONDS = 2.0
JSON_KEYS = {
    "exchange_median_us", "exchange_p99_us", "bare_median_us", "bare_p99_us", "exchange_ratio",
    "exchange_p99_ratio", "exchange_target_met", "lockstep_realtime_factor", "inprocess_realtime_factor",
    "realtime_period_error_p99_ms", "realtime_period_error_max_ms", "realtime_start_error_median_ms",
    "realtime_start_error_p99_ms", "realtime_overruns", "realtime_link_overruns", "realtime_cycles",
    "realtime_plc_scans",
    "realtime_sign_of_life_alarms", "realtime_longest_gc_pause_ms", "realtime_involuntary_switches",
    "realtime_target_met", "realtime_seconds",
}


@pytest.fixture(scope="module")
def lines_and_result() -> tuple[list[str], LinkBenchmark]:
    lines: list[str] = []
    result = run_link_benchmark(TURN_MILL, realtime_seconds=REALTIME_SECONDS, lockstep_seconds=LOCKSTEP_SECONDS,
                                exchanges=EXCHANGES, say=lines.append)
    return lines, result


@pytest.fixture(scope="module")
def result(lines_and_result: tuple[list[str], LinkBenchmark]) -> LinkBenchmark:
    return lines_and_result[1]


def test_an_exchange_reads_and_writes_the_whole_tables_in_the_largest_chunks(result: LinkBenchmark) -> None:
    register_map = register_map_of(load_machine(TURN_MILL))
    exchange = result.exchange
    assert exchange.nc_to_plc_registers == register_map.registers(Table.NC_TO_PLC)
    assert exchange.plc_to_nc_registers == register_map.registers(Table.PLC_TO_NC)
    assert exchange.requests_per_exchange == (math.ceil(exchange.nc_to_plc_registers / READ_LIMIT)
                                              + math.ceil(exchange.plc_to_nc_registers / WRITE_LIMIT))
    assert exchange.exchanges == EXCHANGES and len(exchange.round_ratios) == exchange.rounds


def test_the_round_trips_of_both_servers_are_plausible(result: LinkBenchmark) -> None:
    exchange = result.exchange
    assert 0 < exchange.median_us <= exchange.p99_us
    assert 0 < exchange.bare_median_us <= exchange.bare_p99_us
    assert exchange.median_ratio > 0 and exchange.p99_ratio > 0
    assert all(ratio > 0 for ratio in exchange.round_ratios)


def test_lockstep_runs_the_workload_over_the_link_and_in_process(result: LinkBenchmark) -> None:
    lockstep = result.lockstep
    assert lockstep.simulated_s >= LOCKSTEP_SECONDS and lockstep.inprocess_simulated_s >= LOCKSTEP_SECONDS
    assert lockstep.wall_s > 0 and lockstep.inprocess_wall_s > 0
    # one PLC scan per PLC period of 10 ms on the turn-mill, each exchanged over the link
    assert lockstep.scans == pytest.approx(lockstep.simulated_s / 0.010, abs=1)
    assert lockstep.realtime_factor > 0 and lockstep.inprocess_realtime_factor > 0


def test_real_time_paces_every_cycle_and_the_plc_process_scans(result: LinkBenchmark) -> None:
    realtime = result.realtime
    pacing = realtime.pacing
    assert realtime.ipo_cycle_ms == pytest.approx(2.0) and realtime.plc_period_ms == pytest.approx(10.0)
    assert realtime.wall_s >= REALTIME_SECONDS * 0.9  # paced, not as fast as possible
    assert pacing.cycles >= REALTIME_SECONDS / 0.002
    assert 0 <= pacing.period_error_p99_ms <= pacing.period_error_max_ms
    assert pacing.error_median_ms <= pacing.error_p99_ms <= pacing.error_max_ms
    assert realtime.plc_scans > 0 and realtime.plc_writes > 0  # the PLC process was alive and wrote


def test_each_measurement_says_its_figures_and_the_targets(lines_and_result: tuple[list[str], LinkBenchmark]) -> None:
    lines, _ = lines_and_result
    text = "\n".join(lines)
    assert text.startswith("exchange:")
    assert "target <= 1.3" in text and "target p99 < 0.5 ms" in text
    assert "lockstep:" in text and "real time:" in text


def test_the_cli_prints_the_figures_as_the_last_line_in_json(
        result: LinkBenchmark, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]) -> None:
    asked: dict[str, object] = {}

    def measured(machine_path: str, **options: object) -> LinkBenchmark:
        asked.update(options, machine_path=machine_path)
        return result  # the measurements ran once, for the whole module

    monkeypatch.setattr(modbus_link, "run_link_benchmark", measured)
    assert main(["bench", "--link", "modbus", "--machine", TURN_MILL, "--seconds", "5", "--exchanges", "40"]) == 0
    assert asked["realtime_seconds"] == 5.0 and asked["exchanges"] == 40 and asked["lockstep_seconds"] == 10.0
    figures = json.loads(capsys.readouterr().out.strip().splitlines()[-1])
    assert set(figures) == JSON_KEYS
    for name, value in figures.items():
        if isinstance(value, bool):
            continue
        assert isinstance(value, int | float), name
        assert value >= 0, name
    for name in ("exchange_median_us", "bare_median_us", "exchange_ratio", "lockstep_realtime_factor",
                 "inprocess_realtime_factor", "realtime_cycles", "realtime_plc_scans", "realtime_seconds"):
        assert figures[name] > 0, name


@pytest.mark.parametrize("kind", list(ServerKind))
def test_a_server_process_answers_and_ends_cleanly(kind: ServerKind) -> None:
    sizes = TableSizes.of(register_map_of(load_machine(TURN_MILL)))
    with ServerProcess(kind, sizes) as server, ExchangeClient(server.port, sizes) as client:
        client.exchange()
    assert server.process.exitcode == 0
