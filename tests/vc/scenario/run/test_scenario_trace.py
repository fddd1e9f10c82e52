"""Traces: CSV and VCD written, then read back; history queries; the recorder's cost."""

from __future__ import annotations

import csv
import os
import shutil
import subprocess
from pathlib import Path

import pytest
from scenario_fakes import FakeTarget, ImageFakeTarget, SimpleNc, machine, scenario
from vcd.reader import TokenKind, tokenize

from vc.scenario.language.model import EdgeKind
from vc.scenario.language.quantities import axis_quantity
from vc.scenario.run.runner import run_scenario
from vc.scenario.run.trace import (
    Recorder,
    Recording,
    measure_sample_cost,
    recorded_quantities,
    vcd_scope_and_name,
    write_csv,
    write_traces,
    write_vcd,
)

MOVE = """\
name: a move, recorded
machine: machines/mini.yaml
plc: none
steps:
  - set: {MODEGROUP.basic.out.mdaMode: 1, MCP.feedOverride: 80}
  - mda: "G1 X1 F3000"
  - pulse: {signal: CHAN1.basic.out.ncStart, for: 20ms}
  - wait: {until: "X1.basic.in.posFineReached == 1", timeout: 1s}
  - expect: "X1.setpoint == 1 and DB31.DBX60.7 == 1"
"""


def recorded(tmp_path: Path) -> Recorder:
    result = run_scenario(scenario(tmp_path, MOVE), FakeTarget(machine(), SimpleNc()))
    assert result.passed, result.failure
    assert result.recorder is not None
    return result.recorder


def test_csv_round_trip(tmp_path: Path) -> None:
    recorder = recorded(tmp_path)
    path = tmp_path / "trace.csv"
    write_csv(recorder, path)
    with open(path, encoding="utf-8", newline="") as handle:
        rows = list(csv.reader(handle))
    assert rows[0] == ["cycle", "time_s", "name", "value", "address", "unit"]
    body = rows[1:]
    assert body == sorted(body, key=lambda row: (int(row[0]), row[2]))
    changes = [row for row in body if row[0] != "0"]
    # 0.1 mm per cycle: X1 arrives after 10 cycles and reports standstill one cycle later
    assert ["0", "0.000000", "CHAN1.basic.out.ncStart", "1", "DB21.DBX7.1", ""] in body
    assert ["10", "0.020000", "CHAN1.basic.out.ncStart", "0", "DB21.DBX7.1", ""] in changes
    assert ["11", "0.022000", "X1.basic.in.posFineReached", "1", "DB31.DBX60.7", ""] in changes
    assert ["0", "0.000000", "MCP.feedOverride", "80", "IB4", ""] in body
    positions = [float(row[3]) for row in body if row[2] == "X1.position"]
    assert positions[0] == 0.0 and positions[-1] == 1.0 and len(positions) == 11
    # the setpoint is recorded because the scenario names it; the physical position is not
    assert any(row[2] == "X1.setpoint" for row in changes)
    assert not any(row[2] == "X1.physical" for row in body)
    # initial values of every recorded signal at cycle 0, then only changes
    assert len([row for row in body if row[2] == "X1.basic.in.enc1Synchronized"]) == 1


def test_vcd_round_trip(tmp_path: Path) -> None:
    recorder = recorded(tmp_path)
    path = tmp_path / "trace.vcd"
    write_vcd(recorder, path, date="test")
    with open(path, "rb") as handle:
        tokens = list(tokenize(handle))
    scopes: list[str] = []
    variables: dict[str, tuple[str, str, int]] = {}  # id -> (scope, name, size)
    changes: dict[str, list[tuple[int, object]]] = {}
    time = 0
    for token in tokens:
        if token.kind is TokenKind.TIMESCALE:
            assert (token.timescale.magnitude, token.timescale.unit.value) == (1, "us")
        elif token.kind is TokenKind.SCOPE:
            scopes.append(token.scope.ident)
        elif token.kind is TokenKind.UPSCOPE:
            scopes.pop()
        elif token.kind is TokenKind.VAR:
            variables[token.var.id_code] = (scopes[-1], token.var.reference, token.var.size)
        elif token.kind is TokenKind.CHANGE_TIME:
            time = token.time_change
        elif token.kind in (TokenKind.CHANGE_SCALAR, TokenKind.CHANGE_VECTOR, TokenKind.CHANGE_REAL):
            data = token.data
            value = data.value
            changes.setdefault(data.id_code, []).append((time, value))
    by_name = {(scope, name): (code, size) for code, (scope, name, size) in variables.items()}
    assert {scope for scope, _ in by_name} >= {"NC", "MODEGROUP", "CHAN1", "X1", "Z1", "SP1", "PLANT", "AXES"}
    code, size = by_name[("CHAN1", "basic.out.ncStart")]
    assert size == 1
    # a VCD shows one value per instant: the write at 0 s hides the initial 0
    assert [(t, str(v)) for t, v in changes[code]] == [(0, "1"), (20_000, "0")]
    code, size = by_name[("X1", "basic.in.posFineReached")]
    assert [(t, str(v)) for t, v in changes[code]] == [(0, "0"), (22_000, "1")]
    code, size = by_name[("PLANT", "MCP.feedOverride")]
    assert size == 8
    assert [(t, v) for t, v in changes[code]] == [(0, 80)]
    code, _ = by_name[("AXES", "X1.position")]
    assert changes[code][-1] == (20_000, 1.0)
    _, size = by_name[("X1", "basic.out.refPointSelection")]
    assert size == 4  # a bits field keeps its width (DB31.DBX2.4 .. 2.7)


