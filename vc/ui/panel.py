"""What the operator page may show and do, from the machine file (no I/O).

The machine control panel is the plant's operator points (``interfaces/plant_io.py``, owner
``operator``): the page lays out exactly the keys and switches the machine file wires, and what it
presses goes where the operator's hand goes, into the plant inputs the PLC reads.  Nothing of the
page writes around the PLC.

Who may force what (the documented force rules, ``docs/ui.md``)::

    plant inputs (I: sensors, keys)     every page: a sensor forced is what the PLC reads
    PLC-to-NC signals (DB.. the PLC     only a page whose address --allow-writers names, as for a
      writes)                           second Modbus writer (interfaces/links/modbus/access.py)
    NC-to-PLC signals, PLC outputs (Q)  never: they are the NC's and the PLC's outputs; watch them

Every refusal comes back as a sentence that says why, and the page shows it.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass
from enum import StrEnum

from interfaces.links.modbus.access import AllowList
from interfaces.plant_io import PlantIoMap, PointOwner
from interfaces.signals import Direction, SignalRef, SignalType


class ControlKind(StrEnum):
    """How a control of the panel acts."""

    KEY = "key"  # momentary: on while the operator holds it (the PLC latches what it must)
    SWITCH = "switch"  # stays where it was put: the emergency-stop button, the door, a selector switch
    KNOB = "knob"  # a byte: an override switch in percent, a handwheel's axis selector


@dataclass(frozen=True, slots=True)
class Control:
    name: str  # the plant function, MCP.jog
    kind: ControlKind
    group: str
    label: str
    maximum: int = 1  # the largest value (a knob's)


# The panel's groups in the order of a SINUMERIK machine control panel, and which functions belong to each.
GROUPS: tuple[tuple[str, str], ...] = (
    ("modes", r"MCP\.(auto|mda|jog|ref)"),
    ("jog functions", r"MCP\.(inc1|inc10|inc100|inc1000|inc10000|incVar|jogContinuous)"),
    ("axes", r"MCP\.(plus|minus)\..+|MCP\.rapid"),
    ("program", r"MCP\.(ncStart|ncStop|reset)"),
    ("feed and spindle", r"MCP\.(feedStop|feedStart|spindleStop|spindleStart)"),
    ("overrides", r"MCP\.(feedOverride|rapidOverride|spindleOverride)"),
    ("handwheels", r"MCP\.handwheel[1-3]"),
    ("switches", r"MCP\.(optionalStop|noOrthogonalCompensation)|Door\.closed"),
    ("emergency stop", r"EStop\.chainOk"),
)
LABELS = {"MCP.auto": "AUTO", "MCP.mda": "MDA", "MCP.jog": "JOG", "MCP.ref": "REF", "MCP.inc1": "INC 1",
          "MCP.inc10": "INC 10", "MCP.inc100": "INC 100", "MCP.inc1000": "INC 1000", "MCP.inc10000": "INC 10000",
          "MCP.incVar": "INC var", "MCP.jogContinuous": "JOG cont.", "MCP.rapid": "RAPID",
          "MCP.ncStart": "NC START", "MCP.ncStop": "NC STOP", "MCP.reset": "RESET", "MCP.feedStop": "FEED STOP",
          "MCP.feedStart": "FEED START", "MCP.spindleStop": "SPINDLE STOP", "MCP.spindleStart": "SPINDLE START",
          "MCP.feedOverride": "feed %", "MCP.rapidOverride": "rapid %", "MCP.spindleOverride": "spindle %",
          "MCP.optionalStop": "M01", "MCP.noOrthogonalCompensation": "NOZAGC", "Door.closed": "door closed",
          "EStop.chainOk": "EMERGENCY STOP"}
OVERRIDE_MAXIMUM = 200  # the override switches are binary-coded percent, 0..200 (interfaces/plant_io.py)
SWITCHES = re.compile(r"EStop\.chainOk|Door\.closed|MCP\.(optionalStop|noOrthogonalCompensation)")
KNOBS = re.compile(r"MCP\.(feedOverride|rapidOverride|spindleOverride|handwheel[1-3])")


def panel_controls(plant_io: PlantIoMap) -> list[Control]:
    """The controls of the machine control panel the machine file wires, grouped, in panel order."""
    operator = [point for point in plant_io.points if point.owner is PointOwner.OPERATOR]
    controls = []
    for group, pattern in GROUPS:
        matcher = re.compile(pattern)
        for point in operator:
            if not matcher.fullmatch(point.name):
                continue
            kind = ControlKind.KNOB if KNOBS.fullmatch(point.name) else (
                ControlKind.SWITCH if SWITCHES.fullmatch(point.name) else ControlKind.KEY)
            maximum = OVERRIDE_MAXIMUM if "Override" in point.name else 255 if kind is ControlKind.KNOB else 1
            controls.append(Control(point.name, kind, group, LABELS.get(point.name, _axis_key_label(point.name)),
                                    maximum))
    return controls


def _axis_key_label(name: str) -> str:
    parts = name.split(".")
    if len(parts) == 3 and parts[1] in ("plus", "minus"):
        return f"{parts[2]} {'+' if parts[1] == 'plus' else '−'}"
    return name


def lamps(plant_io: PlantIoMap) -> list[str]:
    """The panel's indicator lamps (PLC outputs ``Lamp.*``)."""
    return [point.name for point in plant_io.points if point.name.startswith("Lamp.")]


