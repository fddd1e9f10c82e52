"""The runner against a fake target: time, waits, timeouts, invariants, events, failure reports."""

from __future__ import annotations

import math
from pathlib import Path

import pytest
from scenario_fakes import CachingImageFakeTarget, FakeTarget, ImageFakeTarget, SimpleNc, machine, scenario

from vc.located_yaml import SourceError
from vc.scenario.language.model import Scenario
from vc.scenario.run.runner import ScenarioResult, run_scenario, run_scenarios
from vc.scenario.run.trace import Recorder

HEAD = """\
name: MDA G1 move
machine: machines/mini.yaml
plc: none
"""

MOVE = """\
  - set: {MODEGROUP.basic.out.mdaMode: 1}
  - mda: "G1 X100 F6000"
  - pulse: {signal: CHAN1.basic.out.ncStart, for: 20ms}
"""


def run(tmp_path: Path, body: str, target: FakeTarget | None = None, head: str = HEAD) -> ScenarioResult:
    loaded = scenario(tmp_path, head + body)
    return run_scenario(loaded, target or FakeTarget(machine(), SimpleNc()))


def test_a_move_passes(tmp_path: Path) -> None:
    result = run(tmp_path, "steps:\n" + MOVE + """\
  - wait: {until: "X1.basic.in.posFineReached == 1", timeout: 5s}
  - expect: {X1.position: "100.000 +- 0.001", X1.velocity: "< 10", CHAN1.basic.in.stateReset: 1}
  - expect: "X1.position > 50 and CHAN1.basic.in.stateReset == 1"
  - expect_order: [CHAN1.basic.out.ncStart rises, "when X1.position > 50", X1.basic.in.posFineReached rises]
  - expect_timing: {from: CHAN1.basic.out.ncStart rises, to: X1.basic.in.posFineReached rises,
                    min: 0.9s, max: 1.1s}
  - expect_no_alarm: all
""")
    assert result.passed, result.failure
    assert result.steps_done == 9
    # 6000 mm/min = 0.2 mm per 2 ms cycle: 500 cycles for 100 mm, then one cycle to report standstill
    assert result.cycles == 501
    assert result.simulated_s == pytest.approx(1.002)


def test_time_passes_only_in_steps_that_take_time(tmp_path: Path) -> None:
    target = FakeTarget(machine())
    result = run(tmp_path, """\
steps:
  - set: {MCP.feedOverride: 50}
  - press: MCP.jog
  - wait: 3ms
  - press: {key: [MCP.plus.X1, MCP.minus.X1], for: 1ms}
  - wait: 500ms
  - hold: MCP.ref
  - release: MCP.ref
""", target)
    assert result.passed
    # press 100 ms = 50 cycles; 3 ms = 2 cycles (rounded up); 1 ms = 1 cycle (at least one); 500 ms = 250
    assert target.cycle == 50 + 2 + 1 + 250
    assert target.writes == [
        (0, "MCP.feedOverride", 50), (0, "MCP.jog", 1), (50, "MCP.jog", 0),
        (52, "MCP.plus.X1", 1), (52, "MCP.minus.X1", 1), (53, "MCP.plus.X1", 0), (53, "MCP.minus.X1", 0),
        (303, "MCP.ref", 1), (303, "MCP.ref", 0),
    ]


def test_wait_until_that_never_comes(tmp_path: Path) -> None:
    result = run(tmp_path, """\
steps:
  - wait: {until: "X1.basic.in.posFineReached == 1", timeout: 2s}
""")
    failure = result.failure
    assert failure is not None and failure.kind == "step"
    assert failure.message == ('waited 2 s for "X1.basic.in.posFineReached == 1"; it did not become true.'
                               " Now: X1.basic.in.posFineReached = 0")
    assert failure.where == f"step 1 (wait) at {tmp_path}/scenario.yaml:5:5"
    assert (failure.mark.line, failure.mark.column) == (5, 5)
    assert result.cycles == 1000
    assert failure.history[0].name == "X1.basic.in.posFineReached"
    assert failure.history[0].address == "DB31.DBX60.7"


