"""Golden traces are named by the scenario's path below its scenario root (the nearest directory marked with
``.vc-scenario-root``, else the scenario's own directory): the same file whatever directory ``vc run`` runs
from and however the path is spelt, and never outside the golden directory."""

from __future__ import annotations

import io
import os
from pathlib import Path

import pytest
from rich.console import Console

from interfaces.links.inprocess import plc_programs
from vc.harness.targets import simulation_for
from vc.scenario.command import EXIT_FAILED, EXIT_PASSED, EXIT_PROBLEMS, run_command
from vc.scenario.outputs.golden import ROOT_MARKER, golden_path, scenario_root

ROOT = Path(__file__).resolve().parents[4]
GOLDEN = ROOT / "tests" / "golden"
SHORT = "name: {name}\nmachine: turn_mill\nplc: basic_machine\nsteps:\n  - wait: 20ms\n"


def _run(paths: list[str], golden: str, update: bool = False) -> tuple[int, str]:
    output = io.StringIO()
    code = run_command(paths, simulation_for, plc_programs().keys(), console=Console(file=output, width=300),
                       golden=golden, update_golden=update)
    return code, output.getvalue()


@pytest.mark.parametrize(("directory", "path"), [
    (".", "scenarios/foundation/jog_traverse.yaml"),
    (".", "./scenarios/foundation/../foundation/jog_traverse.yaml"),
    (".", str(ROOT / "scenarios/foundation/jog_traverse.yaml")),
    ("scenarios", "foundation/jog_traverse.yaml"),
    ("scenarios/foundation", "jog_traverse.yaml"),
    ("tests", "../scenarios/foundation/jog_traverse.yaml"),
], ids=["from-the-project", "dotted", "absolute", "from-scenarios", "from-its-directory", "from-tests"])
def test_the_golden_trace_is_the_same_file_however_the_scenario_is_named(
        directory: str, path: str, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(ROOT / directory)
    assert golden_path(GOLDEN, path) == GOLDEN / "foundation" / "jog_traverse.json"
    golden = os.path.relpath(GOLDEN)
    code, output = _run([path], golden)
    assert code == EXIT_PASSED, output


def test_the_project_marks_its_scenario_trees() -> None:
    for tree in ("scenarios", "examples", "campaigns"):
        assert (ROOT / tree / ROOT_MARKER).is_file()
    assert scenario_root(str(ROOT / "examples/awlsim/turn_mill_bringup.yaml")) == ROOT / "examples"
    assert golden_path(GOLDEN, str(ROOT / "examples/awlsim/turn_mill_bringup.yaml")).is_file()


def test_a_path_that_climbs_out_writes_inside_the_golden_directory(tmp_path: Path,
                                                                   monkeypatch: pytest.MonkeyPatch) -> None:
    (tmp_path / "s").mkdir()
    (tmp_path / "s" / "x.yaml").write_text(SHORT.format(name="x"))
    deep = tmp_path / "a" / "b" / "c"
    deep.mkdir(parents=True)
    monkeypatch.chdir(deep)
    code, output = _run(["../../../s/x.yaml"], "golden", update=True)
    assert code == EXIT_PASSED, output
    written = sorted(str(path.relative_to(tmp_path)) for path in tmp_path.rglob("*.json"))
    assert written == ["a/b/c/golden/x.json"]
    assert _run(["../../../s/x.yaml"], "golden")[0] == EXIT_PASSED


def test_two_scenarios_that_would_share_a_golden_trace_are_a_problem_until_their_tree_is_marked(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    for group in ("one", "two"):
        (tmp_path / group).mkdir()
        (tmp_path / group / "x.yaml").write_text(SHORT.format(name=group))
    monkeypatch.chdir(tmp_path)
    code, output = _run(["one", "two"], "golden", update=True)
    assert code == EXIT_PROBLEMS
    assert output.strip() == (f"vc run --golden: one/x.yaml and two/x.yaml would share the golden trace golden/x.json:"
                              f" put a file {ROOT_MARKER} into the directory that holds their tree (docs/scenarios.md)")
    (tmp_path / ROOT_MARKER).write_text("")
    code, output = _run(["one", "two"], "golden", update=True)
    assert code == EXIT_PASSED, output
    assert sorted(str(path.relative_to(tmp_path)) for path in tmp_path.rglob("*.json")) == [
        "golden/one/x.json", "golden/two/x.json"]


def test_a_missing_golden_trace_names_the_root_it_was_named_from(tmp_path: Path,
                                                                 monkeypatch: pytest.MonkeyPatch) -> None:
    (tmp_path / "x.yaml").write_text(SHORT.format(name="x"))
    monkeypatch.chdir(tmp_path)
    code, output = _run(["x.yaml"], "golden")
    assert code == EXIT_FAILED
    assert f"no golden trace golden/x.json (named by the scenario's path below its scenario root {tmp_path});" \
           in output
