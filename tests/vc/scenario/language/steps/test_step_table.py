"""The table of step kinds (vc/scenario/language/steps/table.py): the kinds docs/scenarios.md documents,
each with a checker that builds the classes its entry names and a runner that acts on the target."""

from __future__ import annotations

import contextlib
import re
import shutil
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any

import pytest

from vc.located_yaml import Mark, Problems
from vc.scenario.language.durations import Duration
from vc.scenario.language.expressions import Evaluator, Expression, Probe
from vc.scenario.language.loader import load_scenario
from vc.scenario.language.model import Event, Scenario, Step
from vc.scenario.language.quantities import Quantity
from vc.scenario.language.steps.common import StepChecker
from vc.scenario.language.steps.table import STEP_KINDS, STEPS, check_step
from vc.scenario.language.target import ScenarioTarget

ROOT = Path(__file__).resolve().parents[5]
MACHINE_FILE = ROOT / "tests" / "vc" / "scenario" / "language" / "bad_scenarios" / "machines" / "mini.yaml"
KNOWN_PROGRAMS = ("basic_machine", "referencing")

EVERY_KIND = """\
name: every kind of step
machine: machines/mini.yaml
plc: none
steps:
  - press: MCP.jog
  - hold: MCP.plus.X1
  - release: MCP.plus.X1
  - set: {MCP.feedOverride: 50}
  - force: {X1.basic.out.enableCtrl: 0}
  - release: X1.basic.out.enableCtrl
  - pulse: {signal: CHAN1.basic.out.ncStart, for: 20ms}
  - mda: "G1 X100 F2000"
  - program: {name: PART1, text: "G1 X10 F100\\nM30"}
  - wait: 500ms
  - wait: {until: "X1.basic.in.posFineReached == 1", timeout: 5s}
  - expect: {X1.position: "100 +- 0.001"}
  - expect: "X1.position > 50"
  - expect_alarm: 10621
  - expect_no_alarm: all
  - expect_order: [MCP.jog rises, MCP.jog falls]
  - expect_timing: {from: MCP.jog rises, to: MCP.jog falls, min: 0.5s, max: 2s}
  - power_cycle: 2s
  - fault: {axis: X1, kind: zero_marks_missing}
  - clear_faults: X1
  - move_by_hand: {axis: X1, velocity: 600}
  - turn: {handwheel1: 20, for: 200ms}
  - acknowledge: alarms
"""

LINK_FAULT = """\
name: a fault of the CAN link
machine: machines/mini.yaml
plc: basic_machine
link: can
steps:
  - link_fault: {kind: loss, for: 300ms}
"""

# what each kind's runner must do (calls on the target, or of the run loop), over the steps above
ACTS: dict[str, set[str]] = {
    "press": {"target.write", "advance"},
    "hold": {"target.write"},
    "release": {"target.write", "target.release"},
    "set": {"target.write"},
    "force": {"target.force"},
    "pulse": {"target.write", "advance"},
    "mda": {"target.load_mda"},
    "program": {"target.select_program"},
    "wait": {"advance", "evaluate"},
    "expect": {"read", "evaluate"},
    "expect_alarm": {"target.alarms", "alarm_present"},
    "expect_no_alarm": {"target.alarms"},
    "expect_order": {"occurrences"},
    "expect_timing": {"occurrences"},
    "power_cycle": {"target.power_cycle", "after_cycle"},
    "fault": {"target.inject_fault"},
    "clear_faults": {"target.clear_faults"},
    "move_by_hand": {"target.move_by_hand"},
    "link_fault": {"target.inject_link_fault"},
    "turn": {"target.turn_handwheel", "advance"},
    "acknowledge": {"target.acknowledge_alarms"},
}


def documented_step_kinds() -> list[str]:
    """The first column of the table under '## Steps' in docs/scenarios.md."""
    text = (ROOT / "docs" / "scenarios.md").read_text(encoding="utf-8")
    section = text.split("\n## Steps\n", 1)[1].split("\n#", 1)[0]
    return re.findall(r"^\| `(\w+)` \|", section, flags=re.MULTILINE)


def load(directory: Path, text: str) -> Scenario:
    (directory / "machines").mkdir(exist_ok=True)
    shutil.copy(MACHINE_FILE, directory / "machines" / "mini.yaml")
    path = directory / "scenario.yaml"
    path.write_text(text, encoding="utf-8")
    return load_scenario(str(path), KNOWN_PROGRAMS)


