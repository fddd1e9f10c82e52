"""The recording reader is bounded (nesting, digits, finite numbers, area sizes, cycle range,
decompressed size), the converted scenario is emitted by a YAML emitter, the writer flushes by
the wall clock and stops at its size limit, and a recording cut short replays up to its last
complete row.  Each of these was a traceback, a hang, a memory error or a refused file."""

from __future__ import annotations

import gzip
import json
import zlib
from pathlib import Path
from typing import Any

import pytest
import yaml
from recording_helpers import HEADER, OPERATOR, record_scenario

from vc.cli.main import main
from vc.located_yaml import SourceError
from vc.recording import format as recording_format
from vc.recording.format import END, LIFE, SIZE_LIMIT, Marker, RecordingWriter, read_recording
from vc.recording.to_scenario import to_scenario


@pytest.fixture(scope="module")
def sound(tmp_path_factory: pytest.TempPathFactory) -> list[Any]:
    """The lines of a recording of the operator scenario, as values."""
    path = tmp_path_factory.mktemp("sound") / "sound.vcrec"
    assert record_scenario(OPERATOR, path).passed
    return [json.loads(line) for line in path.read_text(encoding="utf-8").splitlines()]


def _write(path: Path, header: Any, rows: list[str]) -> Path:
    path.write_text(json.dumps(header) + "\n" + "".join(row + "\n" for row in rows), encoding="utf-8")
    return path


def _problems(path: Path) -> list[str]:
    with pytest.raises(SourceError) as caught:
        read_recording(str(path))
    return [str(problem).replace(str(path), "F") for problem in caught.value.problems]


@pytest.mark.parametrize(("header_change", "row", "expected"), [
    # each ended in a traceback (RecursionError, ValueError, OverflowError, MemoryError) or a hang
    ({}, "[" * 50_000 + "]" * 50_000, "F:3:1: arrays and objects nested more than 8 deep"),
    ({}, "[" + "9" * 5000 + ', "life"]', "F:3:1: a whole number of 5,000 digits (at most 20)"),
    ({}, '[0, "op", "write", "MCP.jog", Infinity]', "F:3:1: Infinity is not a number JSON knows"),
    ({}, '[0, "op", "move_by_hand", "X1", NaN]', "F:3:1: NaN is not a number JSON knows"),
    ({}, '[0, "op", "power_cycle", 1e999]', "F:3:1: the number 1e999 is not finite"),
    ({}, f'[{10**30}, "life"]', "F:3:1: a whole number of 31 digits (at most 20)"),
    ({}, f'[{10**18}, "life"]', "F:3:1: cycle 1000000000000000000 lies beyond 7 days of IPO cycles (302,400,000 at"
                                " 2000 us), the longest recording"),
    ({}, '[0, "op", "power_cycle", 1000000000]', "F:3:1: an op row power_cycle: off_seconds must be a time in seconds"
                                                  " from 0 to 86,400, not 1000000000"),
    ({}, '[0, "op", "handwheel", 1, 5, 1000000000]', "F:3:1: an op row handwheel: its cycles run beyond the longest"
                                                      " recording"),
    ({"areas": {"DB31": 10**12}}, '[0, "life"]', "F:1:1: header: areas must map each data block and I / Q (at most"
                                                 " 256) to its size in bytes, 1 to 65,536"),
    ({"ipo_cycle_us": 10**30}, '[0, "life"]', "F:1:1: a whole number of 31 digits (at most 20)"),
])
def test_hostile_values_are_located_problems(tmp_path: Path, header_change: dict[str, Any], row: str,
                                             expected: str) -> None:
    header = {**HEADER.to_json(), **header_change}
    path = _write(tmp_path / "r.vcrec", header, ['[0, "nc", "DB31", 60, "c010"]', row])
    assert any(problem.startswith(expected) for problem in _problems(path)), _problems(path)


