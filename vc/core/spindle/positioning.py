"""Spindle positioning (seed 003 §13.2.5): the motion of SPOS / SPOSA / M19, one IPO cycle at a time.

:class:`Positioning` is one running order (also the approach to the gear-change position);
:class:`PositioningDrive` computes its velocity command.  The spindle owns the positioning mode
(84.5) and switches into and out of it; the drive only moves::

    start ─unsynchronised─▶ search: turn at MD35300 (from standstill in the direction MD35350, or
      │                     ACP / ACN) until a zero mark; none within MD34060: alarm 20002
      │  ─turning faster than MD35300─▶ brake to MD35300 keeping the direction
      │  ─ACP / ACN (or IC) against the rotation─▶ brake to a stop, then the other way (L18000-18004)
      ▼ synchronised, at most MD35300, in the approach direction
    approach: position control (61.5), a planned profile with MD35210 onto the target beyond
      │       the braking distance
      ▼ on the target setpoint
    done (85.5 "in position" once in exact stop fine, SPOS / SPOSA / M19 only)
"""

from __future__ import annotations

from dataclasses import dataclass

from vc.config import md_dictionary as MD
from vc.core.axis.axis import MachineAxis
from vc.core.axis.motion import braking_distance, stopping_velocity
from vc.core.axis.owner import Owner

_ARRIVED = 1e-9


@dataclass(slots=True)
class Positioning:
    """A running SPOS / SPOSA / M19 (or the approach to the gear-change position)."""

    mode: str  # AC, IC, DC, ACP, ACN
    value: float  # degrees
    wait: bool  # SPOS and M19 hold the block until the target; SPOSA does not
    programmed: bool = True  # SPOS / SPOSA / M19; False: the approach to the gear-change position
    direction: int = 0  # the direction of the approach, once chosen
    searched: float = 0.0  # degrees turned looking for a zero mark
    target: float | None = None  # the setpoint where the spindle stops (NC coordinates)
    done: bool = False

    def reached(self, axis: MachineAxis) -> bool:
        """On the position: done and in exact stop fine."""
        return self.done and abs(axis.distance_to_end_point) <= axis.dyn.fine_window

    def holds_block_end(self, axis: MachineAxis) -> bool:
        """SPOS / M19 until the spindle stands on its target (60.6, §13.8.8)."""
        if not self.wait:
            return False
        if not self.done:
            return True
        return abs(axis.distance_to_end_point) > axis.dyn.coarse_window

    def in_position(self, axis: MachineAxis) -> bool:
        """85.5: after SPOS / SPOSA / M19 while synchronised, in exact stop fine, on the target;
        only for the function "spindle positioning", not at the gear-change position (L17059-17068)."""
        return (self.programmed and self.done and axis.encoder.referenced and axis.owner is Owner.NONE
                and abs(axis.distance_to_end_point) <= axis.dyn.fine_window)


class PositioningDrive:
    """The velocity command of a spindle's running positioning (see the module docstring)."""

    def __init__(self, axis: MachineAxis, dt: float):
        self._axis = axis
        self._md = axis.config.md
        self._dt = dt
        self.planned = False  # this cycle's command is a planned profile, not a ramp target
        # what the motion asks of the spindle's position control this cycle: off while it searches a
        # zero mark, on for the approach; None leaves it as it is
        self.position_control: bool | None = None
        self.zero_mark_missing = False  # no zero mark within MD34060: the spindle raises 20002

    def step(self, positioning: Positioning, limit: float, accel: float) -> float:
        """SPOS: brake to ``limit`` (MD35300 of the gear with the override, deg/s), synchronise, then
        land on the target in position control with ``accel`` (MD35210 of the gear, deg/s^2).
        Returns the velocity command; ``planned`` tells the drive not to ramp it again."""
        self.planned = False
        self.position_control = None
        axis = self._axis
        velocity = axis.command_velocity
        if positioning.direction == 0:
            positioning.direction = self._approach_direction(positioning, velocity)
        direction = positioning.direction
        if not axis.encoder.referenced:
            self.position_control = False
            positioning.searched += abs(velocity) * self._dt
            if positioning.mode != "IC" and positioning.searched > self._md.float(MD.REFP_MAX_MARKER_DIST):
                self.zero_mark_missing = True  # no zero mark within MD34060 (L16912-16915)
                return 0.0
            return direction * limit  # turn (at most MD35300) until the next zero mark
        if abs(velocity) > limit + 1e-9 and velocity * direction > 0:
            return direction * limit  # brake to the position-control speed first
        if velocity * direction < 0:
            # ACP / ACN (or IC) against the rotation: brake to a stop along the ramp of the mode,
            # then approach from the other side (L18000-18004)
            return 0.0
        self.position_control = True
        self.planned = True
        if positioning.target is None:
            positioning.target = self._target_setpoint(positioning, abs(velocity), accel)
        remaining = (positioning.target - axis.setpoint) * direction
        if remaining <= _ARRIVED:
            axis.setpoint = positioning.target
            positioning.done = True
            return 0.0
        speed = min(abs(velocity) + accel * self._dt, limit, stopping_velocity(remaining, accel, self._dt))
        return direction * speed

    def _approach_direction(self, positioning: Positioning, velocity: float) -> int:
        if positioning.mode == "ACP":
            return 1
        if positioning.mode == "ACN":
            return -1
        if positioning.mode == "IC":
            return 1 if positioning.value >= 0 else -1
        if abs(velocity) > self._axis.dyn.standstill_velocity:
            return 1 if velocity > 0 else -1  # keep the direction of rotation (L16745-16759)
        if not self._axis.encoder.referenced:
            return 1 if self._md.int(MD.SPIND_POSITIONING_DIR) == 3 else -1
        # synchronised at standstill, AC / DC: the shorter way
        error = (positioning.value - self._axis.shown(self._axis.setpoint)) % 360.0
        return 1 if error <= 180.0 else -1

    def _target_setpoint(self, positioning: Positioning, speed: float, accel: float) -> float:
        """Where the spindle stops: the programmed angle ahead in the approach direction, beyond
        the braking distance (or the incremental distance)."""
        axis = self._axis
        direction = positioning.direction
        if positioning.mode == "IC":
            return axis.setpoint + positioning.value
        ahead = ((positioning.value - axis.setpoint) * direction) % 360.0
        needed = braking_distance(speed, accel)
        while ahead + 1e-9 < needed:
            ahead += 360.0
        return axis.setpoint + direction * ahead
