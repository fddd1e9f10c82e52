"""The whole scenario library with the PLC behind the lockstep CAN link gives the in-process golden
traces (``vc run --link can``).

The frames, the handshake and the PLC's node are the same whatever carries them, so the whole
library runs over a virtual bus with the PLC node in this process (every frame through python-can
and the codec); across processes, with ``python -m plc_stub --can`` on UDP multicast, runs one
scenario of every machine and PLC program, one PLC process serving them all in sequence."""

from __future__ import annotations

import io
from collections.abc import Callable, Iterator
from pathlib import Path

import pytest
from rich.console import Console

from interfaces.links.inprocess import plc_programs
from vc.harness.external_plc import CanPlcProcess
from vc.harness.links.can import VirtualCanPlc
from vc.harness.targets import simulation_for
from vc.scenario.command import EXIT_PASSED, run_command
from vc.scenario.language.loader import load_scenarios, scenario_files
from vc.scenario.language.model import Scenario
from vc.simulation.lockstep import Simulation

ROOT = Path(__file__).resolve().parents[2]
LIBRARY = [str(Path(path).relative_to(ROOT)) if Path(path).is_absolute() else path
           for path in scenario_files([str(ROOT / "scenarios")])[0]]

pytestmark = pytest.mark.link


@pytest.fixture(autouse=True)
def _in_repository(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(ROOT)


def _run(paths: list[str], make_target: Callable[[Scenario], Simulation]) -> tuple[int, str]:
    output = io.StringIO()
    code = run_command(paths, make_target, plc_programs().keys(), console=Console(file=output, width=200),
                       golden="tests/golden")
    return code, output.getvalue()


@pytest.fixture(scope="module")
def virtual_plc() -> Iterator[VirtualCanPlc]:
    with VirtualCanPlc() as virtual:
        yield virtual


@pytest.mark.parametrize("path", LIBRARY, ids=[Path(path).stem for path in LIBRARY])
def test_the_scenario_over_a_virtual_can_bus_gives_the_in_process_golden_trace(
        path: str, virtual_plc: VirtualCanPlc) -> None:
    sessions, frames = virtual_plc.link.session, virtual_plc.link.bus.sent
    behind_the_bus: list[str] = []

    def make(scenario: Scenario) -> Simulation:
        if scenario.plc_program is None or scenario.link is not None:
            return simulation_for(scenario)
        behind_the_bus.append(scenario.path)
        return virtual_plc.simulation(scenario.machine, scenario.plc_program)

    code, output = _run([path], make)
    assert code == EXIT_PASSED, output
    if behind_the_bus:  # a new session per power-on, and the interface went through frames
        assert virtual_plc.link.session > sessions
        assert virtual_plc.link.bus.sent > frames


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
