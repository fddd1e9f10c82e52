"""Interpolation in program coordinates through a transform (tool centre point, tilted plane).

Under G43.4 the channel interpolates the tool tip and the rotary angles, not the machine
axes: the path parameter ``s`` runs over the path in program coordinates and, every IPO
cycle, a transform turns the program point at ``s`` into machine axis positions
(``positions_at``).  The machine axes then move on curves, and their velocities are not in
a fixed ratio to the path velocity as in a linear block (``vc/core/interpolation/path.py``).

Axis limits.  When the segment is planned, ``positions_at`` is sampled along the path once
(``samples``, also the points the software limits are checked at); the largest first and second
derivatives of every axis position with respect to ``s`` (q' and q'') bound what the axis needs
at path velocity v and path acceleration a::

    axis velocity      = q' v                     <= MD32000 of the axis
    axis acceleration  = q' a + q'' v^2           <= MD32300 of the axis

The path velocity is limited so that the curvature term uses at most half of each axis's
acceleration, and the path acceleration gets what is left.  The limits hold for the whole
segment: a block that needs an axis fast at one place is slowed down over its full length
(no look-ahead across the segment) [control: the SINUMERIK slows the path where an axis would
exceed its limits; its velocity profile along the block is finer].
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field

from vc.core.axis.axis import MachineAxis
from vc.core.axis.motion import path_step

SAMPLES_MIN = 32  # samples along a segment for its axis limits ...
SAMPLES_MAX = 512  # ... about one per mm or degree of the path or of the largest machine-axis travel
CURVATURE_SHARE = 0.5  # share of an axis's acceleration the path velocity may use on curved axis motion

PositionsAt = Callable[[float], Sequence[float]]  # fraction of the path 0 .. 1 -> positions of the axes


@dataclass(slots=True)
class ToolPathSegment:
    axes: list[MachineAxis]
    positions_at: PositionsAt
    length: float  # path length in program coordinates (mm, or degrees for a pure orientation change)
    command_velocity: float  # programmed path velocity per second, before the override, within the limit
    velocity_limit: float  # the largest path velocity the axes allow
    accel: float  # path acceleration the axes allow
    rapid: bool
    samples: list[list[float]]  # axis positions at evenly spaced points from start to end
    s: float = 0.0
    velocity: float = 0.0
    _previous: list[float] = field(default_factory=list)  # axis positions handed out last cycle
    _released: set[int] = field(default_factory=set)  # indices in ``positions_at`` of axes an ESR retract took

    @classmethod
    def plan(cls, axes: list[MachineAxis], positions_at: PositionsAt, length: float, feed: float,
             rapid: bool) -> ToolPathSegment:
        """Plan a move of ``length`` along ``positions_at``; ``feed`` per second (ignored for G0)."""
        start = list(positions_at(0.0))
        if length <= 0.0:
            return cls(axes, positions_at, 0.0, 0.0, 0.0, 1.0, rapid, [start], _previous=start)
        # a swing of the rotary axes with the tip standing or nearly so moves the machine axes far
        end = positions_at(1.0)
        travel = max((abs(finish - begin) for begin, finish in zip(start, end, strict=True)), default=0.0)
        count = max(SAMPLES_MIN, min(SAMPLES_MAX, math.ceil(max(length, travel))))
        samples = [start] + [list(positions_at(index / count)) for index in range(1, count + 1)]
        velocity_limit, accel = _axis_limits(axes, samples, length / count)
        command = velocity_limit if rapid else min(feed, velocity_limit)
        return cls(axes, positions_at, length, command, velocity_limit, accel, rapid, samples, _previous=start)

    @property
    def finished(self) -> bool:
        """Arrived and standing: the cycle after the arrival (which still moved) ends the block."""
        return self.velocity == 0.0 and self.s >= self.length

    def cycle(self, override: float, hold: bool, dt: float) -> None:
        """Advance one IPO cycle and hand each axis its position setpoint (the end point once there)."""
        if self.s < self.length:
            target = 0.0 if hold else min(self.command_velocity * override, self.velocity_limit)
            self.s, self.velocity = path_step(self.s, self.length, self.velocity, target, self.accel, dt)
        else:
            self.velocity = 0.0
        if self.length > 0.0:
            self._hand_out(self.s / self.length, dt)

    def release_axis(self, axis: MachineAxis) -> None:
        """``axis`` leaves the tool path (an ESR retract takes it); the others go on along it."""
        if axis in self.axes:
            index = self.axes.index(axis)
            following = [number for number in range(len(self._previous)) if number not in self._released]
            self._released.add(following[index])
            del self.axes[index]

    def _hand_out(self, fraction: float, dt: float) -> None:
        positions = list(self.positions_at(fraction))
        following = (item for number, item in enumerate(zip(positions, self._previous, strict=True))
                     if number not in self._released)
        for axis, (position, previous) in zip(self.axes, following, strict=True):
            axis.set_path_setpoint(position, (position - previous) / dt)
        self._previous = positions


def _axis_limits(axes: list[MachineAxis], samples: list[list[float]], step: float) -> tuple[float, float]:
    """The path velocity and acceleration within every axis's MD32000 / MD32300 (module docstring),
    from the axis positions at path points ``step`` apart."""
    count = len(samples) - 1
    derivatives = []  # per axis: the largest |q'| and |q''| along the path
    for number in range(len(axes)):
        values = [sample[number] for sample in samples]
        slope = max(abs(b - a) for a, b in itertools.pairwise(values)) / step
        bend = max((abs(values[k + 1] - 2.0 * values[k] + values[k - 1]) for k in range(1, count)),
                   default=0.0) / (step * step)
        derivatives.append((slope, bend))
    velocity_limit = math.inf
    for axis, (slope, bend) in zip(axes, derivatives, strict=True):
        if slope > 0.0:
            velocity_limit = min(velocity_limit, axis.dyn.max_velocity / slope)
        if bend > 0.0:
            velocity_limit = min(velocity_limit, math.sqrt(CURVATURE_SHARE * axis.dyn.max_accel / bend))
    if math.isinf(velocity_limit):
        return 0.0, 1.0  # no axis moves
    accel = min(((axis.dyn.max_accel - bend * velocity_limit ** 2) / slope
                 for axis, (slope, bend) in zip(axes, derivatives, strict=True) if slope > 0.0), default=1.0)
    return velocity_limit, accel
