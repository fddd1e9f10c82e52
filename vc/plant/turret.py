"""A lathe's tool turret: a disk with tool stations, an indexing drive and a lock pin, wired to the PLC.

The PLC pulls the lock pin with its solenoid ``Turret.unlock`` (the pin's sensors: ``Turret.locked``
while it is engaged, ``Turret.unlocked`` once it is fully pulled), turns the disk with
``Turret.indexCw`` or ``Turret.indexCcw`` (clockwise = towards higher stations) and reads the
station from the binary code ``Turret.code1``, ``code2`` .. (0 between two stations).  Dropping the
solenoid lets the spring push the pin in; it engages only at a station, between two it rests on
the disk and neither sensor reads 1 ("lock not reached").  The code reads inside a window of a
fifth of the pitch either side of a station, wide enough for the PLC to stop the drive in it; the
pin's cone centres the disk on the station as it engages::

    LOCKED ──unlock on──▶ UNLOCKING ──lock_time──▶ UNLOCKED
    UNLOCKED ──indexCw / indexCcw alone──▶ the disk turns, index_time per station
    UNLOCKED ──unlock off──▶ LOCKING ──lock_time, at a station──▶ LOCKED
    LOCKING ──between two stations──▶ the pin rests on the disk: neither sensor
    any ──the drive on while the pin is not fully pulled──▶ the pin holds the disk: no motion

Faults a scenario injects (``fault: {kind: turret_...}``, repaired with ``clear_faults: Turret``):
``turret_sensor_missing`` (the unlocked sensor's wire is broken: it reads 0), ``turret_lock_jammed``
(the pin does not engage: ``Turret.locked`` never comes), ``turret_drive_stalled`` (the drive runs,
the disk does not turn: the station is never reached).

Time is counted in IPO cycles, so the model is deterministic; it does no I/O.
"""

from __future__ import annotations

from interfaces.image import ProcessImage
from interfaces.plant_io import TURRET, PlantIoMap
from vc.config.model import TurretPlant
from vc.plant.indexing import Cylinder, IndexingDisk, Output, Sensors, code_names, code_values, cycles_of

FAULTS = ("turret_sensor_missing", "turret_lock_jammed", "turret_drive_stalled")


class Turret:
    name = TURRET

    def __init__(self, config: TurretPlant, io: PlantIoMap, ipo_cycle_us: int, station: int | None = None):
        """``station``: where the disk stands at power-on, where it differs from the machine file's
        (a turret keeps its station while the machine is switched off)."""
        self.disk = IndexingDisk.at_station(config.stations, cycles_of(config.index_time_s, ipo_cycle_us),
                                            station or config.station_at_power_on)
        self.pin = Cylinder(cycles_of(config.lock_time_s, ipo_cycle_us), 0)  # engaged at power-on
        self._unlock = Output(io, f"{TURRET}.unlock")
        self._cw = Output(io, f"{TURRET}.indexCw")
        self._ccw = Output(io, f"{TURRET}.indexCcw")
        self._sensors = Sensors(io, (f"{TURRET}.locked", f"{TURRET}.unlocked", *code_names(TURRET, config.stations)))
        self.sensor_missing = False
        self.lock_jammed = False
        self._commands: tuple[bool, bool, bool] | None = None  # unlock, cw, ccw as last seen
        self._settled = False  # nothing moves until a command changes

    @property
    def station(self) -> int:
        return self.disk.station

    def step(self, io: ProcessImage) -> bool:
        """One IPO cycle: read the outputs, move pin and disk, write the sensors; True while the pin
        or the disk moves."""
        outputs = io.areas["Q"]
        commands = (self._unlock.on(outputs), self._cw.on(outputs), self._ccw.on(outputs))
        if self._settled and commands == self._commands:
            return False
        self._commands = commands
        unlock, cw, ccw = commands
        pin, disk = self.pin, self.disk
        stroke, position = pin.stroke, disk.position
        at_station = disk.station != 0
        # the spring pushes the pin into the disk's notch at a station, onto its face between two
        pin.step(unlock, lowest=0 if at_station and not self.lock_jammed else 1)
        if pin.out and cw != ccw:
            disk.turn(1 if cw else -1)
        elif not pin.out:
            disk.centre()  # the pin's cone pulls the disk onto the station as it enters the notch
        self._settled = pin.stroke == stroke and disk.position == position
        self.write_sensors(io)
        return not self._settled

    def write_sensors(self, io: ProcessImage) -> None:
        pin, disk = self.pin, self.disk
        self._sensors.write(io, (int(pin.back), int(pin.out and not self.sensor_missing),
                                 *code_values(disk.station, disk.stations)))

    def forget_sensors(self) -> None:
        self._sensors.forget()
        self._settled = False

    def inject(self, kind: str) -> None:
        if kind == "turret_sensor_missing":
            self.sensor_missing = True
        elif kind == "turret_lock_jammed":
            self.lock_jammed = True
        elif kind == "turret_drive_stalled":
            self.disk.stalled = True
        self._settled = False

    def repair(self) -> None:
        self.sensor_missing = self.lock_jammed = self.disk.stalled = False
        self._settled = False
