"""Replaying a session recording without the PLC: ``vc replay FILE``.

The recorded machine (or another machine file, to see what a change of machine data does) is
powered on with a stand-in for the PLC (:class:`RecordedPlc`); then the rows are played in their
order: after the cycle a row names, the recorded PLC bytes go into the wire and the plant outputs
exactly as the PLC left them, the operator's actions happen again, and the NC runs on
deterministically.  The stand-in does only what the NC watches of a PLC: its sign of life changes
with every scan, except in the scans the recording marks as stalled.

After every cycle the NC's NC-to-PLC bytes are compared with the recorded ones; the first
difference ends the replay, reported by signal with the cycle and both values.
A recording of a real-time session replays in lockstep: the PLC's timing is in the recording.
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass

from interfaces.image import ProcessImage, Value, decode
from interfaces.plc import PlcEnvironment
from interfaces.signals import SignalRef
from vc.config.loader import load_machine, load_machine_text
from vc.config.model import MachineConfig
from vc.located_yaml import LocatedMap, Mark, Problem, SourceError, load_text
from vc.recording.format import LIFE, NC, Action, Bytes, Marker, Recording, Row
from vc.simulation.lockstep import Simulation
from vc.simulation.observed import perform

NOT_REPLAYED = ("link_fault",)  # a fault of the CAN link: its effect, the timing of the PLC's writes, is recorded


class RecordedPlc:
    """The PLC of a replay: it writes nothing itself (the replay puts the recorded bytes in place),
    and its sign of life changes with every scan unless the recording says it stood still."""

    def __init__(self) -> None:
        self.life = 0
        self.stall_next_scan = False

    @property
    def sign_of_life(self) -> int:
        return self.life

    def scan(self, interface: ProcessImage, plant: ProcessImage) -> None:
        if not self.stall_next_scan:
            self.life = (self.life + 1) & 0xFFFF


class RecordedPlcConnector:
    """Gives every power-on of the replay a :class:`RecordedPlc`; ``plc`` is the present one."""

    def __init__(self) -> None:
        self.plc = RecordedPlc()

    def connect(self, environment: PlcEnvironment, program: str) -> RecordedPlc:
        self.plc = RecordedPlc()
        return self.plc


@dataclass(frozen=True, slots=True)
class SignalDifference:
    name: str
    address: str
    recorded: Value
    replayed: Value


@dataclass(frozen=True, slots=True)
class Difference:
    """The first cycle at which the NC's bytes differ from the recording, and how."""

    cycle: int
    signals: tuple[SignalDifference, ...]  # every signal that differs at that cycle (the first one first)
    time_s: float

    def __str__(self) -> str:
        first = self.signals[0]
        others = len(self.signals) - 1
        more = f" (and {others} more signal{'s' if others != 1 else ''} at that cycle)" if others else ""
        return (f"first difference at cycle {self.cycle} (t = {self.time_s:.3f} s): {first.name} ({first.address})"
                f" recorded {first.recorded}, replayed {first.replayed}{more}")


@dataclass(frozen=True, slots=True)
class ReplayResult:
    cycles: int  # the last cycle compared
    difference: Difference | None
    machine: MachineConfig


def recorded_machine(recording: Recording, machine_path: str | None = None) -> MachineConfig:
    """The machine of the recording (or the file ``machine_path``), with the recorded scenario's
    ``machine_data`` overrides.  Raises :class:`SourceError`."""
    overrides, overrides_file = _scenario_overrides(recording)
    if machine_path is not None:
        return load_machine(machine_path, overrides, overrides_file)
    machine = recording.header.machine
    return load_machine_text(machine.text, f"{recording.path} (machine {machine.file})", overrides, overrides_file)


def _scenario_overrides(recording: Recording) -> tuple[LocatedMap | None, str]:
    scenario = recording.header.scenario
    if scenario is None:
        return None, ""
    name = f"{recording.path} (scenario {scenario.file})"
    document, problems = load_text(scenario.text, name)
    if problems:
        raise SourceError(problems)
    overrides = document.get("machine_data") if isinstance(document, dict) else None
    return (overrides if isinstance(overrides, LocatedMap) and overrides else None), name


def check_interface(recording: Recording, simulation: Simulation) -> None:
    """The recording's areas must be those of this interface (same catalogue, same machine layout)."""
    sizes = {**simulation.catalog.area_sizes, **simulation.plant_io.area_sizes()}
    if sizes != recording.header.areas:
        differing = sorted(key for key in set(sizes) | set(recording.header.areas)
                           if sizes.get(key) != recording.header.areas.get(key))
        raise SourceError([Problem(Mark(recording.path, 1, 1),
                                   f"the recording's interface differs from this machine's in {', '.join(differing)}"
                                   " (another catalogue or machine layout): it cannot be replayed here")])


