"""The alarms present show with a failure: in its message, as marks in the timing diagram, and as DB100's
alarm list in the CSV and VCD traces; the golden traces compare them as before, as the list of alarms raised."""

from __future__ import annotations

import csv
from pathlib import Path

import pytest
from vcd.reader import TokenKind, tokenize

from interfaces.links.inprocess import plc_programs
from vc.harness.targets import simulation_for
from vc.scenario.language.loader import load_scenario
from vc.scenario.language.quantities import signal_quantity
from vc.scenario.outputs.diagram import save
from vc.scenario.outputs.golden import summarize
from vc.scenario.outputs.timing import AlarmMark, alarm_marks, timing_diagram
from vc.scenario.run.runner import run_one
from vc.scenario.run.trace import History, Recording, is_alarm_number

ROOT = Path(__file__).resolve().parents[4]
MESHING = ROOT / "scenarios/spindle/meshing_with_nc_oscillation.yaml"
GEAR_ALARM = ("65830 Channel CHAN1 spindle 1 gear stage change not acknowledged within MD10192 = 0.3 s (SP1)")


@pytest.fixture(scope="module")
def failed(tmp_path_factory: pytest.TempPathFactory) -> tuple[object, Path]:
    """The library's gear change with MD10192 = 0.3 s: the NC gives up on the PLC's acknowledgement (65830)
    while the scenario waits for gearChangeoverDone."""
    directory = tmp_path_factory.mktemp("alarm")
    text = MESHING.read_text().replace("machine: ../machines/", f"machine: {ROOT}/scenarios/machines/")
    path = directory / "meshing.yaml"
    path.write_text(text.replace("machine_data:\n", "machine_data:\n  NC: {MD10192: 0.3}\n", 1))
    result = run_one(load_scenario(str(path), plc_programs().keys()), simulation_for, trace_dir=directory,
                     trace_name="meshing")
    return result, directory


def test_the_failure_names_the_alarms_present(failed: tuple[object, Path]) -> None:
    result, _ = failed
    failure = result.failure  # type: ignore[attr-defined]
    assert failure is not None
    assert failure.message == ('waited 1 s for "SP1.spindle.out.gearChangeoverDone == 1"; it did not become true.'
                               f" Now: SP1.spindle.out.gearChangeoverDone = 0; alarms present: {GEAR_ALARM}")


def test_the_diagram_marks_the_alarm_where_it_was_raised(failed: tuple[object, Path]) -> None:
    result, directory = failed
    diagram = timing_diagram(result)  # type: ignore[arg-type]
    assert diagram is not None and [mark.number for mark in diagram.alarms] == [65830]
    assert diagram.failure_s is not None and 0 < diagram.alarms[0].time_s < diagram.failure_s
    width, height = save(diagram, directory / "meshing.png")
    assert width > 0 and height > 0


def test_the_traces_carry_the_alarm_list(failed: tuple[object, Path]) -> None:
    _, directory = failed
    with (directory / "meshing.csv").open(newline="") as handle:
        numbers = [(row["value"], row["address"]) for row in csv.DictReader(handle)
                   if row["name"] == "ALARMS.entry[1].in.number"]
    assert numbers == [("0", "DB100.DBD4"), ("65830", "DB100.DBD4")]
    with (directory / "meshing.vcd").open("rb") as handle:
        tokens = list(tokenize(handle))
    code = next(token.var.id_code for token in tokens
                if token.kind is TokenKind.VAR and token.var.reference == "entry[1].in.number")
    assert any(token.kind is TokenKind.CHANGE_VECTOR and token.vector_change.id_code == code
               and token.vector_change.value == 65830 for token in tokens)


def test_the_golden_summary_keeps_the_alarm_list_out_of_the_digital_signals(failed: tuple[object, Path]) -> None:
    result, _ = failed
    recorder = result.recorder  # type: ignore[attr-defined]
    assert any(is_alarm_number(history.quantity) for history in recorder.histories)
    summary = summarize(recorder, recorder.alarm_numbers())
    assert not any(name.endswith(".in.number") for name in summary.digital)
    assert summary.alarms == [65830]
    named = summarize(recorder, recorder.alarm_numbers(), {"ALARMS.entry[1].in.number"})
    assert named.digital["ALARMS.entry[1].in.number"][-1][1] == 65830  # a scenario that names it keeps it


def test_an_alarm_that_moves_up_the_list_is_not_raised_again(failed: tuple[object, Path]) -> None:
    result, _ = failed
    catalog = result.scenario.catalog  # type: ignore[attr-defined]
    first, second = (History(signal_quantity(catalog.resolve(f"ALARMS.entry[{n}].in.number"))) for n in (1, 2))
    for history, changes in ((first, [(0, 0), (10, 3000), (30, 2000), (40, 0)]),
                             (second, [(0, 0), (20, 2000), (30, 0)])):  # 2000 moves up as 3000 goes
        for cycle, value in changes:
            history.add(cycle, value)
    marks = alarm_marks(Recording(2000, [first, second]))
    assert marks == (AlarmMark(0.02, 3000), AlarmMark(0.04, 2000))
