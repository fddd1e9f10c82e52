"""A short version of the campaign's session-takeover part (vc/bench/robustness/takeover.py): the
PLC killed in a JOG, every claim a local process can make refused, the restarted PLC refused until
the operator's new session, then its owner.  ``vc serve`` and ``python -m plc_stub`` in their own
processes on loopback with ephemeral ports."""

from __future__ import annotations

import pytest

from vc.bench.robustness.campaign import CampaignSettings, table
from vc.bench.robustness.takeover import run_session_takeover

SHORT = CampaignSettings(modbus_frames=400, seed=7)  # 60 attempts


@pytest.mark.timeout(240)
def test_session_takeover() -> None:
    row = run_session_takeover(SHORT, lambda text: None)
    assert (row.crashes, row.hangs, row.tracebacks, row.lost_requests, row.violations) == (0, 0, 0, 0, 0), table([row])
    assert row.inputs == 60
    assert "0 of 60 attempts taken" in row.notes
    assert "was refused until the operator's new session, then owned session 2" in row.notes
