"""The ``vc`` command line as a user sees it: map, bench, run with a broken file."""

from __future__ import annotations

import csv
import io
import json
from pathlib import Path

import pytest

from vc.cli.main import build_parser, main
from vc_build import status as build_status

ROOT = Path(__file__).resolve().parents[3]
MACHINE = str(ROOT / "scenarios" / "machines" / "turn_mill.yaml")


def test_map_csv_starts_with_the_required_columns_and_lists_every_instance(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["map", "--machine", MACHINE, "--format", "csv"]) == 0
    rows = list(csv.DictReader(io.StringIO(capsys.readouterr().out)))
    assert list(rows[0])[:7] == ["symbol", "address", "direction", "type", "modbus_table", "modbus_address", "bit"]
    by_symbol = {row["symbol"]: row for row in rows}
    # turn_mill: X1 is machine axis 1 (DB31), SP3 machine axis 6 (DB36); one channel (DB21)
    assert by_symbol["X1.basic.in.enc1Synchronized"]["address"] == "DB31.DBX60.4"
    assert by_symbol["SP3.basic.in.enc1Synchronized"]["address"] == "DB36.DBX60.4"
    assert by_symbol["CHAN1.basic.out.reset"]["address"] == "DB21.DBX7.7"
    assert by_symbol["MODEGROUP.basic.out.jogMode"]["direction"] == "plc_to_nc"
    assert by_symbol["MCP.jog"]["direction"] == "plant_to_plc"
    instances = {row["instance"] for row in rows}
    assert instances == {"NC", "MODEGROUP", "HMI", "CHAN1", "X1", "Z1", "Y1", "SP1", "SP2", "SP3", "ALARMS",
                         "PLCALARMS", "PLANT", "LINK", "COMMISSIONING"}
    referenced = by_symbol["X1.basic.in.enc1Synchronized"]
    assert (referenced["modbus_table"], referenced["bit"]) == ("discrete_input", "")
    register, register_bit = int(referenced["register"]), int(referenced["register_bit"])
    assert int(referenced["modbus_address"]) == 16 * register + (register_bit + 8) % 16
    assert referenced["modbus_number"] == f"1{int(referenced['modbus_address']) + 1:04d}"
    override = by_symbol["CHAN1.basic.out.pathFeedrateOvrFactor"]  # DB21.DBB4: an even byte, the high half
    assert (override["modbus_table"], override["bit"]) == ("holding_register", "8")
    assert by_symbol["LINK.scanDone"]["modbus_address"] == "0"


def test_map_json_and_markdown(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["map", "--machine", MACHINE, "--format", "json"]) == 0
    entries = json.loads(capsys.readouterr().out)
    assert {"symbol": "X1.basic.out.refPointApproachCam", "address": "DB31.DBX12.7"}.items() <= entries[
        [e["symbol"] for e in entries].index("X1.basic.out.refPointApproachCam")].items()
    assert main(["map", "--machine", MACHINE, "--format", "md"]) == 0
    markdown = capsys.readouterr().out
    assert "## X1 (DB31)" in markdown and "| X1.basic.in.enc1Synchronized | DB31.DBX60.4 |" in markdown


