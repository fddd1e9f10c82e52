"""Commissioning facts a PLC engineer needs besides the addresses (pure, no I/O).

Per axis: how it is referenced and in which direction (MD34010), where its reference cam and
its limit switches are wired on the slide (physical machine coordinates, as in the machine
file's ``plant:``), its software limits, its step in channel-specific referencing (MD34110) and
what must come before it (the inclined-axis rule, alarm 65820).  Per machine: the order of
channel-specific referencing, and what the plant needs from the PLC (the cam and limit copies,
the drive line-up, the gearbox and its oscillation, the chucks, the emergency stop).

The harness builds them from the machine (:mod:`vc.simulation.commissioning`); ``vc map`` prints
them, and the link description carries them to a PLC as JSON (:meth:`Commissioning.as_dict`).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import asdict, dataclass, field
from typing import Any


@dataclass(frozen=True, slots=True)
class AxisFacts:
    axis: str
    db: int  # its interface data block DB(30 + n)
    kind: str  # "linear axis", "rotary axis" or "spindle"
    unit: str  # "mm" or "deg"
    referencing: str  # how the active measuring system is referenced, in words
    approach: str  # "plus" or "minus" (MD34010); "" where no direction applies
    reference_cycle: int  # MD34110: -1 not needed for NC start, 0 not in channel referencing, 1..15 its step
    reference_position: float | None = None  # MD34100[0]: the position after referencing
    cam: tuple[float, float] | None = None  # the slide stands on the reference cam inside [start, end]
    hw_limit_minus: float | None = None  # the minus limit switch is actuated at or below this position
    hw_limit_plus: float | None = None
    sw_limits: tuple[float, float] | None = None  # MD36100 / MD36110, active once referenced
    before: tuple[str, ...] = ()  # axes that must be referenced first
    prerequisite: str = ""  # the rule behind ``before``, in words
    gear_stages: int = 0  # a spindle's gear stages (0: no gearbox)

    def summary(self) -> str:
        """The facts as one sentence (the map's meaning column)."""
        parts = [f"{self.kind}; {self.referencing}"]
        if self.approach:
            parts.append(f"approach {self.axis}{'+' if self.approach == 'plus' else '-'}"
                         f" (MD34010 = {1 if self.approach == 'minus' else 0})")
        if self.reference_position is not None:
            parts.append(f"reference point {self.reference_position:g} {self.unit} (MD34100)")
        if self.cam is not None:
            parts.append(f"reference cam at {self.cam[0]:g} .. {self.cam[1]:g} {self.unit}")
        if self.hw_limit_minus is not None or self.hw_limit_plus is not None:
            parts.append(f"hardware limit switches at {_position(self.hw_limit_minus, self.unit)} /"
                         f" {_position(self.hw_limit_plus, self.unit)}")
        if self.sw_limits is not None:
            parts.append(f"software limits {self.sw_limits[0]:g} .. {self.sw_limits[1]:g} {self.unit}"
                         " (MD36100 / MD36110, once referenced)")
        parts.append(_cycle_text(self.reference_cycle))
        if self.prerequisite:
            parts.append(self.prerequisite)
        if self.gear_stages:
            parts.append(f"{self.gear_stages} gear stages")
        return "; ".join(parts)


def _position(value: float | None, unit: str) -> str:
    return "-" if value is None else f"{value:g} {unit}"


def _cycle_text(cycle: int) -> str:
    if cycle < 0:
        return "MD34110 = -1: need not be referenced for NC start"
    if cycle == 0:
        return "MD34110 = 0: not part of channel-specific referencing"
    return f"channel-specific referencing step {cycle} (MD34110)"


@dataclass(frozen=True, slots=True)
class PlantNeed:
    """Something the simulated plant (or the NC) needs the PLC to do with its I/O."""

    name: str  # what it concerns: "X1.refCam", "SP1.gearbox", "Drives"
    rule: str  # what the PLC does, one of RULES
    plant_io: tuple[str, ...]  # the plant I/O involved, "X1.refCam (I7.0)"
    interface: tuple[str, ...]  # the interface signals involved, "DB31.DBX12.7"
    text: str = ""  # the same in words (the map and the guide; the description carries no prose)


RULES = {
    "copy": "copy the input to the signal every scan",
    "copy_inverse": "copy the inverse of the (normally closed) input to the signal every scan",
    "emergency_stop": "the e-stop chain, its acknowledgement and the reset that ends alarm 3000",
    "drives": "switch the drive line-up on, then give the enables",
    "gearbox": "the gear stage change: actuator, oscillation, stage report",
    "chuck": "the chuck's valve and its end-position sensors",
    "auxiliary_functions": "the NC's M, S, T, D, H, F output: read the change signals, hold the program with 6.1",
    "turret": "the tool turret: lock pin, indexing drive, station code",
    "tool_changer": "the tool magazine and the changer arm",
    "coolant": "the coolant pump and its pressure switch",
    "tailstock": "the tailstock quill's travel to fixed stop and its sleeve sensors",
    "clamp": "an axis clamp: its valve, its end-position sensors and DB31.DBX2.3 while it clamps",
    "holding_brake": "an axis's holding brake: release it after the enables, engage it before they drop",
}


@dataclass(frozen=True, slots=True)
class Commissioning:
    axes: tuple[AxisFacts, ...]
    reference_order: Mapping[str, tuple[tuple[str, ...], ...]] = field(default_factory=dict)  # channel -> steps
    needs: tuple[PlantNeed, ...] = ()
    # the machine's devices besides the axes (its plant:): "turret" -> {"stations": 8, ..}
    devices: Mapping[str, Mapping[str, float]] = field(default_factory=dict)

    def axis(self, name: str) -> AxisFacts:
        return next(facts for facts in self.axes if facts.axis == name)

    def order_text(self, channel: str) -> str:
        steps = self.reference_order.get(channel, ())
        if not steps:
            return "no axis takes part in channel-specific referencing"
        return " then ".join(" and ".join(step) for step in steps) + " (MD34110, equal numbers together)"

    def as_dict(self) -> dict[str, Any]:
        """The facts as JSON for the link description; the plant needs without their prose (RULES)."""
        return {
            "axes": [{key: (list(value) if isinstance(value, tuple) else value)
                      for key, value in asdict(facts).items()} for facts in self.axes],
            "reference_order": {channel: [list(step) for step in steps]
                                for channel, steps in self.reference_order.items()},
            "plant_needs": [{"name": need.name, "rule": need.rule, "plant_io": list(need.plant_io),
                             "interface": list(need.interface)} for need in self.needs],
            "devices": {name: dict(facts) for name, facts in self.devices.items()},
        }

    @classmethod
    def from_dict(cls, document: Mapping[str, Any]) -> Commissioning:
        axes = []
        for entry in document.get("axes", []):
            values = dict(entry)
            for key in ("cam", "sw_limits", "before"):
                if values.get(key) is not None:
                    values[key] = tuple(values[key])
            axes.append(AxisFacts(**values))
        order = {channel: tuple(tuple(step) for step in steps)
                 for channel, steps in document.get("reference_order", {}).items()}
        needs = tuple(PlantNeed(need["name"], need["rule"], tuple(need["plant_io"]), tuple(need["interface"]))
                      for need in document.get("plant_needs", []))
        devices = {str(name): {str(key): float(value) for key, value in facts.items()}
                   for name, facts in document.get("devices", {}).items()}
        return cls(tuple(axes), order, needs, devices)

    def rows(self, channels: Sequence[str]) -> list[tuple[str, str, str]]:
        """``(name, addresses, meaning)`` for the map: every axis, every channel's order, every need."""
        rows = [(f"{facts.axis}.commissioning", f"DB{facts.db}", facts.summary()) for facts in self.axes]
        rows += [(f"{channel}.referenceOrder", "-", self.order_text(channel)) for channel in channels]
        rows += [(f"wiring.{need.name}", " ".join(need.plant_io + need.interface), need.text) for need in self.needs]
        return rows

