"""``vary:`` and campaign files: each variant a checked scenario with a stable id, ``${...}`` filled in,
every problem of every variant located before anything runs."""

from __future__ import annotations

from pathlib import Path

import pytest

from interfaces.links.inprocess import plc_programs
from vc.config.md_dictionary import JOG_VELO
from vc.located_yaml import SourceError
from vc.scenario.language.loader import load_scenarios
from vc.scenario.language.model import ExpectValues, InjectFault, Scenario, SetValues
from vc.scenario.language.placeholders import PlaceholderError, fill, shown
from vc.scenario.outputs.golden import golden_file, golden_path
from vc.scenario.run.runner import trace_names

ROOT = Path(__file__).resolve().parents[4]
FILES = Path(__file__).resolve().parents[1] / "campaign_files"
MACHINE = ROOT / "scenarios" / "machines" / "turn_mill.yaml"
PROGRAMS = plc_programs().keys()

HEAD = f"""name: jog
machine: {MACHINE}
plc: basic_machine
timeout: 10s
"""
STEPS = """steps:
  - set: {MCP.feedOverride: "${override}"}
  - press: MCP.jog
  - hold: MCP.plus.X1
  - wait: 300ms
  - expect: {X1.velocity: "${20 * override} +- 0.01"}
  - release: MCP.plus.X1
"""


def _load(tmp_path: Path, text: str, name: str = "s.yaml", **options: object) -> list[Scenario]:
    path = tmp_path / name
    path.write_text(text, encoding="utf-8")
    return load_scenarios([str(path)], PROGRAMS, **options)  # type: ignore[arg-type]


def _problems(tmp_path: Path, text: str, name: str = "s.yaml") -> list[str]:
    with pytest.raises(SourceError) as caught:
        _load(tmp_path, text, name)
    return [str(problem) for problem in caught.value.problems]


# ---------------------------------------------------------------------------------- placeholders


def test_a_placeholder_alone_gives_the_value_itself_and_inside_a_text_its_text() -> None:
    values = {"X1.plant.ref_cam": [280, 295], "side": -1, "override": 50, "X1.MD34100[0]": 273.5}
    assert fill("${override}", values) == 50
    assert fill("${X1.plant.ref_cam}", values) == [280, 295]
    assert fill("${X1.plant.ref_cam[0] + 7 * side} +- 0.001", values) == "273 +- 0.001"
    assert fill("${X1.MD34100[0]}", values) == 273.5  # a varied item of an array
    assert fill("${5000 * override / 100}", values) == 2500.0
    assert fill("< ${-(override - 60) / 4}", values) == "< 2.5"
    used: set[str] = set()
    fill("${override} and ${side}", values, used)
    assert used == {"override", "side"}
    assert shown(2500.0) == "2500" and shown(0.1 + 0.2) == "0.3" and shown({"axis": "X1"}) == "{axis: X1}"


@pytest.mark.parametrize(("text", "message", "column"), [
    ("${nope}", "'nope' is not varied (varied: override, cam)", 1),
    ("x ${override / (override - 50)}", "division by zero", 3),
    ("${override +}", "is not a varied key or arithmetic", 1),
    ("${cam[5]}", "[5] is outside the list [1, 2]", 1),
    ("${override[0]}", "[0] needs a list, and the value is 50", 1),
    ("${__import__('os')}", "is not a varied key or arithmetic of them (+ - * /): unexpected ''' at column 12", 1),
    ("${abs(override)}", "'abs(' calls a function", 1),
    ("${cam + 1}", "'+' needs numbers, and [1, 2] is not one", 1),
    ("a ${override", "'${' without its closing '}'", 3),
    ("${ }", "is empty", 1),
])
def test_a_placeholder_that_cannot_be_filled_says_why_and_where(text: str, message: str, column: int) -> None:
    with pytest.raises(PlaceholderError) as caught:
        fill(text, {"override": 50, "cam": [1, 2]})
    assert message in caught.value.message
    assert caught.value.column == column


