"""The coverage data: value records, merging, and the file - written and read back as it was, and a
file that is not one is a list of problems at their lines."""

from __future__ import annotations

import json
from collections.abc import Callable
from pathlib import Path
from typing import Any

import pytest
from hypothesis import given
from hypothesis import strategies as st

from vc.coverage.data import FALLS, MAX_DISTINCT, RISES, CoverageData, MachineCoverage, ValueRecord
from vc.located_yaml import SourceError


def test_a_value_record_keeps_edges_extremes_and_distinct_values() -> None:
    record = ValueRecord()
    record.saw(0)
    for old, new in ((0, 1), (1, 0), (0, 5)):
        record.changed(old, new)
    assert (record.values, record.edges, record.low, record.high) == ({0, 1, 5}, RISES | FALLS, 0, 5)
    many = ValueRecord()
    for value in range(MAX_DISTINCT + 10):
        many.saw(value)
    assert len(many.values) == MAX_DISTINCT and many.more and many.distinct == MAX_DISTINCT + 1
    assert many.high == MAX_DISTINCT + 9  # the extremes are kept whatever the count


@given(st.lists(st.integers(0, 300), max_size=40), st.lists(st.integers(0, 300), max_size=40))
def test_merging_two_records_is_seeing_both(first: list[int], second: list[int]) -> None:
    def seen(values: list[int]) -> ValueRecord:
        record = ValueRecord()
        for value in values:
            record.saw(value)
        return record

    merged = seen(first)
    merged.merge(seen(second))
    both = seen(first + second)
    assert (merged.low, merged.high) == (both.low, both.high)
    if both.more:  # beyond MAX_DISTINCT only the count is approximate
        assert merged.more or len(merged.values) == MAX_DISTINCT
    else:
        assert (merged.values, merged.more) == (both.values, False)


def _sample() -> CoverageData:
    data = CoverageData(scenarios=2, cycles=500)
    machine = data.machines["mini"] = MachineCoverage(source="machines/mini.yaml", instances={"X1": 31})
    machine.signals["X1.basic.in.enc1Synchronized"] = ValueRecord({0, 1}, False, 0, 1, RISES)
    machine.types["X1.basic.in.enc1Synchronized"] = "bool"
    machine.not_applicable.add("X1.spindle.in.gearChangeoverActive")
    machine.plant["X1.refCam"] = ValueRecord({0}, False, 0, 0, 0)
    function = data.function("gear_change")
    function.instances.add("mini/SP1")
    function.entered("NONE")
    function.took("NONE", "REQUESTED")
    data.alarm(3000).raised = 1
    data.alarm(3000).cleared_by("emergency_stop_ack")
    return data


def test_the_file_reads_back_as_it_was_written(tmp_path: Path) -> None:
    path = tmp_path / "coverage.json"
    _sample().save(str(path))
    assert CoverageData.load(str(path)).to_json() == _sample().to_json()
    assert json.loads(path.read_text())["format"] == "vc-coverage"


def _problems(tmp_path: Path, text: str) -> list[str]:
    path = tmp_path / "c.json"
    path.write_text(text, encoding="utf-8")
    with pytest.raises(SourceError) as error:
        CoverageData.load(str(path))
    return [str(problem).replace(str(path), "F") for problem in error.value.problems]


def test_a_file_that_is_not_a_coverage_file_is_located(tmp_path: Path) -> None:
    assert _problems(tmp_path, "{\n  \"format\": \"vc-coverage\",\n  oops\n}") == [
        "F:3:3: not a coverage file of vc run --coverage (not JSON: Expecting property name enclosed in double quotes)"]
    assert _problems(tmp_path, '{"format": "vc-recording", "version": 1}') == [
        'F:1:12: not a coverage file of vc run --coverage ("format" must be "vc-coverage")']
    assert _problems(tmp_path, '{"format": "vc-coverage", "version": 9}') == [
        "F:1:38: coverage file version 9: this vc reads version 1"]
    text = json.dumps(_sample().to_json(), indent=1)
    text = text.replace('"cycles": 500', '"cycles": -4').replace('"edges": 1', '"edges": 9')
    text = text.replace('"raised": 1', '"raised": "once"')
    problems = _problems(tmp_path, text)
    lines = text.splitlines()

    def line_of(fragment: str) -> int:
        return next(number for number, line in enumerate(lines, start=1) if fragment in line)

    cycles, edges, raised = line_of('"cycles": -4'), line_of('"edges": 9'), line_of('"raised": "once"')
    assert problems == [  # in the order of the file
        f"F:{cycles}:12: cycles must be a whole number >= 0, not -4",
        f"F:{edges}:15: machines.mini.signals.X1.basic.in.enc1Synchronized.edges must be 0..3 (1 rises, 2 falls)",
        f'F:{raised}:14: alarms.3000.raised must be a whole number >= 0, not "once"']
    assert _problems(tmp_path, '{"format": "vc-coverage", "version": 1, "extra": 1}') == [
        "F:1:50: unknown key 'extra' (known: alarms, cycles, format, functions, machines, scenarios, version)"]


