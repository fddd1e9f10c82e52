"""Velocity profiles for one IPO cycle at a time, and the axial jerk filter.

All motion in the core is planned online, one cycle at a time, so that overrides, feed
stop, NC stop and limit switches act at once: the velocity ramps toward its command with
the acceleration limit and never exceeds the velocity from which the motion can still
stop at its end point.

Jerk limitation is the control's axial jerk filter (MD32400 AX_JERK_ENABLE, MD32402
AX_JERK_MODE, MD32410 AX_JERK_TIME): a filter on the position setpoint.  Both modes keep
the end position exactly (unit DC gain); the motion ends later by the filter time.
"""

from __future__ import annotations

import math
from collections import deque


def ramp(velocity: float, target: float, accel: float, dt: float) -> float:
    """Move ``velocity`` toward ``target`` by at most ``accel * dt``."""
    step = accel * dt
    if target > velocity + step:
        return velocity + step
    if target < velocity - step:
        return velocity - step
    return target


def stopping_velocity(remaining: float, accel: float, dt: float) -> float:
    """Largest speed for the next cycle from which the motion can still stop exactly at ``remaining``.

    Time is discrete: a speed v moves ``v*dt`` in its cycle, and braking lowers the speed by
    at most ``a*dt`` per cycle.  Going at v and then braking as hard as allowed covers
    ``T(v) = (n+1)*v*dt - a*dt**2*n*(n+1)/2`` with ``n = floor(v/(a*dt))``; T grows with v.
    The largest v with ``T(v) <= remaining``: the largest n with ``a*dt**2*n*(n+1)/2 <=
    remaining``, then v from T(v) = remaining, capped at ``(n+1)*a*dt``.  Any longer distance
    can be covered exactly by braking a little less, so a motion planned with this speed ends
    on its end point without overshoot and never brakes harder than ``a`` (for the last
    cycle v = remaining/dt <= a*dt).
    """
    if remaining <= 0.0:
        return 0.0
    step = accel * dt * dt
    n = math.floor((math.sqrt(1.0 + 8.0 * remaining / step) - 1.0) / 2.0)
    while n > 0 and step * n * (n + 1) / 2.0 > remaining:
        n -= 1  # guard against rounding in the square root
    velocity = (remaining + step * n * (n + 1) / 2.0) / ((n + 1) * dt)
    return min(velocity, (n + 1) * accel * dt)


def stopping_distance(speed: float, accel: float, dt: float) -> float:
    """The distance a motion at ``speed`` still covers when it brakes as hard as ``accel`` allows
    from the next cycle on: ``T(v)`` of ``stopping_velocity``, whose inverse it is."""
    if speed <= 0.0:
        return 0.0
    if accel <= 0.0:
        return math.inf
    n = math.floor(speed / (accel * dt))
    return (n + 1) * speed * dt - accel * dt * dt * n * (n + 1) / 2.0


def path_step(s: float, length: float, velocity: float, target: float, accel: float, dt: float) -> tuple[float, float]:
    """One IPO cycle along a path of ``length`` at ``s``: the velocity ramps toward ``target``
    and never exceeds the velocity from which the path can stop at its end.  Returns the new
    ``(s, velocity)``; ``s`` lands exactly on ``length`` in the cycle that arrives."""
    velocity = min(ramp(velocity, target, accel, dt), stopping_velocity(length - s, accel, dt))
    s += velocity * dt
    if length - s <= 1e-12 * max(1.0, length):
        s = length  # arrived: the last cycle covered exactly the rest (rounding aside)
    return s, velocity


def braking_distance(speed: float, accel: float) -> float:
    return speed * speed / (2.0 * accel) if accel > 0.0 else math.inf


class JerkFilter:
    """Axial jerk filter on the position setpoint (MD32402: 1 = 2nd order, 2 = moving average),
    followed by the dead time of dynamic-response matching (MD32900 / MD32910) where set."""

    __slots__ = ("_alpha", "_delay_cycles", "_delay_fraction", "_delayed", "_history", "_mode", "_repeats",
                 "_stage1", "_stage2", "_window")

    def __init__(self, mode: int, filter_time: float, dt: float, start: float, delay: float = 0.0):
        self._mode = mode
        self._window = max(1, round(filter_time / dt))
        self._history: deque[float] = deque([start] * self._window, maxlen=self._window)
        self._repeats = self._window  # how many of the latest inputs equal the newest one
        # Two first-order stages of time constant T/2 each: critically damped 2nd order.
        self._alpha = dt / (dt + 0.5 * filter_time) if filter_time > 0.0 else 1.0
        self._stage1 = start
        self._stage2 = start
        # Dynamic-response matching delays the filtered setpoint by ``delay`` [control]: whole
        # cycles from the history, a fraction of a cycle interpolated between two of them, so a
        # constant velocity v lags by exactly v x delay.
        self._delay_cycles = int(delay / dt + 1e-9)
        self._delay_fraction = delay / dt - self._delay_cycles if delay > 0.0 else 0.0
        self._delayed: deque[float] = deque()
        self._reset_delay(start)

    def apply(self, value: float) -> float:
        return self._delay(self._filter(value))

    def _filter(self, value: float) -> float:
        if self._mode == 2:
            self._repeats = self._repeats + 1 if value == self._history[-1] else 1
            self._history.append(value)
            if self._repeats >= self._window:
                return value  # settled: exactly the input, free of rounding in the sum
            return sum(self._history) / self._window
        self._stage1 += self._alpha * (value - self._stage1)
        self._stage2 += self._alpha * (self._stage1 - self._stage2)
        if abs(self._stage2 - value) < 1e-9 and abs(self._stage1 - value) < 1e-9:
            self._stage1 = self._stage2 = value  # settled: snap to the input
        return self._stage2

    def _delay(self, value: float) -> float:
        self._delayed.append(value)
        newer = self._delayed[-1 - self._delay_cycles]
        older = self._delayed[0]  # one cycle before ``newer`` where a fraction of a cycle is kept
        if newer == older:
            return newer
        return newer + (older - newer) * self._delay_fraction

    def _reset_delay(self, value: float) -> None:
        length = self._delay_cycles + (2 if self._delay_fraction else 1)
        self._delayed = deque([value] * length, maxlen=length)

    def settled(self, value: float, tolerance: float) -> bool:
        """True when the filter output has reached ``value`` (within ``tolerance``)."""
        delaying = self._delay_cycles or self._delay_fraction
        if delaying and any(abs(item - value) > tolerance for item in self._delayed):
            return False
        if self._mode == 2:
            return all(abs(item - value) <= tolerance for item in self._history)
        return abs(self._stage2 - value) <= tolerance and abs(self._stage1 - value) <= tolerance

    def reset(self, value: float) -> None:
        self._history = deque([value] * self._window, maxlen=self._window)
        self._repeats = self._window
        self._stage1 = value
        self._stage2 = value
        self._reset_delay(value)