# ---------------------------------------------------------------------------------- matrices


def test_a_product_gives_every_combination_first_key_slowest_with_stable_ids() -> None:
    scenarios = load_scenarios([str(FILES / "jog_variants.yaml")], PROGRAMS)
    arguments = [scenario.variant.arguments for scenario in scenarios if scenario.variant is not None]
    assert arguments == [
        "X1.MD32020=1000,override=50,dwell=0.2s", "X1.MD32020=1000,override=100,dwell=0.2s",
        "X1.MD32020=3000,override=50,dwell=0.2s", "X1.MD32020=3000,override=100,dwell=0.2s"]
    first = scenarios[0]
    assert first.name == "JOG of X1 at its JOG velocity times the override[X1.MD32020=1000,override=50,dwell=0.2s]"
    assert [scenario.variant.first for scenario in scenarios if scenario.variant] == [True, False, False, False]
    assert first.machine.axis("X1").md.float(JOG_VELO) == 1000  # the varied machine datum
    set_step = first.steps[0]
    assert isinstance(set_step, SetValues) and set_step.values[0][1] == 50  # "${override}" stays a number
    expect = next(step for step in scenarios[3].steps if isinstance(step, ExpectValues))
    assert str(expect.checks[0][1]) == "3000 ± 0.01"
    assert first.sources == (str(FILES / "jog_variants.yaml"), str(MACHINE))
    assert trace_names(scenarios)[1] == "jog_variants[X1.MD32020=1000,override=100,dwell=0.2s]"
    assert golden_file("golden", first) == golden_path("golden", str(FILES / "jog_variants.yaml")).with_name(
        "jog_variants[X1.MD32020=1000,override=50,dwell=0.2s].json")


def test_a_campaign_runs_its_scenarios_over_its_own_matrix() -> None:
    scenarios = load_scenarios([str(FILES / "jog_campaign.yaml")], PROGRAMS)
    assert len(scenarios) == 20
    variant = scenarios[7].variant
    assert variant is not None and variant.origin == str(FILES / "jog_campaign.yaml") and variant.index == 7
    assert variant.campaign == "JOG velocities, overrides and start positions"
    assert variant.arguments == "X1.MD32020=3000,override=100,X1.sim.start_position=150,dwell=0.2s"
    assert scenarios[7].path == str(FILES / "jog_variants.yaml")
    assert scenarios[7].machine.axis("X1").sim.start_position == 150
    assert golden_file("golden", scenarios[7]).parts[-2:] == (
        "jog_campaign", "jog_variants[X1.MD32020=3000,override=100,X1.sim.start_position=150,dwell=0.2s].json")
    only = load_scenarios([str(FILES / "jog_campaign.yaml")], PROGRAMS, variant=7)
    assert [scenario.name for scenario in only] == [scenarios[7].name]


def test_cases_go_together_and_a_list_names_its_variants(tmp_path: Path) -> None:
    cases = _load(tmp_path, HEAD + """vary:
  cases:
    - {X1.MD32020: 1000, override: 50}
    - {X1.MD32020: 2000, override: 100}
  X1.plant.ref_cam: [[280, 295], [200, 215]]
""" + STEPS)
    assert [s.variant.arguments for s in cases if s.variant] == [
        "X1.MD32020=1000,override=50,X1.plant.ref_cam=[280,295]",
        "X1.MD32020=1000,override=50,X1.plant.ref_cam=[200,215]",
        "X1.MD32020=2000,override=100,X1.plant.ref_cam=[280,295]",
        "X1.MD32020=2000,override=100,X1.plant.ref_cam=[200,215]"]
    assert cases[1].machine.axis("X1").plant.ref_cam == (200.0, 215.0)
    listed = _load(tmp_path, HEAD + """vary:
  - {X1.MD32020: 1000, override: 50, plc_parameters.referencing_order: [[X1]]}
  - {X1.MD32020: 1500, override: 70, plc_parameters.referencing_order: [[Z1]]}
""" + STEPS)
    assert [s.variant.arguments for s in listed if s.variant] == [
        "X1.MD32020=1000,override=50,plc_parameters.referencing_order=[[X1]]",
        "X1.MD32020=1500,override=70,plc_parameters.referencing_order=[[Z1]]"]
    assert listed[1].machine.plc_parameters["referencing_order"] == [["Z1"]]


