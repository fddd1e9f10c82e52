"""A short version of the campaign's isolation part (vc/bench/robustness/isolation.py): busy processes
beside ``vc serve --realtime`` and ``python -m plc_stub``, without and with --cpu and --fifo.  The
figures are the full campaign's on a known host, never asserted here; the run must be clean and say
what each process got."""

from __future__ import annotations

import pytest

from vc.bench.robustness.campaign import CampaignSettings, table
from vc.bench.robustness.isolation import run_isolation

SHORT = CampaignSettings(flood_seconds=2.0, seed=7)


@pytest.mark.realtime
@pytest.mark.timeout(300)
def test_isolation() -> None:
    row = run_isolation(SHORT, lambda text: None)
    assert (row.crashes, row.hangs, row.tracebacks, row.violations) == (0, 0, 0, 0), table([row])
    assert row.inputs > 0
    assert "default: " in row.notes and "--cpu: " in row.notes and "--cpu --fifo: " in row.notes
    assert "server pinned to CPU" in row.notes and "PLC pinned to CPU" in row.notes
