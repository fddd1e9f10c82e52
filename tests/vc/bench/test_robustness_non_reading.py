"""A short version of the campaign's non-reading part (vc/bench/robustness/non_reading.py): clients
that pipeline reads and never take their answers, while the PLC scans and a client reads; the
server's memory stays within its bound.  ``vc serve`` and ``python -m plc_stub`` in their own
processes on loopback with ephemeral ports."""

from __future__ import annotations

import pytest

from vc.bench.robustness.campaign import CampaignSettings, table
from vc.bench.robustness.non_reading import run_non_reading

SHORT = CampaignSettings(flood_seconds=2.0, flood_connections=4, seed=7)


@pytest.mark.timeout(180)
def test_non_reading_clients() -> None:
    row = run_non_reading(SHORT, lambda text: None)
    assert (row.crashes, row.hangs, row.tracebacks, row.lost_requests, row.violations) == (0, 0, 0, 0, 0), table([row])
    assert row.inputs > 0
    assert "a client reading meanwhile" in row.notes and "0 lost" in row.notes
