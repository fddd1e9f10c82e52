"""The whole scenario library with the PLC in its own process over the lockstep Modbus TCP link:
every scenario passes and matches the same golden trace as in-process (``vc run --link modbus``)."""

from __future__ import annotations

import io
from pathlib import Path

import pytest
from rich.console import Console

from interfaces.links.inprocess import plc_programs
from vc.harness.external_plc import PlcProcess
from vc.scenario.command import EXIT_PASSED, run_command

ROOT = Path(__file__).resolve().parents[2]


# The whole library runs here: the global 300 s hang guard is too short for it on a busy machine.
@pytest.mark.timeout(1200)
def test_the_library_over_modbus_gives_the_in_process_golden_traces(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(ROOT)
    output = io.StringIO()
    with PlcProcess() as process:
        code = run_command(["scenarios"], process.target_factory(), plc_programs().keys(),
                           console=Console(file=output, width=200), golden="tests/golden")
        sessions = process.link.session
    assert code == EXIT_PASSED, output.getvalue()
    assert sessions > 60  # one session per power-on of a scenario with a PLC
