"""Recording a live session (``vc serve --record FILE``): what the PLC wrote, what the NC showed,
what the operator did, cycle by cycle, and which PLC it was.

:class:`SessionRecorder` observes the served simulation (``vc.simulation.observed``).  After every
IPO cycle it compares

* the PLC's bytes - the PLC-to-NC data of the wire and the plant outputs Q - and
* the NC's bytes - the NC-to-PLC data of the NC's data blocks -

with the cycle before (one ``memcmp`` per area, the ranges of a direction only where an area
changed) and writes the changed bytes as ``plc`` and ``nc`` rows; after a PLC scan whose sign of
life did not change, a ``life`` row.  Every action of the operator becomes an ``op`` row, followed
by the bytes it changed.  After a power-on (the first, and every power cycle) all bytes are
written, so that a replay starts from the recorded state whatever the fresh images hold.

A PLC on a link tells who it is (:class:`DescribedPlc`: "external PLC over modbus from
127.0.0.1"); whenever that changes (the PLC claims the session, another one does after a power
cycle) a ``peer`` row says so.  The writer flushes the rows every second of the wall clock and
ends the recording at its size limit (``vc serve --record-limit``), saying so once through
``say``; the session goes on.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Protocol, runtime_checkable

from vc.config.machine_files import machine_file
from vc.input_limits import MAX_RECORDING_BYTES
from vc.recording.format import (
    LIFE,
    NC,
    PLC,
    Action,
    Bytes,
    Header,
    Marker,
    Peer,
    RecordedFile,
    RecordingWriter,
    Row,
)
from vc.simulation.lockstep import Simulation
from vc.simulation.observed import OperatorAction

MERGE_GAP = 4  # changed bytes this close together go into one row


@dataclass(slots=True)
class _Range:
    area: str
    start: int
    stop: int


class ImageWatch:
    """Byte ranges of some areas and their bytes as last seen; what changed since, as runs."""

    def __init__(self, source: str, ranges: dict[str, list[tuple[int, int]]]):
        self.source = source
        self.ranges = ranges  # area -> [(start, stop)]
        self.seen: dict[str, bytes] = {}

    def forget(self) -> None:
        """After a power-on: the next look reports every watched byte."""
        self.seen = {}

    def changes(self, cycle: int, areas: dict[str, bytearray]) -> list[Bytes]:
        rows: list[Bytes] = []
        seen = self.seen
        for area, spans in self.ranges.items():
            now = areas[area]
            before = seen.get(area)
            if before is not None and now == before:
                continue
            for start, stop in spans:
                if before is None:
                    rows.append(Bytes(cycle, self.source, area, start, bytes(now[start:stop])))
                    continue
                rows.extend(self._runs(cycle, area, now, before, start, stop))
            seen[area] = bytes(now)
        return rows

    def _runs(self, cycle: int, area: str, now: bytearray, before: bytes, start: int, stop: int) -> list[Bytes]:
        rows = []
        first = last = -1
        for index in range(start, stop):
            if now[index] == before[index]:
                continue
            if first >= 0 and index - last > MERGE_GAP:
                rows.append(Bytes(cycle, self.source, area, first, bytes(now[first:last + 1])))
                first = -1
            if first < 0:
                first = index
            last = index
        if first >= 0:
            rows.append(Bytes(cycle, self.source, area, first, bytes(now[first:last + 1])))
        return rows


def _spans(ranges: list[tuple[str, int, int]]) -> dict[str, list[tuple[int, int]]]:
    result: dict[str, list[tuple[int, int]]] = {}
    for area, start, stop in ranges:
        result.setdefault(area, []).append((start, stop))
    return result


@dataclass(frozen=True, slots=True)
class SessionInfo:
    """What the header says besides the machine and the PLC program: the scenario that played the
    operator, the PLC's link (``inprocess``: the built-in program in the harness's process) and its
    mode (lockstep, free_running); and the recording's size limit."""

    scenario: RecordedFile | None
    link: str
    mode: str
    created_by: str = ""
    limit_bytes: int = MAX_RECORDING_BYTES


@runtime_checkable
class DescribedPlc(Protocol):
    """A PLC on a link that says who holds its session ("" while nobody does)."""

    @property
    def peer(self) -> str: ...


