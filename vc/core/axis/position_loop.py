"""The position control loop of one machine axis: Kv, speed feedforward with its symmetrising
model, and the drive as a first-order lag (MD32200, MD32620 / MD32610, MD32810).

Each IPO cycle the interpolated setpoint (plus any overlay) passes the axial jerk filter and the
delay of dynamic-response matching (``JerkFilter``) and becomes the loop's ``setpoint``.  The
loop commands the drive Kv x (setpoint - actual value) plus the speed feedforward; with
feedforward it compares the actual value not with the setpoint but with a model of it lagged as
the drive lags (MD32810), so the loop corrects real deviations and not the drive's own delay.
While a synchronous spindle coupling is active its ``CoupledLoop`` replaces Kv, the feedforward
weight and the symmetrising time (vc/core/spindle/coupling.py).  On the speed controller alone
(``speed_control``) the drive gets the setpoint's speed and nothing pulls it to the position.

The axis owns the slide and its actual value; ``close`` returns when the loop has settled below
the measuring resolution, and the axis then puts the slide on the setpoint.
"""

from __future__ import annotations

from vc.core.axis.dynamics import AxisDynamics, CoupledLoop
from vc.core.axis.motion import JerkFilter

_RESOLUTION = 1e-6  # mm or degrees: far below the control's internal precision of 1 um


class PositionLoop:
    """Kv loop with speed feedforward; the drive is a first-order lag (MD32810)."""

    def __init__(self, dt: float, start: float, jerk_filter: JerkFilter | None):
        self._dt = dt
        self.setpoint = start  # the setpoint after the jerk filter: what the loop compares
        self.model_position = start  # the setpoint as the drive can follow it (symmetrising)
        self.model_velocity = 0.0
        self.drive_velocity = 0.0
        self.speed_setpoint = 0.0  # what the loop commanded the drive in its last cycle (the drive's n set)
        self.jerk_filter = jerk_filter
        self.coupled: CoupledLoop | None = None  # set each cycle while the spindle is coupled
        # on the speed controller alone (the FS of a VV coupling without position control, L21965-21968):
        # the drive gets the setpoint's speed and nothing pulls the slide back to the setpoint position
        self.speed_control = False

    def parameters(self, dyn: AxisDynamics) -> tuple[float, float, float]:
        """Kv, feedforward weight and symmetrising time: the coupling's while coupled, else the axis's."""
        loop = self.coupled
        if loop is not None:
            return loop.kv, loop.feedforward, loop.symmetrising_time
        return dyn.kv, dyn.feedforward, dyn.drive_time_constant

    def set_coupled(self, dyn: AxisDynamics, loop: CoupledLoop | None) -> None:
        before = self.parameters(dyn)[2]
        self.coupled = loop
        after = self.parameters(dyn)[2]
        if after != before:
            # the symmetrising model lags a moving setpoint by its time constant: it takes the new lag
            # at once (integrating the velocity alone it would keep the old one for good)
            self.model_position -= self.model_velocity * (after - before)

    def lag_per_velocity(self, dyn: AxisDynamics) -> float:
        """Following error per unit of a constant velocity (s), by the loop of ``close``: with
        feedforward the symmetrising model, and the slide on it, lags the setpoint by the drive's
        MD32810 less the cycle it is compared in; without it the Kv loop needs velocity / Kv.
        Dynamic-response matching (MD32910) delays the setpoint before the loop and adds its time."""
        kv, feedforward, symmetrising_time = self.parameters(dyn)
        if feedforward:
            return max(symmetrising_time - self._dt, 0.0) + dyn.dyn_match_time
        return (1.0 / kv if kv else 0.0) + dyn.dyn_match_time

    def hold_at(self, position: float) -> None:
        """Every stage of the setpoint stands at ``position`` (follow-up, enable returns, power-on)."""
        self.setpoint = self.model_position = position
        self.model_velocity = 0.0
        if self.jerk_filter:
            self.jerk_filter.reset(position)

    def shift(self, delta: float) -> None:
        """The NC coordinates move by ``delta``: the setpoint stages with them."""
        self.setpoint += delta
        self.model_position += delta
        if self.jerk_filter:
            self.jerk_filter.reset(self.setpoint)

    def close(self, dyn: AxisDynamics, target: float, actual: float, command_velocity: float) -> bool:
        """One IPO cycle of the loop towards the interpolated ``target``; True when it has settled
        below the measuring resolution (the slide is to stand on ``setpoint``).

        With feedforward the setpoint is compared with the actual value only after the
        same lag as the drive's (the control's symmetrising with MD32810), so the loop
        corrects real deviations and not the drive's own delay: no overshoot at the end.
        """
        dt = self._dt
        previous = self.setpoint
        loop_setpoint = self.jerk_filter.apply(target) if self.jerk_filter else target
        self.setpoint = loop_setpoint
        kv, weight, symmetrising_time = self.parameters(dyn)
        feedforward = (loop_setpoint - previous) / dt * weight
        tau = dyn.drive_time_constant
        lag = dt / tau if tau > dt else 1.0
        model_lag = dt / symmetrising_time if symmetrising_time > dt else 1.0
        symmetrising = bool(feedforward or self.model_velocity)
        # The model and the slide are compared at the same instant, then both move on.
        compare = self.model_position if symmetrising else loop_setpoint
        if self.speed_control:
            velocity_command = (loop_setpoint - previous) / dt
        else:
            velocity_command = kv * (compare - actual) + feedforward
        limit = 1.2 * dyn.max_velocity
        velocity_command = max(-limit, min(limit, velocity_command))
        self.speed_setpoint = velocity_command
        self.drive_velocity += (velocity_command - self.drive_velocity) * lag
        if symmetrising:
            self.model_velocity += (feedforward - self.model_velocity) * model_lag
            self.model_position += self.model_velocity * dt
        else:
            self.model_position = loop_setpoint
        if (not self.speed_control and command_velocity == 0.0 and abs(loop_setpoint - actual) < _RESOLUTION
                and abs(self.drive_velocity) < _RESOLUTION / dt and abs(self.model_velocity) < _RESOLUTION / dt):
            self.drive_velocity = self.model_velocity = 0.0
            self.model_position = loop_setpoint
            return True
        return False