@pytest.mark.parametrize(("text", "message"), [
    # each gave a traceback (RecursionError, ValueError) or was taken
    ('{"format": "vc-coverage", "version": 1, "machines": ' + "[" * 100_000 + "]" * 100_000 + "}",
     "F:1:1: not a coverage file of vc run --coverage (arrays and objects nested more than 8 deep)"),
    ('{"format": "vc-coverage", "version": 1, "scenarios": ' + "9" * 5000 + "}",
     "F:1:1: not a coverage file of vc run --coverage (a whole number of 5,000 digits (at most 20))"),
    ('{"format": "vc-coverage", "version": 1, "cycles": Infinity}',
     "F:1:1: not a coverage file of vc run --coverage (Infinity is not a number JSON knows (numbers must be finite))"),
])
def test_a_hostile_file_is_a_located_problem(tmp_path: Path, text: str, message: str) -> None:
    assert _problems(tmp_path, text) == [message]


def test_the_plc_user_alarms_of_db2_are_names_the_harness_knows(tmp_path: Path) -> None:
    """A run with the turret's alarm 700002 wrote a file that vc coverage report refused."""
    from vc.coverage.names import CoverageNames

    document = _sample().to_json()
    document["alarms"].update({"700002": {"raised": 1}, "700063": {"raised": 1}})
    path = tmp_path / "c.json"
    path.write_text(json.dumps(document, indent=1), encoding="utf-8")
    assert {700002, 700063} <= set(CoverageData.load(str(path), CoverageNames.of_this_harness()).alarms)
    document["alarms"].update({"700064": {"raised": 1}})
    path.write_text(json.dumps(document, indent=1), encoding="utf-8")
    with pytest.raises(SourceError) as caught:
        CoverageData.load(str(path), CoverageNames.of_this_harness())
    assert "alarm 700064 is no alarm of this NC (vc/core/alarms.py) and no PLC user alarm (700000 .. 700063)" in str(
        caught.value)


@pytest.mark.parametrize(("change", "message"), [
    (lambda d: d["machines"]["mini"]["signals"].update({"X1.basic.in.noSuchSignal": {"values": [0, 1]}}),
     "'X1.basic.in.noSuchSignal' is no signal of the catalogue for DB31"),
    (lambda d: d["machines"]["mini"]["signals"].update({"Q9.basic.in.enc1Synchronized": {"values": [0]}}),
     "'Q9.basic.in.enc1Synchronized': its instance 'Q9' is not one of the file's instances"),
    (lambda d: d["machines"]["mini"]["plant"].update({"X1.teleporter": {"values": [0]}}),
     "'X1.teleporter' is no plant I/O point of the harness"),
    (lambda d: d["functions"]["gear_change"]["states"].update({"FLYING": 1}),
     "'FLYING' is no state of gear_change"),
    (lambda d: d["functions"].update({"warp_drive": {"instances": [], "states": {}, "transitions": []}}),
     "'warp_drive' is no state machine of the harness"),
    (lambda d: d["alarms"].update({"123456": {"raised": 1}}), "alarm 123456 is no alarm of this NC"),
    (lambda d: d["machines"]["mini"]["instances"].update({"X7": 7}), "DB7 of 'X7' is no data block of the interface"),
])
def test_a_name_the_harness_does_not_know_is_refused_with_the_file_and_the_key(
        tmp_path: Path, change: Callable[[dict[str, Any]], None], message: str) -> None:
    """Unknown signals were merged silently."""
    from vc.coverage.names import CoverageNames

    document = _sample().to_json()
    change(document)
    path = tmp_path / "c.json"
    path.write_text(json.dumps(document, indent=1), encoding="utf-8")
    CoverageData.load(str(path))  # without the names of the harness, the file is only JSON of the right shape
    with pytest.raises(SourceError) as caught:
        CoverageData.load(str(path), CoverageNames.of_this_harness())
    (problem,) = caught.value.problems
    key = message.split("'")[1] if "'" in message else message.split()[1]
    line = next(number for number, text in enumerate(path.read_text().splitlines(), start=1) if key in text)
    assert problem.mark.file == str(path) and problem.mark.line == line and message in problem.message
