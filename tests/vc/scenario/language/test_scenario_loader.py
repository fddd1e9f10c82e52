"""Loading sound scenario files: what each step becomes."""

from __future__ import annotations

import os
from pathlib import Path

import pytest
from scenario_fakes import KNOWN_PROGRAMS, MACHINE_FILE, scenario, write_scenario

from interfaces.signals import Direction
from vc.config import md_dictionary as mdd
from vc.located_yaml import SourceError
from vc.scenario.language.durations import Duration
from vc.scenario.language.loader import DEFAULT_TIMEOUT, load_scenarios, scenario_files
from vc.scenario.language.model import (
    EdgeKind,
    ExpectAlarm,
    ExpectCondition,
    ExpectOrder,
    ExpectTiming,
    ExpectValues,
    Hold,
    LoadMda,
    Press,
    Release,
    SelectProgram,
    SetValues,
    Wait,
    WaitUntil,
)
from vc.scenario.language.quantities import QuantityKind
from vc.scenario.language.values import ExpectedValue

EVERY_STEP = """\
name: MDA G1 move with feed override changes
description: >
  Every kind of step once.
machine: machines/mini.yaml
plc: none
machine_data:
  CHAN1: {MD20700: 0}
timeout: 120s
invariants:
  - "abs(X1.followingError) < 3"
steps:
  - press: MCP.jog
  - press: {key: [MCP.plus.X1, MCP.minus.X1], for: 300ms}
  - hold: MCP.plus.X1
  - release: MCP.plus.X1
  - set: {MCP.feedOverride: 50, DB21.DBX4.0: 1, CHAN1.basic.out.ncStart: true}
  - force: {X1.basic.out.enableCtrl: 0, X1.basic.in.enc1Synchronized: 1}
  - release: [X1.basic.out.enableCtrl, X1.basic.in.enc1Synchronized]
  - pulse: {signal: CHAN1.basic.out.ncStart, for: 20ms}
  - pulse: DB21.DBX7.1
  - mda: "G1 X100 F2000"
  - mda: {channel: CHAN1, text: "G0 X0"}
  - program: {name: PART1, text: "G1 X10 F100\\nM30"}
  - program: {name: PART2, file: programs/part2.mpf, channel: CHAN1}
  - wait: 500ms
  - wait: {until: "X1.basic.in.posFineReached == 1", timeout: 5s}
  - wait: {until: "time >= 10"}
  - expect: {X1.position: "100.000 +- 0.001", DB21.DBX36.2: 0, X1.velocity: "< 10", I0.2: false}
  - expect: "X1.position > 50 and CHAN1.basic.in.stateReset == 0"
  - expect_alarm: 10621
  - expect_alarm: {number: 21614, axis: X1}
  - expect_no_alarm: {number: 10203, channel: CHAN1}
  - expect_no_alarm: all
  - expect_order: [X1.basic.out.refPointApproachCam rises, X1.basic.in.enc1Synchronized rises]
  - expect_timing: {from: "CHAN1.basic.out.ncStart rises", to: "when X1.position > 99.9", min: 0.5s, max: 2s}
  - expect_timing: {from: MCP.jog falls, to: X1.position changes, max: 1min}
"""


