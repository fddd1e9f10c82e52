"""Checks of the run so far: ``expect`` (values or a condition now), ``expect_alarm`` and
``expect_no_alarm`` (alarms now), ``expect_order`` (events in this order) and ``expect_timing``
(the time from one event to the next within a window).

A check that cannot fail is refused like any other mistake: an expected value every value of the
quantity meets, an ``expect_timing`` whose ``max`` is as long as the run can be
(:func:`check_timing_bounds`, once all steps are checked) or whose only bound is ``min: 0``.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

from interfaces.image import value_range
from interfaces.signals import SignalType
from vc.config.machine_data import MdType
from vc.config.md_dictionary import BY_NUMBER
from vc.config.model import PLC_USER_ALARMS
from vc.core.alarms import ALARM_TEXTS, known_alarm
from vc.input_limits import MAX_MAGNITUDE
from vc.located_yaml import LocatedList, LocatedMap, Mark
from vc.scenario.language.durations import Duration, format_seconds
from vc.scenario.language.model import (
    EdgeKind,
    Event,
    ExpectAlarm,
    ExpectCondition,
    ExpectOrder,
    ExpectTiming,
    ExpectValues,
    PowerCycle,
    Step,
)
from vc.scenario.language.quantities import Quantity, QuantityKind
from vc.scenario.language.steps.common import StepChecker, StepKind, StepRun, alarms_text, built, kind_of_value
from vc.scenario.language.values import ExpectedValue, ExpectedValueError, parse_expected

# -- checking ------------------------------------------------------------------------------


def check_expect(checker: StepChecker, index: int, mark: Mark, value: Any, value_mark: Mark) -> Step | None:
    if isinstance(value, str):
        condition = checker.expression(value, value_mark)
        return ExpectCondition(index, "expect", mark, condition) if condition is not None else None
    if not isinstance(value, LocatedMap) or not value:
        checker.add(value_mark, "expect takes a condition in quotes or a mapping of names and expected"
                    ' values, e.g. expect: {X1.position: "100 +- 0.001"}')
        return None
    checks: list[tuple[Quantity, ExpectedValue]] = []
    for name, item, item_mark in value.located_items():
        quantity = checker.resolve(name, value.mark_of_key(name))
        try:
            expected = parse_expected(item)
        except ExpectedValueError as error:
            checker.add(item_mark, str(error))
            continue
        if quantity is None:
            continue
        if expected_in_range(checker, quantity, expected, item_mark):
            checks.append((quantity, expected))
    if len(checks) != len(value):
        return None
    return ExpectValues(index, "expect", mark, tuple(checks))


def check_expect_alarm(checker: StepChecker, index: int, mark: Mark, value: Any, value_mark: Mark) -> Step | None:
    return check_alarm(checker, index, mark, value, value_mark, present=True)


def check_expect_no_alarm(checker: StepChecker, index: int, mark: Mark, value: Any, value_mark: Mark) -> Step | None:
    return check_alarm(checker, index, mark, value, value_mark, present=False)


def check_alarm(checker: StepChecker, index: int, mark: Mark, value: Any, value_mark: Mark,
                present: bool) -> Step | None:
    kind = "expect_alarm" if present else "expect_no_alarm"
    place, text = "", ""
    number_value, number_mark = value, value_mark
    if isinstance(value, LocatedMap):
        if not checker.check_keys(value, ("number", "axis", "channel", "text"), ("number",), kind):
            return None
        if "axis" in value and "channel" in value:
            checker.add(value.mark, f"{kind} takes 'axis' or 'channel', not both")
            return None
        for key in ("axis", "channel"):
            if key in value:
                place = checker.place(value[key], value.mark_of(key), key) or ""
                if not place:
                    return None
        number_value, number_mark = value["number"], value.mark_of("number")
        text = value.get("text", "")
        if not isinstance(text, str):
            checker.add(value.mark_of("text"), f"{kind}: text takes a part of the alarm text, e.g. 'block N20'")
            return None
    if not present and number_value == "all" and not place:
        return ExpectAlarm(index, kind, mark, 0, "", present)
    if isinstance(number_value, bool) or not isinstance(number_value, int):
        also = " or all" if not present else ""
        hint = " (all is for expect_no_alarm)" if number_value == "all" else ""
        checker.add(number_mark,
                    f"{kind} takes an alarm number{also}, not {kind_of_value(number_value)}{hint}")
        return None
    if not known_alarm(number_value):
        known = ", ".join(str(number) for number in sorted(ALARM_TEXTS))
        checker.add(number_mark, f"alarm {number_value} is not an alarm of the simulated control"
                    f" (known: {known}, and the PLC user alarms {PLC_USER_ALARMS.start} .."
                    f" {PLC_USER_ALARMS.stop - 1})")
        return None
    return ExpectAlarm(index, kind, mark, number_value, place, present, text)


def check_expect_order(checker: StepChecker, index: int, mark: Mark, value: Any, value_mark: Mark) -> Step | None:
    if not isinstance(value, LocatedList) or len(value) < 2:
        checker.add(value_mark, "expect_order takes a list of two or more events, e.g."
                    " [X1.basic.out.refPointApproachCam rises, X1.basic.in.enc1Synchronized rises]")
        return None
    events = [check_event(checker, item, item_mark) for _, item, item_mark in value.located_items()]
    checked = [event for event in events if event is not None]
    if len(checked) != len(events):
        return None
    return ExpectOrder(index, "expect_order", mark, tuple(checked))


def check_expect_timing(checker: StepChecker, index: int, mark: Mark, value: Any, value_mark: Mark) -> Step | None:
    if not isinstance(value, LocatedMap):
        checker.add(value_mark, "expect_timing takes a mapping"
                    " {from: EVENT, to: EVENT, min: TIME, max: TIME}")
        return None
    if not checker.check_keys(value, ("from", "to", "min", "max"), ("from", "to"), "expect_timing"):
        return None
    start = check_event(checker, value["from"], value.mark_of("from"))
    end = check_event(checker, value["to"], value.mark_of("to"))
    minimum = checker.duration(value["min"], value.mark_of("min")) if "min" in value else None
    maximum = checker.duration(value["max"], value.mark_of("max")) if "max" in value else None
    if "min" not in value and "max" not in value:
        checker.add(value.mark, "expect_timing needs 'min', 'max' or both")
        return None
    if minimum is not None and maximum is not None and minimum > maximum:
        checker.add(value.mark_of("max"), f"max ({maximum}) is shorter than min ({minimum})")
        return None
    if minimum is not None and minimum.microseconds == 0 and "max" not in value:
        checker.add(value.mark_of("min"), "min: 0 s alone holds for every interval, so the check cannot fail"
                    " (give a max, or a min above 0)")
        return None
    if start is None or end is None or (("min" in value) != (minimum is not None)) \
            or (("max" in value) != (maximum is not None)):
        return None
    return ExpectTiming(index, "expect_timing", mark, start, end, minimum, maximum)


def check_timing_bounds(checker: StepChecker, steps: Sequence[Step]) -> None:
    """An ``expect_timing`` max as long as the run can be cannot fail: no interval of the run is
    longer than its timeout plus the time the machine is switched off in power cycles."""
    longest = checker.timeout.microseconds + sum(step.off.microseconds for step in steps
                                                 if isinstance(step, PowerCycle))
    for step in steps:
        if isinstance(step, ExpectTiming) and step.maximum is not None and step.maximum.microseconds >= longest:
            checker.add(step.mark, f"expect_timing: max ({step.maximum}) is as long as the whole run can be"
                        f" ({format_seconds(longest / 1e6)}: the timeout and the power cycles), so the check"
                        " cannot fail")


def expected_in_range(checker: StepChecker, quantity: Quantity, expected: ExpectedValue, mark: Mark) -> bool:
    """Whether ``expected`` can both pass and fail for the values ``quantity`` can take."""
    low, high, whole, kind = _value_range(quantity)
    judgement = expected.judgement(low, high, whole)
    if not judgement:
        return True
    span = f"{int(low)}..{int(high)}" if whole else f"{low:g}..{high:g}"
    if judgement == "never" and expected.exact is not None:
        checker.add(mark, f"{quantity.label} is a {kind} ({span}); it can never be {expected.exact}")
    elif judgement == "never":
        checker.add(mark, f"{quantity.label} is a {kind} ({span}); it is never {relation(expected)}")
    else:
        checker.add(mark, f"{quantity.label} is a {kind} ({span}); it is always {relation(expected)},"
                    " so the check cannot fail")
    return False


def check_event(checker: StepChecker, value: Any, mark: Mark) -> Event | None:
    usage = "write 'NAME rises', 'NAME falls', 'NAME changes' or 'when CONDITION'"
    if not isinstance(value, str):
        checker.add(mark, f"an event is a text ({usage}), not {kind_of_value(value)}")
        return None
    text = value.strip()
    head, _, rest = text.partition(" ")
    if head.lower() == "when":
        condition_text = rest.lstrip()
        offset = len(value.rstrip()) - len(condition_text)
        condition = checker.expression(condition_text, mark, offset=offset, shown=value)
        return Event(text, EdgeKind.WHEN, condition=condition) if condition is not None else None
    name, _, edge = text.rpartition(" ")
    kinds = {kind.value: kind for kind in EdgeKind if kind is not EdgeKind.WHEN}
    if edge.lower() not in kinds or not name.strip():
        checker.add(mark, f"'{text}' is not an event ({usage})")
        return None
    quantity = checker.resolve(name.strip(), mark)
    if quantity is None:
        return None
    return Event(text, kinds[edge.lower()], quantity=quantity)


def _value_range(quantity: Quantity) -> tuple[float, float, bool, str]:
    """The values ``quantity`` can take: lowest, highest, whether only whole numbers, what it is."""
    if quantity.ref is not None:
        low, high = value_range(quantity.ref.type, quantity.ref.bits)
        return low, high, quantity.ref.type is not SignalType.REAL, quantity.ref.type.value
    if quantity.kind is QuantityKind.MACHINE_DATUM:
        md = BY_NUMBER[int(quantity.quantity)]
        if md.type is MdType.BOOL:
            return 0, 1, True, "machine datum of true/false"
        if md.type in (MdType.INT, MdType.FLOAT) and md.minimum is not None and md.maximum is not None:
            whole = md.type is MdType.INT
            return md.minimum, md.maximum, whole, f"machine datum of {'whole ' if whole else ''}numbers"
    return -MAX_MAGNITUDE, MAX_MAGNITUDE, False, "number"


def relation(expected: ExpectedValue) -> str:
    """``expected`` after a name: ``= 100 +- 0.001``, ``> 5``."""
    shown = str(expected)
    return shown if shown[0] in "<>!=" else f"= {shown}"


# -- running -------------------------------------------------------------------------------


def run_expect(run: StepRun, step: Step) -> None:
    if isinstance(step, ExpectCondition):
        if not run.evaluate(step.condition.compile(run.probe), step.condition):
            raise run.fail(step, f"expected {step.condition}{run.now(step.quantities, '; found ')}")
        return
    values = built(step, ExpectValues)
    wrong = []
    for quantity, expected in values.checks:
        actual = run.read(quantity)
        if not expected.matches(actual):
            wrong.append(f"expected {quantity.name} {relation(expected)}, found {run.shown(quantity, actual)}")
    if wrong:
        raise run.fail(values, "; ".join(wrong))


def run_expect_alarm(run: StepRun, step: Step) -> None:
    """``expect_alarm`` and ``expect_no_alarm``."""
    alarm = built(step, ExpectAlarm)
    place = f" ({alarm.place})" if alarm.place else ""
    place += f" showing '{alarm.text}'" if alarm.text else ""
    alarms = list(run.target.alarms())
    present = alarms_text(alarms)
    if alarm.present:
        if not run.probe.alarm_present(alarm.number, alarm.place, alarm.text):
            raise run.fail(alarm, f"expected alarm {alarm.number}{place} to be present;"
                           f" present alarms: {present}")
        return
    if alarm.number == 0:
        if alarms:
            raise run.fail(alarm, f"expected no alarm; present alarms: {present}")
        return
    if run.probe.alarm_present(alarm.number, alarm.place, alarm.text):
        raise run.fail(alarm, f"expected no alarm {alarm.number}{place}; present alarms: {present}")


def run_expect_order(run: StepRun, step: Step) -> None:
    order = built(step, ExpectOrder)
    found: list[str] = []
    after = 0
    for event in order.events:
        cycles = run.occurrences(event)
        later = [cycle for cycle in cycles if cycle >= after]
        if not later:
            expected = "expected " + ", then ".join(f"'{e}'" for e in order.events)
            so_far = "; " + ", ".join(found) if found else ""
            if not cycles:
                missing = f"'{event}' did not occur"
            else:
                missing = (f"'{event}' did not occur after that (only at"
                           f" {', '.join(run.at(c) for c in cycles[:3])})")
            raise run.fail(order, f"{expected}{so_far}; {missing}")
        after = later[0]
        found.append(f"'{event}' at {run.at(after)}")


def run_expect_timing(run: StepRun, step: Step) -> None:
    timing = built(step, ExpectTiming)
    window = _window(timing.minimum, timing.maximum)
    head = f"expected '{timing.start}' to '{timing.end}' to take {window}"
    starts = run.occurrences(timing.start)
    if not starts:
        raise run.fail(timing, f"{head}; '{timing.start}' did not occur")
    start = starts[0]
    ends = [cycle for cycle in run.occurrences(timing.end) if cycle >= start]
    if not ends:
        raise run.fail(timing, f"{head}; '{timing.end}' did not occur after '{timing.start}'"
                       f" (at {run.at(start)})")
    end = ends[0]
    took_us = (end - start) * run.ipo_cycle_us
    too_short = timing.minimum is not None and took_us < timing.minimum.microseconds
    too_long = timing.maximum is not None and took_us > timing.maximum.microseconds
    if too_short or too_long:
        raise run.fail(timing, f"{head}; it took {format_seconds(took_us / 1e6)}"
                       f" ('{timing.start}' at {run.at(start)}, '{timing.end}' at {run.at(end)})")


def _window(minimum: Duration | None, maximum: Duration | None) -> str:
    if minimum is not None and maximum is not None:
        return f"{minimum} .. {maximum}"
    if minimum is not None:
        return f"at least {minimum}"
    return f"at most {maximum}"


# -- the kinds -----------------------------------------------------------------------------

EXPECT = StepKind("expect", 'expect: {X1.position: "100 +- 0.001"}', (ExpectValues, ExpectCondition), check_expect,
                  run_expect)
EXPECT_ALARM = StepKind("expect_alarm", "expect_alarm: 10621", (ExpectAlarm,), check_expect_alarm, run_expect_alarm)
EXPECT_NO_ALARM = StepKind("expect_no_alarm", "expect_no_alarm: all", (ExpectAlarm,), check_expect_no_alarm,
                           run_expect_alarm)
EXPECT_ORDER = StepKind("expect_order", "expect_order: [MCP.jog rises, MCP.jog falls]", (ExpectOrder,),
                        check_expect_order, run_expect_order)
EXPECT_TIMING = StepKind("expect_timing", "expect_timing: {from: MCP.jog rises, to: MCP.jog falls, max: 1s}",
                         (ExpectTiming,), check_expect_timing, run_expect_timing)