def every_kind(directory: Path) -> list[Step]:
    return [*load(directory, EVERY_KIND).steps, *load(directory, LINK_FAULT).steps]


def test_the_table_lists_exactly_the_documented_step_kinds() -> None:
    documented = documented_step_kinds()
    assert len(documented) == len(set(documented)) >= 20
    assert sorted(STEPS) == sorted(documented)


def test_every_entry_has_its_name_an_example_a_checker_and_a_runner() -> None:
    for name, kind in STEPS.items():
        assert kind.name == name
        assert kind.example.startswith(f"{name}: ")
        assert callable(kind.check) and callable(kind.run)
        assert kind.builds and all(issubclass(built, Step) for built in kind.builds)


def test_each_checker_builds_the_classes_its_entry_names(tmp_path: Path) -> None:
    steps = every_kind(tmp_path)
    assert {step.kind for step in steps} == set(STEPS)
    for step in steps:
        assert type(step) in STEPS[step.kind].builds, step


@pytest.mark.parametrize("name", STEP_KINDS)
def test_a_kind_without_its_value_is_shown_its_example(name: str) -> None:
    problems = Problems()
    assert check_step(StepChecker("x.yaml", problems, Duration(1_000_000)), 1, name, Mark("x.yaml", 3, 5)) is None
    assert [str(problem) for problem in problems.items] == \
        [f"x.yaml:3:5: '{name}' needs a colon and what to do, e.g. '- {STEPS[name].example}'"]


class _Failed(Exception):
    pass


class _Recorder:
    """Stands for the target, the probe and the run loop at once: records what a runner calls."""

    def __init__(self, calls: list[str], prefix: str = ""):
        self._calls = calls
        self._prefix = prefix

    def __getattr__(self, name: str) -> Callable[..., Any]:
        def call(*arguments: object) -> list[object]:
            self._calls.append(self._prefix + name)
            return []
        return call


class RecordingRun:
    """A :class:`~vc.scenario.language.steps.common.StepRun` that records the calls of a step's runner."""

    def __init__(self) -> None:
        self.calls: list[str] = []
        self.forced: set[str] = {"X1.basic.out.enableCtrl"}
        self.ipo_cycle_us = 2000

    @property
    def target(self) -> ScenarioTarget:
        target: ScenarioTarget = _Recorder(self.calls, "target.")  # type: ignore[assignment]
        return target

    @property
    def probe(self) -> Probe:
        run = self

        class _Probe:
            def reader(self, quantity: Quantity) -> Evaluator:
                return lambda: 1.0

            def alarm_present(self, number: int, place: str, text: str = "") -> bool:
                run.calls.append("alarm_present")
                return False
        return _Probe()

    def advance(self, cycles: int | None, until: Evaluator | None = None,
                until_expression: Expression | None = None) -> bool:
        self.calls.append("advance")
        return True

    def after_cycle(self) -> None:
        self.calls.append("after_cycle")

    def after_writes(self, written: Sequence[Quantity]) -> None:
        self.calls.append("after_writes")

    def evaluate(self, evaluator: Evaluator, expression: Expression | None) -> float:
        self.calls.append("evaluate")
        return 0.0

    def fail(self, step: Step, message: str, names: Sequence[Quantity] | None = None) -> Exception:
        return _Failed(message)

    def read(self, quantity: Quantity) -> float:
        self.calls.append("read")
        return 0.0

    def now(self, names: Sequence[Quantity], lead: str) -> str:
        return ""

    def shown(self, quantity: Quantity, value: float) -> str:
        return str(value)

    def occurrences(self, event: Event) -> list[int]:
        self.calls.append("occurrences")
        return [0]

    def at(self, cycle: int) -> str:
        return f"{cycle}"


def test_each_runner_acts_on_the_target_as_its_kind_says(tmp_path: Path) -> None:
    assert set(ACTS) == set(STEPS)
    done: dict[str, set[str]] = {name: set() for name in STEPS}
    for step in every_kind(tmp_path):
        run = RecordingRun()
        # an expectation the recorder does not meet fails: what it read is recorded all the same
        with contextlib.suppress(_Failed):
            STEPS[step.kind].run(run, step)
        done[step.kind] |= set(run.calls)
    for name, acts in ACTS.items():
        assert acts <= done[name], name
