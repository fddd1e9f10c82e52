"""Gear stages of a spindle (seed 003 §13.4): which gear, and the NC/PLC gear-change dialog.

Gear selection (:func:`select_gear`): M41..M45 name the gear; M40 chooses it from the
programmed speed with the switching thresholds MD35110 / MD35120 (§13.8.9, L18481-18510,
L21275-21357).

The dialog (:class:`GearChange`), one change at a time per spindle (spec B.4.5-B.4.8)::

    TO_POSITION ─ MD35010 bit 1 only: position to MD35012 with the current gear (84.5),
       │          exact stop fine, then wait MD35310; not reached: alarm 22020, no dialog
       ▼
    REQUESTED ── 82.0-82.2 = set gear, 82.3 = 1, oscillation mode (84.6); the spindle brakes
       │         (with MD35410 when 18.5 is already set, else with MD35200)
       ▼ stationary (61.4)
    AT_STANDSTILL ── oscillates while the PLC enables it: 18.5 by the NC (MD35400 alternately
       │             MD35440 in M3 and MD35450 in M4 direction), 18.4 + 18.6 / 18.7 by the PLC
       ▼ 16.3 gear changed (accepted from REQUESTED on)
    done: the reported gear 16.0-16.2 becomes active (its parameter set and limits), 82.3 = 0,
          alarm 22010 when it is not the set gear (MD11410 bit 3 = 0), control mode again

A change the PLC does not acknowledge within MD10192 raises alarm 65830; a reset or the
spindle reset DB31.DBX2.2 ends it without alarm and takes the gear the PLC reports.  With
MD35010 bit 3 the NC simulates the dialog: nothing is output, the set gear becomes active at
standstill.
"""

from __future__ import annotations

from dataclasses import dataclass
from enum import Enum

from vc.config import md_dictionary as MD
from vc.config.machine_data import MachineData

GEAR_CHANGE_WITH_OSCILLATION = 1 << 0  # MD35010 bit 0
GEAR_CHANGE_AT_POSITION = 1 << 1  # MD35010 bit 1
GEAR_CHANGE_SIMULATED = 1 << 3  # MD35010 bit 3
ALARM_GEAR_CHANGE_NOT_POSSIBLE = 22000
ALARM_WRONG_GEAR = 22010
ALARM_CATCH_UP_IMPOSSIBLE = 22011  # the programmed stage cannot be caught up (L20054-20055)
ALARM_POSITION_NOT_REACHED = 22020
ALARM_NOT_ACKNOWLEDGED = 65830  # project number: the seed names none (spec B.5) [control: an alarm follows]
SUPPRESS_WRONG_GEAR = 1 << 3  # MD11410 bit 3


def select_gear(md: MachineData, speed: float, current: int) -> int | None:
    """The gear M40 chooses for ``speed`` (rev/min), or None to keep the current one.

    The current gear stays while the speed lies in its switching window [MD35120, MD35110]
    (L18489-18491); otherwise the first gear whose window holds the speed, searched upwards
    (the seed's example L21662-21679).  Beyond every window: above all -> the highest gear,
    below gear 1's lower threshold -> gear 1; S0 changes nothing unless MD35120[1] = 0
    (L21335-21357).
    """
    gears = md.int(MD.NUM_GEAR_STEPS)
    low, high = MD.GEAR_STEP_MIN_VELO, MD.GEAR_STEP_MAX_VELO
    if speed == 0.0:
        return 1 if md.float(low, 1) == 0.0 and current != 1 else None
    if 1 <= current <= gears and md.float(low, current) <= speed <= md.float(high, current):
        return None
    for gear in range(1, gears + 1):
        if md.float(low, gear) <= speed <= md.float(high, gear):
            return gear
    if speed > max(md.float(high, gear) for gear in range(1, gears + 1)):
        return gears
    return 1


class GearState(Enum):
    TO_POSITION = "to the gear-change position"
    POSITION_DELAY = "waiting MD35310 at the gear-change position"
    REQUESTED = "change requested, braking"
    AT_STANDSTILL = "at standstill, waiting for the PLC"


@dataclass(slots=True)
class GearChange:
    """One running gear-stage change of a spindle (see the module docstring)."""

    target: int  # the set gear
    state: GearState
    started_cycle: int
    simulated: bool  # MD35010 bit 3: the NC does not talk to the PLC
    mode_before: Enum  # the spindle's mode at the request: after the change M5 if it was positioning
    delay_cycles: int = 0  # MD35310 still to wait at the change position
    oscillation_direction: int = 0  # +1 M3, -1 M4: the NC's oscillation
    oscillation_cycles: int = 0  # time in the present oscillation direction
    acknowledged_timeout: bool = False  # alarm 65830 raised

    @property
    def dialog_open(self) -> bool:
        """82.3 is set: the PLC may (and must) change the gear."""
        return not self.simulated and self.state in (GearState.REQUESTED, GearState.AT_STANDSTILL)


@dataclass(frozen=True, slots=True)
class Oscillation:
    """The NC's oscillation for meshing (MD35400 speed, MD35410 acceleration, MD35440 / MD35450
    times in the M3 / M4 direction, MD35430 start direction), in internal units."""

    speed: float  # deg/s
    accel: float  # deg/s^2
    cycles_cw: int
    cycles_ccw: int
    start_direction: int  # MD35430: 0..2 = against the last rotation, 3 = M3, 4 = M4

    @classmethod
    def of(cls, md: MachineData, dt: float) -> Oscillation:
        return cls(md.float(MD.SPIND_OSCILL_DES_VELO) * 6.0, md.float(MD.SPIND_OSCILL_ACCEL) * 360.0,
                   max(1, round(md.float(MD.SPIND_OSCILL_TIME_CW) / dt)),
                   max(1, round(md.float(MD.SPIND_OSCILL_TIME_CCW) / dt)), md.int(MD.SPIND_OSCILL_START_DIR))

    def first_direction(self, last_rotation: int) -> int:
        if self.start_direction == 3:
            return 1
        if self.start_direction == 4:
            return -1
        return -last_rotation if last_rotation else 1

    def step(self, change: GearChange, last_rotation: int) -> float:
        """The NC's oscillation velocity command for this cycle; alternates the direction."""
        if change.oscillation_direction == 0:
            change.oscillation_direction = self.first_direction(last_rotation)
            change.oscillation_cycles = 0
        change.oscillation_cycles += 1
        limit = self.cycles_cw if change.oscillation_direction > 0 else self.cycles_ccw
        if change.oscillation_cycles > limit:
            change.oscillation_direction = -change.oscillation_direction
            change.oscillation_cycles = 1
        return change.oscillation_direction * self.speed