def test_a_gzip_bomb_is_refused_at_the_size_limit(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """A 2 MB gzip file expanding to 2 GB ended in MemoryError (here: 8 MiB of rows against 1 MiB)."""
    monkeypatch.setattr(recording_format, "MAX_RECORDING_BYTES", 1 << 20)
    path = tmp_path / "bomb.vcrec.gz"
    with gzip.open(path, "wt", encoding="utf-8") as handle:
        handle.write(json.dumps(HEADER.to_json()) + "\n")
        handle.write('[0, "nc", "DB31", 60, "c010"]\n' * 300_000)
    assert path.stat().st_size < 100_000
    (problem,) = _problems(path)
    assert problem.startswith("F:") and "the recording holds more than 1 MiB (decompressed)" in problem


def test_a_newline_in_a_header_text_stays_inside_its_value_of_the_scenario(tmp_path: Path, sound: list[Any]) -> None:
    """"x\\nmachine_data: ..." in the machine's name made a top-level machine_data: of the scenario."""
    header = json.loads(json.dumps(sound[0]))
    injected = "x\nmachine_data: {X1: {MD32000: 1}}\nsteps: []\n#"
    header["machine"]["name"] = header["plc"]["program"] = header["scenario"]["file"] = injected
    path = tmp_path / "injected.vcrec"
    path.write_text("".join(json.dumps(value) + "\n" for value in [header, *sound[1:]]), encoding="utf-8")
    conversion = to_scenario(read_recording(str(path)), str(tmp_path / "out.yaml"))
    document = yaml.safe_load(conversion.text)
    assert set(document) == {"name", "description", "machine", "plc", "timeout", "steps"}
    assert injected in document["name"] and injected in document["description"]
    assert len(document["steps"]) > 10


def test_the_writer_flushes_every_second_of_the_wall_clock(tmp_path: Path) -> None:
    """Rows reached the file only every 200 rows: a killed server lost 80 of 93 s."""
    now = [0.0]
    path = tmp_path / "r.vcrec"
    writer = RecordingWriter(str(path), HEADER, clock=lambda: now[0])
    writer.write(Marker(1, LIFE))
    assert path.read_text(encoding="utf-8").count("\n") == 1  # the header only: within the second
    now[0] = 1.5
    writer.write(Marker(2, LIFE))
    assert path.read_text(encoding="utf-8").count("\n") == 3  # both rows, without closing
    writer.write(Marker(3, LIFE))
    now[0] = 3.0
    writer.flush_if_due()  # the recorder asks after every cycle, rows or not
    assert path.read_text(encoding="utf-8").count("\n") == 4
    writer.close(4)


def test_the_writer_stops_at_its_size_limit_and_the_replay_says_so(
        tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    path = tmp_path / "limited.vcrec"
    writer = RecordingWriter(str(path), HEADER, limit_bytes=2000)
    for cycle in range(1000):
        writer.write(Marker(cycle, LIFE))
    assert writer.limited and writer.closed
    writer.close(1000)  # the session's end: the recording has ended already
    assert path.stat().st_size <= 2000
    recording = read_recording(str(path))
    assert recording.end == Marker(recording.last_cycle, END, SIZE_LIMIT)


def test_the_recorder_says_once_that_it_stopped_at_its_limit(tmp_path: Path, sound: list[Any]) -> None:
    from interfaces.links.inprocess import InProcessConnector, plc_programs
    from vc.recording.format import RecordedFile
    from vc.recording.recorder import SessionInfo, SessionRecorder
    from vc.scenario.language.loader import load_scenario
    from vc.scenario.run.runner import run_scenario
    from vc.simulation.lockstep import Simulation
    from vc.simulation.observed import ObservedSimulation

    said: list[str] = []
    path = tmp_path / "limited.vcrec"
    scenario = load_scenario(str(OPERATOR), plc_programs().keys())
    header, rows = len(json.dumps(sound[0])), sum(len(json.dumps(row)) + 1 for row in sound[1:])
    recorder = SessionRecorder(str(path), SessionInfo(RecordedFile(str(OPERATOR), OPERATOR.read_text(encoding="utf-8")),
                                                      "inprocess", "lockstep", "test", limit_bytes=header + rows // 2),
                               said.append)
    run_scenario(scenario, ObservedSimulation(Simulation(scenario.machine, scenario.plc_program,
                                                         connector=InProcessConnector()), [recorder]))
    recorder.close()
    assert len(said) == 1 and "the recording stopped at its size limit" in said[0]
    recording = read_recording(str(path))
    assert recording.end is not None and recording.end.reason == SIZE_LIMIT and recording.row_count < len(sound) - 1
    assert main(["replay", str(path)]) == 0


def test_a_cut_last_line_replays_up_to_the_last_complete_row(
        tmp_path: Path, sound: list[Any], capsys: pytest.CaptureFixture[str]) -> None:
    """The docs promised it; the reader refused the whole file."""
    text = "".join(json.dumps(value) + "\n" for value in sound)
    cut = tmp_path / "cut.vcrec"
    cut.write_text(text[:-9], encoding="utf-8")  # the end row and part of the row before: torn
    recording = read_recording(str(cut))
    lines = len(sound)
    assert recording.cut is not None and recording.cut.line == lines and not recording.complete
    assert main(["replay", str(cut)]) == 0
    captured = capsys.readouterr()
    assert f"{cut}:{lines}: the recording was cut here (a torn last line" in captured.err
    assert f"no difference in {recording.last_cycle} IPO cycles" in captured.out


def test_a_cut_gzip_stream_replays_up_to_its_last_complete_row(
        tmp_path: Path, sound: list[Any], capsys: pytest.CaptureFixture[str]) -> None:
    text = "".join(json.dumps(value) + "\n" for value in sound).encode()
    header_end = text.index(b"\n") + 1
    compressor = zlib.compressobj(6, zlib.DEFLATED, 31)
    cut = tmp_path / "cut.vcrec.gz"
    cut.write_bytes(compressor.compress(text[: header_end + (len(text) - header_end) // 2])
                    + compressor.flush(zlib.Z_SYNC_FLUSH))
    recording = read_recording(str(cut))
    assert recording.cut is not None and recording.cut.why == "the compressed stream ends early"
    assert main(["replay", str(cut)]) == 0
    assert "the recording was cut here (the compressed stream ends early" in capsys.readouterr().err
