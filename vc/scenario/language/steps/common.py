"""What every step family shares: the checking context, the run context, the table entry.

:class:`StepChecker` is the state of one scenario file while its steps are checked (its machine,
the names it resolves against, which names earlier steps force) with the checks several families
use: keys, durations, conditions, signal names and who may write them, machine axes and
channels.  Every problem goes to the file's :class:`~vc.located_yaml.Problems` with its mark.

:class:`StepRun` is what a step's runner may do against the target while a scenario runs (let
cycles pass, note writes, evaluate, fail); :class:`vc.scenario.run.runner` provides it.

:class:`StepKind` is one entry of the table of step kinds (:mod:`vc.scenario.language.steps.table`).
"""

from __future__ import annotations

import difflib
import os
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, Protocol, TypeVar

from interfaces.plant_io import PointOwner
from interfaces.signals import HMI_INSTANCE, Direction, SignalType, UnknownSignalError
from vc.config.model import MachineConfig
from vc.input_limits import MAX_MAGNITUDE
from vc.located_yaml import LocatedList, LocatedMap, Mark, Problems
from vc.scenario.language.durations import Duration, DurationError, parse_duration
from vc.scenario.language.expressions import (
    AlarmCall,
    Evaluator,
    Expression,
    ExpressionError,
    Name,
    Probe,
    parse_expression,
    walk,
)
from vc.scenario.language.model import NO_PLC, Event, Step
from vc.scenario.language.quantities import NameResolver, Quantity, QuantityKind
from vc.scenario.language.target import ScenarioTarget

if TYPE_CHECKING:
    from vc.core.alarms import Alarm

DEFAULT_PRESS = Duration(100_000)  # press, pulse and turn without 'for'


def suggest(word: str, choices: Sequence[str]) -> str:
    close = difflib.get_close_matches(word, choices, n=1, cutoff=0.6)
    return f"; did you mean {close[0]}?" if close else ""


def looked_for(written: str, location: str) -> str:
    return "" if os.path.normpath(written) == location else f" (looked for {location})"


def brief(text: str) -> str:
    """A text of the file as a message quotes it: whole if short, else its start and its length."""
    return text if len(text) <= 200 else f"{text[:160]}... ({len(text):,} characters)"


def kind_of_value(value: object) -> str:
    if isinstance(value, LocatedMap):
        return "a mapping"
    if isinstance(value, LocatedList):
        return "a list"
    if isinstance(value, bool):
        return "true/false"
    if value is None:
        return "empty"
    return f"'{brief(str(value))}'"


