"""The whole scenario library with the PLC behind the lockstep CAN link gives the in-process golden
traces (``vc run --link can``).

The frames, the handshake and the PLC's node are the same whatever carries them, so the whole
library runs over a virtual bus with the PLC node in this process (every frame through python-can
and the codec); across processes, with ``python -m plc_stub --can`` on UDP multicast, runs one
scenario of every machine and PLC program, one PLC process serving them all in sequence."""

from __future__ import annotations

import io
from collections.abc import Callable
from pathlib import Path

import pytest
from rich.console import Console

from interfaces.links.inprocess import plc_programs
from vc.harness.can_link import VirtualCanPlc
from vc.harness.external_plc import CanPlcProcess
from vc.harness.scenarios import simulation_for
from vc.harness.simulation import Simulation
from vc.scenario.command import EXIT_PASSED, run_command
from vc.scenario.loader import load_scenarios
from vc.scenario.model import Scenario

ROOT = Path(__file__).resolve().parents[2]


@pytest.fixture(autouse=True)
def _in_repository(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(ROOT)


def _run(paths: list[str], make_target: Callable[[Scenario], Simulation]) -> tuple[int, str]:
    output = io.StringIO()
    code = run_command(paths, make_target, plc_programs().keys(), console=Console(file=output, width=200),
                       golden="tests/golden")
    return code, output.getvalue()


# The whole library runs here: the global 300 s hang guard is too short for it on a busy machine.
@pytest.mark.timeout(1200)
def test_the_library_over_a_virtual_can_bus_gives_the_in_process_golden_traces() -> None:
    with VirtualCanPlc() as virtual:
        def make(scenario: Scenario) -> Simulation:
            if scenario.plc_program is None or scenario.link is not None:
                return simulation_for(scenario)
            return virtual.simulation(scenario.machine, scenario.plc_program)

        code, output = _run(["scenarios"], make)
        sessions = virtual.link.session
        frames = virtual.link.bus.sent
    assert code == EXIT_PASSED, output
    assert sessions > 150  # one session per power-on of a scenario with a PLC
    assert frames > 500_000


def representatives() -> list[str]:
    """The first scenario (in file order) of every machine and PLC program the library uses."""
    first: dict[tuple[str, str], str] = {}
    for scenario in load_scenarios(["scenarios"], plc_programs().keys()):
        if scenario.plc_program is not None and scenario.link is None:
            first.setdefault((scenario.machine.name, scenario.plc_program), scenario.path)
    return list(first.values())


def test_one_scenario_of_each_machine_and_program_across_processes_gives_the_golden_traces() -> None:
    paths = representatives()
    assert len(paths) >= 9  # turn_mill with seven programs, mill_3axis and mill_5axis
    with CanPlcProcess() as process:
        code, output = _run(paths, process.target_factory())
        sessions = process.link.session
    assert code == EXIT_PASSED, output
    assert sessions >= len(paths)