class Rules:
    """What a page at a given address may press and force (see the module docstring)."""

    def __init__(self, plant_io: PlantIoMap, allow_writers: tuple[str, ...]):
        self.plant_io = plant_io
        self.controls = {control.name: control for control in panel_controls(plant_io)}
        self.writers = AllowList(allow_writers, admits_all_when_empty=False)
        self.allow_writers = allow_writers

    def key_refusal(self, name: str, value: float) -> str | None:
        """Why the panel may not set ``name`` to ``value`` (None: it may)."""
        control = self.controls.get(name)
        if control is None:
            return (f"'{name}' is no key or switch of this machine's control panel; the page presses only what"
                    " the machine file wires as the operator's (force a sensor in the watch table)")
        return _value_refusal(value, control.maximum)

    def force_refusal(self, ref: SignalRef, value: float, peer: str) -> str | None:
        """Why a page at ``peer`` may not force ``ref`` to ``value`` (None: it may)."""
        if ref.direction is Direction.PLANT_TO_PLC:
            pass
        elif ref.direction is Direction.PLC_TO_NC:
            if not self.writers.admits(peer):
                given = f" (it names {', '.join(self.allow_writers)})" if self.allow_writers else ""
                return (f"{ref.name} is written by the PLC: forcing it needs vc serve --allow-writers naming this"
                        f" page's address {peer}{given}")
        elif ref.direction is Direction.NC_TO_PLC:
            return f"{ref.name} is the NC's output to the PLC: it can be watched, not forced"
        else:
            return f"{ref.name} is a PLC output to the plant: it can be watched, not forced (force the plant's input)"
        return _value_refusal(value, _largest(ref))


def _largest(ref: SignalRef) -> int | None:
    if ref.type is SignalType.BOOL:
        return 1
    if ref.type is SignalType.REAL:
        return None
    return (1 << ref.bits) - 1 if ref.bits else {SignalType.BYTE: 255, SignalType.WORD: 65535}.get(ref.type)


def _value_refusal(value: float, maximum: int | None) -> str | None:
    if not math.isfinite(value):
        return f"{value} is not a finite number"
    if maximum is None:
        return None if abs(value) <= 3.4e38 else f"{value} is beyond a REAL's range"
    if value != int(value) or not 0 <= value <= maximum:
        return f"{value:g} is out of range: a whole number 0 .. {maximum}"
    return None
