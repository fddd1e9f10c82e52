"""A lathe's tailstock quill: an NC axis whose centre presses the part against the main spindle.

The part's face is the fixed stop the quill travels to (FXS, seed 003 chapter 17): past ``stop``
the quill compresses the part and the centre like a spring of ``stiffness`` N/mm, so that the drive,
pushing with its torque limit (percent of ``max_force``), holds the quill ``force / stiffness``
beyond the face.  Above ``force_limit`` N the part slips away and the stop is lost.  The sleeve
sensors: ``Tailstock.retracted`` at or behind ``retracted``, ``Tailstock.atPart`` while the centre
presses against the part (the fixed-stop sensor a PLC hands to DB31.DBX1.2)::

    AT_PART ──force above force_limit, or the fault stop_lost──▶ LOST: the quill goes through freely
    AT_PART ──the fault no_part──▶ LOST (no part clamped: nothing to stop the quill)
    LOST ──repair──▶ AT_PART (a part is in place again)

The axis asks :meth:`hold` where its slide may stand (``vc/core/axis/axis.py``, ``Obstacle``); the
sensors are written each IPO cycle when they change.  No I/O, no clock.
"""

from __future__ import annotations

from enum import Enum

from interfaces.image import ProcessImage
from interfaces.plant_io import TAILSTOCK, PlantIoMap
from vc.config.model import TailstockPlant

FAULTS = ("stop_lost", "no_part")


class PartState(Enum):
    AT_PART = "a part is clamped: its face stops the quill"
    LOST = "the part slipped away or is missing: nothing stops the quill"


class Tailstock:
    """The quill's fixed stop and its sleeve sensors (the machine file's ``plant: tailstock:``)."""

    name = TAILSTOCK

    def __init__(self, config: TailstockPlant, io: PlantIoMap):
        self.config = config
        self.axis = config.axis
        self.state = PartState.AT_PART
        # the quill moves towards the part in the direction from the retracted position to the stop
        self._direction = 1.0 if config.stop >= config.retracted else -1.0
        retracted, at_part = io.by_name(f"{TAILSTOCK}.retracted"), io.by_name(f"{TAILSTOCK}.atPart")
        self._retracted = retracted.ref() if retracted else None
        self._at_part = at_part.ref() if at_part else None
        self.position = config.retracted  # the quill's tip, as the axis last reported it
        self.force = 0.0  # N the quill presses with
        self._written: tuple[int, int] | None = None

    def hold(self, previous: float, position: float, force_percent: float) -> float:
        """Where the quill stands: beyond the face by what the drive's force compresses (the axis's
        ``Obstacle``)."""
        config = self.config
        direction = self._direction
        if self.state is PartState.LOST or (position - config.stop) * direction <= 0.0:
            self.force = 0.0
            self.position = position
            return position
        force = force_percent / 100.0 * config.max_force
        if force > config.force_limit:
            self.state = PartState.LOST  # pushed harder than the part takes: it slips away
            self.force = 0.0
            self.position = position
            return position
        self.force = force
        deepest = config.stop + direction * force / config.stiffness
        held = min(position, deepest) if direction > 0.0 else max(position, deepest)
        self.position = held
        return held

    @property
    def at_part(self) -> bool:
        return self.state is PartState.AT_PART and (self.position - self.config.stop) * self._direction >= 0.0

    def step(self, io: ProcessImage) -> bool:
        self.write_sensors(io)
        return False

    def write_sensors(self, io: ProcessImage) -> None:
        retracted = 1 if (self.position - self.config.retracted) * self._direction <= 0.0 else 0
        sensors = (retracted, 1 if self.at_part else 0)
        if sensors == self._written:
            return
        self._written = sensors
        if self._retracted is not None:
            io.write(self._retracted, sensors[0])
        if self._at_part is not None:
            io.write(self._at_part, sensors[1])

    def forget_sensors(self) -> None:
        self._written = None

    def inject(self, kind: str) -> None:
        if kind not in FAULTS:
            raise KeyError(f"the tailstock knows the faults {', '.join(FAULTS)}, not {kind!r}")
        self.state = PartState.LOST

    def repair(self) -> None:
        self.state = PartState.AT_PART