class SessionRecorder:
    """Writes a recording of the simulation it observes (see the module docstring)."""

    def __init__(self, path: str, session: SessionInfo, say: Callable[[str], None] = print):
        self.path = path
        self.session = session
        self.say = say
        self.writer: RecordingWriter | None = None
        self.plc_watch: ImageWatch | None = None
        self.nc_watch: ImageWatch | None = None
        self.life: int | None = None
        self.peer = ""  # the PLC on the link as last written
        self.ipo_cycle_us = 1
        self.described: DescribedPlc | None = None  # the simulation's PLC, when it says who it is
        self.cycle = 0

    # ------------------------------------------------------------------ SimulationObserver
    def attached(self, simulation: Simulation) -> None:
        if self.writer is not None:
            raise RuntimeError("a session recording holds one simulation; this one has begun already")
        machine = simulation.machine
        with open(machine_file(machine.source) or machine.source, encoding="utf-8") as handle:
            text = handle.read()  # a packaged machine is named by its name, and read where the package has it
        catalog = simulation.catalog
        session = self.session
        self.ipo_cycle_us = simulation.ipo_cycle_us
        header = Header(machine.name, RecordedFile(machine.source, text), session.scenario, simulation.plc_name or "",
                        session.link, session.mode, simulation.ipo_cycle_us, simulation.plc_period,
                        {**catalog.area_sizes, **machine.plant_io.area_sizes()}, session.created_by)
        self.writer = RecordingWriter(self.path, header, limit_bytes=session.limit_bytes)
        nck = simulation.nck
        q_size = len(simulation.plant_image.areas["Q"])
        self.plc_watch = ImageWatch(PLC, _spans([*nck.plc_to_nc_ranges, ("Q", 0, q_size)]))
        self.nc_watch = ImageWatch(NC, _spans(nck.nc_to_plc_ranges))
        self._powered_on(simulation)

    def cycle_done(self, simulation: Simulation) -> None:
        self._bytes(simulation)
        plc = simulation.plc
        if plc is not None and simulation.nck.cycle % simulation.plc_period == 0:
            life = plc.sign_of_life
            if life == self.life:
                self._write(Marker(simulation.cycle, LIFE))
            self.life = life
            self._peer(simulation)
        if self.writer is not None:
            self.writer.flush_if_due()

    def acted(self, simulation: Simulation, action: OperatorAction) -> None:
        cycle = self.cycle
        self._write(Action(cycle, action))
        if action.kind == "power_cycle":
            self._powered_on(simulation)
        else:
            self._bytes(simulation)

    def close(self) -> None:
        if self.writer is not None:
            self.writer.close(self.cycle)

    # ------------------------------------------------------------------ parts
    def _powered_on(self, simulation: Simulation) -> None:
        assert self.plc_watch is not None and self.nc_watch is not None
        self.plc_watch.forget()
        self.nc_watch.forget()
        self._bytes(simulation)
        self.life = simulation.plc.sign_of_life if simulation.plc is not None else None
        self.described = simulation.plc if isinstance(simulation.plc, DescribedPlc) else None
        self._peer(simulation)

    def _peer(self, simulation: Simulation) -> None:
        """A peer row when the PLC that holds the link's session changed."""
        if self.described is not None:
            peer = self.described.peer
            if peer and peer != self.peer:
                self.peer = peer
                self._write(Peer(simulation.cycle, peer))

    def _bytes(self, simulation: Simulation) -> None:
        assert self.plc_watch is not None and self.nc_watch is not None
        cycle = self.cycle = simulation.cycle
        for row in self.nc_watch.changes(cycle, simulation.nck.image.areas):
            self._write(row)
        plc_areas = {**simulation.interface.areas, "Q": simulation.plant_image.areas["Q"]}
        for row in self.plc_watch.changes(cycle, plc_areas):
            self._write(row)

    def _write(self, row: Row) -> None:
        writer = self.writer
        assert writer is not None
        if writer.closed:
            return
        writer.write(row)
        if writer.limited:
            self.say(f"{self.path}: the recording stopped at its size limit of {writer.limit_bytes >> 20:,} MiB at"
                     f" cycle {row.cycle} ({row.cycle * self.ipo_cycle_us / 1e6:.3f} s); the session"
                     " goes on (vc serve --record-limit MIB)")
