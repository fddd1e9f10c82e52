"""``plc: awlsim:FILE`` in a scenario: the program file relative to the scenario, checked with its location."""

from __future__ import annotations

from pathlib import Path

import pytest

from interfaces.links.inprocess import plc_programs
from vc.located_yaml import SourceError
from vc.scenario.language.loader import load_scenario

ROOT = Path(__file__).resolve().parents[4]


def _scenario(tmp_path: Path, plc: str, extra: str = "") -> str:
    path = tmp_path / "s.yaml"
    path.write_text(f"name: s\nmachine: {ROOT / 'scenarios/machines/turn_mill.yaml'}\nplc: {plc}\n{extra}"
                    "steps:\n  - wait: 10ms\n")
    return str(path)


def test_the_program_is_found_next_to_the_scenario(tmp_path: Path) -> None:
    (tmp_path / "p.awl").write_text("")
    scenario = load_scenario(_scenario(tmp_path, "awlsim:p.awl"), plc_programs().keys())
    assert scenario.external_plc == ("awlsim", str(tmp_path / "p.awl"))
    assert scenario.plc_program == f"awlsim:{tmp_path / 'p.awl'}"


@pytest.mark.parametrize(("plc", "extra", "message"), [
    ("awlsim:missing.awl", "", "3:6: no awlsim program 'missing.awl'"),
    ("'awlsim:'", "", "3:6: plc: awlsim: needs the program file"),
    ("awlsim:p.awl", "link: can\n", "4:7: link: can is for the built-in programs; awlsim runs over its own"),
    ("awlsimm:p.awl", "", "3:6: unknown PLC program 'awlsimm:p.awl'"),
])
def test_a_wrong_external_plc_is_reported_where_it_stands(tmp_path: Path, plc: str, extra: str,
                                                          message: str) -> None:
    (tmp_path / "p.awl").write_text("")
    with pytest.raises(SourceError) as caught:
        load_scenario(_scenario(tmp_path, plc, extra), plc_programs().keys())
    assert any(message in str(problem) for problem in caught.value.problems), caught.value.problems