def test_every_step(tmp_path: Path) -> None:
    (tmp_path / "programs").mkdir()
    (tmp_path / "programs" / "part2.mpf").write_text("G1 X20 F100\nM30\n", encoding="utf-8")
    loaded = scenario(tmp_path, EVERY_STEP)
    assert loaded.name == "MDA G1 move with feed override changes"
    assert loaded.description == "Every kind of step once."
    assert loaded.plc == "none" and loaded.plc_program is None
    assert loaded.timeout == Duration(120_000_000)
    assert loaded.machine_file == str(tmp_path / "machines" / "mini.yaml")
    assert loaded.machine.channel("CHAN1").md.int(mdd.REFP_NC_START_LOCK) == 0  # the override applies
    assert [invariant.condition.text for invariant in loaded.invariants] == ["abs(X1.followingError) < 3"]
    assert loaded.invariants[0].mark.line == 10
    steps = loaded.steps
    assert [step.index for step in steps] == list(range(1, 26))
    assert [step.kind for step in steps][:9] == [
        "press", "press", "hold", "release", "set", "force", "release", "pulse", "pulse"]
    assert steps[0].mark.line == 12 and steps[0].label == "step 1 (press)"

    press = steps[0]
    assert isinstance(press, Press) and press.duration == Duration(100_000)
    assert [key.name for key in press.keys] == ["MCP.jog"] and press.keys[0].address == "I0.2"
    both = steps[1]
    assert isinstance(both, Press) and [k.name for k in both.keys] == ["MCP.plus.X1", "MCP.minus.X1"]
    assert both.duration == Duration(300_000)
    assert isinstance(steps[2], Hold) and isinstance(steps[3], Release)

    values = steps[4]
    assert isinstance(values, SetValues) and not values.forced
    assert [(q.name, v) for q, v in values.values] == [
        ("MCP.feedOverride", 50), ("DB21.DBX4.0", 1), ("CHAN1.basic.out.ncStart", 1)]
    raw = values.values[1][0]
    assert raw.ref is not None and raw.ref.direction is Direction.PLC_TO_NC
    forced = steps[5]
    assert isinstance(forced, SetValues) and forced.forced
    released = steps[6]
    assert isinstance(released, Release) and len(released.names) == 2

    pulse, pulse_by_address = steps[7], steps[8]
    assert isinstance(pulse, Press) and pulse.kind == "pulse" and pulse.duration == Duration(20_000)
    assert isinstance(pulse_by_address, Press) and pulse_by_address.keys[0].name == "CHAN1.basic.out.ncStart"

    assert steps[9] == LoadMda(10, "mda", steps[9].mark, "CHAN1", "G1 X100 F2000")
    assert isinstance(steps[10], LoadMda) and steps[10].text == "G0 X0"
    program, from_file = steps[11], steps[12]
    assert isinstance(program, SelectProgram) and program.text == "G1 X10 F100\nM30"
    assert isinstance(from_file, SelectProgram)
    assert (from_file.name, from_file.text) == ("PART2", "G1 X20 F100\nM30\n")

    assert isinstance(steps[13], Wait) and steps[13].duration == Duration(500_000)
    until = steps[14]
    assert isinstance(until, WaitUntil) and until.timeout == Duration(5_000_000)
    assert [q.name for q in until.quantities] == ["X1.basic.in.posFineReached"]
    forever = steps[15]
    assert isinstance(forever, WaitUntil) and forever.timeout is None
    assert forever.condition.names[0].kind is QuantityKind.TIME

    expect = steps[16]
    assert isinstance(expect, ExpectValues)
    assert [(q.name, e) for q, e in expect.checks] == [
        ("X1.position", ExpectedValue("+-", 100.0, 0.001)),
        ("CHAN1.basic.in.allAxesReferenced", ExpectedValue("==", 0)),
        ("X1.velocity", ExpectedValue("<", 10)),
        ("MCP.jog", ExpectedValue("==", 0)),
    ]
    assert isinstance(steps[17], ExpectCondition)
    assert steps[18] == ExpectAlarm(19, "expect_alarm", steps[18].mark, 10621, "", True)
    assert steps[19] == ExpectAlarm(20, "expect_alarm", steps[19].mark, 21614, "X1", True)
    assert steps[20] == ExpectAlarm(21, "expect_no_alarm", steps[20].mark, 10203, "CHAN1", False)
    assert steps[21] == ExpectAlarm(22, "expect_no_alarm", steps[21].mark, 0, "", False)

    order = steps[22]
    assert isinstance(order, ExpectOrder)
    assert [(e.kind, e.quantity.name if e.quantity else "") for e in order.events] == [
        (EdgeKind.RISES, "X1.basic.out.refPointApproachCam"),
        (EdgeKind.RISES, "X1.basic.in.enc1Synchronized"),
    ]
    timing = steps[23]
    assert isinstance(timing, ExpectTiming)
    assert timing.start.kind is EdgeKind.RISES and timing.end.kind is EdgeKind.WHEN
    assert timing.end.condition is not None and timing.end.condition.text == "X1.position > 99.9"
    assert (timing.minimum, timing.maximum) == (Duration(500_000), Duration(2_000_000))
    changes = steps[24]
    assert isinstance(changes, ExpectTiming)
    assert changes.end.kind is EdgeKind.CHANGES and changes.minimum is None

    names = [q.name for q in loaded.quantities]
    assert names[0] == "X1.followingError" and "time" in names and len(names) == len(set(names))
    assert [event.text for event in loaded.events][-1] == "X1.position changes"


def test_defaults(tmp_path: Path) -> None:
    text = "name: n\nmachine: machines/mini.yaml\nplc: basic_machine\nsteps:\n  - wait: 1s\n"
    loaded = scenario(tmp_path, text)
    assert loaded.timeout == DEFAULT_TIMEOUT and loaded.invariants == () and loaded.description == ""
    assert loaded.plc_program == "basic_machine"


