"""The scenario library with the PLC in its own process over the lockstep Modbus TCP link: every
scenario passes and matches the same golden trace as in-process (``vc run --link modbus``).

One test per scenario, so a failure names its scenario and the tests spread over the test
workers; each worker keeps one ``python -m plc_stub`` process for all the scenarios it runs, as
``vc run --link modbus`` does."""

from __future__ import annotations

import io
from collections.abc import Iterator
from pathlib import Path

import pytest
from rich.console import Console

from interfaces.links.inprocess import plc_programs
from vc.harness.external_plc import PlcProcess
from vc.scenario.command import EXIT_PASSED, run_command
from vc.scenario.language.loader import load_scenarios, scenario_files

ROOT = Path(__file__).resolve().parents[2]
# the files, found without checking them at collection (each test's run checks its own file): a file
# with a matrix is one test that runs every variant, as in-process
FILES, _ = scenario_files([str(ROOT / "scenarios")])

pytestmark = pytest.mark.link


@pytest.fixture(scope="module")
def plc_process() -> Iterator[PlcProcess]:
    with PlcProcess() as process:
        yield process


@pytest.mark.parametrize("path", FILES, ids=[Path(path).stem for path in FILES])
def test_the_scenario_over_modbus_gives_the_in_process_golden_trace(path: str, plc_process: PlcProcess,
                                                                     monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(ROOT)
    relative = str(Path(path).relative_to(ROOT))
    output = io.StringIO()
    sessions_before = plc_process.link.session
    code = run_command([relative], plc_process.target_factory(), plc_programs().keys(),
                       console=Console(file=output, width=200), golden="tests/golden")
    assert code == EXIT_PASSED, output.getvalue()
    scenario = load_scenarios([relative], plc_programs().keys())[0]  # a matrix's variants share PLC and link
    if scenario.plc_program is not None and scenario.link is None:  # its PLC ran behind the link
        assert plc_process.link.session > sessions_before
