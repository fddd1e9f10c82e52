"""``vc run -j N``: worker processes give the report, the JUnit file and the traces of a serial run."""

from __future__ import annotations

import io
import os
import re
import signal
import subprocess
import sys
import xml.etree.ElementTree as ElementTree
from pathlib import Path

import pytest
from rich.console import Console

from interfaces.links.inprocess import plc_programs
from vc.harness.targets import simulation_for
from vc.scenario.command import EXIT_FAILED, EXIT_INTERRUPTED, EXIT_PASSED, run_command
from vc.scenario.distribution.tasks import SEND_ALL, SEND_DIAGRAM, RunSettings
from vc.scenario.language.model import Scenario
from vc.simulation.lockstep import Simulation

ROOT = Path(__file__).resolve().parents[4]
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


def _dies_once_in_each(scenario: Scenario) -> Simulation:
    """A target factory whose worker process dies at the first build of each of two scenarios."""
    for stem in ("feed_stop", "mode_changes"):
        marker = Path(os.environ["VC_TEST_DIE_MARKER"] + stem)
        if scenario.path.endswith(f"{stem}.yaml") and not marker.exists():
            marker.write_text("died")
            os._exit(9)
    return simulation_for(scenario)


def _always_dies_in_feed_stop(scenario: Scenario) -> Simulation:
    if scenario.path.endswith("feed_stop.yaml"):
        os._exit(9)
    return simulation_for(scenario)


WORKER = r"\S+:\d+"  # host:pid, the one way workers are named


def test_two_workers_that_die_cost_only_what_they_held_and_are_named(tmp_path: Path,
                                                                     monkeypatch: pytest.MonkeyPatch) -> None:
    """Before, each death broke the pool and charged every pending scenario an attempt: after two deaths
    the scenarios that never ran were errors ("died 2 times")."""
    monkeypatch.setenv("VC_TEST_DIE_MARKER", str(tmp_path / "died-"))
    code, report = _run([FOUNDATION], 2, tmp_path, _dies_once_in_each)
    assert code == EXIT_PASSED, report
    assert "15 passed, 0 failed, 0 errors of 15 scenarios" in report
    reruns = [line for line in report.splitlines() if line.startswith("re-run: ")]
    assert len(reruns) == 2, report
    for line, scenario in zip(reruns, ("Feed stop", "Mode changes"), strict=True):
        assert re.fullmatch(rf"re-run: {scenario}.*: the worker {WORKER} died while it had this task;"
                            rf" it ran again on {WORKER}", line), line


def test_a_scenario_whose_worker_dies_twice_is_the_only_error(tmp_path: Path) -> None:
    code, report = _run([FOUNDATION], 2, tmp_path, _always_dies_in_feed_stop)
    assert code == EXIT_FAILED
    assert "14 passed, 0 failed, 1 errors of 15 scenarios" in report, report
    assert "the worker process running this scenario died 2 times (killed or out of memory)" in report
    (rerun,) = [line for line in report.splitlines() if line.startswith("re-run: ")]
    assert re.fullmatch(rf"re-run: Feed stop.*: the worker {WORKER}, {WORKER} died while it had this task;"
                        " it did not finish on any worker", rerun), rerun


@pytest.mark.parametrize("jobs", ["2", "1"])
def test_ctrl_c_stops_the_workers_and_keeps_the_junit_and_the_report_of_what_finished(jobs: str,
                                                                                       tmp_path: Path) -> None:
    junit, page = tmp_path / "junit.xml", tmp_path / "report" / "index.html"
    process = subprocess.Popen([sys.executable, "-m", "vc.cli.main", "run", "scenarios", "-j", jobs, "--junit",
                                str(junit), "--report", str(tmp_path / "report")], cwd=ROOT,
                               stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    assert process.stdout is not None
    seen = []
    for line in process.stdout:
        seen.append(line)
        if line.startswith("PASS"):  # the workers are running
            process.send_signal(signal.SIGINT)
            break
    rest, _ = process.communicate(timeout=120)
    assert process.returncode == EXIT_INTERRUPTED, "".join(seen) + rest
    found = re.search(r"interrupted after (\d+) of (\d+) scenarios", rest)
    assert found is not None, rest
    finished, total = int(found.group(1)), int(found.group(2))
    assert 1 <= finished < total
    suite = ElementTree.parse(junit).getroot().find("testsuite")
    assert suite is not None and suite.get("tests") == str(total) and suite.get("skipped") == str(total - finished)
    interrupted = suite.find("properties/property[@name='interrupted']")
    assert interrupted is not None and f"after {finished} of {total}" in str(interrupted.get("value"))
    skipped = suite.findall("testcase/skipped")
    assert len(skipped) == total - finished and all("interrupted" in str(s.get("message")) for s in skipped)
    text = page.read_text(encoding="utf-8")
    assert f"The run was interrupted (Ctrl-C) after {finished} of {total} scenarios" in text


def test_a_worker_records_everything_only_for_traces_golden_traces_or_the_report() -> None:
    plain = RunSettings(("basic_machine",), simulation_for)
    assert not plain.records_all
    for asked in (RunSettings(("basic_machine",), simulation_for, trace_dir="traces"),
                  RunSettings(("basic_machine",), simulation_for, golden="tests/golden"),
                  RunSettings(("basic_machine",), simulation_for, send_back=SEND_DIAGRAM),
                  RunSettings(("basic_machine",), simulation_for, send_back=SEND_ALL)):
        assert asked.records_all
