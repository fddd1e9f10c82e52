"""A tool magazine turned by an NC axis that the PLC positions (FC18, seed 003 §9.7): its lock pin and
pocket sensor, wired to the PLC.

The magazine's disk is a modulo rotary axis of the NC (the machine file's ``plant: axis_magazine:
axis:``); the PLC moves it with FC18 (plc_stub/programs/magazine.py).  A lock pin holds the disk at
a pocket: the PLC pulls it with its solenoid ``AxisMagazine.unlock`` (sensors ``AxisMagazine.locked``
while it is engaged, ``AxisMagazine.unlocked`` once fully pulled); dropping the solenoid lets the
spring push the pin in, which engages only while a pocket stands within ``window`` degrees of the pin
(between two pockets it rests on the disk and neither sensor reads 1).  ``AxisMagazine.inPocket``
reads 1 while a pocket stands within the window.  ``AxisMagazine.driveReady`` is the ready contact of
the magazine's drive::

    LOCKED ──unlock on──▶ UNLOCKING ──lock_time──▶ UNLOCKED
    UNLOCKED ──unlock off, at a pocket──▶ LOCKING ──lock_time──▶ LOCKED
    UNLOCKED ──unlock off between two pockets──▶ the pin rests on the disk: neither sensor

Faults a scenario injects (``fault: {kind: axis_magazine_...}``, repaired with ``clear_faults:
AxisMagazine``): ``axis_magazine_lock_sensor`` (the locked sensor's wire is broken: it reads 0),
``axis_magazine_drive_fault`` (the drive reports not ready).

Time is counted in IPO cycles, so the model is deterministic; it does no I/O.
"""

from __future__ import annotations

from typing import Protocol

from interfaces.image import ProcessImage
from interfaces.plant_io import AXIS_MAGAZINE, PlantIoMap
from vc.config.model import AxisMagazinePlant
from vc.plant.indexing import Cylinder, Output, Sensors, cycles_of

FAULTS = ("axis_magazine_lock_sensor", "axis_magazine_drive_fault")


class Slide(Protocol):
    @property
    def physical(self) -> float: ...


class AxisMagazine:
    name = AXIS_MAGAZINE

    def __init__(self, config: AxisMagazinePlant, io: PlantIoMap, ipo_cycle_us: int, slide: Slide):
        self.config = config
        self.axis = config.axis
        self._slide = slide
        self._pitch = 360.0 / config.pockets
        self.pin = Cylinder(cycles_of(config.lock_time_s, ipo_cycle_us), 0)  # engaged at power-on
        self._unlock = Output(io, f"{AXIS_MAGAZINE}.unlock")
        self._sensors = Sensors(io, tuple(f"{AXIS_MAGAZINE}.{name}"
                                          for name in ("locked", "unlocked", "inPocket", "driveReady")))
        self.lock_sensor_broken = False
        self.drive_fault = False

    @property
    def pocket(self) -> int:
        """The pocket (1 ..) within the window of the pin, 0 between two."""
        angle = self._slide.physical % 360.0
        nearest = round(angle / self._pitch)
        if abs(angle - nearest * self._pitch) > self.config.window:
            return 0
        return nearest % self.config.pockets + 1

    def step(self, io: ProcessImage) -> bool:
        """One IPO cycle: move the pin, write the sensors; True while the pin moves."""
        stroke = self.pin.stroke
        # the spring pushes the pin into a pocket's notch, onto the disk's face between two
        self.pin.step(self._unlock.on(io.areas["Q"]), lowest=0 if self.pocket else 1)
        self.write_sensors(io)
        return self.pin.stroke != stroke

    def write_sensors(self, io: ProcessImage) -> None:
        pin = self.pin
        self._sensors.write(io, (int(pin.back and not self.lock_sensor_broken), int(pin.out), int(self.pocket != 0),
                                 int(not self.drive_fault)))

    def forget_sensors(self) -> None:
        self._sensors.forget()

    def inject(self, kind: str) -> None:
        if kind == "axis_magazine_lock_sensor":
            self.lock_sensor_broken = True
        elif kind == "axis_magazine_drive_fault":
            self.drive_fault = True
        else:
            raise KeyError(f"the axis magazine knows the faults {', '.join(FAULTS)}, not {kind!r}")

    def repair(self) -> None:
        self.lock_sensor_broken = False
        self.drive_fault = False