def test_wait_until_true_at_once_takes_no_time(tmp_path: Path) -> None:
    result = run(tmp_path, 'steps:\n  - wait: {until: "X1.position == 0", timeout: 1s}\n')
    assert result.passed and result.cycles == 0


def test_scenario_timeout(tmp_path: Path) -> None:
    result = run(tmp_path, """\
timeout: 1s
steps:
  - wait: 0.5s
  - wait: {until: "X1.position > 1"}
""")
    failure = result.failure
    assert failure is not None and failure.kind == "timeout"
    assert failure.message == ("the scenario's timeout of 1 s was reached"
                               ' while waiting for "X1.position > 1". Now: X1.position = 0.0 mm')
    assert failure.where == f"timeout during step 2 (wait) at {tmp_path}/scenario.yaml:7:5"
    assert result.cycles == 500


def test_invariant_violation(tmp_path: Path) -> None:
    result = run(tmp_path, """\
invariants:
  - "X1.position < 50"
  - "abs(X1.velocity) < 100000"
steps:
""" + MOVE + """\
  - wait: 2s
""")
    failure = result.failure
    assert failure is not None and failure.kind == "invariant"
    # 50 mm at 0.2 mm per cycle: cycle 250 reaches 50.0 (started in cycle 1)
    assert failure.cycle == 250
    assert failure.message == ('invariant "X1.position < 50" was violated at cycle 250 (t = 0.5 s):'
                               " X1.position = 50 mm")
    assert (failure.mark.line, failure.mark.column) == (5, 5)
    assert failure.where == f"invariant at {tmp_path}/scenario.yaml:5:5, during step 4 (wait, line 11)"
    trail = failure.history[0]
    assert trail.name == "X1.position" and trail.address == ""
    assert len(trail.entries) == 10  # the last ten changes
    assert trail.entries[-1] == (0.5, pytest.approx(50.0))


def test_expect_values_report_expected_and_found(tmp_path: Path) -> None:
    result = run(tmp_path, "steps:\n" + MOVE + """\
  - wait: 0.5s
  - expect: {X1.position: "100 +- 0.001", X1.basic.in.posFineReached: 0, CHAN1.basic.in.stateReset: 1}
""")
    failure = result.failure
    assert failure is not None
    assert failure.message == ("expected X1.position = 100 ± 0.001, found 52 mm;"
                               " expected CHAN1.basic.in.stateReset = 1, found 0")
    assert failure.where == f"step 5 (expect) at {tmp_path}/scenario.yaml:9:5"
    assert [trail.name for trail in failure.history] == [
        "X1.position", "X1.basic.in.posFineReached", "CHAN1.basic.in.stateReset"]


def test_expect_condition(tmp_path: Path) -> None:
    result = run(tmp_path, 'steps:\n  - expect: "X1.position > 50 and not MCP.jog"\n')
    assert result.failure is not None
    assert result.failure.message == ("expected X1.position > 50 and not MCP.jog;"
                                      " found X1.position = 0.0 mm, MCP.jog = 0")


def test_division_by_zero_fails_the_step(tmp_path: Path) -> None:
    result = run(tmp_path, 'steps:\n  - expect: "1 / X1.position > 2"\n')
    assert result.failure is not None
    assert result.failure.message == 'cannot evaluate in "1 / X1.position > 2": division by zero (1 / 0)'


