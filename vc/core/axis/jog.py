"""JOG of one machine axis: the traverse keys and the handwheel's distance (seed 003 §16.6 JOG).

Continuous JOG is level-triggered: while the PLC holds one traverse key (DB31.DBX4.6 / 4.7) the
axis runs at its JOG velocity MD32020 (MD32010 with the rapid overlay DB31.DBX4.5) times the axis
override, ramped with MD32300; both keys or none stop it.  The handwheel's pulses
(vc/core/axis/handwheel.py) give a distance the axis travels at the same velocity, braking to stop
on its end point; a traverse key drops what is left of it.  JOG goes only away from an actuated
hardware limit switch and, once the software limits are active, stops exactly on a software limit
switch MD36100 / MD36110 and raises alarm 10621 while the key is held against it.  A transform
may keep the axis inside a window of setpoints in their place (``JogLimits.window``).

``AxisJog`` holds what JOG keeps between cycles (the handwheel's rest, the window of the last
cycle) and moves the axis it is given, which it sees as a ``JoggedAxis``: the axis owns its
setpoint and its motion owner, JOG only steers them.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Protocol

from vc.core.alarms import AlarmList
from vc.core.axis.dynamics import AxisDynamics, fixed_feed
from vc.core.axis.jog_keys import CONTINUOUS_JOG, JogKeyState, JogSelection, TraverseKeys
from vc.core.axis.motion import ramp, stopping_velocity
from vc.core.axis.owner import Owner
from vc.core.axis.signals import AxisInputs

_TINY = 1e-9


@dataclass(frozen=True, slots=True)
class JogLimits:
    """What JOG may do with an axis beyond its own data: the traverse keys it follows, and a
    velocity and acceleration an axis moved along with it needs (manual retraction's spindle)."""

    plus: bool = True
    minus: bool = True
    velocity: float = math.inf  # per second
    accel: float = math.inf  # per second squared
    # The setpoints between which JOG keeps the axis in place of its software limit switches
    # MD36100 / MD36110, where a transform checks them in other coordinates (inclined axis, AOT).
    window: tuple[float, float] | None = None
    # JOG to a fixed point / to a position (vc/core/axis/jog_target.py): the axis stops exactly on it
    target: float | None = None

    def and_(self, other: JogLimits) -> JogLimits:
        """Both sets of limits at once."""
        if other is FREE_JOG:
            return self
        if self is FREE_JOG:
            return other
        window = self.window if other.window is None else other.window if self.window is None else \
            (max(self.window[0], other.window[0]), min(self.window[1], other.window[1]))
        return JogLimits(self.plus and other.plus, self.minus and other.minus,
                         min(self.velocity, other.velocity), min(self.accel, other.accel), window,
                         self.target if other.target is None else other.target)


FREE_JOG = JogLimits()


class JoggedAxis(Protocol):
    """The machine axis as JOG moves it (vc/core/axis/axis.py)."""

    name: str
    channel: str
    inputs: AxisInputs
    dyn: AxisDynamics
    owner: Owner
    setpoint: float
    command_velocity: float
    override: float
    at_software_limit: int  # -1 / +1 while resting on the minus / plus software limit switch

    @property
    def drive_ready(self) -> bool: ...

    @property
    def software_limits_active(self) -> bool: ...

    @property
    def software_limits(self) -> tuple[float, float]: ...

    def take(self, owner: Owner) -> None: ...

    def release(self) -> None: ...


class AxisJog:
    """JOG of one axis: the traverse keys (level-triggered) and the handwheel's travel."""

    def __init__(self, dt: float):
        self._dt = dt
        self.handwheel_rest = 0.0  # the handwheel's distance still to travel (vc/core/axis/handwheel.py)
        self.window: tuple[float, float] | None = None  # JogLimits.window of the last JOG cycle
        self.keys = TraverseKeys()  # what the traverse keys command: continuous or an increment

    def add_handwheel_travel(self, distance: float) -> None:
        """Handwheel pulses in JOG: ``distance`` more to travel (sign = direction)."""
        self.handwheel_rest += distance

    def cycle(self, axis: JoggedAxis, allowed: bool, channel_feed_disable: bool, limits: JogLimits,
              selection: JogSelection = CONTINUOUS_JOG) -> None:
        """JOG with the traverse keys (continuous or an increment, ``vc/core/axis/jog_keys.py``), or
        the handwheel's travel, one IPO cycle."""
        inp = axis.inputs
        self.window = limits.window
        bounded = self.bounded(axis)
        keys = self.keys
        plus, minus = allowed and inp.key_plus, allowed and inp.key_minus
        direction = keys.command(axis.owner, plus, minus, selection,
                                 not allowed or inp.reset_movement or not axis.drive_ready,
                                 self._may_go(axis, 1, limits, bounded), self._may_go(axis, -1, limits, bounded))
        state = keys.state
        increment = keys.way if state is JogKeyState.INCREMENT else 0
        incrementing = increment or state is JogKeyState.INCREMENT_HELD
        handwheel = self._handwheel_direction(inp, allowed, direction or increment, limits)
        if (direction or handwheel or increment) and axis.owner is Owner.NONE and axis.drive_ready:
            axis.take(Owner.JOG)
        if axis.owner is not Owner.JOG:
            self.handwheel_rest = 0.0
            return
        dyn = axis.dyn
        # DB31.DBX3.2-3.5: a fixed feedrate MD12202 / MD12204 in place of the JOG velocity (seed 003 L9692-9701)
        speed = fixed_feed(dyn.fixed_feeds, inp.fixed_feed) if inp.fixed_feed else 0.0
        if speed <= 0.0:
            speed = dyn.jog_rapid_velocity if inp.rapid_key else dyn.jog_velocity
        stopped = inp.feed_stop or channel_feed_disable or not axis.drive_ready
        target = 0.0 if stopped else direction * min(speed * axis.override, limits.velocity)
        accel = min(dyn.max_accel, limits.accel)
        if increment and not stopped:
            # the increment at JOG velocity, braking to stop on its end point
            target = increment * min(speed * axis.override, limits.velocity,
                                     stopping_velocity(abs(keys.rest), accel, self._dt))
        elif handwheel and not stopped:
            # the handwheel's distance at JOG velocity, braking to stop on its end point
            target = handwheel * min(speed * axis.override, limits.velocity,
                                     stopping_velocity(abs(self.handwheel_rest), accel, self._dt))
        velocity = ramp(axis.command_velocity, target, accel, self._dt)
        if bounded:
            velocity = self._limit_to_software_limits(axis, velocity, accel)
        on_target = False
        jog_target = limits.target
        if jog_target is not None:
            velocity, on_target = self._limit_to_target(axis, velocity, accel, jog_target)
        axis.command_velocity = velocity
        axis.setpoint += velocity * self._dt
        if on_target and jog_target is not None:
            axis.setpoint = jog_target
        if incrementing:
            held = (1 if plus else -1) if plus != minus else 0
            self._travel_increment(axis, velocity * self._dt, held == keys.direction)
        if handwheel:
            self._travel_handwheel(axis, velocity * self._dt, handwheel)
        if on_target:  # the motion that reaches the target ends there: an increment, the handwheel's distance too
            self.handwheel_rest = 0.0
            if keys.state is not JogKeyState.IDLE and keys.state is not JogKeyState.AT_END:
                keys.end_motion(plus or minus)
        if bounded:
            self._arrive_at_software_limits(axis)
        if handwheel and velocity == 0.0 and axis.at_software_limit == handwheel:
            self.handwheel_rest = 0.0  # the rest lies beyond the software limit switch
        if incrementing and velocity == 0.0 and axis.at_software_limit == keys.way:
            keys.increment_travelled(plus or minus)  # the rest lies beyond the software limit switch
        if velocity == 0.0 and not self.handwheel_rest and keys.state is not JogKeyState.INCREMENT_HELD and \
                not keys.travelling_increment and (direction == 0 or axis.at_software_limit == direction):
            axis.release()  # stopped: key released, the increment done, or resting on the software limit

    def _limit_to_target(self, axis: JoggedAxis, velocity: float, accel: float,
                         target: float) -> tuple[float, bool]:
        """Brake so as to stop exactly on the target of JOG to a fixed point / a position when the
        axis travels towards it; True when it arrives this cycle (the setpoint is snapped to it)."""
        distance = target - axis.setpoint
        if velocity > 0.0 and distance > 0.0:
            velocity = min(velocity, stopping_velocity(max(distance, 0.0), accel, self._dt))
            return velocity, distance - velocity * self._dt <= _TINY
        if velocity < 0.0 and distance < 0.0:
            velocity = max(velocity, -stopping_velocity(max(-distance, 0.0), accel, self._dt))
            return velocity, velocity * self._dt - distance <= _TINY
        return velocity, False

    def _may_go(self, axis: JoggedAxis, direction: int, limits: JogLimits, bounded: bool) -> bool:
        """JOG may start ``direction``: not a way it is kept from, only away from an actuated hardware
        limit switch and, resting on a software limit switch, only away from it."""
        inp = axis.inputs
        if direction > 0:
            return limits.plus and not inp.hw_limit_plus and not (
                bounded and axis.owner is Owner.NONE and axis.setpoint >= self.soft_limits(axis)[1])
        return limits.minus and not inp.hw_limit_minus and not (
            bounded and axis.owner is Owner.NONE and axis.setpoint <= self.soft_limits(axis)[0])

    def _travel_increment(self, axis: JoggedAxis, travelled: float, key_held: bool) -> None:
        """Count the travel off the increment's rest; land exactly on its end point."""
        keys = self.keys
        rest = keys.rest - travelled
        if rest * keys.way <= _TINY:
            axis.setpoint += rest
            keys.increment_travelled(key_held)
        else:
            keys.rest = rest

    def _handwheel_direction(self, inp: AxisInputs, allowed: bool, key_direction: int, limits: JogLimits) -> int:
        """The direction of the handwheel's travel this cycle (0: none); the traverse keys, a
        direction JOG may not go and an actuated limit switch drop what is left of it."""
        rest = self.handwheel_rest
        if not rest:
            return 0
        way = 1 if rest > 0 else -1
        if not allowed or key_direction or not (limits.plus if way > 0 else limits.minus) or \
                (inp.hw_limit_plus if way > 0 else inp.hw_limit_minus):
            self.handwheel_rest = 0.0
            return 0
        return way

    def _travel_handwheel(self, axis: JoggedAxis, travelled: float, way: int) -> None:
        """Count the travel off the handwheel's distance; land exactly on its end point."""
        rest = self.handwheel_rest - travelled
        if rest * way <= _TINY:
            axis.setpoint += rest
            rest = 0.0
        self.handwheel_rest = rest

    def bounded(self, axis: JoggedAxis) -> bool:
        """JOG stops on ``soft_limits``: the axis's own once they are active, and a transform's window
        (the limits of an axis it carries) even while this axis is not referenced."""
        return axis.software_limits_active or self.window is not None

    def soft_limits(self, axis: JoggedAxis) -> tuple[float, float]:
        """The software limits JOG keeps: MD36100 / MD36110, or the window a transform gave."""
        return self.window if self.window is not None else axis.software_limits

    def _limit_to_software_limits(self, axis: JoggedAxis, velocity: float, accel: float) -> float:
        """Brake so as to stop exactly on a software limit switch (JOG), never harder than ``accel``."""
        dt = self._dt
        minus, plus = self.soft_limits(axis)
        if velocity > 0.0:
            return min(velocity, stopping_velocity(plus - axis.setpoint, accel, dt))
        if velocity < 0.0:
            return max(velocity, -stopping_velocity(axis.setpoint - minus, accel, dt))
        return velocity

    def _arrive_at_software_limits(self, axis: JoggedAxis) -> None:
        """Snap the rounding rest when the setpoint reached a software limit switch."""
        minus, plus = self.soft_limits(axis)
        if axis.command_velocity > 0.0 and plus - axis.setpoint <= _TINY:
            axis.setpoint = plus
            axis.at_software_limit = 1
        elif axis.command_velocity < 0.0 and axis.setpoint - minus <= _TINY:
            axis.setpoint = minus
            axis.at_software_limit = -1

    def monitor_software_limit(self, axis: JoggedAxis, cycle: int, alarms: AlarmList) -> None:
        """Alarm 10621 while the axis rests on the software limit switch it reached; it clears
        once the axis has moved away from it."""
        minus, plus = self.soft_limits(axis)
        resting_on_limit = (axis.at_software_limit > 0 and axis.setpoint >= plus - _TINY) or \
                           (axis.at_software_limit < 0 and axis.setpoint <= minus + _TINY)
        if resting_on_limit:
            alarms.raise_alarm(10621, cycle, axis.channel, axis.name,
                               "+" if axis.at_software_limit > 0 else "-", channel=axis.channel, axis=axis.name)
        else:
            axis.at_software_limit = 0
            alarms.clear(10621, axis=axis.name)
