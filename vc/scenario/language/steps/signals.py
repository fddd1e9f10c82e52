"""Writing interface signals: ``set`` (once, as the owner would), ``force`` (held against the
owner until ``release``) and ``pulse`` (a signal to 1 for a while, as ``press`` does a key).

Who may write what is :meth:`~vc.scenario.language.steps.common.StepChecker.write_refusal`; a value
must fit the signal's type.
"""

from __future__ import annotations

from typing import Any

from interfaces.image import Value, value_range
from interfaces.signals import SignalType
from vc.input_limits import MAX_MAGNITUDE
from vc.located_yaml import LocatedMap, Mark
from vc.scenario.language.model import Press, SetValues, Step
from vc.scenario.language.quantities import Quantity
from vc.scenario.language.steps.common import StepChecker, StepKind, StepRun, built, kind_of_value
from vc.scenario.language.steps.operator import check_keys_pressed, run_press

# -- checking ------------------------------------------------------------------------------


def check_set(checker: StepChecker, index: int, mark: Mark, value: Any, value_mark: Mark) -> Step | None:
    return check_values(checker, index, mark, value, value_mark, forced=False)


def check_force(checker: StepChecker, index: int, mark: Mark, value: Any, value_mark: Mark) -> Step | None:
    return check_values(checker, index, mark, value, value_mark, forced=True)


def check_pulse(checker: StepChecker, index: int, mark: Mark, value: Any, value_mark: Mark) -> Step | None:
    return check_keys_pressed(checker, index, mark, value, value_mark, "pulse", "signal")


def check_values(checker: StepChecker, index: int, mark: Mark, value: Any, value_mark: Mark,
                 forced: bool) -> Step | None:
    """``set`` or ``force``: a mapping of names and values."""
    kind = "force" if forced else "set"
    if not isinstance(value, LocatedMap) or not value:
        checker.add(value_mark, f"{kind} takes a mapping of names and values,"
                    f" e.g. {kind}: {{MCP.feedOverride: 50}}")
        return None
    values: list[tuple[Quantity, Value]] = []
    for name, item, item_mark in value.located_items():
        name_mark = value.mark_of_key(name)
        quantity = checker.resolve(name, name_mark)
        if quantity is None:
            continue
        if not forced and not checker.check_writable(quantity, name_mark, kind):
            continue
        if forced and not checker.check_signal(quantity, name_mark, kind):
            continue
        checked = signal_value(checker, quantity, item, item_mark)
        if checked is not None:
            values.append((quantity, checked))
            if forced:
                checker.forced.add(quantity.name)
    if len(values) != len(value):
        return None
    return SetValues(index, kind, mark, tuple(values), forced)


def signal_value(checker: StepChecker, quantity: Quantity, value: Any, mark: Mark) -> Value | None:
    """``value`` as ``quantity``'s signal holds it, or None (reported): a number within its type."""
    assert quantity.ref is not None
    ref = quantity.ref
    if isinstance(value, bool):
        value = int(value)
    if not isinstance(value, (int, float)):
        checker.add(mark, f"the value for {quantity.label} must be a number (or true/false),"
                    f" not {kind_of_value(value)}")
        return None
    if ref.type is SignalType.REAL:
        if not abs(value) <= MAX_MAGNITUDE:
            checker.add(mark, f"{quantity.label} is a real; {value:g} is beyond {MAX_MAGNITUDE:g}, the largest"
                        " number a scenario may write")
            return None
        return float(value)
    if isinstance(value, float):
        if not value.is_integer():
            checker.add(mark, f"{quantity.label} is a {ref.type.value}; {value} is not a whole number")
            return None
        value = int(value)
    low, high = value_range(ref.type, ref.bits)
    number = int(value)
    if not low <= number <= high:
        checker.add(mark, f"{quantity.label} is a {ref.type.value};"
                    f" {number} is outside {int(low)}..{int(high)}")
        return None
    return number


# -- running -------------------------------------------------------------------------------


def run_values(run: StepRun, step: Step) -> None:
    """``set`` writes once; ``force`` holds the value until a ``release``."""
    values = built(step, SetValues)
    for quantity, value in values.values:
        assert quantity.ref is not None
        if values.forced:
            run.target.force(quantity.ref, value)
            run.forced.add(quantity.name)
        else:
            run.target.write(quantity.ref, value)
    run.after_writes(values.quantities)


# -- the kinds -----------------------------------------------------------------------------

SET = StepKind("set", "set: {MCP.feedOverride: 50}", (SetValues,), check_set, run_values)
FORCE = StepKind("force", "force: {X1.basic.out.enableCtrl: 0}", (SetValues,), check_force, run_values)
PULSE = StepKind("pulse", "pulse: {signal: CHAN1.basic.out.ncStart, for: 20ms}", (Press,), check_pulse, run_press)
