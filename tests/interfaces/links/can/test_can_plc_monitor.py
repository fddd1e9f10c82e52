"""The PLC's time-out monitor of the NC's frames: scans in lockstep, its own clock free-running."""

from __future__ import annotations

from types import SimpleNamespace
from typing import Any

import pytest

from interfaces.links.can import plc_end as can_plc
from interfaces.signals import Direction


def _session(lockstep: bool, arrived_at: float) -> Any:
    layout = SimpleNamespace(slots={Direction.NC_TO_PLC: [SimpleNamespace(area="DB31", start=0, stop=2)]})
    areas = {"DB31": bytearray(b"\x01\x02")}
    return can_plc._Session(1, lockstep, None, layout, None, None, None, areas,  # type: ignore[arg-type]
                            timeout_s=0.05, scan_s=0.01, arrived={0x200: arrived_at})


def test_in_lockstep_the_monitor_counts_the_scans_as_the_nc_s_plc_period() -> None:
    session = _session(lockstep=True, arrived_at=0.0)
    session.scans = 5
    assert not session.watch()  # 50 ms: not longer than the time-out
    session.scans = 6
    assert session.watch() and session.areas["DB31"] == bytearray(2)  # substitute values 0


def test_free_running_the_monitor_uses_the_wall_clock_whatever_the_scan_rate(monkeypatch: pytest.MonkeyPatch) -> None:
    clock = [100.0]
    monkeypatch.setattr(can_plc.wallclock, "monotonic", lambda: clock[0])
    session = _session(lockstep=False, arrived_at=100.0)
    session.scans = 1000  # a PLC scanning every millisecond: 1000 scans are 1 s, not 10 s of the NC
    clock[0] = 100.04
    assert not session.watch()
    clock[0] = 100.06
    assert session.watch()
