"""Faults and power: ``power_cycle`` (off and on again), ``fault`` (a fault of the simulated
machine: on an axis, the mains, or a device such as the turret), ``clear_faults`` (repaired),
``link_fault`` (a fault of the CAN bus between NC and PLC, ``link: can``).  The faults are
``FAULTS`` and ``LINK_FAULTS`` of :mod:`vc.simulation.observables`.
"""

from __future__ import annotations

from typing import Any

from vc.located_yaml import LocatedMap, Mark
from vc.scenario.language.durations import Duration
from vc.scenario.language.model import LINK_CAN, ClearFaults, InjectFault, InjectLinkFault, PowerCycle, Step
from vc.scenario.language.steps.common import StepChecker, StepKind, StepRun, built, kind_of_value, suggest
from vc.simulation.observables import (
    DEVICE_FAULTS,
    FAULTS,
    LINK_AREA,
    LINK_DIRECTIONS,
    LINK_FAULTS,
    MACHINE_FAULTS,
    MAINS,
    machine_devices,
)

DEFAULT_POWER_OFF = Duration(1_000_000)
LINK_FAULT_KEYS = ("kind", "for", "direction", "frames", "by", "every")

# -- checking ------------------------------------------------------------------------------


def check_power_cycle(checker: StepChecker, index: int, mark: Mark, value: Any, value_mark: Mark) -> Step | None:
    off = DEFAULT_POWER_OFF
    if isinstance(value, LocatedMap):
        if not checker.check_keys(value, ("off",), ("off",), "power_cycle"):
            return None
        value, value_mark = value["off"], value.mark_of("off")
    if value is not None:
        parsed = checker.duration(value, value_mark, positive=True)
        if parsed is None:
            return None
        off = parsed
    return PowerCycle(index, "power_cycle", mark, off)


def check_fault(checker: StepChecker, index: int, mark: Mark, value: Any, value_mark: Mark) -> Step | None:
    if not isinstance(value, LocatedMap):
        checker.add(value_mark, f"fault takes a mapping, e.g. {FAULT.example}")
        return None
    kind = value.get("kind")
    machine_fault = kind in MACHINE_FAULTS
    if not checker.check_keys(value, ("kind",) if machine_fault else ("axis", "kind", "from", "to", "by", "encoder"),
                              ("kind",) if machine_fault else ("axis", "kind"), "fault"):
        return None
    if kind == "mains_failure" and checker.machine is not None and checker.machine.dc_link is None:
        checker.add(value.mark_of("kind"), f"a {kind} fault needs the machine's DC link: this machine has no"
                                           " dc_link: section (only Drives.ready would fall)")
        return None
    if kind in DEVICE_FAULTS and checker.machine is not None and \
            DEVICE_FAULTS[kind] not in machine_devices(checker.machine):
        checker.add(value.mark_of("kind"), f"a {kind} fault needs the machine's {DEVICE_FAULTS[kind]}: this machine"
                                           f" has none (plant: of its machine file)")
        return None
    if machine_fault:
        return InjectFault(index, "fault", mark, "", str(kind), 0.0, 0.0, 0.0, 1)
    axis = checker.machine_axis(value["axis"], value.mark_of("axis"))
    if kind not in FAULTS:
        hint = suggest(str(kind), FAULTS) or f" (faults: {', '.join(FAULTS)})"
        checker.add(value.mark_of("kind"), f"unknown fault '{kind}'{hint}")
        return None
    needed = {"reference_marks_missing": ("from", "to"), "encoder_slip": ("by",), "load_disturbance": ("by",),
              "workpiece_clamp": ("by",), "motor_temperature": ("to",)}.get(kind, ())
    numbers: dict[str, float] = {}
    for key in ("from", "to", "by", "encoder"):
        if key in value:
            if key not in (*needed, "encoder"):
                checker.add(value.mark_of_key(key), f"a {kind} fault takes no '{key}'")
                return None
            number = checker.number(value[key], value.mark_of(key), key)
            if number is None:
                return None
            numbers[key] = float(number)
    missing = [key for key in needed if key not in numbers]
    if missing:
        checker.add(value.mark, f"a {kind} fault needs {' and '.join(missing)}")
        return None
    if kind == "reference_marks_missing" and numbers["from"] == numbers["to"]:
        checker.add(value.mark_of("to"), "from and to are the same position: no reference mark would be missing")
        return None
    encoder = int(numbers.get("encoder", 1))
    if encoder not in (1, 2):
        checker.add(value.mark_of("encoder"), "encoder is the measuring system 1 or 2")
        return None
    if axis is None:
        return None
    if kind == "motor_temperature" and checker.machine is not None and not checker.machine.axis(axis).drive.messages:
        checker.add(value.mark_of("kind"), f"a motor_temperature fault needs the drive of {axis} to report its"
                                           " messages (drive: messages: 1 in the machine file)")
        return None
    return InjectFault(index, "fault", mark, axis, str(kind), numbers.get("from", 0.0), numbers.get("to", 0.0),
                       numbers.get("by", 0.0), encoder)


def check_clear_faults(checker: StepChecker, index: int, mark: Mark, value: Any, value_mark: Mark) -> Step | None:
    if value == MAINS:
        return ClearFaults(index, "clear_faults", mark, MAINS)
    if checker.machine is not None and value in machine_devices(checker.machine):
        return ClearFaults(index, "clear_faults", mark, str(value))
    if checker.machine is not None and value in DEVICE_FAULTS.values():
        checker.add(value_mark, f"this machine has no {value} (plant: of its machine file) whose faults could be"
                                " repaired")
        return None
    axis = checker.machine_axis(value, value_mark)
    return ClearFaults(index, "clear_faults", mark, axis) if axis is not None else None