def test_alarms(tmp_path: Path) -> None:
    def limit_switch(target: FakeTarget) -> None:
        if target.cycle == 10:
            target.raise_alarm(21614, axis="X1")

    body = """\
steps:
  - expect_no_alarm: all
  - wait: 100ms
  - expect_alarm: 21614
  - expect_alarm: {number: 21614, axis: X1}
  - expect_no_alarm: {number: 21614, axis: Z1}
  - expect_no_alarm: 3000
  - expect: "alarm(21614, X1) and not alarm(21614, Z1)"
"""
    assert run(tmp_path, body, FakeTarget(machine(), limit_switch)).passed
    failing = run(tmp_path, "steps:\n  - wait: 100ms\n  - expect_no_alarm: all\n",
                  FakeTarget(machine(), limit_switch))
    assert failing.failure is not None
    assert failing.failure.message == ("expected no alarm; present alarms:"
                                       " 21614 Channel %1 axis %2 hardware limit switch %3 (X1)")
    missing = run(tmp_path, "steps:\n  - expect_alarm: {number: 3000, channel: CHAN1}\n")
    assert missing.failure is not None
    assert missing.failure.message == "expected alarm 3000 (CHAN1) to be present; present alarms: none"


def test_acknowledge_clears_the_alarms_of_the_cancel_key_only(tmp_path: Path) -> None:
    def two_alarms(target: FakeTarget) -> None:
        if target.cycle == 1:
            target.raise_alarm(22025, axis="X1")  # cleared with the cancel key
            target.raise_alarm(21614, axis="X1")  # cleared with a reset

    body = """\
steps:
  - wait: 10ms
  - expect_alarm: 22025
  - acknowledge: alarms
  - expect_no_alarm: 22025
  - expect_alarm: 21614
"""
    assert run(tmp_path, body, FakeTarget(machine(), two_alarms)).passed
    with pytest.raises(SourceError, match="acknowledge takes 'alarms'"):
        run(tmp_path, "steps:\n  - acknowledge: 22025\n")


def test_force_holds_against_the_owner_until_released(tmp_path: Path) -> None:
    def nc(target: FakeTarget) -> None:
        target.set("X1.basic.in.enc1Synchronized", 1)

    result = run(tmp_path, """\
steps:
  - force: {X1.basic.in.enc1Synchronized: 0}
  - wait: 10ms
  - expect: {X1.basic.in.enc1Synchronized: 0}
  - release: X1.basic.in.enc1Synchronized
  - wait: 2ms
  - expect: {X1.basic.in.enc1Synchronized: 1}
  - expect_order: [X1.basic.in.enc1Synchronized rises]
""".replace("  - expect_order: [X1.basic.in.enc1Synchronized rises]\n",
            "  - expect_order: [X1.basic.in.enc1Synchronized rises, X1.basic.in.enc1Synchronized changes]\n"),
        FakeTarget(machine(), nc))
    assert result.passed, result.failure


ORDER_BODY = "steps:\n" + MOVE + """\
  - wait: {until: "X1.basic.in.posFineReached == 1", timeout: 5s}
  - expect_order: [X1.basic.in.posFineReached rises, CHAN1.basic.out.ncStart rises]
"""


def test_expect_order_failure(tmp_path: Path) -> None:
    result = run(tmp_path, ORDER_BODY)
    assert result.failure is not None
    assert result.failure.message == (
        "expected 'X1.basic.in.posFineReached rises', then 'CHAN1.basic.out.ncStart rises';"
        " 'X1.basic.in.posFineReached rises' at 1.002 s; 'CHAN1.basic.out.ncStart rises' did not occur after"
        " that (only at 0 s)")
    never = run(tmp_path, "steps:\n  - wait: 10ms\n  - expect_order: [MCP.jog rises, MCP.jog falls]\n")
    assert never.failure is not None
    assert never.failure.message == ("expected 'MCP.jog rises', then 'MCP.jog falls';"
                                     " 'MCP.jog rises' did not occur")


def test_expect_order_counts_events_of_one_cycle_as_in_order(tmp_path: Path) -> None:
    result = run(tmp_path, "steps:\n" + MOVE + """\
  - wait: 1.1s
  - expect_order: [X1.basic.in.posFineReached rises, CHAN1.basic.in.stateReset rises]
  - expect_order: [CHAN1.basic.in.stateReset rises, X1.basic.in.posFineReached rises]
""")
    assert result.passed, result.failure


