"""The parts a turret and a tool changer are made of: a disk the PLC indexes, a cylinder with end
sensors, and the I/O they share.

:class:`IndexingDisk`: stations 1..n around a disk (a turret's tool stations, a magazine's
pockets), turned by a drive the PLC switches on in one direction.  Its position counts the IPO
cycles of travel from station 1; station k stands at ``(k - 1) * cycles_per_station``.  The
station code the plant reports is the station's number while the disk stands inside the
station's window (a fifth of the pitch either side, as a code disk's cams are wide enough for a
PLC to stop the drive inside them), 0 between two; what locks the disk there (a lock pin's cone,
a gripper) centres it on the station (:meth:`IndexingDisk.centre`).

:class:`Cylinder`: a single-acting cylinder with a spring return, pushed out while its solenoid is
on; its stroke counts IPO cycles from 0 (spring end) to ``travel_cycles`` (solenoid end).  The
turret's lock pin is one (out = pulled, unlocked), the tool changer's arm another (out = at the
spindle).  What stops a stroke early (a pin resting on the disk between two stations, a jammed
arm) is its owner's business.

Time is counted in IPO cycles, so the models are deterministic; they do no I/O.
"""

from __future__ import annotations

from dataclasses import dataclass

from interfaces.image import ProcessImage
from interfaces.plant_io import PlantIoMap, station_code_bits
from interfaces.signals import SignalRef


def cycles_of(seconds: float, ipo_cycle_us: int) -> int:
    """``seconds`` as whole IPO cycles, at least one."""
    return max(1, round(seconds * 1_000_000 / ipo_cycle_us))


WINDOW_SHARE = 5  # the station window: a fifth of the pitch either side


@dataclass(slots=True)
class IndexingDisk:
    stations: int
    cycles_per_station: int
    position: int  # IPO cycles of travel from station 1, 0 .. stations * cycles_per_station - 1
    stalled: bool = False  # a fault: the drive runs, the disk does not turn

    @classmethod
    def at_station(cls, stations: int, cycles_per_station: int, station: int) -> IndexingDisk:
        return cls(stations, cycles_per_station, (station - 1) * cycles_per_station)

    @property
    def window(self) -> int:
        """IPO cycles of travel either side of a station inside which its code reads."""
        return self.cycles_per_station // WINDOW_SHARE

    @property
    def station(self) -> int:
        """The station whose window the disk stands in, 0 between two."""
        pitch = self.cycles_per_station
        nearest, offset = divmod(self.position + pitch // 2, pitch)
        if abs(offset - pitch // 2) > self.window:
            return 0
        return nearest % self.stations + 1

    def centre(self) -> None:
        """Something engages the disk inside a station's window: it stands exactly on the station."""
        station = self.station
        if station:
            self.position = (station - 1) * self.cycles_per_station

    def turn(self, direction: int) -> None:
        """One IPO cycle of the drive: +1 clockwise (towards higher stations), -1 counter-clockwise."""
        if direction and not self.stalled:
            self.position = (self.position + direction) % (self.stations * self.cycles_per_station)


@dataclass(slots=True)
class Cylinder:
    travel_cycles: int
    stroke: int  # 0 = spring end .. travel_cycles = solenoid end
    jammed: bool = False  # a fault: the piston does not move

    @property
    def out(self) -> bool:
        return self.stroke == self.travel_cycles

    @property
    def back(self) -> bool:
        return self.stroke == 0

    def step(self, solenoid: bool, lowest: int = 0) -> None:
        """One IPO cycle: out while the solenoid is on, back towards ``lowest`` (where something
        stops the piston) while it is off."""
        if self.jammed:
            return
        if solenoid:
            self.stroke = min(self.stroke + 1, self.travel_cycles)
        elif self.stroke > lowest:
            self.stroke -= 1


class Output:
    """A plant output (Q) a device reads every cycle: its byte and mask, resolved once."""

    __slots__ = ("byte", "mask")

    def __init__(self, io: PlantIoMap, name: str):
        point = io.by_name(name)
        assert point is not None, f"{name} is not wired (the loader checks the device's I/O)"
        self.byte = point.address.byte
        self.mask = 1 << point.address.bit

    def on(self, outputs: bytearray) -> bool:
        return bool(outputs[self.byte] & self.mask)


class Sensors:
    """Plant inputs a device writes, each only when its value changes (and all after a force ended)."""

    def __init__(self, io: PlantIoMap, names: tuple[str, ...]):
        refs = []
        for name in names:
            point = io.by_name(name)
            assert point is not None, f"{name} is not wired (the loader checks the device's I/O)"
            refs.append(point.ref())
        self._refs: tuple[SignalRef, ...] = tuple(refs)
        self._written: tuple[int, ...] | None = None

    def write(self, io: ProcessImage, values: tuple[int, ...]) -> None:
        if values == self._written:
            return
        self._written = values
        for ref, value in zip(self._refs, values, strict=True):
            io.write(ref, value)

    def forget(self) -> None:
        self._written = None


def code_names(prefix: str, stations: int) -> tuple[str, ...]:
    """The inputs of a binary station code: Turret.code1, Turret.code2, .."""
    return tuple(f"{prefix}.code{bit}" for bit in station_code_bits(stations))


def code_values(station: int, stations: int) -> tuple[int, ...]:
    """The bits of ``station`` for the code inputs of :func:`code_names`."""
    return tuple(1 if station & bit else 0 for bit in station_code_bits(stations))
