"""``vc run -j N``: worker processes give the report, the JUnit file and the traces of a serial run."""

from __future__ import annotations

import io
import os
import re
import signal
import subprocess
import sys
from pathlib import Path

import pytest
from rich.console import Console

from interfaces.links.inprocess import plc_programs
from vc.harness.targets import simulation_for
from vc.scenario.command import EXIT_FAILED, EXIT_INTERRUPTED, EXIT_PASSED, run_command
from vc.scenario.model import Scenario
from vc.simulation.lockstep import Simulation

ROOT = Path(__file__).resolve().parents[3]
FOUNDATION = "scenarios/foundation"
WALL_TIME = re.compile(r"\d+\.\d+ s wall")


@pytest.fixture(autouse=True)
def _in_repository(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(ROOT)


def _run(paths: list[str], jobs: int, tmp: Path, make_target: object = simulation_for) -> tuple[int, str]:
    output = io.StringIO()
    code = run_command(paths, make_target, plc_programs().keys(),  # type: ignore[arg-type]
                       console=Console(file=output, width=300), junit=tmp / "junit.xml", trace_dir=tmp / "traces",
                       golden="tests/golden", jobs=jobs)
    return code, output.getvalue()


def _without_times(text: str) -> str:
    return WALL_TIME.sub("WALL", re.sub(r'time="[0-9.]+"', 'time="T"', text))


def test_workers_give_the_serial_report_junit_and_traces(tmp_path: Path) -> None:
    serial, parallel = tmp_path / "serial", tmp_path / "parallel"
    serial_code, serial_report = _run([FOUNDATION], 1, serial)
    parallel_code, parallel_report = _run([FOUNDATION], 2, parallel)
    assert serial_code == parallel_code == EXIT_PASSED, parallel_report
    assert _without_times(parallel_report) == _without_times(serial_report)
    parallel_junit = (parallel / "junit.xml").read_text().replace(str(parallel), str(serial))
    assert _without_times(parallel_junit) == _without_times((serial / "junit.xml").read_text())
    traces = sorted(path.name for path in (serial / "traces").iterdir())
    assert len(traces) >= 2 * 10
    assert traces == sorted(path.name for path in (parallel / "traces").iterdir())
    for name in traces:
        assert (parallel / "traces" / name).read_bytes() == (serial / "traces" / name).read_bytes(), name


def test_a_failure_is_reported_in_file_order_with_its_location(tmp_path: Path) -> None:
    failing = tmp_path / "failing.yaml"
    failing.write_text((ROOT / FOUNDATION / "jog_traverse.yaml").read_text().replace(
        "machine: ../machines/", f"machine: {ROOT}/scenarios/machines/") + "  - expect: {X1.position: 12345}\n")
    code, report = _run([FOUNDATION, str(failing)], 2, tmp_path)
    assert code == EXIT_FAILED
    lines = [line for line in report.splitlines() if line.startswith(("PASS", "FAIL"))]
    assert lines[-1].startswith("FAIL") and "failing.yaml" in lines[-1]
    assert f"{failing}:" in report and "12345" in report


def _dies_the_first_time(scenario: Scenario) -> Simulation:
    """A target factory whose worker process dies at the first scenario it builds (once per run)."""
    marker = Path(os.environ["VC_TEST_DIE_MARKER"])
    if scenario.path.endswith("feed_stop.yaml") and not marker.exists():
        marker.write_text("died")
        os._exit(9)
    return simulation_for(scenario)


def test_a_worker_that_dies_costs_no_scenario(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    marker = tmp_path / "died"
    monkeypatch.setenv("VC_TEST_DIE_MARKER", str(marker))
    code, report = _run([FOUNDATION], 2, tmp_path, _dies_the_first_time)
    assert marker.exists()  # a worker did die
    assert code == EXIT_PASSED, report
    assert "feed_stop.yaml" in report


def test_ctrl_c_stops_the_workers_and_says_how_far_the_run_got() -> None:
    process = subprocess.Popen([sys.executable, "-m", "vc.cli.main", "run", "scenarios", "-j", "2"], cwd=ROOT,
                               stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    assert process.stdout is not None
    seen = []
    for line in process.stdout:
        seen.append(line)
        if line.startswith("PASS"):  # the workers are running
            process.send_signal(signal.SIGINT)
            break
    rest, _ = process.communicate(timeout=60)
    assert process.returncode == EXIT_INTERRUPTED, "".join(seen) + rest
    assert re.search(r"interrupted after \d+ of \d+ scenarios", rest), rest
