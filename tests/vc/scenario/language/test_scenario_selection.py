"""``vc run -k EXPRESSION`` and ``--shard I/N`` (vc/scenario/language/selection.py): which scenarios
and variants of a run run, as pytest's -k reads its expression and as a CI matrix splits a run."""

from __future__ import annotations

from pathlib import Path

import pytest

from vc.cli.main import build_parser, main
from vc.scenario.language.selection import SelectionError, Shard, keyword_match

IDS = ["scenarios/referencing/abort_channel_reset.yaml abort in phase 1",
       "scenarios/referencing/ref_cam.yaml ref_cam[x1.md34050=1,override=50]",
       "scenarios/spindle/gear_change.yaml gear change m40"]


def chosen(expression: str) -> list[int]:
    match = keyword_match(expression)
    return [number for number, text in enumerate(IDS) if match(text.lower())]


@pytest.mark.parametrize(("expression", "expected"), [
    ("referencing", [0, 1]),
    ("REFERENCING and not abort", [1]),
    ("md34050=1 or gear", [1, 2]),
    ("not (referencing or m40)", []),
    ("spindle or referencing and abort", [0, 2]),  # and binds closer than or, as in pytest
    ("(spindle or referencing) and not (abort)", [1, 2]),
])
def test_the_expression_combines_words_found_in_the_id_as_pytest_k_does(expression: str, expected: list[int]) -> None:
    assert chosen(expression) == expected


@pytest.mark.parametrize(("expression", "message"), [
    ("", "the expression is empty"),
    ("abort and", "the expression ends where a word or '(' is missing"),
    ("(abort or ref", "a '(' is not closed"),
    ("abort ref", "unexpected 'ref' at word 2"),
    ("or abort", "unexpected 'or' at word 1"),
    ("abort )", "unexpected ')' at word 2"),
])
def test_an_expression_that_cannot_be_read_says_where(expression: str, message: str) -> None:
    with pytest.raises(SelectionError, match=message.replace("(", r"\(").replace(")", r"\)")):
        keyword_match(expression)


@pytest.mark.parametrize("text", ["0/3", "4/3", "1/0", "a/b", "2", "1/10001"])
def test_a_shard_outside_one_to_n_is_refused(text: str) -> None:
    with pytest.raises(SelectionError):
        Shard.parse(text)


def _matrix(tmp_path: Path) -> Path:
    scenario = tmp_path / "matrix.yaml"
    scenario.write_text("name: a matrix\nmachine: mill_3axis\nplc: basic_machine\n"
                        "vary: {wait: [10ms, 20ms, 30ms, 40ms, 50ms]}\nsteps:\n  - wait: ${wait}\n")
    return scenario


def test_the_shards_of_a_run_run_every_variant_exactly_once(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    scenario = _matrix(tmp_path)
    passed: list[str] = []
    for index in (1, 2, 3):
        junit = tmp_path / f"shard{index}.xml"
        assert main(["run", str(scenario), "--shard", f"{index}/3", "-j", "1", "--junit", str(junit)]) == 0
        passed += [line.split(' name="')[1].split('"')[0] for line in junit.read_text().splitlines()
                   if "<testcase" in line]
    out = capsys.readouterr().out
    assert "--shard 1/3: 2 of 5 scenarios" in out and "--shard 3/3: 1 of 5 scenarios" in out
    assert sorted(passed) == sorted(f"a matrix[wait={wait}ms]" for wait in (10, 20, 30, 40, 50))


def test_k_selects_variants_by_their_arguments_and_nothing_selected_is_a_problem(
        tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    scenario = _matrix(tmp_path)
    assert main(["run", str(scenario), "-k", "wait=20ms or wait=40ms", "-j", "1"]) == 0
    out = capsys.readouterr().out
    assert "-k 'wait=20ms or wait=40ms': 2 of 5 scenarios" in out and "2 passed" in out
    assert main(["run", str(scenario), "-k", "nothing_like_it", "-j", "1"]) == 2
    assert "selects none of the 5 scenarios" in capsys.readouterr().out
    assert main(["run", str(scenario), "-k", "wait and (", "-j", "1"]) == 2
    assert "the expression ends where" in capsys.readouterr().err
    with pytest.raises(SystemExit):
        build_parser().parse_args(["run", str(scenario), "--shard", "0/2"])
