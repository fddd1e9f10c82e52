"""A recording as a scenario with plc: none: the PLC's writes as set steps, the NC's responses as
expectations; it passes in the ordinary runner, and fails where the NC answers otherwise."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from recording_helpers import OPERATOR, ROOT, record_scenario

from interfaces.links.inprocess import plc_programs
from vc.cli.main import main
from vc.harness.targets import simulation_for
from vc.recording.format import read_recording
from vc.recording.to_scenario import ConversionError, to_scenario
from vc.scenario.language.loader import load_scenario
from vc.scenario.run.runner import run_scenario

POWER_FAILURE = ROOT / "scenarios" / "manual_retraction" / "power_failure_during_g331.yaml"


def _converted(recorded: Path, out: Path) -> Path:
    conversion = to_scenario(read_recording(str(recorded)), str(out))
    out.write_text(conversion.text, encoding="utf-8")
    assert conversion.machine_file == ""  # the recorded machine file exists unchanged: named, not copied
    return out


@pytest.mark.parametrize("scenario_file", [OPERATOR, POWER_FAILURE], ids=["reference_x1", "power_failure"])
def test_the_scenario_of_a_recording_passes(scenario_file: Path, tmp_path: Path,
                                            monkeypatch: pytest.MonkeyPatch) -> None:
    recorded = tmp_path / "session.vcrec"
    assert record_scenario(scenario_file, recorded).passed
    scenario_path = _converted(recorded, tmp_path / "generated.yaml")
    text = scenario_path.read_text(encoding="utf-8")
    assert "plc: none" in text and "  - set: {" in text and "  - expect: {" in text and "  - wait: " in text
    monkeypatch.chdir(ROOT)  # the machine file is named as the recording has it, from the repository
    scenario = load_scenario(str(scenario_path), plc_programs().keys())
    assert scenario.plc_program is None
    result = run_scenario(scenario, simulation_for(scenario))
    assert result.passed, result.failure
    assert result.cycles == read_recording(str(recorded)).last_cycle


def test_the_scenario_fails_where_the_nc_answers_otherwise(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    recorded = tmp_path / "session.vcrec"
    assert record_scenario(OPERATOR, recorded).passed
    scenario_path = _converted(recorded, tmp_path / "generated.yaml")
    text = scenario_path.read_text(encoding="utf-8")
    # X1 creeps at 200 instead of 300 mm/min in phase 2: its zero mark, and what follows, come later
    scenario_path.write_text(text.replace("plc: none\n", "plc: none\nmachine_data: {X1: {MD34040: 200}}\n"),
                             encoding="utf-8")
    monkeypatch.chdir(ROOT)
    scenario = load_scenario(str(scenario_path), plc_programs().keys())
    result = run_scenario(scenario, simulation_for(scenario))
    assert not result.passed and result.failure is not None
    assert result.failure.message.startswith("expected X1.")


def test_vc_replay_to_scenario_writes_it_and_the_machine_beside_it_when_the_recorded_one_is_gone(
        tmp_path: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch) -> None:
    session = tmp_path / "session.vcrec"
    assert record_scenario(OPERATOR, session).passed
    lines = session.read_text(encoding="utf-8").splitlines()
    header = json.loads(lines[0])
    header["machine"]["file"] = "machines/gone.yaml"  # recorded on another host: the path leads nowhere here
    recorded = tmp_path / "elsewhere.vcrec"
    recorded.write_text("\n".join([json.dumps(header), *lines[1:]]) + "\n", encoding="utf-8")
    monkeypatch.chdir(tmp_path)
    out = tmp_path / "out" / "from_recording.yaml"
    out.parent.mkdir()
    assert main(["replay", str(recorded), "--to-scenario", str(out), "--name", "X1 referenced, as recorded"]) == 0
    assert (out.parent / "from_recording.machine.yaml").read_text(encoding="utf-8") == \
        read_recording(str(recorded)).header.machine.text
    text = out.read_text(encoding="utf-8")
    assert "name: X1 referenced, as recorded\n" in text and "machine: from_recording.machine.yaml\n" in text
    assert main(["run", str(out)]) == 0
    assert "1 passed" in capsys.readouterr().out


def test_a_write_during_a_handwheel_turn_cannot_be_placed(tmp_path: Path) -> None:
    recorded = tmp_path / "session.vcrec"
    assert record_scenario(OPERATOR, recorded).passed
    lines = recorded.read_text(encoding="utf-8").splitlines()
    # a 10 s handwheel turn at cycle 0: the PLC's writes after it lie inside the turn
    turned = tmp_path / "turned.vcrec"
    turned.write_text("\n".join([lines[0], '[0, "op", "handwheel", 1, 5, 5000]', *lines[1:]]) + "\n",
                      encoding="utf-8")
    with pytest.raises(ConversionError, match=r"turned.vcrec:\d+:1: cycle \d+ lies inside a handwheel turn"):
        to_scenario(read_recording(str(turned)), str(tmp_path / "x.yaml"))