@pytest.mark.parametrize(("window", "message"), [
    ("max: 0.5s", "expected 'CHAN1.basic.out.ncStart rises' to 'X1.basic.in.posFineReached rises' to take"
                  " at most 0.5 s; it took 1.002 s ('CHAN1.basic.out.ncStart rises' at 0 s,"
                  " 'X1.basic.in.posFineReached rises' at 1.002 s)"),
    ("min: 1.5s", "expected 'CHAN1.basic.out.ncStart rises' to 'X1.basic.in.posFineReached rises' to take"
                  " at least 1.5 s; it took 1.002 s ('CHAN1.basic.out.ncStart rises' at 0 s,"
                  " 'X1.basic.in.posFineReached rises' at 1.002 s)"),
    ("min: 0.2s, max: 0.4s", "expected 'CHAN1.basic.out.ncStart rises' to 'X1.basic.in.posFineReached rises'"
                             " to take 0.2 s .. 0.4 s; it took 1.002 s"
                             " ('CHAN1.basic.out.ncStart rises' at 0 s,"
                             " 'X1.basic.in.posFineReached rises' at 1.002 s)"),
])
def test_expect_timing_failure(tmp_path: Path, window: str, message: str) -> None:
    result = run(tmp_path, "steps:\n" + MOVE + """\
  - wait: {until: "X1.basic.in.posFineReached == 1", timeout: 5s}
  - expect_timing: {from: CHAN1.basic.out.ncStart rises, to: X1.basic.in.posFineReached rises, WINDOW}
""".replace("WINDOW", window))
    assert result.failure is not None
    assert result.failure.message == message


def test_expect_timing_with_when_events(tmp_path: Path) -> None:
    result = run(tmp_path, "steps:\n" + MOVE + """\
  - wait: 2s
  - expect_timing: {from: "when X1.position > 10", to: "when X1.position >= 60", min: 0.49s, max: 0.5s}
  - expect_timing: {from: "when X1.position > 10", to: "when time > 5", max: 1s}
""")
    assert result.failure is not None
    assert result.failure.message == (
        "expected 'when X1.position > 10' to 'when time > 5' to take at most 1 s;"
        " 'when time > 5' did not occur after 'when X1.position > 10' (at 0.102 s)")
    assert result.steps_done == 5


def test_run_scenarios_writes_traces_and_survives_harness_errors(tmp_path: Path) -> None:
    good = scenario(tmp_path, HEAD + "steps:\n" + MOVE + "  - wait: 1.2s\n", "move.yaml")
    broken = scenario(tmp_path, HEAD + "steps:\n  - wait: 1s\n", "broken.yaml")

    def make_target(loaded: Scenario) -> FakeTarget:
        if loaded is broken:
            raise RuntimeError("the simulation could not start")
        return FakeTarget(loaded.machine, SimpleNc())

    results = run_scenarios([good, broken], make_target, trace_dir=tmp_path / "traces")
    assert [result.status for result in results] == ["PASS", "ERROR"]
    traces = tmp_path / "traces"
    assert results[0].trace_files == [str(traces / "move.csv"), str(traces / "move.vcd"), str(traces / "move.gtkw")]
    assert "RuntimeError: the simulation could not start" in results[1].error


def test_the_image_fast_path_records_the_same_history(tmp_path: Path) -> None:
    body = "steps:\n" + MOVE + """\
  - force: {X1.basic.in.enc1Synchronized: 1}
  - wait: 1.2s
  - press: MCP.jog
"""
    targets = [FakeTarget(machine(), SimpleNc()), ImageFakeTarget(machine(), SimpleNc()),
               CachingImageFakeTarget(machine(), SimpleNc())]
    recorders = [run(tmp_path, body, target).recorder for target in targets]
    as_rows = []
    for recorder in recorders:
        assert isinstance(recorder, Recorder)
        as_rows.append([(cycle, h.quantity.name, value) for cycle, h, value in recorder.changes()])
    assert as_rows[0] == as_rows[1] == as_rows[2]
    # a write between two cycles belongs to the cycle before it: ncStart rises at 0 s, falls at 20 ms
    start = "CHAN1.basic.out.ncStart"
    assert [row for row in as_rows[0] if row[1] == start] == [(0, start, 0), (0, start, 1), (10, start, 0)]
    assert [row for row in as_rows[0] if row[1] == "X1.basic.in.enc1Synchronized"] == [
        (0, "X1.basic.in.enc1Synchronized", 0), (10, "X1.basic.in.enc1Synchronized", 1)]


