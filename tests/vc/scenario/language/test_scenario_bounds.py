"""Scenario files that would pass falsely, or end in a traceback, a hang or a memory blow-up,
are refused when they are loaded, each problem at its line and column."""

from __future__ import annotations

import os
from pathlib import Path

import pytest
from scenario_fakes import KNOWN_PROGRAMS, write_scenario

from interfaces.links.inprocess import plc_programs
from vc.located_yaml import SourceError
from vc.scenario.language.loader import load_scenario, load_scenarios, scenario_files

HEAD = "name: n\nmachine: machines/mini.yaml\nplc: none\n"


def problems(tmp_path: Path, text: str, programs: object = KNOWN_PROGRAMS) -> list[str]:
    path = write_scenario(tmp_path, text)
    with pytest.raises(SourceError) as caught:
        load_scenario(str(path), programs)  # type: ignore[arg-type]
    return [f"{problem.mark.line}:{problem.mark.column}: {problem.message}" for problem in caught.value.problems]


def test_an_infinite_expected_value_is_refused(tmp_path: Path) -> None:
    """``expect: {X1.position: .inf}`` passed while X1 stood at 0."""
    assert problems(tmp_path, HEAD + "steps:\n  - expect: {X1.position: .inf, X1.velocity: -.inf}\n") == [
        "5:27: '.inf' is not a finite number (the harness reads no infinity and no NaN)",
        "5:46: '-.inf' is not a finite number (the harness reads no infinity and no NaN)",
    ]


@pytest.mark.parametrize(("expected", "message"), [
    ('"1e308"', "'1e308' is beyond 1e+15, the largest number an expectation may hold"),
    ('"0 +- 1e400"', "'1e400' is beyond 1e+15, the largest number an expectation may hold"),
    ('"0 +- 1e15"', "X1.position is a number (-1e+15..1e+15); it is always = 0 ± 1000000000000000.0, so the"
                    " check cannot fail"),
])
def test_expected_values_beyond_the_range_of_numbers_are_refused(tmp_path: Path, expected: str,
                                                                  message: str) -> None:
    assert problems(tmp_path, HEAD + f"steps:\n  - expect: {{X1.position: {expected}}}\n") == [f"5:27: {message}"]


@pytest.mark.parametrize(("expected", "message"), [
    ('"<= 1"', "CHAN1.basic.in.allAxesReferenced (DB21.DBX36.2) is a bool (0..1); it is always <= 1, so the check"
               " cannot fail"),
    ('"!= 7"', "CHAN1.basic.in.allAxesReferenced (DB21.DBX36.2) is a bool (0..1); it is always != 7, so the check"
               " cannot fail"),
    ('"0.5 +- 0.5"', "CHAN1.basic.in.allAxesReferenced (DB21.DBX36.2) is a bool (0..1); it is always = 0.5 ± 0.5,"
                     " so the check cannot fail"),
    ('"> 1"', "CHAN1.basic.in.allAxesReferenced (DB21.DBX36.2) is a bool (0..1); it is never > 1"),
    ("2", "CHAN1.basic.in.allAxesReferenced (DB21.DBX36.2) is a bool (0..1); it can never be 2"),
])
def test_an_expectation_a_signal_meets_with_every_value_is_refused(tmp_path: Path, expected: str,
                                                                   message: str) -> None:
    assert problems(tmp_path, HEAD + f"steps:\n  - expect: {{DB21.DBX36.2: {expected}}}\n") == [f"5:28: {message}"]


def test_an_expectation_a_machine_datum_meets_with_every_value_is_refused(tmp_path: Path) -> None:
    assert problems(tmp_path, HEAD + 'steps:\n  - expect: {X1.MD34210: ">= 0"}\n') == [
        "5:26: X1.MD34210 is a machine datum of whole numbers (0..3); it is always >= 0, so the check cannot fail"]


def test_expectations_that_can_fail_still_load(tmp_path: Path) -> None:
    text = HEAD + ('steps:\n  - expect: {DB21.DBX36.2: "< 1", MCP.feedOverride: ">= 1", X1.position: "0 +- 1e14",'
                   ' X1.MD34210: "<= 2"}\n')
    loaded = load_scenario(str(write_scenario(tmp_path, text)), KNOWN_PROGRAMS)
    assert len(loaded.steps) == 1


