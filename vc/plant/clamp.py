"""The clamp of an axis: a rotary table's (or a slide's) hydraulic clamp the PLC closes once the
axis stands on its position, so that the machining load does not rest on the drive.

A cylinder (``vc/plant/indexing.py``) driven by ``Clamp.close``: it closes in ``travel_time`` while the
solenoid is on and opens as long when it drops.  Its end-position sensors ``Clamp.closed`` and
``Clamp.opened`` read 1 at the ends.  Closed, it holds the axis's slide where it stands whatever the
drive does (the axis's ``Obstacle``, ``vc/core/axis/axis.py``); the NC learns of the clamp only
from the PLC (DB31.DBX2.3 "clamping in progress", whose clamping monitor MD36050 / alarm 26000
watches the position while it is set).

Faults a scenario injects (``fault: {kind: ...}``), repaired with ``clear_faults: Clamp``::

    clamp_not_closing   the clamp does not close (no pressure, a jammed piston): Clamp.closed never
                        comes and nothing holds the slide
    clamp_opening       the closed clamp gives way under the machining load: Clamp.closed drops and
                        the load (``load``, mm/min or deg/min) pushes the axis off its position

No I/O, no clock: the stroke counts IPO cycles.
"""

from __future__ import annotations

from interfaces.image import ProcessImage
from interfaces.plant_io import CLAMP, PlantIoMap
from vc.config.model import ClampPlant
from vc.plant.indexing import Cylinder, Output, Sensors, cycles_of

FAULTS = ("clamp_not_closing", "clamp_opening")


class AxisClamp:
    """The clamp of one axis (the machine file's ``plant: clamp:``)."""

    name = CLAMP

    def __init__(self, config: ClampPlant, io: PlantIoMap, ipo_cycle_us: int):
        self.axis = config.axis
        self.cylinder = Cylinder(cycles_of(config.travel_time_s, ipo_cycle_us), 0)  # open at power-on
        self._load_per_cycle = config.load / 60.0 * ipo_cycle_us / 1_000_000  # the load's push per IPO cycle
        self._close = Output(io, f"{CLAMP}.close")
        self._sensors = Sensors(io, (f"{CLAMP}.closed", f"{CLAMP}.opened"))
        self.given_way = False  # clamp_opening: it opened under the load, which pushes the axis

    @property
    def closed(self) -> bool:
        return self.cylinder.out and not self.given_way

    def hold(self, previous: float, position: float, force_percent: float) -> float:
        """Where the slide stands: held where it was while the clamp is closed; pushed on by the load
        once the clamp has given way under it."""
        if self.closed:
            return previous
        return position + self._load_per_cycle if self.given_way else position

    def step(self, io: ProcessImage) -> bool:
        solenoid = self._close.on(io.areas["Q"])
        cylinder = self.cylinder
        cylinder.step(solenoid)
        self.write_sensors(io)
        return not cylinder.jammed and (not cylinder.out if solenoid else not cylinder.back)

    def write_sensors(self, io: ProcessImage) -> None:
        cylinder = self.cylinder
        self._sensors.write(io, (1 if self.closed else 0, 1 if cylinder.back else 0))

    def forget_sensors(self) -> None:
        self._sensors.forget()

    def inject(self, kind: str) -> None:
        if kind not in FAULTS:
            raise KeyError(f"the clamp knows the faults {', '.join(FAULTS)}, not {kind!r}")
        if kind == "clamp_not_closing":
            self.cylinder.stroke = 0
            self.cylinder.jammed = True
        else:
            self.given_way = True  # neither end: the piston was pushed back off its closed end

    def repair(self) -> None:
        self.cylinder.jammed = False
        self.given_way = False
