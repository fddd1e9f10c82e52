"""The holding brake of an axis's motor: a spring-applied brake the drive releases on the PLC's order
(DB31.DBX20.5), with the released contact the drive reports in DB31.DBX92.5.

A vertical axis's weight pulls its slide down whenever nothing holds it: the brake holds it while
engaged, the drive while it gives torque (the NC's position control, the servo on).  With the brake
open and no torque - the enables taken away before the brake engaged, the brake opened before they
came, a brake that does not engage - the slide sags at ``sag`` (mm/min, signed; the weight against
the motor's and the slide's friction [INF: a constant speed, the seed gives no plant]) and the NC's
standstill monitoring reacts (25040, vc/core/axis/axis.py)::

    ENGAGED ──DBX20.5 = 1──▶ RELEASING ──switch_time──▶ RELEASED: the contact reads 1 (DBX92.5)
    RELEASED ──DBX20.5 = 0──▶ ENGAGING ──switch_time──▶ ENGAGED: the contact reads 0
    (the brake holds the slide while ENGAGED and RELEASING; it lets it go from RELEASED until the
    linings hold again at the end of ENGAGING: the contact reads 1 for as long)

Faults a scenario injects (``fault: {kind: ...}``), repaired with ``clear_faults: Brake``::

    brake_not_opening   the brake does not release (a broken coil, no 24 V): DBX92.5 never comes and
                        the brake holds the slide against the drive
    brake_not_closing   the brake does not engage once released (a stuck armature): DBX92.5 stays 1
                        and nothing holds a slide the drive does not hold

The axis asks :meth:`hold` where its slide may stand (``vc/core/axis/axis.py``, ``Obstacle``); the
brake follows the order each IPO cycle (a machine with a brake pays one comparison a cycle at rest).
No I/O, no clock: the switching counts IPO cycles.
"""

from __future__ import annotations

from typing import Protocol

from interfaces.image import ProcessImage
from interfaces.plant_io import HOLDING_BRAKE
from vc.config.model import HoldingBrakePlant
from vc.plant.indexing import Cylinder, cycles_of

FAULTS = ("brake_not_opening", "brake_not_closing")


class BrakeSignals(Protocol):
    """The drive's side of the brake (vc/core/axis/holding_brake.py): the PLC's order, the feedback."""

    @property
    def release_ordered(self) -> bool: ...
    def report(self, released: bool) -> None: ...


class BrakedAxis(Protocol):
    """The braked axis as the brake sees it: whether its drive gives torque; woken when it sags."""

    servo_on: bool
    resting: bool


class HoldingBrake:
    """The holding brake of one axis (the machine file's ``plant: holding_brake:``)."""

    name = HOLDING_BRAKE

    def __init__(self, config: HoldingBrakePlant, ipo_cycle_us: int):
        self.axis = config.axis
        # the armature: 0 engaged (the spring's end) .. switch cycles released (the coil's end)
        self.armature = Cylinder(cycles_of(config.switch_time_s, ipo_cycle_us), 0)
        self._sag_per_cycle = config.sag / 60.0 * ipo_cycle_us / 1_000_000
        self.released = False  # the contact (and whether the brake lets the slide go): engaged at power-on
        self._stuck_at = 0  # brake_not_closing: the armature goes back no further than released
        self._signals: BrakeSignals | None = None
        self._axis: BrakedAxis | None = None

    def fit(self, axis: BrakedAxis, signals: BrakeSignals) -> None:
        """The composed machine puts the brake on ``axis``'s motor, switched through ``signals``."""
        self._axis = axis
        self._signals = signals

    def hold(self, previous: float, position: float, force_percent: float) -> float:
        """Where the slide stands: held where it was while the brake is engaged; released, moved on
        by the weight while the drive gives no torque."""
        if not self.released:
            return previous
        return position + self._sag_per_cycle if force_percent == 0.0 else position

    def cycle(self) -> None:
        """One IPO cycle: the armature follows the drive's order, the contact is reported, a slide the
        brake no longer holds nor the drive is woken to sag."""
        signals, axis = self._signals, self._axis
        if signals is None or axis is None:
            return
        armature = self.armature
        armature.step(signals.release_ordered, self._stuck_at)
        if armature.out:
            self.released = True  # the armature is off the linings: the contact reads 1
        elif armature.back:
            self.released = False  # the linings hold again
        released = self.released
        signals.report(released)
        if released and not axis.servo_on and self._sag_per_cycle:
            axis.resting = False

    def step(self, io: ProcessImage) -> bool:
        return False  # no plant outputs: the brake follows the drive in :meth:`cycle`

    def write_sensors(self, io: ProcessImage) -> None:
        pass  # its contact is read by the drive (DB31.DBX92.5), no plant input

    def forget_sensors(self) -> None:
        pass

    def inject(self, kind: str) -> None:
        if kind not in FAULTS:
            raise KeyError(f"the holding brake knows the faults {', '.join(FAULTS)}, not {kind!r}")
        armature = self.armature
        if kind == "brake_not_opening":
            armature.stroke = 0  # no coil current: the spring engages it
            armature.jammed = True
            self.released = False
        else:
            self._stuck_at = armature.travel_cycles  # once released it stays released

    def repair(self) -> None:
        self.armature.jammed = False
        self._stuck_at = 0
