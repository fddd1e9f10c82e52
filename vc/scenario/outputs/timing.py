"""What a scenario's timing diagram shows, in the manner of the manual's (spindle chapter B.4.6, B.4.8).

* Digital lanes: the keys the scenario presses, the switches it sets and the signals it names in
  ``expect``, ``wait``, ``expect_order`` and ``expect_timing``, in the order the scenario first
  names them; a bool as a 0/1 trace, a byte or word as a bus with its values written in.
* Analog lanes: the axis and spindle quantities the scenario names, and position and velocity
  of every axis it names (or, naming none, of the axes that moved), machine data and link
  quantities it reads.
* On the time axis: where each step began, the failing step and the moment of the failure, the
  moments alarms were raised (from DB100's alarm list, with their numbers); an
  ``expect_timing`` window shaded on its ``to`` lane (from its ``from`` event plus ``min`` to
  plus ``max``), and the time a ``wait until`` may take shaded lightly on the lanes it watches.

:func:`diagram_quantities` says which recorded names a diagram needs (a worker sends back only
those); :func:`timing_diagram` builds the description :mod:`vc.scenario.outputs.diagram` draws.  Nothing
here draws or imports matplotlib.
"""

from __future__ import annotations

from dataclasses import dataclass

from interfaces.signals import SignalType
from vc.config.model import MachineConfig
from vc.scenario.language.model import (
    EdgeKind,
    ExpectCondition,
    ExpectOrder,
    ExpectTiming,
    ExpectValues,
    Hold,
    Press,
    Scenario,
    SetValues,
    Step,
    WaitUntil,
)
from vc.scenario.language.quantities import Quantity, QuantityKind, axis_quantity, unit_of
from vc.scenario.run.runner import ScenarioResult
from vc.scenario.run.trace import Recording, is_alarm_number

MAX_DIGITAL_LANES = 24
MAX_ANALOG_LANES = 6
MOVED = 1e-3  # an axis whose position changed by more than this moved
DIGITAL, BUS, ANALOG = "digital", "bus", "analog"
_NAMING_STEPS = (Press, Hold, SetValues, ExpectValues, ExpectCondition, WaitUntil, ExpectOrder, ExpectTiming)


@dataclass(frozen=True, slots=True)
class Lane:
    name: str
    kind: str  # DIGITAL, BUS or ANALOG
    times: tuple[float, ...]  # seconds since the start; values[i] holds from times[i] on
    values: tuple[float, ...]
    unit: str = ""


@dataclass(frozen=True, slots=True)
class StepMark:
    index: int  # 1-based, as in messages ("step 4 (wait)")
    kind: str
    time_s: float
    failed: bool = False


@dataclass(frozen=True, slots=True)
class Window:
    """An expected window on a lane: shaded from ``start_s`` to ``end_s``."""

    lane: str
    start_s: float
    end_s: float
    label: str
    strong: bool  # an expect_timing window; a wait's time limit is drawn lightly


@dataclass(frozen=True, slots=True)
class AlarmMark:
    """An alarm raised: the moment it entered DB100's alarm list."""

    time_s: float
    number: int


@dataclass(frozen=True, slots=True)
class TimingDiagram:
    title: str
    status: str  # PASS, FAIL, ERROR
    lanes: tuple[Lane, ...]
    steps: tuple[StepMark, ...]
    windows: tuple[Window, ...]
    end_s: float
    failure_s: float | None = None
    failure: str = ""  # where and what, one line
    left_out: int = 0  # lanes beyond the limits, not drawn
    alarms: tuple[AlarmMark, ...] = ()


def named_quantities(scenario: Scenario) -> list[Quantity]:
    """The names the scenario presses, sets, expects, waits for and orders, in the order it first names them."""
    found: dict[str, Quantity] = {}
    for step in scenario.steps:
        if isinstance(step, _NAMING_STEPS):
            for quantity in step.quantities:
                if quantity.kind is not QuantityKind.TIME:
                    found.setdefault(quantity.name, quantity)
    return list(found.values())


def diagram_quantities(scenario: Scenario, recording: Recording) -> list[Quantity]:
    """The recorded names a diagram of ``scenario`` shows (digital lanes first), within the limits."""
    digital, analog = _lanes_wanted(scenario, recording)
    alarms = [history.quantity for history in recording.histories if is_alarm_number(history.quantity)]
    return digital[:MAX_DIGITAL_LANES] + analog[:MAX_ANALOG_LANES] + alarms


def _lanes_wanted(scenario: Scenario, recording: Recording) -> tuple[list[Quantity], list[Quantity]]:
    named = named_quantities(scenario)
    digital = [q for q in named if q.kind is QuantityKind.SIGNAL and recording.history(q) is not None]
    analog = [q for q in named if q.kind is not QuantityKind.SIGNAL and recording.history(q) is not None]
    axes = [axis.name for axis in scenario.machine.axes]
    mentioned = [axis for axis in axes if any(_axis_of(q) == axis for q in named)]
    if not mentioned:
        mentioned = [axis for axis in axes if _moved(recording, axis)]
    for axis in mentioned:
        for name in ("position", "velocity"):
            quantity = axis_quantity(axis, name)
            history = recording.history(quantity)
            if history is not None and len(history) > 1 and all(q.name != quantity.name for q in analog):
                analog.append(quantity)
    return digital, analog