@pytest.mark.parametrize(("step", "message"), [
    ("wait: 1e400s", "5:11: '1e400s' is longer than 86400 s, the longest time a scenario may name"),
    ("wait: {until: X1.position > 5, timeout: 1e400s}",
     "5:45: '1e400s' is longer than 86400 s, the longest time a scenario may name"),
    ("press: {key: MCP.jog, for: 2000min}", "5:32: '2000min' is longer than 86400 s, the longest time a scenario"
                                            " may name"),
])
def test_durations_beyond_a_day_are_refused(tmp_path: Path, step: str, message: str) -> None:
    assert problems(tmp_path, HEAD + f"steps:\n  - {step}\n") == [message]


def test_a_timeout_that_is_not_a_number_is_refused(tmp_path: Path) -> None:
    """``timeout: .nan`` ended in decimal.InvalidOperation."""
    assert problems(tmp_path, HEAD + "timeout: .nan\nsteps:\n  - wait: 1s\n") == [
        "4:10: '.nan' is not a finite number (the harness reads no infinity and no NaN)"]


def test_a_timing_bound_that_cannot_fail_is_refused(tmp_path: Path) -> None:
    """No interval of a run is longer than its timeout plus the time switched off in power cycles."""
    text = HEAD + ("timeout: 10s\nsteps:\n"
                   "  - expect_timing: {from: MCP.jog rises, to: MCP.jog falls, min: 0s}\n"
                   "  - expect_timing: {from: MCP.jog rises, to: MCP.jog falls, max: 15s}\n"
                   "  - power_cycle: 5s\n"
                   "  - expect_timing: {from: MCP.jog rises, to: MCP.jog falls, max: 14s}\n"
                   "  - expect_timing: {from: MCP.jog rises, to: MCP.jog falls, min: 0s, max: 1s}\n")
    assert problems(tmp_path, text) == [
        "6:66: min: 0 s alone holds for every interval, so the check cannot fail (give a max, or a min above 0)",
        "7:5: expect_timing: max (15 s) is as long as the whole run can be (15 s: the timeout and the power cycles),"
        " so the check cannot fail",
    ]


def test_a_condition_that_reads_nothing_is_refused(tmp_path: Path) -> None:
    text = HEAD + 'invariants: ["1 == 1"]\nsteps:\n  - expect: "2 > 1"\n  - wait: {until: "0"}\n'
    assert problems(tmp_path, text) == [
        '4:14: "1 == 1" reads no signal, quantity, time or alarm: it never changes, so as a check it always holds or'
        " never does",
        '6:13: "2 > 1" reads no signal, quantity, time or alarm: it never changes, so as a check it always holds or'
        " never does",
        '7:19: "0" reads no signal, quantity, time or alarm: it never changes, so as a check it always holds or'
        " never does",
    ]


def test_conditions_beyond_the_expression_limits_are_refused(tmp_path: Path) -> None:
    nested = "(" * 500 + "X1.position" + ")" * 500
    chained = " and ".join(["X1.position > 0"] * 200)
    found = problems(tmp_path, HEAD + f'steps:\n  - expect: "{nested}"\n  - wait: {{until: "{chained}"}}\n')
    assert found[0].startswith('5:13: in "((((') and found[0].endswith(
        "more than 32 parentheses, brackets, not, signs and abs inside one another at column 33")
    assert found[1].startswith('6:19: in "X1.position > 0 and')
    assert found[1].endswith("more than 100 operators one inside the other (split the expression, or group long"
                             " chains with parentheses) at column 33")


@pytest.mark.parametrize(("step", "message"), [
    ("force: {X1.basic.in.posAxisFeedrateValue: 1.0e+300}",
     "5:47: X1.basic.in.posAxisFeedrateValue (DB31.DBD78) is a real; 1e+300 is beyond 1e+15, the largest number a"
     " scenario may write"),
    ("move_by_hand: {axis: X1, velocity: 1.0e+300}",
     "5:40: velocity (mm/min or rev/min): 1e+300 is beyond 1e+15, the largest number a scenario may write"),
    ("fault: {axis: X1, kind: encoder_slip, by: 1.0e+16}",
     "5:47: by: 1e+16 is beyond 1e+15, the largest number a scenario may write"),
    ("fault: {axis: X1, kind: reference_marks_missing, from: 5, to: 5}",
     "5:67: from and to are the same position: no reference mark would be missing"),
    ("turn: {handwheel1: 10000000000000000000}", "5:24: handwheel1 takes a whole number of detents, not"
                                                 " '10000000000000000000'"),
])
def test_numbers_a_scenario_hands_to_the_simulation_are_bounded(tmp_path: Path, step: str, message: str) -> None:
    assert problems(tmp_path, HEAD + f"steps:\n  - {step}\n") == [message]