def check_link_fault(checker: StepChecker, index: int, mark: Mark, value: Any, value_mark: Mark) -> Step | None:
    if not isinstance(value, LocatedMap):
        checker.add(value_mark, f"link_fault takes a mapping, e.g. {LINK_FAULT.example}")
        return None
    if checker.link != LINK_CAN:
        checker.add(mark, f"a link fault acts on the CAN bus: the scenario needs 'link: {LINK_CAN}' and a PLC"
                    " program behind it")
    if not checker.check_keys(value, LINK_FAULT_KEYS, ("kind", "for"), "link_fault"):
        return None
    kind = value["kind"]
    if kind not in LINK_FAULTS:
        hint = suggest(str(kind), LINK_FAULTS) or f" (link faults: {', '.join(LINK_FAULTS)})"
        checker.add(value.mark_of("kind"), f"unknown link fault '{kind}'{hint}")
        return None
    takes = {"loss": ("direction", "frames", "every"), "delay": ("direction", "frames", "by"),
             "bus_off": ()}[kind]
    for key in value:
        if key in LINK_FAULT_KEYS[2:] and key not in takes:
            checker.add(value.mark_of_key(key), f"a {kind} link fault takes no '{key}'"
                        + (" (bus-off stops every frame both ways)" if kind == "bus_off" else ""))
    if kind == "delay" and "by" not in value:
        checker.add(value.mark, "a delay link fault needs 'by' (how much later the frames arrive, e.g. 50ms)")
    duration = checker.duration(value["for"], value.mark_of("for"), positive=True)
    delay = checker.duration(value["by"], value.mark_of("by"), positive=True) if "by" in value else Duration(0)
    directions: tuple[str, ...] = LINK_DIRECTIONS
    if "direction" in value:
        direction = value["direction"]
        if direction in LINK_DIRECTIONS:
            directions = (str(direction),)
        elif direction != "both":
            hint = suggest(str(direction), [*LINK_DIRECTIONS, "both"])
            checker.add(value.mark_of("direction"), f"direction is {', '.join(LINK_DIRECTIONS)} or both, not"
                        f" {kind_of_value(direction)}{hint}")
    every = value.get("every", 1)
    if isinstance(every, bool) or not isinstance(every, int) or every < 1:
        checker.add(value.mark_of("every"), f"every is a whole number from 1 (1 = every frame), not"
                    f" {kind_of_value(every)}")
        every = 1
    areas = link_frames(checker, value["frames"], value.mark_of("frames")) if "frames" in value else ()
    if duration is None or delay is None or areas is None:
        return None
    return InjectLinkFault(index, "link_fault", mark, str(kind), duration, directions, areas, delay, every)


def link_frames(checker: StepChecker, value: Any, mark: Mark) -> tuple[str, ...] | None:
    """The areas whose frames a link fault hits: instance names (X1, CHAN1, NC, MODEGROUP, HMI), data
    blocks (DB31), the plant areas I and Q, or link (the link frames)."""
    if checker.machine is None:
        return None
    names = checker.name_list(value, mark, "frames")
    if names is None:
        return None
    layout = checker.machine.layout
    instances = {"NC": "DB10", "MODEGROUP": "DB11", "HMI": "DB19",
                 **{name: f"DB{layout.channel_db(name)}" for name in layout.channels},
                 **{name: f"DB{layout.axis_db(name)}" for name in layout.axes}}
    known = {*instances.values(), "I", "Q", LINK_AREA}
    areas = []
    for name, name_mark in names:
        area = instances.get(name, name)
        if area not in known:
            choices = [*instances, *sorted(known)]
            hint = suggest(name, choices) or f" (e.g. {', '.join(choices[:4])}, I, Q, {LINK_AREA})"
            checker.add(name_mark, f"'{name}' names no frames of this machine{hint}")
            return None
        areas.append(area)
    return tuple(dict.fromkeys(areas))


# -- running -------------------------------------------------------------------------------


def run_power_cycle(run: StepRun, step: Step) -> None:
    run.target.power_cycle(built(step, PowerCycle).off.seconds)
    run.after_cycle()


def run_fault(run: StepRun, step: Step) -> None:
    fault = built(step, InjectFault)
    run.target.inject_fault(fault.axis, fault.fault, fault.start, fault.end, fault.amount, fault.encoder)


def run_clear_faults(run: StepRun, step: Step) -> None:
    run.target.clear_faults(built(step, ClearFaults).axis)


def run_link_fault(run: StepRun, step: Step) -> None:
    fault = built(step, InjectLinkFault)
    run.target.inject_link_fault(fault.fault, fault.duration.microseconds, fault.directions, fault.areas,
                                 fault.delay.microseconds, fault.every)


# -- the kinds -----------------------------------------------------------------------------

POWER_CYCLE = StepKind("power_cycle", "power_cycle: 2s", (PowerCycle,), check_power_cycle, run_power_cycle)
FAULT = StepKind("fault", "fault: {axis: X1, kind: zero_marks_missing}", (InjectFault,), check_fault, run_fault)
CLEAR_FAULTS = StepKind("clear_faults", "clear_faults: X1", (ClearFaults,), check_clear_faults, run_clear_faults)
LINK_FAULT = StepKind("link_fault", "link_fault: {kind: loss, for: 300ms}", (InjectLinkFault,), check_link_fault,
                      run_link_fault)
