"""A session recording as a scenario: ``vc replay FILE --to-scenario OUT.yaml``.

The scenario has no PLC (``plc: none``): its ``set`` steps write what the PLC wrote, signal by
signal, at the recorded cycles (``wait`` steps between them), the operator's actions become their
steps again (``set`` for keys, ``mda``, ``program``, ``power_cycle``, ``fault`` ...), and after each
cycle in which the NC's outputs changed an ``expect`` step checks the NC-to-PLC signals that
changed, with their recorded values.  It runs in the ordinary library (``vc run``) and can have a
golden trace like any other scenario.

What a scenario cannot say is left out and reported as a note: a PLC sign of life that stood still
(without a PLC the NC does not watch it), faults of the CAN link (their effect, the timing of the
PLC's writes, is in the recording), bytes of the wire that no catalogue signal holds, the NC's
responses during a handwheel turn.  A turn takes its time in a scenario: a PLC write or an action
of the operator during it cannot be placed, and the conversion stops with a message.

The file is written by PyYAML's emitter from the scenario as data, never by formatting text:
whatever the recording's header holds (a newline in a file name, a quote in a program name), it
stays inside its value.
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass, field
from typing import Any

import yaml

from interfaces.catalog import load_catalog
from interfaces.errors import VcError
from interfaces.image import ProcessImage, Value, decode
from interfaces.signals import Direction, SignalRef, expand
from vc.config.machine_files import looks_like_a_path, machine_file
from vc.config.model import MachineConfig
from vc.located_yaml import load_text
from vc.recording.format import LIFE, NC, Bytes, Marker, Peer, Recording
from vc.recording.replay import recorded_machine
from vc.scenario.language.values import format_value
from vc.simulation.observed import OperatorAction


class ConversionError(VcError, ValueError):
    """The recording holds something a scenario cannot express (with where and why)."""


@dataclass(slots=True)
class Conversion:
    text: str  # the scenario file
    notes: list[str] = field(default_factory=list)  # what was left out
    machine_file: str = ""  # a machine file written next to the scenario (empty: an existing one is named)


def _duration(microseconds: int) -> str:
    if microseconds % 1000:
        return f"{microseconds}us"
    return f"{microseconds // 1000}ms"


class _Writer:
    def __init__(self, recording: Recording, machine: MachineConfig):
        self.recording = recording
        self.machine = machine
        self.ipo_us = recording.header.ipo_cycle_us
        self.steps: list[dict[str, Any]] = []
        self.notes: list[str] = []
        areas = recording.header.areas
        self.nc = ProcessImage(areas)  # the NC's bytes as the recording showed them
        self.plc = ProcessImage(areas)  # the PLC's bytes as the scenario wrote them
        self.nc_known = False  # the first power-on's bytes are the start, not a response
        self.now = 0  # the cycle the scenario's steps have reached
        self.due = 0  # the cycle of the rows now read: a wait goes before the next step
        self.pending_expect: dict[str, Value] = {}
        self.pending_set: dict[str, Value] = {}
        catalog_refs = [item.ref() for item in expand(load_catalog(), machine.layout).signals]
        plant_refs = [point.ref() for point in machine.plant_io.points]
        self.nc_refs = self._by_area([ref for ref in catalog_refs if ref.direction is Direction.NC_TO_PLC])
        self.plc_refs = self._by_area([ref for ref in catalog_refs if ref.direction is Direction.PLC_TO_NC] +
                                      [ref for ref in plant_refs if ref.direction is Direction.PLC_TO_PLANT])

    @staticmethod
    def _by_area(refs: list[SignalRef]) -> dict[str, list[SignalRef]]:
        result: dict[str, list[SignalRef]] = {}
        for ref in refs:
            result.setdefault(ref.area_key, []).append(ref)
        return result

    # ------------------------------------------------------------------ steps
    def catch_up(self) -> None:
        """The wait that brings the scenario to the cycle of the rows read."""
        if self.due > self.now:
            self.steps.append({"wait": _duration((self.due - self.now) * self.ipo_us)})
            self.now = self.due

    def step(self, kind: str, value: Any) -> None:
        self.catch_up()
        self.steps.append({kind: value})

    def flush(self) -> None:
        for step, values in (("set", self.pending_set), ("expect", self.pending_expect)):
            if values:
                self.step(step, dict(values))
                values.clear()

    def reach(self, cycle: int, where: str, placed: bool) -> bool:
        """Go on to the rows of ``cycle``; False if a step cannot be placed there (inside a handwheel turn,
        whose step takes its time): an expectation is then left out, a write stops the conversion."""
        if cycle < self.now:
            if placed:
                raise ConversionError(f"{where}: cycle {cycle} lies inside a handwheel turn that lasts until cycle"
                                      f" {self.now}; a scenario's turn step takes that time, so the PLC's write or"
                                      " the operator's action there cannot be placed")
            return False
        if cycle > self.due:
            self.flush()
            self.due = cycle
        return True

    def nc_bytes(self, row: Bytes, expected: bool) -> None:
        area = self.nc.areas[row.area]
        before = bytes(area)
        area[row.offset:row.offset + len(row.data)] = row.data
        if not (self.nc_known and expected):
            return
        for ref in self._refs_in(self.nc_refs, row):
            value = decode(area, ref)
            if value != decode(before, ref) and self.finite(row, ref, value):
                self.pending_expect[ref.name] = value

    def plc_bytes(self, row: Bytes) -> None:
        if self.pending_expect:
            self.flush()
        area = self.plc.areas[row.area]
        before = bytes(area)
        area[row.offset:row.offset + len(row.data)] = row.data
        for ref in self._refs_in(self.plc_refs, row):
            value = decode(area, ref)
            if value != decode(before, ref) and self.finite(row, ref, value):
                self.pending_set[ref.name] = value

    def finite(self, row: Bytes, ref: SignalRef, value: Value) -> bool:
        """A REAL that is not finite cannot be written in a scenario: left out, with a note."""
        if isinstance(value, float) and not math.isfinite(value):
            self.notes.append(f"cycle {row.cycle}: {ref.name} = {value} left out (a scenario holds finite numbers)")
            return False
        return True

    @staticmethod
    def _refs_in(refs: dict[str, list[SignalRef]], row: Bytes) -> list[SignalRef]:
        end = row.offset + len(row.data)
        return [ref for ref in refs.get(row.area, ())
                if ref.address.byte < end and ref.address.byte + ref.address.size > row.offset]

    def action(self, cycle: int, action: OperatorAction) -> None:
        self.flush()
        kind, arguments = action.kind, action.arguments
        if kind in ("write", "force"):
            step = "set" if kind == "write" else "force"
            self.step(step, {arguments[0]: arguments[1]})
        elif kind == "release":
            self.step("release", arguments[0])
        elif kind == "mda":
            self.step("mda", {"channel": arguments[0], "text": arguments[1]})
        elif kind == "program":
            self.step("program", {"channel": arguments[0], "name": arguments[1], "text": arguments[2]})
        elif kind == "power_cycle":
            off = arguments[0]
            off_us = round((off if isinstance(off, (int, float)) else 0.0) * 1_000_000)
            self.step("power_cycle", _duration(off_us))
            self.now = self.due = cycle + round(off_us / self.ipo_us)
            self.plc = ProcessImage(self.recording.header.areas)  # a fresh wire, the outputs dropped
        elif kind == "fault":
            axis, fault, start, end, amount, encoder = arguments
            self.step("fault", {"axis": axis, "kind": fault, "from": start, "to": end, "by": amount,
                                "encoder": encoder})
        elif kind == "clear_faults":
            self.step("clear_faults", arguments[0])
        elif kind == "acknowledge":
            self.step("acknowledge", "alarms")
        elif kind == "move_by_hand":
            self.step("move_by_hand", {"axis": arguments[0], "velocity": arguments[1]})
        elif kind == "handwheel":
            number, detents, cycles = (int(item) if isinstance(item, (int, float)) else 0 for item in arguments)
            self.step("turn", {f"handwheel{number}": detents, "for": _duration(cycles * self.ipo_us)})
            self.now = self.due = cycle + cycles
        else:  # link_fault: its effect on the PLC's timing is in the recorded writes
            self.notes.append(f"cycle {cycle}: {kind} left out (its effect on the PLC's writes is recorded)")

    # ------------------------------------------------------------------ the whole
    def convert(self) -> list[dict[str, Any]]:
        recording = self.recording
        stalls = 0
        for row, mark in recording.rows():
            if isinstance(row, Peer):
                continue  # who the PLC was is in the description
            if isinstance(row, Marker):
                stalls += row.kind == LIFE
                self.due = max(self.due, row.cycle)  # the end row: the scenario lasts as long as the session
                continue
            nc = isinstance(row, Bytes) and row.source == NC
            placed = self.reach(row.cycle, str(mark), not nc)
            if isinstance(row, Bytes) and nc:
                self.nc_bytes(row, placed)
                continue
            self.nc_known = True  # the NC's bytes before this were its power-on state
            if isinstance(row, Bytes):
                self.plc_bytes(row)
            else:
                self.action(row.cycle, row.action)
        self.flush()
        self.catch_up()
        if stalls:
            self.notes.append(f"the PLC's sign of life stood still in {stalls} scans; without a PLC the NC does not"
                              " watch it (alarm 2000 cannot occur in the scenario)")
        if recording.cut is not None:
            self.notes.append(f"the recording was cut at line {recording.cut.line} ({recording.cut.why}): the"
                              f" scenario ends with its last complete row, at cycle {recording.last_cycle}")
        return self.steps


def _machine_reference(recording: Recording, out: str) -> tuple[str, str]:
    """The ``machine:`` of the scenario (relative to it, or a packaged machine's name) and the
    machine file to write beside it (or "")."""
    recorded = recording.header.machine
    directory = os.path.dirname(os.path.abspath(out))
    found = machine_file(recorded.file)
    if found is not None and os.path.isfile(found):
        with open(found, encoding="utf-8") as handle:
            if handle.read() == recorded.text:
                if not looks_like_a_path(recorded.file) and not os.path.exists(recorded.file):
                    return recorded.file, ""  # a packaged machine, by its name
                return os.path.relpath(os.path.abspath(found), directory), ""
    stem = os.path.splitext(os.path.basename(out))[0]
    written = os.path.join(directory, f"{stem}.machine.yaml")
    return os.path.basename(written), written


def _machine_data(recording: Recording) -> Any:
    """The recorded scenario's ``machine_data`` overrides, as plain data (None without)."""
    scenario = recording.header.scenario
    if scenario is None:
        return None
    document, _ = load_text(scenario.text, scenario.file)
    if not isinstance(document, dict) or not document.get("machine_data"):
        return None
    return _plain(document["machine_data"])


def _plain(value: object) -> object:
    if isinstance(value, dict):
        return {str(key): _plain(item) for key, item in value.items()}
    if isinstance(value, list):
        return [_plain(item) for item in value]
    return value


class _Step(dict[str, Any]):
    """A step: written ``- kind: value``, its value in flow style (``{X1.position: 5}``)."""


class _ScenarioDumper(yaml.SafeDumper):
    """PyYAML's safe emitter, with the items of a list indented under their key and one line per
    step, as the library's scenarios are written."""

    def increase_indent(self, flow: bool = False, indentless: bool = False) -> None:
        super().increase_indent(flow, False)


def _represent_step(dumper: yaml.SafeDumper, step: _Step) -> yaml.Node:
    node = dumper.represent_mapping("tag:yaml.org,2002:map", step, flow_style=False)
    for _, value in node.value:
        if isinstance(value, yaml.CollectionNode):
            value.flow_style = True
    return node


_ScenarioDumper.add_representer(_Step, _represent_step)


def _line(text: str) -> str:
    """A text for a comment line: control characters (a newline) shown, not written."""
    return "".join(character if character.isprintable() else repr(character)[1:-1] for character in text)


def to_scenario(recording: Recording, out: str, name: str | None = None) -> Conversion:
    """The scenario text for ``recording``, to be written to ``out``.  Raises :class:`ConversionError`
    or (for the recorded machine) ``SourceError``."""
    machine = recorded_machine(recording)
    writer = _Writer(recording, machine)
    steps = writer.convert()
    machine_reference, machine_file_written = _machine_reference(recording, out)
    header = recording.header
    played = f"; the operator: {header.scenario.file}" if header.scenario else ""
    seconds = recording.last_cycle * header.ipo_cycle_us / 1e6
    scenario: dict[str, Any] = {
        "name": name or f"Recorded session on {header.machine_name}: {recording.plc} over {header.link}",
        "description": f"Generated by vc replay --to-scenario from {os.path.basename(recording.path)}: a"
                       f" {header.mode} session of {recording.plc} over {header.link}{played}.  The PLC's writes"
                       " are the set steps at their recorded cycles, the NC's recorded responses the expectations"
                       " on the signals that changed.",
        "machine": machine_reference,
        "plc": "none",
    }
    overrides = _machine_data(recording)
    if overrides is not None:
        scenario["machine_data"] = overrides
    scenario["timeout"] = f"{format_value(round(seconds + 1.0, 3))}s"
    scenario["steps"] = [_Step(step) for step in steps]
    text = yaml.dump(scenario, Dumper=_ScenarioDumper, sort_keys=False, allow_unicode=True, width=1 << 20,
                     default_flow_style=None)
    notes = "".join(f"# note: {_line(note)}\n" for note in writer.notes)
    return Conversion(text + notes, writer.notes, machine_file_written)