class StepChecker:
    """One scenario file while it is checked: what its steps are checked against, and the checks
    they share.  The loader's checker of the whole file builds on it."""

    def __init__(self, path: str, problems: Problems, timeout: Duration):
        self.path = path
        self.directory = os.path.dirname(path)
        self.problems = problems
        self.machine: MachineConfig | None = None
        self.resolver: NameResolver | None = None
        self.plc = NO_PLC
        self.link: str | None = None
        self.forced: set[str] = set()  # the names forced by the steps checked so far
        self.timeout = timeout  # the scenario's, once its timeout: is checked
        self.sources = [path]  # the files this scenario reads: what travels with it to another machine

    def add(self, mark: Mark, message: str) -> None:
        self.problems.add(mark, message)

    def check_keys(self, mapping: LocatedMap, allowed: Sequence[str], required: Sequence[str],
                   where: str) -> bool:
        """Report unknown and missing keys; True if all required keys are there."""
        for key in mapping:
            if key not in allowed:
                hint = suggest(key, allowed) or f" (known: {', '.join(allowed)})"
                self.add(mapping.mark_of_key(key), f"unknown key '{key}' in {where}{hint}")
        missing = [key for key in required if key not in mapping]
        for key in missing:
            self.add(mapping.mark, f"{where} needs '{key}'")
        return not missing

    def text(self, mapping: LocatedMap, key: str) -> str:
        value = mapping.get(key)
        if key in mapping and (not isinstance(value, str) or not value.strip()):
            self.add(mapping.mark_of(key), f"{key} must be a text, not {kind_of_value(value)}")
            return ""
        return str(value or "").strip()

    # -- names and who may write them -----------------------------------------------------

    def resolve(self, name: object, mark: Mark) -> Quantity | None:
        if not isinstance(name, str) or not name.strip():
            self.add(mark, f"expected a signal name, not {kind_of_value(name)}")
            return None
        if self.resolver is None:
            return None
        try:
            return self.resolver.resolve(name)
        except UnknownSignalError as error:
            self.add(mark, error.message)
            return None

    def name_list(self, value: Any, mark: Mark, kind: str) -> list[tuple[str, Mark]] | None:
        if isinstance(value, str):
            return [(value, mark)]
        if isinstance(value, LocatedList) and value and all(isinstance(item, str) for item in value):
            return [(item, item_mark) for _, item, item_mark in value.located_items()]
        self.add(mark, f"{kind} takes a name or a list of names, not {kind_of_value(value)}")
        return None

    def writable_keys(self, value: Any, mark: Mark, kind: str) -> tuple[Quantity, ...] | None:
        names = self.name_list(value, mark, kind)
        if names is None:
            return None
        keys = []
        for name, name_mark in names:
            quantity = self.resolve(name, name_mark)
            if quantity is not None and self.check_key(quantity, name_mark, kind):
                keys.append(quantity)
        return tuple(keys) if len(keys) == len(names) else None

    def check_key(self, quantity: Quantity, mark: Mark, kind: str) -> bool:
        """A key for press/hold/release/pulse: a bool the scenario may write."""
        refusal = self.key_refusal(quantity, kind)
        if refusal:
            self.add(mark, refusal)
        return not refusal

    def check_writable(self, quantity: Quantity, mark: Mark, kind: str) -> bool:
        """Whether the scenario may write ``quantity`` once (as its owner would)."""
        refusal = self.write_refusal(quantity, kind)
        if refusal:
            self.add(mark, refusal)
        return not refusal

    def check_signal(self, quantity: Quantity, mark: Mark, kind: str) -> bool:
        refusal = self.signal_refusal(quantity, kind)
        if refusal:
            self.add(mark, refusal)
        return not refusal

    def signal_refusal(self, quantity: Quantity, kind: str) -> str:
        if quantity.kind is QuantityKind.SIGNAL:
            return ""
        what = {QuantityKind.AXIS: "the simulated axis", QuantityKind.MACHINE_DATUM: "the control's machine data",
                QuantityKind.LINK: "the CAN link"}.get(quantity.kind, "the simulation")
        return f"cannot {kind} {quantity.label}: it is a quantity of {what}, not a signal"

    def write_refusal(self, quantity: Quantity, kind: str) -> str:
        refusal = self.signal_refusal(quantity, kind)
        if refusal:
            return refusal
        assert quantity.ref is not None
        direction = quantity.ref.direction
        owner = ""
        if direction is Direction.NC_TO_PLC and not _operator_panel_key(quantity):
            owner = "it is written by the NC"
        elif direction in (Direction.PLC_TO_NC, Direction.PLC_TO_PLANT) and self.plc != NO_PLC:
            owner = f"it is written by the PLC program {self.plc}"
        elif direction is Direction.PLANT_TO_PLC and not self.is_operator_input(quantity):
            owner = "it is driven by the simulated machine"
        return f"cannot {kind} {quantity.label}: {owner}; use force to override it" if owner else ""

    def key_refusal(self, quantity: Quantity, kind: str) -> str:
        refusal = self.write_refusal(quantity, kind)
        if refusal:
            return refusal
        assert quantity.ref is not None
        if quantity.ref.type is not SignalType.BOOL:
            return (f"{kind} works on keys and bool signals; {quantity.label} is a"
                    f" {quantity.ref.type.value} (use set)")
        return ""

    def is_operator_input(self, quantity: Quantity) -> bool:
        """Plant inputs an operator works: the panel keys and switches, the emergency-stop button."""
        assert quantity.ref is not None
        if self.machine is None:
            return False
        address = quantity.ref.address
        for point in self.machine.plant_io.points:
            inside = point.address.area == address.area and \
                point.address.byte <= address.byte < point.address.byte + point.address.size
            if point.address == address or (address.is_bit and not point.address.is_bit and inside):
                return point.owner is PointOwner.OPERATOR
        return False

    def number(self, value: Any, mark: Mark, what: str) -> float | None:
        """A number the scenario hands to the simulation: finite and at most MAX_MAGNITUDE."""
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            self.add(mark, f"{what} must be a number, not {kind_of_value(value)}")
            return None
        if not abs(value) <= MAX_MAGNITUDE:
            self.add(mark, f"{what}: {value:g} is beyond {MAX_MAGNITUDE:g}, the largest number a scenario may write")
            return None
        return float(value)

    def duration(self, value: Any, mark: Mark, positive: bool = False) -> Duration | None:
        try:
            duration = parse_duration(value)
        except DurationError as error:
            self.add(mark, str(error))
            return None
        if positive and duration.microseconds == 0:
            self.add(mark, "the time must be longer than 0 s")
            return None
        return duration

    def expression(self, value: Any, mark: Mark, offset: int = 0, shown: str = "") -> Expression | None:
        if not isinstance(value, str):
            self.add(mark, f"a condition is a text in quotes (e.g. \"X1.position > 5\"),"
                     f" not {kind_of_value(value)}")
            return None
        try:
            expression = parse_expression(value, self.resolver)
        except ExpressionError as error:
            where = f" at column {error.column + offset}" if error.column is not None else ""
            self.add(mark, f'in "{brief(shown or value)}": {error.message}{where}')
            return None
        if not any(isinstance(node, Name | AlarmCall) for node in walk(expression.root)):
            self.add(mark, f'"{brief(shown or value)}" reads no signal, quantity, time or alarm: it never changes,'
                     " so as a check it always holds or never does")
            return None
        return expression

    def first_channel(self) -> str | None:
        if self.machine is None:
            return None
        return self.machine.channels[0].name if self.machine.channels else None

    def channel(self, mapping: LocatedMap, default: str | None) -> str | None:
        if "channel" not in mapping:
            return default
        return self.place(mapping["channel"], mapping.mark_of("channel"), "channel")

    def place(self, value: Any, mark: Mark, key: str) -> str | None:
        if not isinstance(value, str):
            self.add(mark, f"{key} must be a name, not {kind_of_value(value)}")
            return None
        if self.machine is None:
            return None
        names = [axis.name for axis in self.machine.axes] if key == "axis" else \
            [channel.name for channel in self.machine.channels]
        if value not in names:
            plural = "axes" if key == "axis" else "channels"
            self.add(mark, f"this machine has no {key} '{value}'{suggest(value, names)}"
                     f" ({plural}: {', '.join(names)})")
            return None
        return value

    def machine_axis(self, value: Any, mark: Mark) -> str | None:
        """A machine axis of the scenario's machine, or None (reported)."""
        if self.machine is None:
            return None
        names = [axis.name for axis in self.machine.axes]
        if not isinstance(value, str) or value not in names:
            hint = suggest(str(value), names) or f" (axes: {', '.join(names)})"
            self.add(mark, f"'{value}' is not a machine axis of this machine{hint}")
            return None
        return value


