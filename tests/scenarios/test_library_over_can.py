"""The whole scenario library with the PLC in its own process over the lockstep CAN link (UDP
multicast, a channel of this run): every scenario passes and matches the same golden trace as
in-process (``vc run --link can``)."""

from __future__ import annotations

import io
from pathlib import Path

import pytest
from rich.console import Console

from interfaces.links.inprocess import plc_programs
from vc.harness.external_plc import CanPlcProcess
from vc.scenario.command import EXIT_PASSED, run_command

ROOT = Path(__file__).resolve().parents[2]


def test_the_library_over_can_gives_the_in_process_golden_traces(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(ROOT)
    output = io.StringIO()
    with CanPlcProcess() as process:
        code = run_command(["scenarios"], process.target_factory(), plc_programs().keys(),
                           console=Console(file=output, width=200), golden="tests/golden")
        sessions = process.link.session
        frames = process.link.bus.sent
    assert code == EXIT_PASSED, output.getvalue()
    assert sessions > 60  # one session per power-on of a scenario with a PLC
    assert frames > 100_000