def test_a_varied_fault_is_inserted_before_its_step(tmp_path: Path) -> None:
    scenarios = _load(tmp_path, HEAD + """vary:
  override: [100]
  fault: [none, {axis: X1, kind: zero_marks_missing}]
  fault.at_step: [2, 7]
""" + STEPS)
    assert len(scenarios) == 4
    assert [type(step).__name__ for step in scenarios[0].steps] == [
        "SetValues", "Press", "Hold", "Wait", "ExpectValues", "Release"]  # none: no fault
    with_fault = scenarios[2]
    assert with_fault.variant is not None
    assert with_fault.variant.arguments == "override=100,fault={axis:X1,kind:zero_marks_missing},fault.at_step=2"
    assert isinstance(with_fault.steps[1], InjectFault) and with_fault.steps[1].fault == "zero_marks_missing"
    assert with_fault.steps[1].label == "step 2 (fault)"
    assert isinstance(scenarios[3].steps[6], InjectFault)  # 7 = after the last of six


def test_a_campaign_varies_the_machine_file_relative_to_itself(tmp_path: Path) -> None:
    scenario = tmp_path / "scenarios" / "jog.yaml"
    scenario.parent.mkdir()
    scenario.write_text(HEAD.replace(str(MACHINE), "machine_does_not_matter.yaml") + "vary: {override: [100]}\n"
                        + STEPS, encoding="utf-8")
    campaign = tmp_path / "campaign.yaml"
    campaign.write_text(f"""campaign: two machines
scenarios: [scenarios/jog.yaml]
vary:
  machine: [{MACHINE}, {MACHINE.parent / 'mill_3axis.yaml'}]
  override: [100]
""", encoding="utf-8")
    scenarios = load_scenarios([str(campaign)], PROGRAMS)
    assert [scenario.machine.name for scenario in scenarios] == ["turn_mill", "mill_3axis"]
    assert str(MACHINE.parent / "mill_3axis.yaml") in scenarios[1].sources


# ---------------------------------------------------------------------------------- problems


def test_every_problem_of_every_variant_is_located_before_anything_runs(tmp_path: Path) -> None:
    problems = _problems(tmp_path, HEAD + """vary:
  X1.MD32020: [1000, -5, 2000]
  override: [50]
  speed: [1, 2]
steps:
  - set: {MCP.feedOverride: "${override}"}
  - wait: "${nope}"
  - expect: {X1.velocity: "${X1.MD32020 / (override - 50)}"}
""")
    path = tmp_path / "s.yaml"
    assert problems == [
        f"{path}:6:22: MD32020 JOG_VELO = -5: below the minimum 0.0 mm/min (in variant"
        " s[X1.MD32020=-5,override=50,speed=1] and 1 more)",
        f"{path}:8:3: 'speed' is varied, but no text of the scenario uses ${{speed}}: every variant would be the same",
        # every variant has these: reported once, without a variant
        f"{path}:11:11: in \"${{nope}}\": ${{nope}}: 'nope' is not varied (varied: X1.MD32020, override, speed)",
        f"{path}:12:27: in \"${{X1.MD32020 / (override - 50)}}\": ${{X1.MD32020 / (override - 50)}}: division"
        " by zero"]


