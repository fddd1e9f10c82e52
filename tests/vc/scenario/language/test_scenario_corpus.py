"""The bad-scenario corpus: each ``bad_scenarios/NAME.yaml`` is refused with exactly the lines
of ``NAME.expected`` (``file:line:column: message``, paths relative to the corpus directory).

Regenerate the expected files after a deliberate change of wording with
``VC_REGENERATE=1 pytest tests/vc/scenario/language/test_scenario_corpus.py`` and review the diff.
"""

from __future__ import annotations

import os
from pathlib import Path

import pytest

from vc.located_yaml import SourceError
from vc.scenario.language.loader import load_scenario, load_scenarios

CORPUS = Path(__file__).parent / "bad_scenarios"
CASES = sorted(path.name for path in CORPUS.glob("*.yaml"))
KNOWN_PROGRAMS = ("basic_machine", "referencing")
REGENERATE = os.environ.get("VC_REGENERATE") == "1"


def problems_of(name: str) -> list[str]:
    with pytest.raises(SourceError) as caught:
        load_scenario(name, KNOWN_PROGRAMS)
    return [str(problem) for problem in caught.value.problems]


def test_corpus_is_large_enough() -> None:
    assert len(CASES) >= 15


@pytest.mark.parametrize("name", CASES)
def test_bad_scenario(name: str, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(CORPUS)
    lines = problems_of(name)
    expected_file = CORPUS / name.replace(".yaml", ".expected")
    if REGENERATE:
        expected_file.write_text("\n".join(lines) + "\n", encoding="utf-8")
    assert lines == expected_file.read_text(encoding="utf-8").splitlines()


def test_every_file_of_a_run_is_checked(monkeypatch: pytest.MonkeyPatch) -> None:
    """Problems of all files come in one error, and the machines directory is not a scenario."""
    monkeypatch.chdir(CORPUS)
    with pytest.raises(SourceError) as caught:
        load_scenarios(["."], KNOWN_PROGRAMS)
    files = {problem.mark.file for problem in caught.value.problems}
    assert {"./unknown_step.yaml", "./empty.yaml", "./bad_alarms.yaml"} <= files
    assert not any(file.startswith("./machines/") for file in files)
    expected = sum(len((CORPUS / c.replace(".yaml", ".expected")).read_text().splitlines()) for c in CASES)
    assert len(caught.value.problems) == expected