def test_with_a_plc_program_operator_keys_and_forces_are_allowed(tmp_path: Path) -> None:
    loaded = scenario(tmp_path, """\
name: operator
machine: machines/mini.yaml
plc: basic_machine
steps:
  - press: MCP.ncStart
  - set: {MCP.feedOverride: 120, I4.0: 1}
  - force: {CHAN1.basic.out.ncStart: 1, X1.refCam: 1, Lamp.ncStart: 1}
  - release: [CHAN1.basic.out.ncStart, X1.refCam, Lamp.ncStart]
""")
    assert [step.kind for step in loaded.steps] == ["press", "set", "force", "release"]


def test_scenario_files(tmp_path: Path) -> None:
    write_scenario(tmp_path, "", "b.yaml")
    (tmp_path / "sub").mkdir()
    (tmp_path / "sub" / "a.yaml").write_text("")
    (tmp_path / "sub" / "notes.txt").write_text("")
    (tmp_path / "sub" / "machines").mkdir()
    (tmp_path / "sub" / "machines" / "m.yaml").write_text("")
    files, problems = scenario_files([str(tmp_path), str(tmp_path / "b.yaml"), str(tmp_path / "missing")])
    assert files == [str(tmp_path / "b.yaml"), str(tmp_path / "sub" / "a.yaml")]
    assert [str(problem) for problem in problems] == [
        f"{tmp_path}/missing:1:1: no such scenario file or directory"]


def test_one_machine_file_is_loaded_once(tmp_path: Path) -> None:
    calls: list[tuple[str, bool]] = []

    def counting_loader(path: str, overrides: object, overrides_file: str):  # type: ignore[no-untyped-def]
        from vc.config.loader import load_machine

        calls.append((os.path.basename(path), overrides is not None))
        return load_machine(path, overrides, overrides_file)  # type: ignore[arg-type]

    text = "name: n\nmachine: machines/mini.yaml\nplc: none\nsteps:\n  - wait: 1s\n"
    for name in ("a.yaml", "b.yaml"):
        write_scenario(tmp_path, text, name)
    overriding = text.replace("plc: none", "plc: none\nmachine_data: {X1: {MD34010: 1}}")
    write_scenario(tmp_path, overriding, "c.yaml")
    loaded = load_scenarios([str(tmp_path)], KNOWN_PROGRAMS, machine_loader=counting_loader)
    assert len(loaded) == 3
    assert calls == [("mini.yaml", False), ("mini.yaml", True)]
    assert loaded[0].machine is loaded[1].machine


def test_problems_of_a_machine_file_carry_its_own_marks(tmp_path: Path) -> None:
    write_scenario(tmp_path, "name: n\nmachine: machines/mini.yaml\nplc: none\nsteps:\n  - wait: 1s\n")
    machine = tmp_path / "machines" / "mini.yaml"
    machine.write_text(MACHINE_FILE.read_text().replace("I0.2: MCP.jog", "I0.2: MCP.jogg"))
    with pytest.raises(SourceError) as caught:
        load_scenarios([str(tmp_path / "scenario.yaml")], KNOWN_PROGRAMS)
    assert [problem.mark.file for problem in caught.value.problems] == [str(machine)]


TURN_MILL = Path(__file__).resolve().parents[4] / "scenarios" / "machines" / "turn_mill.yaml"


@pytest.mark.skipif(not TURN_MILL.exists(), reason="the library machine turn_mill.yaml is not there yet")
def test_the_design_example_loads_for_the_turn_mill(tmp_path: Path) -> None:
    path = tmp_path / "mda_move.yaml"
    path.write_text(f"""\
name: MDA G1 move with feed override changes
machine: {TURN_MILL}
plc: basic_machine
machine_data:
  CHAN1: {{MD20700: 0}}
timeout: 120s
invariants:
  - "abs(X1.followingError) < 3"
steps:
  - press: MCP.mda
  - mda: "G1 X100 F2000"
  - set: {{MCP.feedOverride: 50}}
  - press: MCP.ncStart
  - wait: {{until: "X1.basic.in.posFineReached == 1", timeout: 5s}}
  - expect: {{X1.position: "100.000 +- 0.001", DB21.DBX36.2: 0, X1.velocity: "< 10"}}
  - expect_no_alarm: all
  - expect_order: [X1.basic.out.refPointApproachCam rises, X1.basic.in.enc1Synchronized rises]
  - expect_timing: {{from: "MCP.ncStart rises", to: "X1.basic.in.posFineReached rises", min: 0.5s, max: 2s}}
""", encoding="utf-8")
    loaded = load_scenarios([str(path)], ("basic_machine",))[0]
    assert loaded.machine.name == "turn_mill" and len(loaded.steps) == 9
