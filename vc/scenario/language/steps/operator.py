"""What the operator does at the machine: ``press``, ``hold``, ``release``, ``turn``,
``acknowledge``, ``move_by_hand``.

Keys are bool signals the scenario may write (the panel's keys and switches, or the PLC's
signals when ``plc: none``); ``release`` also ends a ``force`` (:mod:`vc.scenario.language.steps.signals`).
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

from vc.core.axis.handwheel import HANDWHEELS
from vc.input_limits import MAX_MAGNITUDE
from vc.located_yaml import LocatedMap, Mark
from vc.scenario.language.model import AcknowledgeAlarms, Hold, MoveByHand, Press, Release, Step, TurnHandwheels
from vc.scenario.language.quantities import Quantity
from vc.scenario.language.steps.common import DEFAULT_PRESS, StepChecker, StepKind, StepRun, built, kind_of_value

# -- checking ------------------------------------------------------------------------------


def check_press(checker: StepChecker, index: int, mark: Mark, value: Any, value_mark: Mark) -> Step | None:
    return check_keys_pressed(checker, index, mark, value, value_mark, "press", "key")


def check_keys_pressed(checker: StepChecker, index: int, mark: Mark, value: Any, value_mark: Mark, kind: str,
                       name_key: str) -> Step | None:
    """``KIND: NAMES`` or ``KIND: {NAME_KEY: NAMES, for: TIME}``: press and pulse."""
    duration = DEFAULT_PRESS
    names_value, names_mark = value, value_mark
    if isinstance(value, LocatedMap):
        if not checker.check_keys(value, (name_key, "for"), (name_key,), kind):
            return None
        names_value, names_mark = value[name_key], value.mark_of(name_key)
        if "for" in value:
            parsed = checker.duration(value["for"], value.mark_of("for"), positive=True)
            if parsed is None:
                return None
            duration = parsed
    keys = checker.writable_keys(names_value, names_mark, kind)
    return Press(index, kind, mark, keys, duration) if keys is not None else None


def check_hold(checker: StepChecker, index: int, mark: Mark, value: Any, value_mark: Mark) -> Step | None:
    keys = checker.writable_keys(value, value_mark, "hold")
    return Hold(index, "hold", mark, keys) if keys is not None else None


def check_release(checker: StepChecker, index: int, mark: Mark, value: Any, value_mark: Mark) -> Step | None:
    names = checker.name_list(value, value_mark, "release")
    if names is None:
        return None
    result: list[Quantity] = []
    for name, name_mark in names:
        quantity = checker.resolve(name, name_mark)
        if quantity is None:
            continue
        if quantity.name in checker.forced:
            checker.forced.discard(quantity.name)
        elif checker.key_refusal(quantity, "release"):
            checker.add(name_mark, f"cannot release {quantity.label}: no step before this one forces it"
                        " (release ends a force, or lets go of a key)")
            continue
        result.append(quantity)
    return Release(index, "release", mark, tuple(result)) if len(result) == len(names) else None


def check_acknowledge(checker: StepChecker, index: int, mark: Mark, value: Any, value_mark: Mark) -> Step | None:
    if value != "alarms":
        checker.add(value_mark, f"acknowledge takes 'alarms' (the alarm cancel key): {ACKNOWLEDGE.example}")
        return None
    return AcknowledgeAlarms(index, "acknowledge", mark)


def check_move_by_hand(checker: StepChecker, index: int, mark: Mark, value: Any, value_mark: Mark) -> Step | None:
    if not isinstance(value, LocatedMap):
        checker.add(value_mark, f"move_by_hand takes a mapping, e.g. {MOVE_BY_HAND.example}")
        return None
    if not checker.check_keys(value, ("axis", "velocity"), ("axis", "velocity"), "move_by_hand"):
        return None
    axis = checker.machine_axis(value["axis"], value.mark_of("axis"))
    velocity = checker.number(value["velocity"], value.mark_of("velocity"), "velocity (mm/min or rev/min)")
    if velocity is None:
        return None
    return MoveByHand(index, "move_by_hand", mark, axis, float(velocity)) if axis is not None else None


def check_turn(checker: StepChecker, index: int, mark: Mark, value: Any, value_mark: Mark) -> Step | None:
    """``turn: {handwheel1: 20, handwheel2: -5, for: 200ms}``: detents per handwheel, turned together."""
    if not isinstance(value, LocatedMap):
        checker.add(value_mark, f"turn takes a mapping, e.g. {TURN.example}")
        return None
    wheels = tuple(f"handwheel{number}" for number in range(1, HANDWHEELS + 1))
    if not checker.check_keys(value, (*wheels, "for"), (), "turn"):
        return None
    detents = []
    for number, key in enumerate(wheels, start=1):
        if key not in value:
            continue
        count = value[key]
        if isinstance(count, bool) or not isinstance(count, int) or not abs(count) <= MAX_MAGNITUDE:
            checker.add(value.mark_of(key), f"{key} takes a whole number of detents, not {kind_of_value(count)}")
            return None
        detents.append((number, count))
    if not detents:
        checker.add(value_mark, f"turn names no handwheel, e.g. {TURN.example}")
        return None
    duration = DEFAULT_PRESS
    if "for" in value:
        parsed = checker.duration(value["for"], value.mark_of("for"), positive=True)
        if parsed is None:
            return None
        duration = parsed
    return TurnHandwheels(index, "turn", mark, tuple(detents), duration)


# -- running -------------------------------------------------------------------------------


def write_keys(run: StepRun, keys: Sequence[Quantity], value: int) -> None:
    for key in keys:
        assert key.ref is not None
        run.target.write(key.ref, value)
    run.after_writes(keys)


def run_press(run: StepRun, step: Step) -> None:
    """Keys to 1, the time passes, keys back to 0 (press and pulse)."""
    press = built(step, Press)
    write_keys(run, press.keys, 1)
    run.advance(press.duration.cycles(run.ipo_cycle_us))
    write_keys(run, press.keys, 0)


def run_hold(run: StepRun, step: Step) -> None:
    write_keys(run, built(step, Hold).keys, 1)


def run_release(run: StepRun, step: Step) -> None:
    release = built(step, Release)
    for quantity in release.names:
        assert quantity.ref is not None
        if quantity.name in run.forced:
            # the owner's value applies again from the next cycle on
            run.forced.discard(quantity.name)
            run.target.release(quantity.ref)
        else:
            run.target.write(quantity.ref, 0)
    run.after_writes(release.names)


def run_acknowledge(run: StepRun, step: Step) -> None:
    built(step, AcknowledgeAlarms)
    run.target.acknowledge_alarms()


def run_move_by_hand(run: StepRun, step: Step) -> None:
    move = built(step, MoveByHand)
    run.target.move_by_hand(move.axis, move.velocity)


def run_turn(run: StepRun, step: Step) -> None:
    turn = built(step, TurnHandwheels)
    cycles = turn.duration.cycles(run.ipo_cycle_us)
    for number, detents in turn.detents:
        run.target.turn_handwheel(number, detents, cycles)
    run.advance(cycles)


# -- the kinds -----------------------------------------------------------------------------

PRESS = StepKind("press", "press: MCP.jog", (Press,), check_press, run_press)
HOLD = StepKind("hold", "hold: MCP.plus.X1", (Hold,), check_hold, run_hold)
RELEASE = StepKind("release", "release: MCP.plus.X1", (Release,), check_release, run_release)
MOVE_BY_HAND = StepKind("move_by_hand", "move_by_hand: {axis: X1, velocity: 600}", (MoveByHand,),
                        check_move_by_hand, run_move_by_hand)
TURN = StepKind("turn", "turn: {handwheel1: 20, for: 200ms}", (TurnHandwheels,), check_turn, run_turn)
ACKNOWLEDGE = StepKind("acknowledge", "acknowledge: alarms", (AcknowledgeAlarms,), check_acknowledge,
                       run_acknowledge)