def _operator_panel_key(quantity: Quantity) -> bool:
    """A request of the operator panel to the PLC (DB19 OP -> PLC, e.g. the MCS/WCS softkey
    HMI.basic.in.mcsWcsSwitched): the operator works it, as the panel's keys."""
    signal = quantity.ref.signal if quantity.ref is not None else None
    return signal is not None and signal.instance == HMI_INSTANCE


# ---------------------------------------------------------------------------------- running


class StepRun(Protocol):
    """What a step's runner does against the target while a scenario runs (the run loop of
    :mod:`vc.scenario.run.runner` provides it)."""

    @property
    def target(self) -> ScenarioTarget: ...

    @property
    def ipo_cycle_us(self) -> int: ...

    @property
    def probe(self) -> Probe: ...

    @property
    def forced(self) -> set[str]:
        """The names forced by the steps run so far."""

    def advance(self, cycles: int | None, until: Evaluator | None = None,
                until_expression: Expression | None = None) -> bool:
        """Run ``cycles`` IPO cycles (None: up to the timeout), or until ``until`` holds; True if it did."""

    def after_cycle(self) -> None:
        """Record, check the invariants and watch the events as after a cycle."""

    def after_writes(self, written: Sequence[Quantity]) -> None:
        """The step wrote between two cycles."""

    def evaluate(self, evaluator: Evaluator, expression: Expression | None) -> float: ...

    def fail(self, step: Step, message: str, names: Sequence[Quantity] | None = None) -> Exception:
        """The exception that ends the scenario with ``step`` failed; the runner raises it."""

    def read(self, quantity: Quantity) -> float: ...

    def now(self, names: Sequence[Quantity], lead: str) -> str:
        """``lead`` and the current values of ``names``, or "" without any."""

    def shown(self, quantity: Quantity, value: float) -> str:
        """A value of ``quantity`` for a message, with its unit (``600.0 rev/min``)."""

    def occurrences(self, event: Event) -> list[int]:
        """The cycles (since the start) ``event`` occurred at."""

    def at(self, cycle: int) -> str:
        """The time of ``cycle`` since the start, as a failure message shows it."""


# ---------------------------------------------------------------------------------- the table entry

# check(checker, index, mark of the step, value, mark of the value) -> the step, or None (reported)
Checker = Callable[[StepChecker, int, Mark, Any, Mark], Step | None]
# run(run, step): act on the target; raises run.fail(...) when the step fails
Runner = Callable[[StepRun, Step], None]

S = TypeVar("S", bound=Step)


@dataclass(frozen=True, slots=True)
class StepKind:
    """One kind of step: the key that starts it in a scenario, an example (for messages and the
    docs), the step classes its checker builds, how its YAML value is checked, how it runs."""

    name: str
    example: str
    builds: tuple[type[Step], ...]
    check: Checker
    run: Runner


def built(step: Step, kind: type[S]) -> S:
    """``step`` as the class its kind's checker built (the table keeps kind and class together)."""
    if not isinstance(step, kind):  # pragma: no cover - the loader builds only the table's classes
        raise TypeError(f"unknown step {step!r}")
    return step


def alarms_text(alarms: Sequence[Alarm]) -> str:
    """The alarms as a failure message lists them: ``65830 Gear stage change ... (SP1), 3000 ...``; "none"."""
    shown = []
    for alarm in alarms:
        place = alarm.axis or alarm.channel
        shown.append(f"{alarm.number} {alarm.text}" if not place or place in alarm.text
                     else f"{alarm.number} {alarm.text} ({place})")
    return ", ".join(shown) or "none"
