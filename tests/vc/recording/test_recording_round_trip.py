"""Round trip with a PLC in its own process, as a user does it: ``vc serve --modbus 127.0.0.1:0
--record FILE --scenario ...`` and ``python -m plc_stub --modbus ...`` reference X1 (lockstep and real
time); ``vc replay FILE`` finds no difference, ``--to-scenario`` gives a scenario that passes, and a
changed machine datum shows as the first difference."""

from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

import pytest
from recording_helpers import OPERATOR, ROOT

from vc.cli.main import main
from vc.recording.format import LIFE, Marker, read_recording

TIMEOUT_S = 120.0


def _record(out: Path, *options: str, served: tuple[str, ...] = ("--scenario", str(OPERATOR), "--duration", "0"),
            cwd: Path = ROOT) -> tuple[int, str]:
    """Serve (the operator scenario by default) with a plc_stub process until the scenario or the
    duration is done; the server's exit code and output."""
    server = subprocess.Popen(
        [sys.executable, "-m", "vc.cli.main", "serve", "--modbus", "127.0.0.1:0", *served,
         "--record", str(out), *options],
        stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, cwd=cwd)
    plc = None
    try:
        assert server.stdout is not None
        banner = ""
        while (port := re.search(r"Modbus TCP on 127\.0\.0\.1:(\d+)", banner)) is None:
            line = server.stdout.readline()
            assert line, f"vc serve ended before it listened: {banner}"
            banner += line
        plc = subprocess.Popen([sys.executable, "-m", "plc_stub", "--modbus", f"127.0.0.1:{port.group(1)}",
                                "--connect-timeout", "30"], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                               cwd=cwd)
        rest, _ = server.communicate(timeout=TIMEOUT_S)
        return server.returncode, banner + rest
    finally:
        for process in (plc, server):
            if process is not None and process.poll() is None:
                process.kill()
                process.wait()


@pytest.mark.timeout(300)
def test_a_lockstep_session_over_modbus_replays_and_becomes_a_passing_scenario(
        tmp_path: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch) -> None:
    out = tmp_path / "reference_x1.vcrec"
    code, output = _record(out)
    assert code == 0 and "PASS" in output and f"session recorded in {out}" in output
    recording = read_recording(str(out))
    assert recording.complete and (recording.header.link, recording.header.mode) == ("modbus", "lockstep")
    assert recording.header.program == "basic_machine"

    assert main(["replay", str(out)]) == 0
    assert f"no difference in {recording.last_cycle} IPO cycles" in capsys.readouterr().out

    scenario = tmp_path / "reference_x1.yaml"
    monkeypatch.chdir(ROOT)
    assert main(["replay", str(out), "--to-scenario", str(scenario)]) == 0
    assert main(["run", str(scenario)]) == 0
    assert "1 passed" in capsys.readouterr().out

    machine = Path(recording.header.machine.file)
    changed = tmp_path / "turn_mill.yaml"
    text = (ROOT / machine).read_text(encoding="utf-8")
    changed.write_text(text.replace("MD34040 REFP_VELO_SEARCH_MARKER: 300", "MD34040 REFP_VELO_SEARCH_MARKER: 240"),
                       encoding="utf-8")
    assert main(["replay", str(out), "--machine", str(changed)]) == 1
    shown = capsys.readouterr().out
    assert re.search(r"first difference at cycle \d+ \(t = [\d.]+ s\): \S+ \(DB\d+\.DBX\d+\.\d\) recorded \d, replayed"
                     r" \d", shown), shown


@pytest.mark.timeout(300)
def test_a_real_time_session_over_modbus_replays_in_lockstep_without_a_difference(
        tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    out = tmp_path / "reference_x1_real_time.vcrec.gz"
    # the scenario's own result depends on how busy this machine is (a late PLC raises alarm 2000);
    # whatever happened was recorded and must replay exactly
    _, output = _record(out, "--realtime", "--speed", "2")
    assert f"session recorded in {out}" in output
    recording = read_recording(str(out))
    assert recording.complete and recording.header.mode == "free_running"
    # before the PLC process connects, and whenever its scan is late, its sign of life stands still
    assert any(isinstance(row, Marker) and row.kind == LIFE for row, _ in recording.rows())
    assert main(["replay", str(out)]) == 0
    assert f"no difference in {recording.last_cycle} IPO cycles" in capsys.readouterr().out


@pytest.mark.timeout(300)
def test_a_machine_by_name_records_and_replays_and_the_recording_names_the_plc_that_ran(
        tmp_path: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch) -> None:
    """vc serve --machine turn_mill --record failed: "turn_mill: No such file or directory"; and vc
    replay called every external PLC basic_machine."""
    out = tmp_path / "by_name.vcrec"
    code, output = _record(out, served=("--machine", "turn_mill", "--duration", "1"), cwd=tmp_path)
    assert code == 0 and f"session recorded in {out}" in output, output
    recording = read_recording(str(out))
    assert recording.header.machine.file == "turn_mill" and "MD34040" in recording.header.machine.text
    assert recording.peers == ["external PLC over modbus from 127.0.0.1"]
    monkeypatch.chdir(tmp_path)
    assert main(["replay", str(out)]) == 0
    shown = capsys.readouterr().out
    assert "lockstep session of external PLC over modbus from 127.0.0.1 (a PLC that follows the harness is asked" \
           " for basic_machine) on turn_mill: no difference" in shown
    assert main(["replay", str(out), "--to-scenario", str(tmp_path / "by_name.yaml")]) == 0
    assert "machine: turn_mill\n" in (tmp_path / "by_name.yaml").read_text(encoding="utf-8")
    assert main(["replay", str(out), "--machine", "turn_mill"]) == 0


@pytest.mark.timeout(300)
def test_a_served_scenario_that_names_its_machine_by_name_records(tmp_path: Path) -> None:
    """With --scenario it raised FileNotFoundError in the recorder."""
    scenario = tmp_path / "operator.yaml"
    scenario.write_text(re.sub(r"(?m)^machine: .*$", "machine: turn_mill", OPERATOR.read_text(encoding="utf-8")),
                        encoding="utf-8")
    out = tmp_path / "scenario_by_name.vcrec"
    code, output = _record(out, served=("--scenario", str(scenario), "--duration", "0"), cwd=tmp_path)
    assert code == 0 and "PASS" in output and "Traceback" not in output, output
    assert read_recording(str(out)).header.machine.file == "turn_mill"
