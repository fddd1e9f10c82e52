"""The file part of the robustness campaign: a short run finds nothing bad, and each of its checks can fail."""

from __future__ import annotations

import dataclasses
from collections.abc import Iterator
from pathlib import Path

import pytest

from vc.bench.robustness import files as robustness_files
from vc.bench.robustness.files import (
    MUTATIONS,
    Mutant,
    Shipped,
    Workspace,
    check_mutant,
    default_root,
    run_file_mutations,
    table,
)
from vc.located_yaml import Mark, Problem

PROBE_THAT_CAN_FAIL = b"""\
name: probe
machine: ../machines/turn_mill.yaml
plc: basic_machine
steps:
  - wait: 100ms
  - expect: {X1.position: "0 +- 1"}
"""


@pytest.fixture(scope="module")
def shipped() -> Shipped:
    return Shipped(default_root())


@pytest.fixture()
def workspace(tmp_path: Path, shipped: Shipped) -> Iterator[Workspace]:
    yield Workspace(shipped.root, tmp_path)


def test_a_short_campaign_finds_no_crash_hang_traceback_false_pass_or_wrong_location() -> None:
    said: list[str] = []
    figures = run_file_mutations(100, 1, said.append)
    assert figures["inputs"] == 100
    bad = {name: figures[name] for name in ("crashes", "hangs", "tracebacks", "false_passes", "wrong_locations")}
    assert bad == dict.fromkeys(bad, 0), said
    assert figures["problems"] + figures["passed"] + figures["failed"] == 100
    assert figures["problems"] > 50  # most mutants are refused, with their location
    assert "false_pass_probe" in table(figures)


def test_mutants_are_deterministic_for_a_seed(shipped: Shipped) -> None:
    first = [shipped.mutant(7, number) for number in range(30)]
    assert first == [shipped.mutant(7, number) for number in range(30)]
    assert first != [shipped.mutant(8, number) for number in range(30)]
    assert {mutant.kind for mutant in (shipped.mutant(1, number) for number in range(400))} == set(MUTATIONS)


def probe(data: bytes, **fields: object) -> Mutant:
    return dataclasses.replace(Mutant(0, "false_pass_probe", "foundation/jog_traverse.yaml", "scenario", data),
                               **fields)


def test_a_probe_that_passes_is_a_false_pass(shipped: Shipped, workspace: Workspace) -> None:
    assert check_mutant(probe(PROBE_THAT_CAN_FAIL), shipped, workspace, 30, 1).outcome == "passed"
    outcome = check_mutant(probe(PROBE_THAT_CAN_FAIL, must_not_pass=True), shipped, workspace, 30, 1)
    assert outcome.outcome == "false_pass"


def test_a_mutant_that_should_be_refused_at_a_line_and_loads_is_a_wrong_location(shipped: Shipped,
                                                                                 workspace: Workspace) -> None:
    outcome = check_mutant(probe(PROBE_THAT_CAN_FAIL, expected_line=3), shipped, workspace, 30, 1)
    assert (outcome.outcome, outcome.detail) == ("wrong_location",
                                                 "expected a problem at line 3 of the mutant; it loaded")
    refused_elsewhere = PROBE_THAT_CAN_FAIL.replace(b"wait: 100ms", b"wiat: 100ms")
    outcome = check_mutant(probe(refused_elsewhere, expected_line=3), shipped, workspace, 30, 1)
    assert outcome.outcome == "wrong_location" and "expected a problem at line 3" in outcome.detail
    assert check_mutant(probe(refused_elsewhere, expected_line=5), shipped, workspace, 30, 1).outcome == "problems"


def test_a_location_printed_otherwise_is_a_wrong_location(shipped: Shipped, workspace: Workspace,
                                                          monkeypatch: pytest.MonkeyPatch) -> None:
    def with_emoji(self: robustness_files.ConsoleReport, error: robustness_files.SourceError) -> None:
        for problem in error.problems:
            self.console.print(str(problem).replace(":5:", "💯"))

    monkeypatch.setattr(robustness_files.ConsoleReport, "print_problems", with_emoji)
    refused = PROBE_THAT_CAN_FAIL.replace(b"wait: 100ms", b"wiat: 100ms")
    outcome = check_mutant(probe(refused), shipped, workspace, 30, 1)
    assert outcome.outcome == "wrong_location" and outcome.detail.startswith("printed otherwise than written")


def test_an_exception_out_of_vc_run_is_a_crash_and_a_long_one_a_hang(shipped: Shipped, workspace: Workspace,
                                                                     monkeypatch: pytest.MonkeyPatch) -> None:
    # 280 s of simulated time take 140,000 IPO cycles, some 0.3 s even at 500x real time: well over the bound
    assert check_mutant(probe(PROBE_THAT_CAN_FAIL.replace(b"100ms", b"280s")), shipped, workspace, 0.05,
                        300).outcome == "hang"

    def broken(*arguments: object, **options: object) -> None:
        raise RecursionError("maximum recursion depth exceeded")

    monkeypatch.setattr(robustness_files, "load_scenarios", broken)
    outcome = check_mutant(probe(PROBE_THAT_CAN_FAIL), shipped, workspace, 30, 1)
    assert (outcome.outcome, outcome.detail) == ("crash", "RecursionError: maximum recursion depth exceeded")


def test_a_harness_error_during_the_run_is_a_traceback(shipped: Shipped, workspace: Workspace,
                                                       monkeypatch: pytest.MonkeyPatch) -> None:
    def broken(scenario: object) -> None:
        raise KeyError("X1")

    monkeypatch.setattr(robustness_files, "simulation_for", broken)
    outcome = check_mutant(probe(PROBE_THAT_CAN_FAIL), shipped, workspace, 30, 1)
    assert (outcome.outcome, outcome.detail) == ("traceback", "KeyError: 'X1'")


def test_the_wall_bound_keeps_a_timer_that_runs_already() -> None:
    """A test's own time-out (pytest-timeout uses SIGALRM too) survives the campaign's bounds."""
    import signal

    fired: list[int] = []
    previous = signal.signal(signal.SIGALRM, lambda signum, frame: fired.append(signum))
    try:
        signal.setitimer(signal.ITIMER_REAL, 100)
        with robustness_files._wall_bound(5):
            pass
        remaining, _ = signal.getitimer(signal.ITIMER_REAL)
        assert 0 < remaining <= 100  # restored (0 would mean the outer time-out was switched off)
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, previous)
    assert fired == []


def test_a_problem_past_the_end_of_the_file_or_over_two_lines_is_a_wrong_location(tmp_path: Path) -> None:
    mutant = tmp_path / "m.yaml"
    mutant.write_text("name: x\nsteps:\n  - wait: [1s\n")  # three lines, the last one ended
    involved = {str(mutant)}

    def judged(line: int, message: str = "YAML syntax error") -> str:
        return robustness_files._location_problem(Problem(
            Mark(str(mutant), line, 1), message), involved, tmp_path)

    assert judged(3) == ""
    assert judged(4).startswith("line 4 of a file of 3 lines")

    class Raw(Problem):  # a problem printed as it was before problems were kept on one line
        def __str__(self) -> str:
            return f"{self.mark}: {self.message}"

    split = Raw(Mark(str(mutant), 1, 1), "unknown signal 'MCP.mda\nN55 M3'")
    assert robustness_files._location_problem(split, involved, tmp_path).startswith("printed over more than one line")
