"""The mutated-machine corpus: malformed machine files and scenario overrides, each with every
problem the machine reader reports (``file:line:column: message``), so that a change of the
reader that changes a message, adds or drops one, or moves its location fails here.

``mutated_machines/machines.jsonl`` holds one machine file a line: its base in ``bases/`` and the
lines it replaces (``[first, end, new lines]``, 0-based, ``end`` excluded).  ``overrides.jsonl``
holds the ``machine_data:`` block of a scenario of the library, mutated; it is applied to its base
machine twice: as read from YAML (the problems carry the block's marks) and as a mapping built in
code (they carry the file's name, ``NAME.built.yaml:1:1``).  The mutants were made by the file
mutations of the robustness campaign (vc/bench/robustness/files.py, seed 1) from the shipped
machines and scenarios; kept were those the YAML reader accepts and whose problems bring a
message not seen in an earlier one.  ``bases/`` are the shipped machines as they were then, kept
as they are: the corpus is about the reader, not about the machines the project ships.

``expected.txt``: each mutant's header line ``# NAME (KIND)`` and its problems, or ``loads``.
Regenerate it after a deliberate change of wording with
``VC_REGENERATE=1 pytest tests/vc/config/test_mutated_machines.py -n 0`` and review the diff.
"""

from __future__ import annotations

import json
import os
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import pytest

from vc.config.loader import load_machine
from vc.located_yaml import LocatedMap, SourceError, load_text

CORPUS = Path(__file__).resolve().parent / "mutated_machines"
EXPECTED = CORPUS / "expected.txt"
REGENERATE = os.environ.get("VC_REGENERATE") == "1"


@dataclass(frozen=True, slots=True)
class Mutant:
    name: str
    kind: str
    text: str  # the mutated machine file, or the mutated scenario block ``machine_data: ...``
    machine: str = ""  # for overrides: the base machine they are applied to

    @property
    def is_overrides(self) -> bool:
        return bool(self.machine)


def _machine_text(base: str, edits: list[list[Any]]) -> str:
    lines = (CORPUS / "bases" / base).read_text(encoding="utf-8").split("\n")
    for first, end, new in reversed(edits):
        lines[first:end] = new
    return "\n".join(lines)


def _mutants() -> list[Mutant]:
    machines = [json.loads(line) for line in (CORPUS / "machines.jsonl").read_text(encoding="utf-8").splitlines()]
    overrides = [json.loads(line) for line in (CORPUS / "overrides.jsonl").read_text(encoding="utf-8").splitlines()]
    return ([Mutant(item["name"], item["kind"], _machine_text(item["base"], item["edits"])) for item in machines]
            + [Mutant(item["name"], item["kind"], item["text"], item["machine"]) for item in overrides])


MUTANTS = _mutants()


def _problems(load: Any, file: str) -> list[str]:
    try:
        load()
    except SourceError as error:
        return [str(problem) for problem in error.problems]
    return [f"{file}: loads"]


def _plain(value: Any) -> Any:
    if isinstance(value, dict):
        return {key: _plain(item) for key, item in value.items()}
    if isinstance(value, list):
        return [_plain(item) for item in value]
    return value


def problems_of(mutant: Mutant, directory: Path) -> list[str]:
    """What the reader reports for the mutant (``directory``: the current one, for the mutated files)."""
    file = f"{mutant.name}.yaml"
    if not mutant.is_overrides:
        (directory / file).write_text(mutant.text, encoding="utf-8")
        return _problems(lambda: load_machine(file), file)
    document, problems = load_text(mutant.text, file)
    assert problems == [] and isinstance(document, LocatedMap), "the corpus holds overrides that YAML reads"
    located = document.get("machine_data")
    base = str(CORPUS / "bases" / mutant.machine)
    built_file = f"{mutant.name}.built.yaml"
    built = LocatedMap(_plain(located)) if isinstance(located, dict) else _plain(located)
    return (_problems(lambda: load_machine(base, located, file), file)
            + _problems(lambda: load_machine(base, built, built_file), built_file))


def _expected() -> dict[str, list[str]]:
    result: dict[str, list[str]] = {}
    lines: list[str] = []
    for line in EXPECTED.read_text(encoding="utf-8").splitlines():
        if line.startswith("# "):
            lines = result.setdefault(line[2:].split()[0], [])
        else:
            lines.append(line)
    return result


def test_the_corpus_is_complete_and_varied(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(tmp_path)
    if REGENERATE:
        EXPECTED.write_text("".join(f"# {mutant.name} ({mutant.kind})\n"
                                    + "".join(f"{line}\n" for line in problems_of(mutant, tmp_path))
                                    for mutant in MUTANTS), encoding="utf-8")
    expected = _expected()
    assert list(expected) == [mutant.name for mutant in MUTANTS]
    assert len([mutant for mutant in MUTANTS if not mutant.is_overrides]) >= 100
    assert len([mutant for mutant in MUTANTS if mutant.is_overrides]) >= 50
    assert sum(len(lines) for lines in expected.values()) >= 400
    assert len({mutant.kind for mutant in MUTANTS}) >= 6  # the kinds the YAML reader lets through


@pytest.mark.parametrize("mutant", MUTANTS, ids=lambda mutant: mutant.name)
def test_mutant(mutant: Mutant, tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    if REGENERATE:
        pytest.skip("the expected problems are being written")
    monkeypatch.chdir(tmp_path)
    assert problems_of(mutant, tmp_path) == _expected()[mutant.name]