def _vcd_names(path: Path) -> dict[str, str]:
    """Every variable of a VCD by its full hierarchical name (as GTKWave names it) -> its type."""
    scopes: list[str] = []
    names: dict[str, str] = {}
    with open(path, "rb") as handle:
        for token in tokenize(handle):
            if token.kind is TokenKind.SCOPE:
                scopes.append(token.scope.ident)
            elif token.kind is TokenKind.UPSCOPE:
                scopes.pop()
            elif token.kind is TokenKind.VAR:
                names[".".join([*scopes, token.var.reference])] = token.var.type_.value
    return names


GTKWAVE, XVFB_RUN = shutil.which("gtkwave"), shutil.which("xvfb-run")
needs_gtkwave = pytest.mark.skipif((GTKWAVE is None or XVFB_RUN is None) and not os.environ.get("VC_REQUIRE_GTKWAVE"),
                                   reason="Debian's gtkwave and xvfb are not installed (.ci/run installs them)")
# GTKWave's own Tcl: the traces the save file put in view, by index (a blank row has no name)
TRACES_IN_VIEW = """
set count [gtkwave::getTotalNumTraces]
for {set index 0} {$index < $count} {incr index} { puts "vc-trace [gtkwave::getTraceNameFromIndex $index]" }
gtkwave::/File/Quit
"""


def gtkwave_traces(save_file: Path) -> list[str]:
    """The names of the traces GTKWave shows when it opens ``save_file`` (headless, under xvfb-run)."""
    script = save_file.with_name("traces_in_view.tcl")
    script.write_text(TRACES_IN_VIEW)
    done = subprocess.run(["xvfb-run", "-a", "gtkwave", "-S", str(script), str(save_file)], capture_output=True,
                          text=True, timeout=120, cwd=save_file.parent)
    assert done.returncode == 0, done.stdout + done.stderr
    return [line.removeprefix("vc-trace ") for line in done.stdout.splitlines()
            if line.startswith("vc-trace ") and line.strip() != "vc-trace"]


@needs_gtkwave
def test_gtkwave_opens_the_save_file_with_the_scenarios_own_signals_in_view(tmp_path: Path) -> None:
    """GTKWave itself opens the .gtkw: the VCD beside it, and exactly the names the scenario uses in view, each
    as GTKWave names it (a dotted VCD name is an escaped identifier, a byte carries its bit range): digital
    signals as traces, reals and axis quantities as analog steps (GTKWave's save-file flags: 0x22 hex
    right-justified, 0x24 dec, 0x48020 real + analog step)."""
    source = scenario(tmp_path, MOVE)
    result = run_scenario(source, FakeTarget(machine(), SimpleNc()))
    assert result.recorder is not None
    files = write_traces(result.recorder, source.quantities, tmp_path / "traces", "move", "a move")
    assert [Path(file).name for file in files] == ["move.csv", "move.vcd", "move.gtkw"]
    save_file = tmp_path / "traces" / "move.gtkw"
    lines = save_file.read_text().splitlines()
    assert lines[:3] == ["[*] vc-harness: a move", '[dumpfile] "move.vcd"', '[savefile] "move.gtkw"']
    assert gtkwave_traces(save_file) == ["\\basic.out.mdaMode", "\\MCP.feedOverride[7:0]", "\\basic.out.ncStart",
                                         "\\basic.in.posFineReached", "\\X1.setpoint"]
    traced = [line for line in lines if line and line[0] not in "[@-*"]
    flags, current = {}, ""
    for line in lines:  # a flags line holds until the next one
        if line.startswith("@"):
            current = line
        elif line in traced:
            flags[line] = current
    assert flags["X1.\\basic.in.posFineReached"] == "@22" and flags["PLANT.\\MCP.feedOverride[7:0]"] == "@24"
    assert flags["AXES.\\X1.setpoint"] == "@48020"
    assert _vcd_names(tmp_path / "traces" / "move.vcd")["AXES.X1.setpoint"] == "real"


