"""The table of step kinds: every key that may start a step of a scenario, in the order the
messages list them, each with its family module, how it is checked and how it runs.

    kind             family (vc/scenario/language/steps/)  builds (vc/scenario/language/model.py)
    press            operator                     Press
    hold             operator                     Hold
    release          operator                     Release
    set              signals                      SetValues
    force            signals                      SetValues (forced)
    pulse            signals                      Press
    mda              programs                     LoadMda
    program          programs                     SelectProgram
    wait             waiting                      Wait, WaitUntil
    expect           expectations                 ExpectValues, ExpectCondition
    expect_alarm     expectations                 ExpectAlarm
    expect_no_alarm  expectations                 ExpectAlarm (absent)
    expect_order     expectations                 ExpectOrder
    expect_timing    expectations                 ExpectTiming
    power_cycle      faults                       PowerCycle
    fault            faults                       InjectFault
    clear_faults     faults                       ClearFaults
    move_by_hand     operator                     MoveByHand
    link_fault       faults                       InjectLinkFault
    turn             operator                     TurnHandwheels
    acknowledge      operator                     AcknowledgeAlarms

The loader checks an item of ``steps:`` with :func:`check_step`; the runner runs a checked step
with ``STEPS[step.kind].run``.  To add a kind: its step class in :mod:`vc.scenario.language.model`, its
checker, runner and :class:`~vc.scenario.language.steps.common.StepKind` in its family's module, its line
here and in the table of docs/scenarios.md (docs/scenarios.md, "Adding a step kind").
"""

from __future__ import annotations

from collections.abc import Mapping
from types import MappingProxyType
from typing import Any

from vc.located_yaml import LocatedMap, Mark
from vc.scenario.language.model import Step
from vc.scenario.language.steps import expectations, faults, operator, programs, signals, waiting
from vc.scenario.language.steps.common import StepChecker, StepKind, kind_of_value, suggest

STEPS: Mapping[str, StepKind] = MappingProxyType({kind.name: kind for kind in (
    operator.PRESS,
    operator.HOLD,
    operator.RELEASE,
    signals.SET,
    signals.FORCE,
    signals.PULSE,
    programs.MDA,
    programs.PROGRAM,
    waiting.WAIT,
    expectations.EXPECT,
    expectations.EXPECT_ALARM,
    expectations.EXPECT_NO_ALARM,
    expectations.EXPECT_ORDER,
    expectations.EXPECT_TIMING,
    faults.POWER_CYCLE,
    faults.FAULT,
    faults.CLEAR_FAULTS,
    operator.MOVE_BY_HAND,
    faults.LINK_FAULT,
    operator.TURN,
    operator.ACKNOWLEDGE,
)})
STEP_KINDS = tuple(STEPS)


def check_step(checker: StepChecker, index: int, item: Any, mark: Mark) -> Step | None:
    """One item of ``steps:`` (``index`` from 1): ``KIND: VALUE``, checked by its kind's checker."""
    if isinstance(item, str) and item in STEPS:
        checker.add(mark, f"'{item}' needs a colon and what to do, e.g. '- {STEPS[item].example}'")
        return None
    if not isinstance(item, LocatedMap) or not item:
        shown = kind_of_value(item)
        hint = suggest(item, STEP_KINDS) if isinstance(item, str) else ""
        checker.add(mark, f"a step is written 'kind: what' (e.g. '- wait: 2s'), not {shown}{hint}")
        return None
    if len(item) > 1:
        kinds = " and ".join(f"'{key}'" for key in item)
        checker.add(item.mark, f"one step per '-': this one has {kinds}"
                    " (options of a step go into a mapping, e.g. press: {key: MCP.jog, for: 300ms})")
        return None
    name = next(iter(item))
    kind = STEPS.get(name)
    if kind is None:
        hint = suggest(name, STEP_KINDS) or f" (steps: {', '.join(STEP_KINDS)})"
        checker.add(item.mark_of_key(name), f"unknown step '{name}'{hint}")
        return None
    return kind.check(checker, index, item.mark, item[name], item.mark_of(name))
