"""The size of a run's matrices: a ceiling counted before any variant is built, and a check that
shares what the variants have in common instead of checking each one from scratch."""

from __future__ import annotations

from pathlib import Path

import pytest

from interfaces.links.inprocess import plc_programs
from vc.input_limits import MAX_RUN_VARIANTS
from vc.located_yaml import LocatedMap, Problems, SourceError
from vc.scenario.language import loader
from vc.scenario.language.loader import load_scenarios
from vc.scenario.language.model import Scenario
from vc.scenario.language.variants import VariantCeiling, check_file

ROOT = Path(__file__).resolve().parents[4]
MACHINE = ROOT / "scenarios" / "machines" / "turn_mill.yaml"
PROGRAMS = plc_programs().keys()

SCENARIO = f"""name: jog
machine: {MACHINE}
plc: basic_machine
timeout: 10s
steps:
  - set: {{MCP.feedOverride: "${{override}}"}}
  - press: MCP.jog
  - hold: MCP.plus.X1
  - wait: 300ms
  - expect: {{X1.velocity: "${{20 * override}} +- 0.01"}}
  - release: MCP.plus.X1
"""


def _values(count: int) -> str:
    return "[" + ", ".join(str(value) for value in range(1, count + 1)) + "]"


def _problems(paths: list[Path], max_variants: int = MAX_RUN_VARIANTS) -> list[str]:
    with pytest.raises(SourceError) as caught:
        load_scenarios([str(path) for path in paths], PROGRAMS, max_variants=max_variants)
    return [str(problem) for problem in caught.value.problems]


def test_a_campaign_of_a_thousand_files_times_a_large_matrix_is_refused_before_a_file_is_read(tmp_path: Path) -> None:
    """1,000 files x 100,000 variants (a 15 kB file) was still being checked after 120 s."""
    listed = ", ".join(f"scenario_{number}.yaml" for number in range(1000))  # none of them exists: none is read
    campaign = tmp_path / "c.yaml"
    campaign.write_text(f"campaign: big\nscenarios: [{listed}]\nvary:\n  override: {_values(10)}\n"
                        f"  a: {_values(100)}\n  b: {_values(100)}\n", encoding="utf-8")
    assert campaign.stat().st_size > 15_000
    assert _problems([campaign]) == [
        f"{campaign}:4:3: this campaign (a matrix of 100,000 over 1,000 scenario files) gives 100,000,000 variants;"
        f" a run holds at most {MAX_RUN_VARIANTS:,} (vc run --max-variants N raises the ceiling)"]


def test_the_ceiling_counts_the_variants_of_every_file_of_the_run(tmp_path: Path) -> None:
    first, second = tmp_path / "a.yaml", tmp_path / "b.yaml"
    first.write_text(SCENARIO + "vary: {override: " + _values(60) + "}\n", encoding="utf-8")
    second.write_text(SCENARIO + "vary: {override: " + _values(60) + "}\n", encoding="utf-8")
    assert _problems([first, second], max_variants=100) == [
        f"{second}:12:7: this matrix gives 60 variants (120 with the files before it); a run holds at most 100"
        " (vc run --max-variants N raises the ceiling)"]
    assert len(load_scenarios([str(first), str(second)], PROGRAMS, max_variants=120)) == 120


def test_a_worker_building_one_variant_is_not_held_to_the_ceiling(tmp_path: Path) -> None:
    """The client counted the run with its own --max-variants; a worker builds the variant it is given."""
    path = tmp_path / "a.yaml"
    path.write_text(SCENARIO + "vary: {override: " + _values(20) + "}\n", encoding="utf-8")
    problems = Problems()
    built = check_file(str(path), _reader, _never_checked, problems, ceiling=VariantCeiling(10))
    assert built == [] and "gives 20 variants" in str(problems.items[0])
    (only,) = load_scenarios([str(path)], PROGRAMS, variant=19, max_variants=1)
    assert only.variant is not None and only.variant.arguments == "override=20"


def _reader(path: str, problems: Problems) -> LocatedMap | None:
    from vc.located_yaml import load_file

    document, found = load_file(path)
    problems.extend(found)
    return document if isinstance(document, LocatedMap) else None


def _never_checked(path: str, document: LocatedMap, problems: Problems) -> Scenario | None:
    raise AssertionError("a matrix beyond the ceiling is not expanded")


def test_variants_that_differ_only_in_machine_data_share_the_check_of_their_document(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """A 100,000-variant file took 8 CPU-minutes to check: every variant was checked from scratch."""
    path = tmp_path / "m.yaml"
    path.write_text(SCENARIO + "vary:\n  override: [50, 100]\n  X1.MD34040: [100, 200, 300]\n"
                               "  X1.plant.ref_cam: [[250, 265], [260, 275]]\n  X1.MD32020: [1000, 2000]\n",
                    encoding="utf-8")
    whole_checks: list[str] = []
    checker = loader._ScenarioChecker
    original = checker.check

    def counted(self: loader._ScenarioChecker, document: LocatedMap) -> Scenario | None:
        whole_checks.append(self.path)
        return original(self, document)

    monkeypatch.setattr(checker, "check", counted)
    shared = load_scenarios([str(path)], PROGRAMS)
    assert len(shared) == 24
    assert len(whole_checks) == 2  # one per value of override, the only key the texts read
    # the same scenarios as a check of every variant in full
    whole_checks.clear()
    monkeypatch.setattr(loader, "machine_shape", lambda machine: id(machine))  # no two shapes alike
    every = load_scenarios([str(path)], PROGRAMS)
    assert len(whole_checks) == 24
    assert [scenario.name for scenario in every] == [scenario.name for scenario in shared]
    for mine, theirs in zip(shared, every, strict=True):
        assert mine.steps == theirs.steps and mine.invariants == theirs.invariants
        assert mine.machine.axis("X1").md.items() == theirs.machine.axis("X1").md.items()
        assert mine.machine.axis("X1").plant == theirs.machine.axis("X1").plant
