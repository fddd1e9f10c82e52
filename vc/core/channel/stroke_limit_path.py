"""Stored stroke limits 2 and 3 on the channel's paths and JOG (``vc/core/axis/stroke_limits.py``).

A block's path is checked before it moves: where it would cross a boundary it is shortened to end
on it (the block then raises the limit's alarm at its end); JOG stops on the boundary, and a key
held against it raises the alarm.  With an inclined-axis control the limits are checked in its
Cartesian coordinates (seed 000).
"""

from __future__ import annotations

from collections.abc import Callable

from vc.core.alarms import AlarmList
from vc.core.axis.axis import MachineAxis
from vc.core.axis.jog import FREE_JOG, JogLimits
from vc.core.axis.owner import Owner
from vc.core.axis.stroke_limits import BOUNDARY, StrokeLimitControl, StrokeStop
from vc.core.interpolation.path import PathSegment
from vc.core.interpolation.tool_path import ToolPathSegment
from vc.core.transforms.inclined_axis_control import InclinedAxisControl


class ChannelStrokeLimits:
    def __init__(self, name: str, control: StrokeLimitControl, geometry: set[str], alarms: AlarmList):
        self.name = name
        self.control = control  # G22 / G23, stroke limit 3 (seed 000)
        self._geometry = geometry
        self._alarms = alarms
        self.inclined: InclinedAxisControl | None = None  # inclined-axis control (seed 000), given by the NCK

    def path_stop(self, segment: PathSegment | ToolPathSegment) -> StrokeStop | None:
        """Where the segment's path first reaches a boundary (None: nowhere)."""
        return self.control.path_stop(self._segment_point(segment), isinstance(segment, PathSegment),
                                      self._stroke_point)

    def _stroke_point(self, limit: int, machine: dict[str, float]) -> dict[str, float]:
        """Machine positions in the coordinates stroke limit ``limit`` is checked in."""
        return self.inclined.stroke_point(limit, machine) if self.inclined is not None else machine

    @staticmethod
    def _segment_point(segment: PathSegment | ToolPathSegment) -> Callable[[float], dict[str, float]]:
        """The machine positions of the segment's axes at a fraction of its path."""
        names = [axis.name for axis in segment.axes]
        if isinstance(segment, PathSegment):
            starts, ends = list(segment.starts), list(segment.ends)
            return lambda fraction: {name: start + (end - start) * fraction
                                     for name, start, end in zip(names, starts, ends, strict=True)}
        positions_at = segment.positions_at
        return lambda fraction: dict(zip(names, positions_at(fraction), strict=True))

    def shortened(self, segment: PathSegment | ToolPathSegment, fraction: float,
                  program_length: float | None) -> PathSegment | ToolPathSegment:
        """The same path up to ``fraction``: it decelerates onto the stroke limit's boundary."""
        if isinstance(segment, PathSegment):
            point = self._segment_point(segment)(fraction)
            return PathSegment.plan(segment.axes, [point[axis.name] for axis in segment.axes],
                                    [axis.name in self._geometry for axis in segment.axes],
                                    segment.command_velocity, segment.rapid,
                                    program_length * fraction if program_length else None)
        positions_at = segment.positions_at
        return ToolPathSegment.plan(segment.axes, lambda part: positions_at(part * fraction),
                                    segment.length * fraction, segment.command_velocity, segment.rapid)

    def jog_limits(self, axis: MachineAxis, cycle: int) -> JogLimits:
        """JOG stops on the boundary of stored stroke limits 2 and 3; held against it, the key raises
        the limit's alarm (docstring of ``vc/core/axis/stroke_limits.py``)."""
        keys = axis.inputs
        if not (keys.key_plus or keys.key_minus or axis.owner is Owner.JOG):
            return FREE_JOG
        inclined = self.inclined
        travel = inclined.jog_travel(axis) if inclined is not None else {axis.name: 1.0}
        room = self.control.jog_room(travel, self._stroke_point)
        if room is None:
            return FREE_JOG
        low, high, low_number, high_number, reached = room
        pressed = 1 if keys.key_plus and not keys.key_minus else -1 if keys.key_minus and not keys.key_plus else 0
        if axis.command_velocity == 0.0 and ((pressed > 0 and high <= BOUNDARY) or (pressed < 0 and low >= -BOUNDARY)):
            self._alarms.raise_alarm(high_number if pressed > 0 else low_number, cycle, self.name, "JOG", reached,
                                     channel=self.name, axis=reached)
        window = (axis.setpoint + low, axis.setpoint + high)
        if axis.software_limits_active and (inclined is None or axis.name not in inclined.machine_axes):
            minus, plus = axis.software_limits
            window = (max(window[0], minus), min(window[1], plus))
        return JogLimits(plus=high > BOUNDARY, minus=low < -BOUNDARY, window=window)
