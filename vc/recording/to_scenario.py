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
"""

from __future__ import annotations

import json
import os
from dataclasses import dataclass, field

from interfaces.catalog import load_catalog
from interfaces.errors import VcError
from interfaces.image import ProcessImage, Value, decode
from interfaces.signals import Direction, SignalRef, expand
from vc.config.model import MachineConfig
from vc.located_yaml import load_text
from vc.recording.format import LIFE, NC, Bytes, Marker, Recording
from vc.recording.replay import recorded_machine
from vc.scenario.values import format_value
from vc.simulation.observed import OperatorAction


class ConversionError(VcError, ValueError):
    """The recording holds something a scenario cannot express (with where and why)."""


@dataclass(slots=True)
class Conversion:
    text: str  # the scenario file
    notes: list[str] = field(default_factory=list)  # what was left out
    machine_file: str = ""  # a machine file written next to the scenario (empty: an existing one is named)


def _json(value: object) -> str:
    return json.dumps(value, ensure_ascii=False)


def _mapping(values: dict[str, Value]) -> str:
    return "{" + ", ".join(f"{_json(name)}: {_json(value)}" for name, value in values.items()) + "}"


def _duration(microseconds: int) -> str:
    if microseconds % 1000:
        return f"{microseconds}us"
    return f"{microseconds // 1000}ms"


class _Writer:
    def __init__(self, recording: Recording, machine: MachineConfig):
        self.recording = recording
        self.machine = machine
        self.ipo_us = recording.header.ipo_cycle_us
        self.steps: list[str] = []
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
            self.steps.append(f"  - wait: {_duration((self.due - self.now) * self.ipo_us)}")
            self.now = self.due

    def step(self, text: str) -> None:
        self.catch_up()
        self.steps.append(text)

    def flush(self) -> None:
        for step, values in (("set", self.pending_set), ("expect", self.pending_expect)):
            if values:
                self.step(f"  - {step}: {_mapping(values)}")
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
            if value != decode(before, ref):
                self.pending_expect[ref.name] = value

    def plc_bytes(self, row: Bytes) -> None:
        if self.pending_expect:
            self.flush()
        area = self.plc.areas[row.area]
        before = bytes(area)
        area[row.offset:row.offset + len(row.data)] = row.data
        for ref in self._refs_in(self.plc_refs, row):
            value = decode(area, ref)
            if value != decode(before, ref):
                self.pending_set[ref.name] = value

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
            self.step(f"  - {step}: {{{_json(arguments[0])}: {_json(arguments[1])}}}")
        elif kind == "release":
            self.step(f"  - release: {_json(arguments[0])}")
        elif kind == "mda":
            self.step(f"  - mda: {{channel: {_json(arguments[0])}, text: {_json(arguments[1])}}}")
        elif kind == "program":
            self.step(f"  - program: {{channel: {_json(arguments[0])}, name: {_json(arguments[1])},"
                              f" text: {_json(arguments[2])}}}")
        elif kind == "power_cycle":
            off = arguments[0]
            off_us = round((off if isinstance(off, (int, float)) else 0.0) * 1_000_000)
            self.step(f"  - power_cycle: {_duration(off_us)}")
            self.now = self.due = cycle + round(off_us / self.ipo_us)
            self.plc = ProcessImage(self.recording.header.areas)  # a fresh wire, the outputs dropped
        elif kind == "fault":
            axis, fault, start, end, amount, encoder = arguments
            self.step(f"  - fault: {{axis: {_json(axis)}, kind: {_json(fault)}, from: {_json(start)},"
                              f" to: {_json(end)}, by: {_json(amount)}, encoder: {_json(encoder)}}}")
        elif kind == "clear_faults":
            self.step(f"  - clear_faults: {_json(arguments[0])}")
        elif kind == "acknowledge":
            self.step("  - acknowledge: alarms")
        elif kind == "move_by_hand":
            self.step(f"  - move_by_hand: {{axis: {_json(arguments[0])}, velocity: {_json(arguments[1])}}}")
        elif kind == "handwheel":
            number, detents, cycles = (int(item) if isinstance(item, (int, float)) else 0 for item in arguments)
            self.step(f"  - turn: {{handwheel{number}: {detents}, for: {_duration(cycles * self.ipo_us)}}}")
            self.now = self.due = cycle + cycles
        else:  # link_fault: its effect on the PLC's timing is in the recorded writes
            self.notes.append(f"cycle {cycle}: {kind} left out (its effect on the PLC's writes is recorded)")

    # ------------------------------------------------------------------ the whole
    def convert(self) -> list[str]:
        recording = self.recording
        stalls = 0
        for row, mark in zip(recording.rows, recording.row_marks, strict=True):
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
        return self.steps


def _machine_reference(recording: Recording, out: str) -> tuple[str, str]:
    """The ``machine:`` of the scenario (relative to it) and the machine file to write (or "")."""
    recorded = recording.header.machine
    directory = os.path.dirname(os.path.abspath(out))
    if os.path.isfile(recorded.file):
        with open(recorded.file, encoding="utf-8") as handle:
            if handle.read() == recorded.text:
                return os.path.relpath(os.path.abspath(recorded.file), directory), ""
    stem = os.path.splitext(os.path.basename(out))[0]
    written = os.path.join(directory, f"{stem}.machine.yaml")
    return os.path.basename(written), written


def _machine_data_block(recording: Recording) -> list[str]:
    scenario = recording.header.scenario
    if scenario is None:
        return []
    document, _ = load_text(scenario.text, scenario.file)
    if not isinstance(document, dict) or not document.get("machine_data"):
        return []
    return [f"machine_data: {_json(_plain(document['machine_data']))}"]


def _plain(value: object) -> object:
    if isinstance(value, dict):
        return {str(key): _plain(item) for key, item in value.items()}
    if isinstance(value, list):
        return [_plain(item) for item in value]
    return value


def to_scenario(recording: Recording, out: str, name: str | None = None) -> Conversion:
    """The scenario text for ``recording``, to be written to ``out``.  Raises :class:`ConversionError`
    or (for the recorded machine) ``SourceError``."""
    machine = recorded_machine(recording)
    writer = _Writer(recording, machine)
    steps = writer.convert()
    machine_reference, machine_file = _machine_reference(recording, out)
    header = recording.header
    played = f"; the operator:\n  {header.scenario.file}" if header.scenario else ""
    seconds = recording.last_cycle * header.ipo_cycle_us / 1e6
    lines = [
        f"name: {_json(name or f'Recorded session on {header.machine_name}: {header.program} over {header.link}')}",
        "description: >",
        f"  Generated by vc replay --to-scenario from {os.path.basename(recording.path)}: a {header.mode}",
        f"  session of the PLC program {header.program} over {header.link}{played}.",
        "  The PLC's writes are the set steps at their recorded cycles, the NC's recorded responses",
        "  the expectations on the signals that changed.",
        f"machine: {_json(machine_reference)}",
        "plc: none",
        *_machine_data_block(recording),
        f"timeout: {format_value(round(seconds + 1.0, 3))}s",
        "steps:",
        *steps,
    ]
    for note in writer.notes:
        lines.append(f"# note: {note}")
    return Conversion("\n".join(lines) + "\n", writer.notes, machine_file)
