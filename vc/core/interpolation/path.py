"""Linear path interpolation of one block (G0 / G1) across the block's axes.

The path parameter ``s`` runs from 0 to the path length; every axis moves in proportion,
so all axes start and arrive together (linear interpolation).  The path length is the
distance travelled by the geometry axes of the block, or of all its axes if it has no
geometry axis; F is the velocity along that length.  Per cycle the path velocity ramps
toward ``command * override`` with the path acceleration and never exceeds the velocity
from which the path can stop at its end point.  A hold (feed disable, NC stop, missing
enable) ramps it to zero on the path, so the contour is kept.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from vc.core.axis.axis import MachineAxis
from vc.core.axis.motion import path_step


@dataclass(slots=True)
class PathSegment:
    axes: list[MachineAxis]
    starts: list[float]
    ends: list[float]
    length: float
    command_velocity: float  # programmed path velocity, per second, before the override
    accel: float
    rapid: bool
    s: float = 0.0
    velocity: float = 0.0
    _unit: list[float] = field(default_factory=list)  # axis displacement per unit of path length

    @classmethod
    def plan(
        cls,
        axes: list[MachineAxis],
        ends: list[float],
        geometry: list[bool],
        feed: float,
        rapid: bool,
        program_length: float | None = None,
    ) -> PathSegment:
        """Plan a linear move; ``feed`` is the programmed path velocity per second (ignored for G0).

        ``program_length``: the length of the programmed path where a transform maps it onto
        machine axes of another length (the inclined axis); F is the velocity along it.
        """
        starts = [axis.setpoint for axis in axes]
        deltas = [end - start for start, end in zip(starts, ends, strict=True)]
        geometry_length = math.sqrt(sum(d * d for d, g in zip(deltas, geometry, strict=True) if g))
        length = geometry_length if geometry_length > 0.0 else math.sqrt(sum(d * d for d in deltas))
        if program_length and length > 0.0:
            length = program_length
        if length == 0.0:
            return cls(axes, starts, ends, 0.0, 0.0, 1.0, rapid)
        unit = [d / length for d in deltas]
        velocity_limit = min((axis.dyn.max_velocity / abs(u) for axis, u in zip(axes, unit, strict=True) if u),
                             default=math.inf)
        accel_limit = min((axis.dyn.max_accel / abs(u) for axis, u in zip(axes, unit, strict=True) if u),
                          default=math.inf)
        command = velocity_limit if rapid else min(feed, velocity_limit)
        return cls(axes, starts, ends, length, command, accel_limit, rapid, _unit=unit)

    @property
    def finished(self) -> bool:
        """At the end point and standing: the cycle after the one that arrived (which still moved)."""
        return self.s >= self.length and self.velocity == 0.0

    @property
    def distance_to_go(self) -> float:
        return self.length - self.s

    def cycle(self, override: float, hold: bool, dt: float) -> None:
        """Advance one IPO cycle and hand each axis its position setpoint."""
        if self.length == 0.0:
            self.velocity = 0.0
            return
        if self.s >= self.length:
            self.velocity = 0.0
            self._hand_out(0.0)
            return
        target = 0.0 if hold else self.command_velocity * override
        self.s, self.velocity = path_step(self.s, self.length, self.velocity, target, self.accel, dt)
        self._hand_out(self.velocity)

    def release_axis(self, axis: MachineAxis) -> None:
        """``axis`` leaves the path (an ESR retract takes it); the others go on along the same line."""
        drop_axis(axis, self.axes, self.starts, self.ends, self._unit)

    def _hand_out(self, velocity: float) -> None:
        if self.s >= self.length:
            for axis, end, unit in zip(self.axes, self.ends, self._unit, strict=True):
                axis.set_path_setpoint(end, unit * velocity)
            return
        s = self.s
        for axis, start, unit in zip(self.axes, self.starts, self._unit, strict=True):
            axis.set_path_setpoint(start + unit * s, unit * velocity)


def drop_axis(axis: MachineAxis, axes: list[MachineAxis], *columns: list[float]) -> None:
    """Take ``axis`` out of a motion's axes and its per-axis ``columns`` (starts, ends, ...)."""
    if axis not in axes:
        return
    index = axes.index(axis)
    del axes[index]
    for values in columns:
        del values[index]
