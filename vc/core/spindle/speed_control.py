"""The speed of a spindle (seed 003 §13.8): limits, ramp, setpoint and speed monitoring, in every mode.

The spindle's mode chooses a velocity command (:mod:`vc.core.spindle.spindle`); :class:`SpeedControl`
turns it into motion and watches the result:

* set speed in speed control (84.7) = S x override, clamped to the gear's MD35130 and MD35100
  (83.1) and raised to its MD35140 (83.2); a position-controlled spindle keeps 10 % control
  reserve below those limits, the encoder's limit frequency MD36300 and MD35135;
* the ramp: MD35200 (speed control) or MD35210 (position control) of the gear, with the kinked
  characteristic MD35220 / MD35230 / MD35242, MD35410 into the gear change's oscillation, capped
  for a leading spindle by its coupled following spindle, set by polygon turning;
* the setpoint integrates the ramped velocity; the spindle owns its axis while it moves;
* 83.5 when the actual speed is within MD35150 x the set speed (always with MD35150 = 0); 83.0
  and alarm 22100 above MD35100 x (1 + MD35150); 61.4 with no setpoint and the actual speed below
  MD36060 (the axis reports it).
"""

from __future__ import annotations

from vc.config import md_dictionary as MD
from vc.core.alarms import AlarmList
from vc.core.axis.axis import MachineAxis
from vc.core.axis.motion import ramp
from vc.core.axis.owner import Owner
from vc.core.overrides import OverrideCoding
from vc.core.spindle.gear_change import GearChange
from vc.core.spindle.signals import SpindleInputs

RPM = 6.0  # rev/min -> deg/s
REV_S2 = 360.0  # rev/s^2 -> deg/s^2
ALARM_CHUCK_SPEED = 22100
POSITION_CONTROL_RESERVE = 0.9  # the speed a position-controlled spindle may use (L16747-16750)


