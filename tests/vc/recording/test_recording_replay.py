"""Replaying recorded sessions without the PLC: zero differences for an unchanged NC, the first
difference for a changed machine datum, the operator's actions and power cycles played again, and a
PLC's sign of life that stood still raising the same alarm again."""

from __future__ import annotations

import json
import re
from pathlib import Path

import pytest
from recording_helpers import OPERATOR, ROOT, record_scenario

from interfaces.image import ProcessImage
from interfaces.links.inprocess import InProcessConnector
from interfaces.plc import PlcEnvironment, SoftPlc
from vc.cli.main import main
from vc.config import md_dictionary as MD
from vc.recording.format import LIFE, Marker, read_recording
from vc.recording.replay import replay

POWER_FAILURE = ROOT / "scenarios" / "manual_retraction" / "power_failure_during_g331.yaml"
TURN_MILL = ROOT / "scenarios" / "machines" / "turn_mill.yaml"


@pytest.fixture(scope="module")
def referencing_x1(tmp_path_factory: pytest.TempPathFactory) -> Path:
    out = tmp_path_factory.mktemp("recording") / "reference_x1.vcrec"
    assert record_scenario(OPERATOR, out).passed
    return out


def test_an_unchanged_nc_replays_the_session_without_a_difference(referencing_x1: Path) -> None:
    recording = read_recording(str(referencing_x1))
    assert recording.complete and recording.header.program == "basic_machine"
    result = replay(recording)
    assert result.difference is None
    assert result.cycles == recording.last_cycle > 3000  # Y1 and X1 referenced: several seconds


def test_a_changed_machine_datum_shows_as_the_first_differing_signal(referencing_x1: Path, tmp_path: Path,
                                                                     capsys: pytest.CaptureFixture[str]) -> None:
    text = TURN_MILL.read_text(encoding="utf-8")
    changed = tmp_path / "turn_mill.yaml"
    # X1's creep velocity in phase 2: the zero mark comes later, so do the NC's signals
    x1 = text.index("  X1:")
    creep = text.index("MD34040 REFP_VELO_SEARCH_MARKER: 300", x1)
    changed.write_text(text[:creep] + "MD34040 REFP_VELO_SEARCH_MARKER: 200" + text[creep + 36:], encoding="utf-8")
    result = replay(read_recording(str(referencing_x1)), str(changed))
    difference = result.difference
    assert difference is not None
    first = difference.signals[0]
    assert first.name.startswith("X1.") and first.recorded != first.replayed
    assert 0 < difference.cycle == result.cycles < read_recording(str(referencing_x1)).last_cycle

    assert main(["replay", str(referencing_x1), "--machine", str(changed)]) == 1
    out = capsys.readouterr().out
    assert f"first difference at cycle {difference.cycle}" in out
    assert f"{first.name} ({first.address}) recorded {first.recorded}, replayed {first.replayed}" in out
    assert main(["replay", str(referencing_x1)]) == 0
    assert "no difference in" in capsys.readouterr().out


def test_operator_actions_machine_data_and_a_power_cycle_replay_too(tmp_path: Path) -> None:
    out = tmp_path / "power_failure.vcrec"
    assert record_scenario(POWER_FAILURE, out).passed
    recording = read_recording(str(out))
    kinds = {row.action.kind for row, _ in recording.rows() if hasattr(row, "action")}
    assert {"write", "power_cycle", "program"} <= kinds
    assert replay(recording).difference is None
    # the scenario's machine data (MD34210 = 3: restore the positions at power-on) belong to the machine
    assert replay(recording).machine.axis("Z1").md.int(MD.ENC_REFP_STATE) == 3


class _LifeStopsAfter:
    """The built-in PLC, whose sign of life stands still from scan ``stop`` on (a PLC that hangs while
    its outputs stay): the NC raises alarm 2000."""

    def __init__(self, plc: SoftPlc, stop: int):
        self.plc, self.stop, self.scans = plc, stop, 0

    @property
    def sign_of_life(self) -> int:
        return self.plc.sign_of_life if self.scans < self.stop else -1

    def scan(self, interface: ProcessImage, plant: ProcessImage) -> None:
        self.scans += 1
        self.plc.scan(interface, plant)


class _HangingConnector:
    def connect(self, environment: PlcEnvironment, program: str) -> SoftPlc:
        return _LifeStopsAfter(InProcessConnector().connect(environment, program), 150)


def test_a_sign_of_life_that_stood_still_raises_the_same_alarm_in_the_replay(tmp_path: Path) -> None:
    out = tmp_path / "hanging.vcrec"
    result = record_scenario(OPERATOR, out, _HangingConnector())
    assert not result.passed  # the axes stop with alarm 2000
    recording = read_recording(str(out))
    assert any(isinstance(row, Marker) and row.kind == LIFE for row, _ in recording.rows())
    assert replay(recording).difference is None

    # the same recording without its life rows: the stand-in PLC lives on, the NC raises no alarm
    lines = [line for line in out.read_text(encoding="utf-8").splitlines() if f'"{LIFE}"' not in line]
    alive = tmp_path / "alive.vcrec"
    alive.write_text("\n".join(lines) + "\n", encoding="utf-8")
    difference = replay(read_recording(str(alive))).difference
    assert difference is not None
    first = difference.signals[0]
    assert (first.name, first.recorded, first.replayed) == ("NC.basic.in.alarmActive", 1, 0)


def test_a_compressed_recording_replays_alike(tmp_path: Path) -> None:
    out = tmp_path / "session.vcrec.gz"
    assert record_scenario(OPERATOR, out).passed
    assert out.read_bytes()[:2] == b"\x1f\x8b"  # gzip
    assert replay(read_recording(str(out))).difference is None


def test_a_recording_cut_short_replays_up_to_its_last_row(referencing_x1: Path, tmp_path: Path,
                                                          capsys: pytest.CaptureFixture[str]) -> None:
    lines = referencing_x1.read_text(encoding="utf-8").splitlines()
    cut = tmp_path / "cut.vcrec"
    cut.write_text("\n".join(lines[:len(lines) // 2]) + "\n", encoding="utf-8")
    recording = read_recording(str(cut))
    assert not recording.complete
    assert main(["replay", str(cut)]) == 0
    captured = capsys.readouterr()
    assert "no end row" in captured.err and f"up to cycle {recording.last_cycle}" in captured.err
    assert re.search(rf"no difference in {recording.last_cycle} IPO cycles", captured.out)


def test_a_recording_of_another_interface_is_refused_with_its_location(referencing_x1: Path, tmp_path: Path,
                                                                       capsys: pytest.CaptureFixture[str]) -> None:
    lines = referencing_x1.read_text(encoding="utf-8").splitlines()
    header = json.loads(lines[0])
    header["areas"]["DB31"] = 200
    other = tmp_path / "other.vcrec"
    other.write_text("\n".join([json.dumps(header), *lines[1:]]) + "\n", encoding="utf-8")
    assert main(["replay", str(other)]) == 2
    err = capsys.readouterr().err
    assert f"{other}:1:1: the recording's interface differs from this machine's in DB31" in err
    assert "Traceback" not in err