def test_a_recording_crosses_a_process_boundary_as_plain_data(tmp_path: Path) -> None:
    source = scenario(tmp_path, MOVE)
    recorder = recorded(tmp_path)
    data = recorder.data()
    assert data.size == sum(16 * len(history) for history in recorder.histories)
    target = FakeTarget(machine(), SimpleNc())
    quantities = recorded_quantities(target.catalog, target.plant_io, ("X1", "Z1", "SP1"), source.quantities)
    again = Recording.from_data(data, quantities)
    assert [list(h.entries()) for h in again.histories] == [list(h.entries()) for h in recorder.histories]
    assert again.alarm_numbers() == recorder.alarm_numbers()
    write_vcd(recorder, tmp_path / "a.vcd", date="x")
    write_vcd(again, tmp_path / "b.vcd", date="x")
    assert (tmp_path / "a.vcd").read_bytes() == (tmp_path / "b.vcd").read_bytes()
    named = recorder.data({"X1.position"})
    assert [name for name, _, _ in named.histories] == ["X1.position"]


def test_vcd_scopes() -> None:
    assert vcd_scope_and_name(axis_quantity("X1", "position")) == ("AXES", "X1.position")


def test_history_queries(tmp_path: Path) -> None:
    recorder = recorded(tmp_path)
    names = {history.quantity.name: history.quantity for history in recorder.histories}
    start = names["CHAN1.basic.out.ncStart"]
    assert recorder.occurrences(start, EdgeKind.RISES) == [0]
    assert recorder.occurrences(start, EdgeKind.FALLS) == [10]
    assert recorder.occurrences(start, EdgeKind.CHANGES) == [0, 10]
    assert recorder.recent(start) == [(0, 0), (0, 1), (10, 0)]
    assert recorder.recent(start, limit=1) == [(10, 0)]
    assert recorder.recent(names["X1.basic.in.enc1Synchronized"], window_s=0.001) == [(0, 0)]
    assert recorder.time_of(11) == 0.022


def test_recorder_cost(tmp_path: Path) -> None:
    """Not a timing assertion: prints the figures the harness engineer needs (pytest -s)."""
    slow = measure_sample_cost(FakeTarget(machine(), SimpleNc()), cycles=300)
    fast = measure_sample_cost(ImageFakeTarget(machine(), SimpleNc()), cycles=300)
    print(f"\nrecorder sample: {slow:.1f} us through read(), {fast:.1f} us through image_areas()")
    assert fast > 0 and slow > 0


FAILING_MOVE = MOVE.replace('"X1.setpoint == 1 and', '"X1.setpoint == 2 and')


def test_without_traces_a_run_records_only_the_scenarios_own_names(tmp_path: Path) -> None:
    """vc run without traces, golden traces or a report records what the steps, conditions and
    failure messages read: the failure (its trail of recent values included) is the same."""
    failing = scenario(tmp_path, FAILING_MOVE)
    everything = run_scenario(failing, ImageFakeTarget(machine(), SimpleNc()))
    lean = run_scenario(failing, ImageFakeTarget(machine(), SimpleNc()), record_all=False)
    assert everything.recorder is not None and lean.recorder is not None
    assert {history.quantity.name for history in lean.recorder.histories} == \
        {quantity.name for quantity in failing.quantities if quantity.name != "time"}
    assert len(everything.recorder.histories) > 10 * len(lean.recorder.histories)
    assert not lean.passed and lean.failure == everything.failure
    assert lean.failure is not None and lean.failure.history
    for history in lean.recorder.histories:
        same = everything.recorder.history(history.quantity)
        assert same is not None and list(same.entries()) == list(history.entries())


class _CountingTarget(ImageFakeTarget):
    def __init__(self) -> None:
        super().__init__(machine(), SimpleNc())
        self.axis_reads = 0

    def axis_quantity(self, axis: str, quantity: str) -> float:
        self.axis_reads += 1
        return super().axis_quantity(axis, quantity)


def test_an_axis_quantity_is_read_once_a_cycle_for_the_recorder_and_the_conditions(tmp_path: Path) -> None:
    text = MOVE.replace("steps:", 'invariants:\n  - "X1.position >= 0"\n  - "X1.position < 2"\nsteps:')
    target = _CountingTarget()
    result = run_scenario(scenario(tmp_path, text), target, record_all=False)
    assert result.passed, result.failure
    # the recorder reads X1.position and X1.setpoint after each cycle, the two invariants take its reading;
    # the steps between two cycles (the expect) read the target itself
    assert result.cycles * 2 <= target.axis_reads <= result.cycles * 2 + 6


def test_the_recorded_names_of_a_machine_are_the_same_for_every_scenario_on_it() -> None:
    first, second = FakeTarget(machine()), FakeTarget(machine())
    names = recorded_quantities(first.catalog, first.plant_io, ["X1"])
    assert names == recorded_quantities(second.catalog, second.plant_io, ["X1"])
    assert "X1.position" in names and "X1.velocity" in names and "CHAN1.basic.out.ncStart" in names
    assert "Z1.position" not in names
