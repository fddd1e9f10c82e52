"""Letting time pass: ``wait: TIME``, or ``wait: {until: CONDITION, timeout: TIME}`` (fails when
the condition has not become true within the timeout; without one, the scenario's timeout ends it).
"""

from __future__ import annotations

from typing import Any

from vc.located_yaml import LocatedMap, Mark
from vc.scenario.language.model import Step, Wait, WaitUntil
from vc.scenario.language.steps.common import StepChecker, StepKind, StepRun, built

# -- checking ------------------------------------------------------------------------------


def check_wait(checker: StepChecker, index: int, mark: Mark, value: Any, value_mark: Mark) -> Step | None:
    if not isinstance(value, LocatedMap):
        duration = checker.duration(value, value_mark)
        return Wait(index, "wait", mark, duration) if duration is not None else None
    if not checker.check_keys(value, ("until", "timeout"), ("until",), "wait"):
        return None
    condition = checker.expression(value["until"], value.mark_of("until"))
    timeout = None
    if "timeout" in value:
        timeout = checker.duration(value["timeout"], value.mark_of("timeout"), positive=True)
        if timeout is None:
            return None
    return WaitUntil(index, "wait", mark, condition, timeout) if condition is not None else None


# -- running -------------------------------------------------------------------------------


def run_wait(run: StepRun, step: Step) -> None:
    if isinstance(step, WaitUntil):
        wait_until(run, step)
    else:
        run.advance(built(step, Wait).duration.cycles(run.ipo_cycle_us))


def wait_until(run: StepRun, step: WaitUntil) -> None:
    condition = step.condition.compile(run.probe)
    if run.evaluate(condition, step.condition):
        return
    limit = step.timeout.cycles(run.ipo_cycle_us) if step.timeout is not None else None
    if not run.advance(limit, condition, step.condition):
        raise run.fail(step, f"waited {step.timeout} for \"{step.condition}\"; it did not become true"
                       f"{run.now(step.quantities, '. Now: ')}")


# -- the kinds -----------------------------------------------------------------------------

WAIT = StepKind("wait", "wait: 500ms", (Wait, WaitUntil), check_wait, run_wait)
