"""The recording file: what the recorder writes reads back as it was; a bad file is a list of
located problems (``file:line:column: message``) and ``vc replay`` exits with 2, never a traceback."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from recording_helpers import HEADER, OPERATOR, record_scenario

from vc.cli.main import main
from vc.located_yaml import SourceError
from vc.recording.format import (
    END,
    NC,
    PLC,
    Action,
    Bytes,
    Marker,
    RecordingWriter,
    Row,
    read_recording,
    row_json,
)
from vc.simulation.observed import OperatorAction


def test_what_the_writer_writes_reads_back(tmp_path: Path) -> None:
    rows: list[Row] = [Bytes(0, NC, "DB31", 60, b"\xc0\x10"), Bytes(0, PLC, "Q", 0, b"\x01"),
            Action(3, OperatorAction("write", ("MCP.jog", 1))), Marker(5, "life"),
            Action(5, OperatorAction("link_fault", ("loss", 40000, ["plc_to_nc"], [], 0, 1)))]
    path = tmp_path / "r.vcrec"
    writer = RecordingWriter(str(path), HEADER)
    for row in rows:
        writer.write(row)
    writer.close(9)
    recording = read_recording(str(path))
    assert recording.header == HEADER
    assert [row for row, _ in recording.rows()] == [*rows, Marker(9, END)]
    assert recording.complete and recording.last_cycle == 9 and recording.stalls == 1 and recording.cut is None
    assert [str(mark) for _, mark in recording.rows()][:2] == [f"{path}:2:1", f"{path}:3:1"]
    assert json.loads(path.read_text().splitlines()[1]) == row_json(rows[0]) == [0, "nc", "DB31", 60, "c010"]


def _problems(tmp_path: Path, *lines: str) -> list[str]:
    path = tmp_path / "bad.vcrec"
    path.write_text("".join(line + "\n" for line in lines), encoding="utf-8")
    with pytest.raises(SourceError) as error:
        read_recording(str(path))
    return [str(problem).replace(str(path), "F") for problem in error.value.problems]


HEAD = json.dumps(HEADER.to_json()).replace('"version": 2', '"version": 1')  # the version 1 files are read


@pytest.mark.parametrize(("lines", "expected"), [
    ((), ["F:1:1: the file is empty: not a recording of vc serve --record"]),
    (("{not json",), ["F:1:2: not JSON: Expecting property name enclosed in double quotes"]),
    (('{"format": "vc-coverage", "version": 1}',),
     ['F:1:1: not a recording of vc serve --record (the first line must be its header, with "format":'
      ' "vc-recording")']),
    ((HEAD.replace('"version": 1', '"version": 7'),),
     ["F:1:1: recording format version 7: this vc reads versions 1, 2"]),
    ((HEAD.replace('"ipo_cycle_us": 2000', '"ipo_cycle_us": -1'),),
     ["F:1:1: header: ipo_cycle_us must be a whole number from 1 to 1,000,000"]),
    ((HEAD, '[0, "plc", "DB99", 0, "00"]', '[1, "nc", "DB31", 159, "0000"]', '[2, "nc", "DB31", 0, "zz"]',
      '[1, "life"]', '[3, "op", "press", "MCP.jog"]', '[3, "op", "write", "MCP.jog"]', '"row"',
      '[4, "end"]', '[5, "life"]'),
     ["F:2:1: area DB99 is not one of the header's areas (DB10, DB31, I, Q)",
      "F:3:1: bytes 159..160 lie outside DB31 (0..159)",
      "F:4:1: 'zz' is not hex (two digits per byte)",
      "F:5:1: cycle 1 comes after cycle 2: the cycles of a recording never decrease",
      "F:6:1: an op row is [cycle, \"op\", kind, ...] with kind one of write, force, release, mda, program,"
      " power_cycle, fault, link_fault, clear_faults, acknowledge, move_by_hand, handwheel",
      "F:7:1: an op row write has the arguments signal, value",
      "F:8:1: a row is [cycle, kind, ...] with kind one of plc, nc, life, op, peer, end, not \"row\"",
      "F:10:1: a row after the end row"]),
])
def test_a_bad_file_is_a_list_of_located_problems(tmp_path: Path, lines: tuple[str, ...],
                                                  expected: list[str]) -> None:
    assert _problems(tmp_path, *lines) == expected


def test_vc_replay_lists_the_problems_and_exits_with_2(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    bad = tmp_path / "bad.vcrec"
    bad.write_text(HEAD + "\n[0, \"nc\"]\n", encoding="utf-8")
    assert main(["replay", str(bad)]) == 2
    err = capsys.readouterr().err
    assert f"{bad}:2:1: a nc row is [cycle, \"nc\", area, byte, hex]" in err and "1 problem found" in err
    assert main(["replay", str(tmp_path / "missing.vcrec")]) == 2
    assert "cannot read the recording: No such file or directory" in capsys.readouterr().err
    binary = tmp_path / "binary.vcrec"
    binary.write_bytes(b"\xff\xfe\x00garbage")
    assert main(["replay", str(binary)]) == 2
    assert "Traceback" not in capsys.readouterr().err


def test_a_broken_machine_file_in_the_recording_is_located_in_it(tmp_path: Path,
                                                                  capsys: pytest.CaptureFixture[str]) -> None:
    good = tmp_path / "good.vcrec"
    assert record_scenario(OPERATOR, good).passed
    lines = good.read_text(encoding="utf-8").splitlines()
    header = json.loads(lines[0])
    header["machine"]["text"] = header["machine"]["text"].replace("MD32000 MAX_AX_VELO: 30000",
                                                                  "MD32000 MAX_AX_VELO: fast", 1)
    broken = tmp_path / "broken.vcrec"
    broken.write_text("\n".join([json.dumps(header), *lines[1:]]) + "\n", encoding="utf-8")
    assert main(["replay", str(broken)]) == 2
    err = capsys.readouterr().err
    assert f"{broken} (machine " in err and "MD32000" in err and "Traceback" not in err


def test_an_action_the_machine_cannot_take_is_located_at_its_row(tmp_path: Path,
                                                                  capsys: pytest.CaptureFixture[str]) -> None:
    good = tmp_path / "good.vcrec"
    assert record_scenario(OPERATOR, good).passed
    lines = good.read_text(encoding="utf-8").splitlines()
    strange = tmp_path / "strange.vcrec"
    strange.write_text("\n".join([lines[0], '[0, "op", "write", "MCP.teleport", 1]', *lines[1:]]) + "\n",
                       encoding="utf-8")
    assert main(["replay", str(strange)]) == 2
    err = capsys.readouterr().err
    assert f"{strange}:2:1: the operator's action write cannot be done again on this machine: " in err
    assert "MCP.teleport" in err and "Traceback" not in err


def test_vc_serve_refuses_a_recording_it_cannot_write(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    target = tmp_path / "missing" / "r.vcrec"
    assert main(["serve", "--modbus", "127.0.0.1:0", "--record", str(target)]) == 2
    assert f"vc serve: {target}: No such file or directory" in capsys.readouterr().err