def _axis_of(quantity: Quantity) -> str:
    if quantity.kind is QuantityKind.AXIS:
        return quantity.axis
    if quantity.ref is not None and quantity.ref.signal is not None:
        return quantity.ref.signal.instance
    return quantity.name.split(".", 1)[0]


def _moved(recording: Recording, axis: str) -> bool:
    history = recording.history(axis_quantity(axis, "position"))
    return history is not None and len(history) > 1 and max(history.values) - min(history.values) > MOVED


def timing_diagram(result: ScenarioResult) -> TimingDiagram | None:
    """The diagram of a run whose recording is at hand (None without one)."""
    recording = result.recorder
    if recording is None:
        return None
    scenario = result.scenario
    digital, analog = _lanes_wanted(scenario, recording)
    left_out = max(0, len(digital) - MAX_DIGITAL_LANES) + max(0, len(analog) - MAX_ANALOG_LANES)
    end_s = max(result.simulated_s, recording.time_of(max(result.step_cycles, default=0)))
    lanes = [_lane(recording, q, scenario.machine) for q in digital[:MAX_DIGITAL_LANES] + analog[:MAX_ANALOG_LANES]]
    failure = result.failure
    failed_step = failure.step if failure is not None else None
    steps = tuple(StepMark(step.index, step.kind, recording.time_of(cycle), step is failed_step)
                  for step, cycle in zip(scenario.steps, result.step_cycles, strict=False))
    windows = _windows(scenario, result, recording, {lane.name for lane in lanes}, end_s)
    where = ""
    if failure is not None:
        where = f"{failure.where}: {failure.message}"
    elif result.error:
        where = result.error.strip().splitlines()[-1] if result.error.strip() else "error"
    return TimingDiagram(scenario.name, result.status, tuple(lanes), steps, windows, end_s,
                         failure.time_s if failure is not None else None, where, left_out, alarm_marks(recording))


def alarm_marks(recording: Recording) -> tuple[AlarmMark, ...]:
    """When each alarm was raised: the moments a number appeared in DB100's alarm list (its first
    eight entries; an alarm that moves up the list as others go is not raised again)."""
    histories = [history for history in recording.histories if is_alarm_number(history.quantity)]
    changes = sorted((cycle, position, int(value)) for position, history in enumerate(histories)
                     for cycle, value in history.entries())
    entries = [0] * len(histories)
    marks: list[AlarmMark] = []
    present: set[int] = set()
    index = 0
    while index < len(changes):
        cycle = changes[index][0]
        while index < len(changes) and changes[index][0] == cycle:
            _, position, number = changes[index]
            entries[position] = number
            index += 1
        now = {number for number in entries if number}
        marks += [AlarmMark(recording.time_of(cycle), number) for number in sorted(now - present)]
        present = now
    return tuple(marks)


def _lane(recording: Recording, quantity: Quantity, machine: MachineConfig) -> Lane:
    history = recording.history(quantity)
    assert history is not None
    times = tuple(recording.time_of(cycle) for cycle in history.cycles)
    values = tuple(history.values)
    ref = quantity.ref
    kind = ANALOG
    if ref is not None and ref.type is not SignalType.REAL:
        kind = DIGITAL if ref.bits == 1 else BUS
    return Lane(quantity.name, kind, times, values, unit_of(quantity, machine))


def _windows(scenario: Scenario, result: ScenarioResult, recording: Recording, shown: set[str],
             end_s: float) -> tuple[Window, ...]:
    windows: list[Window] = []
    started = dict(zip((step.index for step in scenario.steps), result.step_cycles, strict=False))
    for step in scenario.steps:
        if step.index not in started:
            break  # the run ended before this step
        if isinstance(step, ExpectTiming):
            windows += _timing_window(step, recording, shown, end_s)
        elif isinstance(step, WaitUntil) and step.timeout is not None:
            begin = recording.time_of(started[step.index])
            limit = begin + step.timeout.seconds
            for quantity in step.quantities:
                if quantity.name in shown:
                    windows.append(Window(quantity.name, begin, min(limit, end_s), _step_label(step), False))
    return tuple(windows)


def _timing_window(step: ExpectTiming, recording: Recording, shown: set[str], end_s: float) -> list[Window]:
    start, end = step.start, step.end
    if start.kind is EdgeKind.WHEN or end.quantity is None or start.quantity is None \
            or end.quantity.name not in shown:
        return []  # a "when" event is not in the recording; its window cannot be placed
    occurrences = recording.occurrences(start.quantity, start.kind)
    if not occurrences:
        return []
    origin = recording.time_of(occurrences[0])
    low = origin + (step.minimum.seconds if step.minimum is not None else 0.0)
    high = origin + step.maximum.seconds if step.maximum is not None else end_s
    if step.minimum is not None and step.maximum is not None:
        bounds = f"{step.minimum} .. {step.maximum}"
    else:
        bounds = f"<= {step.maximum}" if step.maximum is not None else f">= {step.minimum}"
    return [Window(end.quantity.name, low, high, f"{_step_label(step)}: {bounds}", True)]


def _step_label(step: Step) -> str:
    return f"step {step.index}"