def test_a_reading_that_is_not_a_number_fails_every_expectation(tmp_path: Path) -> None:
    """A NaN position made ``!= 100`` pass; an infinite one made ``< 5`` and ``> 5`` pass."""
    for value, expected in ((math.nan, '"!= 100"'), (-math.inf, '"< 5"'), (math.inf, '"> 5"')):
        target = FakeTarget(machine())
        target.axes["X1"]["position"] = value
        result = run(tmp_path, f"steps:\n  - expect: {{X1.position: {expected}}}\n", target)
        assert not result.passed
        assert result.failure is not None and result.failure.message.startswith("expected X1.position")


def test_a_condition_on_a_reading_that_is_not_a_number_fails_the_step(tmp_path: Path) -> None:
    target = FakeTarget(machine())
    target.axes["X1"]["position"] = math.nan
    result = run(tmp_path, 'steps:\n  - wait: {until: "X1.position != 100", timeout: 1s}\n', target)
    assert result.failure is not None
    assert result.failure.message == ('cannot evaluate in "X1.position != 100": cannot compare nan != 100: a value'
                                      " that is not finite")


def test_an_invariant_on_a_reading_that_is_not_a_number_is_violated(tmp_path: Path) -> None:
    target = FakeTarget(machine())
    result = run(tmp_path, 'invariants: ["not X1.position > 5"]\nsteps:\n  - wait: 10ms\n', target)
    assert result.passed
    target = FakeTarget(machine())
    target.axes["X1"]["position"] = math.nan
    result = run(tmp_path, 'invariants: ["not X1.position > 5"]\nsteps:\n  - wait: 10ms\n', target)
    assert result.failure is not None and "a value that is not finite" in result.failure.message


class _ReadCounting(ImageFakeTarget):
    """Counts what the scenario reads through read() (the recorder reads the images)."""

    def __init__(self) -> None:
        super().__init__(machine(), SimpleNc())
        self.reads: dict[str, int] = {}

    def read(self, ref):  # type: ignore[no-untyped-def]
        self.reads[ref.name] = self.reads.get(ref.name, 0) + 1
        return super().read(ref)


def test_a_condition_on_signals_is_judged_again_only_when_one_of_them_changed(tmp_path: Path) -> None:
    target = _ReadCounting()
    result = run(tmp_path, """\
invariants:
  - "CHAN1.basic.out.ncStart + MODEGROUP.basic.out.mdaMode <= 2"
steps:
""" + MOVE + """\
  - wait: 1100ms
  - expect_order: ["when CHAN1.basic.out.ncStart == 1", "X1.basic.in.posFineReached rises"]
""", target)
    assert result.passed, result.failure
    assert result.cycles > 500
    # mdaMode set once, ncStart up and down: a few judgements, not one a cycle
    assert target.reads["CHAN1.basic.out.ncStart"] < 12


def test_a_condition_on_signals_still_fails_in_the_cycle_its_signal_changed(tmp_path: Path) -> None:
    result = run(tmp_path, """\
invariants:
  - "CHAN1.basic.out.ncStart == 0"
steps:
  - wait: 30ms
""" + MOVE, ImageFakeTarget(machine(), SimpleNc()))
    failure = result.failure
    assert failure is not None and failure.kind == "invariant"
    assert failure.cycle == 16  # set between cycles 15 and 16, judged after the next cycle as before
    assert failure.message.startswith('invariant "CHAN1.basic.out.ncStart == 0" was violated at cycle')