class SpeedControl:
    """The speed side of one spindle (see the module docstring)."""

    def __init__(self, axis: MachineAxis, gear_change: GearChange, inputs: SpindleInputs,
                 override_coding: OverrideCoding, feed_coding: OverrideCoding, channel: str, dt: float):
        self._axis = axis
        self._md = axis.config.md
        self._gears = gear_change
        self._inputs = inputs
        self._override_coding = override_coding
        self._feed_coding = feed_coding
        self._channel = channel
        self._dt = dt
        self.set_speed = 0.0  # after override and limits, rev/min (monitoring)
        self.limited = False
        self.raised = False
        self.at_chuck_limit = False
        self.last_rotation = 0  # direction of the last rotation, for the oscillation start
        self.speed_cap: float | None = None  # leading spindle: the coupled FS's limit over the ratio
        self.acceleration_cap: float | None = None  # leading spindle: the coupled FS's acceleration over the ratio
        self.acceleration_override: float | None = None  # deg/s^2 while polygon turning sets the ramp

    def override(self) -> float:
        """The spindle override DBB19, or the axis's feed override DBB0 with DBX17.0."""
        axis = self._axis
        if self._inputs.use_feed_override:
            return self._feed_coding.factor(axis.inputs.override_raw, axis.inputs.override_active)
        return self._override_coding.factor(self._inputs.override_raw, axis.inputs.override_active)

    def max_speed(self, position_control: bool) -> float:
        """Largest set speed of the active gear (rev/min): MD35130, the chuck MD35100, MD32000.

        Under position control 10 % is kept as control reserve: 90 % of that and of the active
        encoder's limit frequency, and MD35135 of the gear when set (L16747-16750, L16834-16838,
        L18226-18228)."""
        gears, md = self._gears, self._md
        limit = min(gears.gear_float(MD.GEAR_STEP_MAX_VELO_LIMIT), md.float(MD.SPIND_VELO_LIMIT),
                    md.float(MD.MAX_AX_VELO))
        if self.speed_cap is not None:
            limit = min(limit, self.speed_cap)
        if not position_control:
            return limit
        if self._axis.active_encoder is not None:
            limit = min(limit, self._axis.encoder.limit_velocity / RPM)
        limit *= POSITION_CONTROL_RESERVE
        position_control_limit = gears.gear_float(MD.GEAR_STEP_PC_MAX_VELO_LIMIT)
        return min(limit, position_control_limit) if position_control_limit > 0.0 else limit

    def min_speed(self) -> float:
        """MD35140 of the active gear, rev/min: the least set speed while it turns."""
        return self._gears.gear_float(MD.GEAR_STEP_MIN_VELO_LIMIT)

    def positioning_speed(self) -> float:
        """MD35300 of the active gear, rev/min: positioning, and a coupled FS's SPOS without FA."""
        return self._gears.gear_float(MD.SPIND_POSCTRL_VELO)

    def position_control_acceleration(self) -> float:
        """MD35210 of the active gear, deg/s^2: positioning, and a coupled FS's own motion."""
        return self._gears.gear_float(MD.GEAR_STEP_POSCTRL_ACCEL) * REV_S2

    def setpoint(self, direction: int, wanted: float, held: bool, position_control: bool) -> float:
        """Speed control: ``wanted`` (S x override, rev/min) within the gear's limits in ``direction``
        (after the M3/M4 inversion); ``held``: feed stop or a coupled FS's spindle stop.  Returns the
        velocity command, deg/s."""
        maximum = self.max_speed(position_control)
        minimum = self.min_speed()
        stopped = direction == 0 or wanted == 0.0 or held
        self.limited = direction != 0 and wanted > maximum
        self.raised = not stopped and 0.0 < wanted < minimum
        set_speed = 0.0 if stopped else min(max(wanted, minimum), maximum)
        self.set_speed = set_speed
        return direction * set_speed * RPM

    def drive(self, command: float, planned: bool, position_control: bool, positioned: bool) -> None:
        """Ramp toward ``command`` (deg/s; ``planned``: a positioning's own profile, taken as it is)
        and move the setpoint; own the axis while it moves.  ``positioned``: the positioning is done."""
        axis = self._axis
        if planned:
            velocity = command  # positioning planned its own profile
        else:
            velocity = ramp(axis.command_velocity, command, self._acceleration(position_control), self._dt)
        if velocity == 0.0 and axis.command_velocity == 0.0:
            if axis.owner is Owner.SPINDLE:
                axis.release()
            return
        if axis.owner is Owner.NONE:
            axis.take(Owner.SPINDLE)
        axis.command_velocity = velocity
        axis.setpoint += velocity * self._dt
        if velocity:
            self.last_rotation = 1 if velocity > 0 else -1
        if velocity == 0.0 and positioned:
            axis.release()

    def _acceleration(self, position_control: bool) -> float:
        if self.acceleration_override is not None:
            return self.acceleration_override
        gears = self._gears
        if gears.brakes_into_oscillation:
            return gears.oscillation.accel  # braking into / during oscillation (L18372-18374)
        if position_control:
            accel = self.position_control_acceleration()
        else:
            accel = gears.gear_float(MD.GEAR_STEP_SPEEDCTRL_ACCEL) * REV_S2
        accel *= self.acceleration_reduction(self._axis.command_velocity)
        return accel if self.acceleration_cap is None else min(accel, self.acceleration_cap)

    def acceleration_reduction(self, velocity: float) -> float:
        """The share of the acceleration left at ``velocity`` (deg/s) by the kinked characteristic
        MD35220 / MD35230 / MD35242 (seed 003 L23797-23810), for speeding up and braking alike.
        Above the speed point, a share of the gear stage's MD35130 [control], the acceleration falls
        to 1 - MD35230 at MD35130 and stays there: at once (0, constant), along a hyperbola through
        both ends (1, the seed's default) [INF] or along a straight line (2)."""
        md = self._md
        factor = md.float(MD.ACCEL_REDUCTION_FACTOR)
        top = self._gears.gear_float(MD.GEAR_STEP_MAX_VELO_LIMIT)
        point = md.float(MD.ACCEL_REDUCTION_SPEED_POINT) * top
        speed = abs(velocity) / RPM
        if factor <= 0.0 or speed <= point:
            return 1.0
        kind = md.int(MD.ACCEL_REDUCTION_TYPE)
        share = min((speed - point) / (top - point), 1.0)  # of the way from the point to MD35130
        if kind == 0:
            return 1.0 - factor
        if kind == 2:
            return 1.0 - factor * share
        return 1.0 / (1.0 + factor / (1.0 - factor) * share)

    def stationary(self) -> bool:
        axis = self._axis
        return axis.command_velocity == 0.0 and abs(axis.velocity) <= axis.dyn.standstill_velocity

    # ------------------------------------------------------------------ monitoring
    def monitor(self, cycle: int, alarms: AlarmList) -> None:
        """83.0 and alarm 22100 above the chuck speed (L20932-21020)."""
        md = self._md
        actual = abs(self._axis.velocity) / RPM
        limit = md.float(MD.SPIND_VELO_LIMIT) * (1.0 + md.float(MD.SPIND_DES_VELO_TOL))
        self.at_chuck_limit = actual > limit
        if self.at_chuck_limit:
            number = self._axis.config.spindle_number
            alarms.raise_alarm(ALARM_CHUCK_SPEED, cycle, self._channel, "", number,
                               channel=self._channel, axis=self._axis.name)

    def reached(self, speed_control: bool, direction: int) -> bool:
        """83.5: actual speed within MD35150 x set speed; always with MD35150 = 0 (L20840-20858).
        ``speed_control``: the spindle is in speed control mode; ``direction`` after the M3/M4
        inversion."""
        tolerance = self._md.float(MD.SPIND_DES_VELO_TOL)
        if tolerance == 0.0:
            return True
        if not speed_control:
            return False
        actual = self._axis.velocity / RPM
        wanted = direction * self.set_speed
        if wanted == 0.0:
            return self.stationary()
        return abs(actual - wanted) <= tolerance * abs(wanted)