@pytest.mark.parametrize(("matrix", "message"), [
    ("vary: 5\n", "vary takes a mapping of keys to lists of values"),
    ("vary: {override: 5}\n", "override: give the values to vary over as a list"),
    ("vary: {override: []}\n", "override: give the values to vary over as a list"),
    ("vary: {cases: [{override: 1}, {speed: 2}]}\n", "every entry of cases names the same keys (override)"),
    ("vary: {override: [1], cases: [{override: 2}]}\n", "'override' is varied twice (first at line 5)"),
    ("vary: {override: [1, 1]}\n", "override=1 appears twice in the matrix (first at line 5): every variant would run"
                                   " twice"),
    ("vary: {override: [1], fault.at_step: [2]}\n", "fault.at_step places a varied fault"),
    ("vary: {override: [1], fault: [{axis: X1, kind: zero_marks_missing}], fault.at_step: [0]}\n",
     "fault.at_step is a step number from 1, not 0"),
    ("vary: {override: [1], fault: [{axis: X1, kind: zero_marks_missing}], fault.at_step: [9]}\n",
     "fault.at_step 9: the scenario has steps 1 to 6 (7 = after the last)"),
    ("vary: {override: [1], fault: [{axis: X9, kind: zero_marks_missing}]}\n", "'X9' is not a machine axis"),
    ("vary: {override: [1], X1..MD32020: [1]}\n", "'X1..MD32020' is no key a matrix varies"),
    ("vary: {override: ['${x}']}\n", "a varied value is written out"),
    ("vary: {override: [1], X9.MD32020: [1]}\n", "X9"),
    ("vary: {override: [1, 2], a: [1, 2, 3, 4, 5, 6, 7, 8, 9, 10], b: [1, 2, 3, 4, 5, 6, 7, 8, 9, 10],"
     " c: [1, 2, 3, 4, 5, 6, 7, 8, 9, 10], d: [1, 2, 3, 4, 5, 6, 7, 8, 9, 10], e: [1, 2, 3, 4, 5, 6, 7, 8, 9, 10]}\n",
     "this matrix gives 200,000 variants; a run holds at most 100,000 (vc run --max-variants N raises the ceiling)"),
])
def test_a_matrix_that_is_not_one_is_refused_with_its_place(tmp_path: Path, matrix: str, message: str) -> None:
    problems = _problems(tmp_path, HEAD + matrix + STEPS)
    assert any(message in problem and problem.startswith(str(tmp_path / "s.yaml")) for problem in problems), problems


def test_a_campaign_file_is_checked_too(tmp_path: Path) -> None:
    (tmp_path / "c.yaml").write_text("campaign: x\nscenarios: [missing.yaml, other.yaml]\nvary: {override: [1]}\n"
                                     "extra: 1\n", encoding="utf-8")
    (tmp_path / "other.yaml").write_text("campaign: nested\nscenarios: [c.yaml]\nvary: {override: [1]}\n",
                                         encoding="utf-8")
    with pytest.raises(SourceError) as caught:
        load_scenarios([str(tmp_path / "c.yaml")], PROGRAMS)
    problems = [str(problem) for problem in caught.value.problems]
    assert f"{tmp_path / 'c.yaml'}:4:1: unknown key 'extra' in a campaign (known: campaign, description, scenarios," \
           " vary)" in problems
    (tmp_path / "c.yaml").write_text("campaign: x\nscenarios: [missing.yaml, other.yaml]\nvary: {override: [1]}\n",
                                     encoding="utf-8")
    with pytest.raises(SourceError) as caught:
        load_scenarios([str(tmp_path / "c.yaml")], PROGRAMS)
    problems = [str(problem) for problem in caught.value.problems]
    assert any(p.startswith(f"{tmp_path / 'c.yaml'}:2:13: scenario file 'missing.yaml' not found") for p in problems)
    assert f"{tmp_path / 'c.yaml'}:2:27: 'other.yaml' is a campaign itself; a campaign names scenario files" \
        in problems
