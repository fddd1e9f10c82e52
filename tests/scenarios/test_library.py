"""The shipped scenario library as regression tests: every scenario passes and behaves as
its golden trace says (tests/golden, compared by meaning; rewrite them with
``vc run scenarios/ --golden tests/golden --update-golden``)."""

from __future__ import annotations

import copy
import io
from pathlib import Path

import pytest
from rich.console import Console

from interfaces.links.inprocess import plc_programs
from vc.harness.targets import simulation_for
from vc.scenario.command import EXIT_FAILED, EXIT_PASSED, run_command
from vc.scenario.language.loader import load_scenario, scenario_files
from vc.scenario.outputs.golden import GoldenCheck, GoldenSummary, compare, golden_path, load, store, summarize
from vc.scenario.run.runner import run_scenario

ROOT = Path(__file__).resolve().parents[2]
LIBRARY = ROOT / "scenarios"
GOLDEN = ROOT / "tests" / "golden"
FILES, _ = scenario_files([str(LIBRARY.relative_to(ROOT))])


def _run(paths: list[str], **options: object) -> tuple[int, str]:
    output = io.StringIO()
    code = run_command(paths, simulation_for, plc_programs().keys(), console=Console(file=output, width=200),
                       **options)  # type: ignore[arg-type]
    return code, output.getvalue()


@pytest.fixture(autouse=True)
def _in_repository(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(ROOT)


def test_the_library_has_the_foundation_scenarios() -> None:
    names = {Path(path).name for path in FILES}
    assert {"jog_traverse.yaml", "mda_feed_override.yaml", "reset_during_move.yaml", "feed_stop.yaml",
            "software_limit_jog.yaml", "emergency_stop.yaml"} <= names


@pytest.mark.parametrize("path", FILES, ids=[Path(p).stem for p in FILES])
def test_scenario_passes_and_matches_its_golden_trace(path: str) -> None:
    code, output = _run([path], golden=str(GOLDEN))
    assert code == EXIT_PASSED, output


def _summary_of(path: str) -> GoldenSummary:
    scenario = load_scenario(path, plc_programs().keys())
    result = run_scenario(scenario, simulation_for(scenario))
    assert result.passed and result.recorder is not None
    alarms = [alarm.number for alarm in result.recorder.target.alarm_history()]
    return summarize(result.recorder, alarms)


def test_a_changed_behaviour_is_caught_by_meaning() -> None:
    path = "scenarios/foundation/emergency_stop.yaml"
    actual = _summary_of(path)
    golden = load(golden_path(GOLDEN, path))
    assert golden is not None and compare(golden, actual, 0.01) == []

    later = copy.deepcopy(golden)
    times = later.digital["NC.basic.in.emergencyStopActive"]
    times[1] = (times[1][0] + 0.05, times[1][1])  # 50 ms later than before: more than one PLC scan
    assert compare(later, actual, 0.01) == [
        f"NC.basic.in.emergencyStopActive became 1 at {actual.digital['NC.basic.in.emergencyStopActive'][1][0]:.3f} s,"
        f" golden {times[1][0]:.3f} s (tolerance 10 ms)"]

    within_a_scan = copy.deepcopy(golden)
    times = within_a_scan.digital["NC.basic.in.emergencyStopActive"]
    times[1] = (times[1][0] + 0.008, times[1][1])
    assert compare(within_a_scan, actual, 0.01) == []

    no_alarm = copy.deepcopy(golden)
    no_alarm.alarms.clear()
    assert compare(no_alarm, actual, 0.01) == ["alarms raised: expected [], got [3000]"]


def test_a_missing_or_different_golden_trace_fails_the_run(tmp_path: Path) -> None:
    path = "scenarios/foundation/nc_start_without_reference.yaml"
    code, output = _run([path], golden=str(tmp_path))
    assert code == EXIT_FAILED
    assert "no golden trace" in output and "--update-golden" in output

    code, _ = _run([path], golden=str(tmp_path), update_golden=True)
    assert code == EXIT_PASSED
    stored = golden_path(tmp_path, path)
    summary = load(stored)
    assert summary is not None and summary.alarms == [10203]
    summary.alarms.append(3000)
    store(summary, stored)
    code, output = _run([path], golden=str(tmp_path))
    assert code == EXIT_FAILED
    assert "differs from the golden trace" in output and "alarms raised: expected [10203, 3000], got [10203]" in output


def test_golden_paths_drop_the_library_directory() -> None:
    assert golden_path("tests/golden", "scenarios/foundation/jog.yaml") == Path("tests/golden/foundation/jog.json")
    assert isinstance(GoldenCheck(Path("x")), GoldenCheck)


def test_a_relation_error_the_scenario_names_is_kept_in_its_golden_trace() -> None:
    path = "scenarios/sync_spindle/polygon_turning_p2_q6.yaml"
    actual = _summary_of(path)
    golden = load(golden_path(GOLDEN, path))
    assert golden is not None and compare(golden, actual, 0.01) == []
    end, lowest, highest = golden.quantities["SP3.couplingRelationError"]
    assert end == 0.0 and -0.5 <= lowest <= highest <= 0.5  # within MD37210 throughout
    assert GoldenSummary.from_json(golden.to_json()) == golden

    disturbed = copy.deepcopy(golden)
    disturbed.quantities["SP3.couplingRelationError"] = (end, -0.7, highest)
    assert compare(disturbed, actual, 0.01) == [
        f"SP3.couplingRelationError lowest: expected -0.7000, got {lowest:.4f}"]
    unnamed = load(golden_path(GOLDEN, "scenarios/foundation/emergency_stop.yaml"))
    assert unnamed is not None and "quantities" not in unnamed.to_json()
