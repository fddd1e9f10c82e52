"""A short version of each part of the robustness campaign (bench/robustness.py): a few hundred
inputs each against ``vc serve`` and ``python -m plc_stub`` in their own processes, on loopback
with ephemeral ports and UDP multicast channels of their own.  Each must end without a crash, a
hang, a traceback, a lost request or a rule violation.  Overruns and memory are figures of the
full campaign on a quiet machine, never asserted here."""

from __future__ import annotations

import pytest

from vc.bench.robustness.campaign import CampaignSettings, Row, table
from vc.bench.robustness.can_noise import run_can_noise
from vc.bench.robustness.control_characters import run_control_characters
from vc.bench.robustness.flood import run_flood
from vc.bench.robustness.modbus_fuzz import _Tally, run_modbus_fuzz
from vc.bench.robustness.s7_probe import run_s7_probe
from vc.bench.robustness.soak import run_soak

SHORT = CampaignSettings(modbus_frames=400, s7_requests=150, can_inputs=300, flood_seconds=2.0, flood_connections=8,
                         soak_minutes=0.1, seed=7)


def _clean(row: Row) -> None:
    assert (row.crashes, row.hangs, row.tracebacks, row.lost_requests or 0, row.violations) == (0, 0, 0, 0, 0), \
        table([row])
    assert row.inputs > 0


def test_modbus_fuzz() -> None:
    said: list[str] = []
    row = run_modbus_fuzz(SHORT, said.append)
    _clean(row)
    assert row.inputs >= SHORT.modbus_frames + 300  # and the 200 connections and 100 half-open ones
    assert any("pipelining" in line for line in said) and any("half-open" in line for line in said)
    assert not any("_Tally(" in line for line in said), said


def test_the_modbus_progress_reads_as_figures() -> None:
    tally = _Tally(frames=120, lost=1, hangs=0, violations=2, refused_connections=3)
    assert str(tally) == ("so far 120 frames, 1 lost, 0 hangs, 2 rule violations, 3 connections closed by the"
                          " server when full")


def test_modbus_flood() -> None:
    row = run_flood(SHORT, lambda text: None)
    _clean(row)
    assert "requests/s answered" in row.notes


def test_s7_probe() -> None:
    row = run_s7_probe(SHORT, lambda text: None)
    _clean(row)
    assert "block download(s) refused" in row.notes


def test_can_noise() -> None:
    row = run_can_noise(SHORT, lambda text: None)
    _clean(row)
    assert "lockstep scenario passed under noise" in row.notes
    assert "on the bus at the end" in row.notes  # error frames, bus-off among their classes, left the NC on the bus


@pytest.mark.timeout(120)
def test_soak() -> None:
    row = run_soak(SHORT, lambda text: None)
    _clean(row)
    assert row.rss_growth_pct is not None and "RSS server" in row.notes


def test_control_characters() -> None:
    """Names with control characters through vc run's console, JUnit, CSV, VCD, GTKWave and HTML outputs:
    nothing of them gets through (before the escaping: 77 findings)."""
    row = run_control_characters(SHORT, lambda text: None)
    _clean(row)
    assert row.inputs == 13
    assert row.notes.startswith("findings: terminal 0, JUnit 0, CSV 0, VCD 0, GTKWave 0, HTML 0; exit code 1")