def test_map_of_a_broken_machine_file_names_file_and_line(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    broken = tmp_path / "broken.yaml"
    broken.write_text("machine: m\nchannels:\n  CHAN1: {axes: [X1]}\naxes:\n  X1: {MD32000: fast}\n")
    assert main(["map", "--machine", str(broken)]) == 2
    error = capsys.readouterr().err
    assert f"{broken}:5:" in error and "MD32000" in error and "nothing was run" in error


def test_bench_prints_a_line_per_workload_and_its_figures_as_the_last_line_in_json(
        capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["bench", "--machine", MACHINE, "--seconds", "1"]) == 0
    lines = capsys.readouterr().out.strip().splitlines()
    light = next(line for line in lines if line.startswith("light: "))
    heavy = next(line for line in lines if line.startswith("heavy: "))
    assert "two axes (X1, Y1), built-in PLC basic_machine: real-time factor" in light
    assert "everything (X1, Z1, Y1, SP1, SP2, SP3; SP2 coupled to SP1), built-in PLC spindle:" in heavy
    assert "us per IPO cycle" in light and "us per IPO cycle" in heavy
    figures = json.loads(lines[-1])
    assert set(figures) == {"realtime_factor", "us_per_cycle", "heavy_realtime_factor", "heavy_us_per_cycle", "build"}
    assert all(figures[key] > 0 for key in figures if key != "build")
    assert figures["build"] == ("compiled" if build_status().compiled else "pure")


def test_bench_scaling_prints_the_table_and_its_rows_in_json(
        capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(ROOT)  # the three machines of scenarios/machines/
    assert main(["bench", "--scaling", "--seconds", "0.3"]) == 0
    lines = capsys.readouterr().out.strip().splitlines()
    assert lines[2] == "| machine | load | moving / axes | us per IPO cycle | real-time factor |"
    assert lines[6].startswith("| mill_3axis | everything | 4 / 4 | ")
    figures = json.loads(lines[-1])
    assert figures["build"] in ("compiled", "pure") and len(figures["scaling"]) == 9
    assert main(["bench", "--scaling", "--machine", MACHINE, "--seconds", "0.3"]) == 0
    rows = json.loads(capsys.readouterr().out.strip().splitlines()[-1])["scaling"]
    assert [(row["machine"], row["load"], row["moving"]) for row in rows] == [
        ("turn_mill", "idle", 0), ("turn_mill", "two axes", 2), ("turn_mill", "everything", 6)]
    assert main(["bench", "--scaling", "--link", "modbus"]) == 2


def test_a_broken_scenario_stops_the_whole_run_before_anything_runs(
        tmp_path: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(ROOT)
    good = ROOT / "scenarios" / "foundation" / "nc_start_without_reference.yaml"
    broken = tmp_path / "broken.yaml"
    broken.write_text(f"name: broken\nmachine: {ROOT / 'scenarios/machines/turn_mill.yaml'}\nplc: basic_machine\n"
                      "steps:\n  - press: MCP.jgo\n")
    assert main(["run", str(good), str(broken)]) == 2
    output = capsys.readouterr()
    text = output.out + output.err
    assert f"{broken}:5:" in text and "MCP.jgo" in text and "did you mean MCP.jog" in text
    assert "PASS" not in text  # nothing ran, not even the good scenario


def test_commands_find_the_default_machine_by_name_from_any_directory(
        tmp_path: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(tmp_path)
    assert build_parser().parse_args(["serve"]).machine == "turn_mill"
    assert build_parser().parse_args(["bench"]).machine is None  # turn_mill; with --scaling the three machines
    assert build_parser().parse_args(["fmu", "export", "-o", "x.fmu"]).machine == "turn_mill"
    assert main(["bench", "--seconds", "0.1"]) == 0
    assert "machine turn_mill," in capsys.readouterr().out
    assert main(["map", "--machine", "mill_5axis", "--format", "csv"]) == 0
    assert "C1.basic.in.enc1Synchronized,DB35.DBX60.4," in capsys.readouterr().out
    scenario = tmp_path / "by_name.yaml"
    scenario.write_text("name: a packaged machine by name\nmachine: mill_3axis\nplc: basic_machine\n"
                        "steps:\n  - wait: 20ms\n")
    assert main(["run", str(scenario)]) == 0
    unknown = tmp_path / "unknown.yaml"
    unknown.write_text("name: an unknown machine\nmachine: lathe\nplc: basic_machine\nsteps:\n  - wait: 20ms\n")
    assert main(["run", str(unknown)]) == 2
    assert f"{unknown}:2:10: no machine file 'lathe' and no packaged machine" in capsys.readouterr().out


def test_run_takes_at_most_four_worker_processes_per_core(capsys: pytest.CaptureFixture[str]) -> None:
    from vc.scenario.distribution.parallel import max_workers

    assert build_parser().parse_args(["run", "-j", str(max_workers())]).jobs == max_workers()
    with pytest.raises(SystemExit) as exit_code:
        build_parser().parse_args(["run", "-j", "100000"])
    assert exit_code.value.code == 2
    assert f"100000: from 1 to {max_workers()} (4 worker processes per core)" in capsys.readouterr().err


def test_run_max_variants_sets_the_ceiling_on_the_variants_of_a_run(
        tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    scenario = tmp_path / "matrix.yaml"
    scenario.write_text("name: a matrix\nmachine: mill_3axis\nplc: basic_machine\nvary: {wait: [10ms, 20ms, 30ms]}\n"
                        "steps:\n  - wait: ${wait}\n")
    assert main(["run", str(scenario), "--max-variants", "2", "-j", "1"]) == 2
    assert f"{scenario}:4:7: this matrix gives 3 variants; a run holds at most 2" in capsys.readouterr().out
    assert main(["run", str(scenario), "--max-variants", "3", "-j", "1"]) == 0
    with pytest.raises(SystemExit):
        build_parser().parse_args(["run", str(scenario), "--max-variants", "0"])