def cycle_groups(recording: Recording) -> Iterator[tuple[int, list[tuple[Row, Mark]]]]:
    """The rows of a recording cycle by cycle: a replay must know, before it runs into a cycle,
    whether the PLC's scan in it left the sign of life unchanged (that row comes last)."""
    group: list[tuple[Row, Mark]] = []
    for row, mark in recording.rows():
        if group and row.cycle != group[0][0].cycle:
            yield group[0][0].cycle, group
            group = []
        group.append((row, mark))
    if group:
        yield group[0][0].cycle, group


class _Replay:
    def __init__(self, recording: Recording, machine: MachineConfig):
        self.recording = recording
        self.connector = RecordedPlcConnector()
        self.simulation = Simulation(machine, recording.header.program, connector=self.connector)
        check_interface(recording, self.simulation)
        self.expected = ProcessImage(recording.header.areas)

    def run(self) -> Difference | None:
        simulation = self.simulation
        for cycle, rows in cycle_groups(self.recording):
            stalled = any(isinstance(row, Marker) and row.kind == LIFE for row, _ in rows)
            while simulation.cycle < cycle:
                difference = self.compare()
                if difference is not None:
                    return difference
                self.connector.plc.stall_next_scan = stalled and simulation.cycle + 1 == cycle
                simulation.step(1)
            for row, mark in rows:
                self.play(row, mark)
        return self.compare()

    def play(self, row: Row, mark: Mark) -> None:
        """Put a row's bytes in place, or do its action again."""
        simulation = self.simulation
        if isinstance(row, Bytes):
            if row.source == NC:
                self.expected.areas[row.area][row.offset:row.offset + len(row.data)] = row.data
            else:
                image = simulation.plant_image if row.area == "Q" else simulation.interface
                image.areas[row.area][row.offset:row.offset + len(row.data)] = row.data
                image.touch()
        elif isinstance(row, Action) and row.action.kind not in NOT_REPLAYED:
            try:
                perform(simulation, row.action)
            except (KeyError, ValueError) as error:
                message = error.args[0] if error.args else error
                raise SourceError([Problem(mark, f"the operator's action {row.action.kind} cannot be done"
                                                 f" again on this machine: {message}")]) from None

    def compare(self) -> Difference | None:
        actual, expected = self.simulation.nck.image.areas, self.expected.areas
        for area, start, stop in self.simulation.nck.nc_to_plc_ranges:
            if actual[area][start:stop] != expected[area][start:stop]:
                return self._difference()
        return None

    def _difference(self) -> Difference:
        simulation = self.simulation
        actual, expected = simulation.nck.image.areas, self.expected.areas
        found: list[SignalDifference] = []
        done: set[str] = set()
        for area, start, stop in simulation.nck.nc_to_plc_ranges:
            for byte in range(start, stop):
                if actual[area][byte] == expected[area][byte]:
                    continue
                for ref in _refs_at(simulation, area, byte):
                    if ref.name in done:
                        continue
                    done.add(ref.name)
                    recorded, replayed = decode(expected[area], ref), decode(actual[area], ref)
                    if recorded != replayed:
                        found.append(SignalDifference(ref.name, str(ref.address), recorded, replayed))
                if not _refs_at(simulation, area, byte):
                    address = f"{area}.DBB{byte}"
                    found.append(SignalDifference(address, address, expected[area][byte], actual[area][byte]))
        return Difference(simulation.cycle, tuple(found), simulation.time_s)


def _refs_at(simulation: Simulation, area: str, byte: int) -> list[SignalRef]:
    """The catalogue signals in one byte of the data block ``area``."""
    refs: dict[str, SignalRef] = {}
    for bit in range(8):
        owner = simulation.catalog.owner_of_bit(area, byte, bit)
        if owner is not None:
            refs.setdefault(owner.symbol, owner.ref())
    return list(refs.values())


def replay(recording: Recording, machine_path: str | None = None) -> ReplayResult:
    """Replay ``recording`` (on the machine file ``machine_path`` instead of the recorded one, if
    given); the result names the first difference, or None.  Raises :class:`SourceError` for a
    machine that cannot be loaded or an interface that differs."""
    machine = recorded_machine(recording, machine_path)
    run = _Replay(recording, machine)
    difference = run.run()
    return ReplayResult(run.simulation.cycle, difference, machine)