def test_a_program_file_that_is_a_device_is_refused(tmp_path: Path) -> None:
    """``program: {file: /dev/zero}`` read until the memory ran out (MemoryError)."""
    if not os.path.exists("/dev/zero"):
        pytest.skip("no /dev/zero here")
    assert problems(tmp_path, HEAD + "steps:\n  - program: {name: P, file: /dev/zero}\n") == [
        "5:30: cannot read the program file '/dev/zero': it is a device, FIFO or socket, not a regular file"]


def test_a_program_file_that_is_not_utf8_is_reported_with_its_line(tmp_path: Path) -> None:
    (tmp_path / "p.mpf").write_bytes(b"G1 X10 F100\nM30 ; \xff\n")
    (found,) = problems(tmp_path, HEAD + "steps:\n  - program: {name: P, file: p.mpf}\n")
    assert found.startswith("5:30: the program file 'p.mpf' is not UTF-8 text (invalid start byte) at line 2, column 7")


@pytest.mark.parametrize("text", ["null\n", "---\n", "~\n"])
def test_a_scenario_file_holding_only_null_is_a_problem_not_nothing(tmp_path: Path, text: str) -> None:
    """It said "no scenario files found"."""
    (found,) = problems(tmp_path, text)
    assert found.startswith("1:1: the document is empty")


def test_a_scenario_path_that_is_a_device_is_reported_as_such() -> None:
    if not os.path.exists("/dev/zero"):
        pytest.skip("no /dev/zero here")
    files, found = scenario_files(["/dev/zero"])
    assert (files, found) == (["/dev/zero"], [])
    with pytest.raises(SourceError) as caught:
        load_scenarios(files, KNOWN_PROGRAMS)
    assert [problem.message for problem in caught.value.problems] == [
        "cannot read the file: it is a device, FIFO or socket, not a regular file"]


def test_parameters_a_plc_program_refuses_are_a_problem_at_load_time(tmp_path: Path) -> None:
    """The program checked them when the run started, which ended in a traceback."""
    text = HEAD.replace("plc: none", "plc: referencing") + \
        "plc_parameters: {referencing_order: 5}\nsteps:\n  - wait: 1s\n"
    assert problems(tmp_path, text, plc_programs()) == [
        "4:17: the PLC program referencing refuses its parameters (the machine file's plc: section and"
        " plc_parameters): plc: referencing_order must be a list of groups of axes, e.g. [[Y1, Z1], [X1]]"]


def test_each_scenario_with_refused_parameters_is_told_though_the_program_starts_once(tmp_path: Path) -> None:
    """The program is started once per machine shape and parameters of a run; every file that gives
    them gets the problem at its own line."""
    text = HEAD.replace("plc: none", "plc: referencing") + \
        "plc_parameters: {referencing_order: 5}\nsteps:\n  - wait: 1s\n"
    first = write_scenario(tmp_path, text, "first.yaml")
    second = write_scenario(tmp_path, "# a comment line first\n" + text, "second.yaml")
    started = []
    programs = dict(plc_programs())
    referencing = programs["referencing"]

    def counted(environment: object) -> object:
        started.append(environment)
        return referencing(environment)  # type: ignore[arg-type]

    programs["referencing"] = counted  # type: ignore[assignment]
    with pytest.raises(SourceError) as caught:
        load_scenarios([str(first), str(second)], programs)
    found = [(Path(problem.mark.file).name, problem.mark.line) for problem in caught.value.problems]
    assert found == [("first.yaml", 4), ("second.yaml", 5)]
    assert len(started) == 1


def test_names_that_resolve_cost_no_did_you_mean_search(monkeypatch: pytest.MonkeyPatch) -> None:
    """Loading the library started each scenario's PLC program, whose plant I/O names were looked up in
    the catalogue first: a "did you mean" search of a millisecond for each, never shown."""
    import difflib

    def refused(*arguments: object, **keywords: object) -> list[str]:
        raise AssertionError("a did-you-mean search while every name resolves")

    monkeypatch.setattr(difflib, "get_close_matches", refused)
    library = Path(__file__).resolve().parents[4] / "scenarios"
    loaded = load_scenarios([str(library / "foundation"), str(library / "spindle")], plc_programs())
    assert len(loaded) > 20
