"""Faults of the CAN bus from scenarios (scenarios/can, ``link: can``): each shows its
documented reaction of the NC, with the PLC behind a virtual bus in this process (``vc run``) and
in its own process over UDP multicast (``vc run --link can``), and both runs leave the same trace."""

from __future__ import annotations

import io
from pathlib import Path

import pytest
from rich.console import Console

from interfaces.links.inprocess import plc_programs
from vc.harness.external_plc import CanPlcProcess, PlcProcess
from vc.harness.targets import simulation_for
from vc.scenario.command import EXIT_PASSED, run_command
from vc.scenario.language.loader import scenario_files

ROOT = Path(__file__).resolve().parents[2]
FAULTS = "scenarios/can"


def _run(make_target, **options: object) -> tuple[int, str]:  # type: ignore[no-untyped-def]
    output = io.StringIO()
    code = run_command([FAULTS], make_target, plc_programs().keys(), console=Console(file=output, width=200),
                       **options)  # type: ignore[arg-type]
    return code, output.getvalue()


@pytest.fixture(autouse=True)
def _in_repository(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(ROOT)


def test_the_fault_scenarios_cover_loss_delay_and_bus_off() -> None:
    texts = [Path(path).read_text(encoding="utf-8") for path in scenario_files([FAULTS])[0]]
    for kind in ("kind: loss", "kind: delay", "kind: bus_off", "every:", "frames:"):
        assert any(kind in text for text in texts), kind
    # each shows the NC's reaction: the sign-of-life alarm, or (a tolerated loss) that none comes
    assert all("link: can" in text and ("alarm(2000)" in text or "expect_no_alarm: all" in text) for text in texts)


def test_the_fault_scenarios_give_the_same_traces_on_a_virtual_bus_and_across_processes(tmp_path: Path) -> None:
    code, output = _run(simulation_for, golden=str(tmp_path), update_golden=True)
    assert code == EXIT_PASSED, output
    with CanPlcProcess() as process:
        code, output = _run(process.target_factory(), golden=str(tmp_path))
    assert code == EXIT_PASSED, output


def test_a_run_over_modbus_keeps_the_can_scenarios_on_a_virtual_bus() -> None:
    with PlcProcess() as process:
        code, output = _run(process.target_factory())
        sessions = process.link.session
    assert code == EXIT_PASSED, output
    assert sessions == 0  # none of them went over Modbus
