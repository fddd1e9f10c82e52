"""G33 thread cutting with constant lead: the axes are slaved to the master spindle's actual position.

``G33 <axes> K|I|J<lead> [SF=<start angle>]``: the lead is the travel per master-spindle revolution
along the axis its address names (I = X, J = Y, K = Z; seed 003 §7.2.3.5 L8356-8372, §22.4.2
L42197-42230); the other axes of the block move in proportion, so the tool follows the straight
line of the block.  The thread starts when the spindle passes its start angle SF (default 0
degrees) so that repeated cuts meet the same groove [control].  Per IPO cycle the path parameter
is the spindle's actual turning since that moment times the lead: a slower spindle gives a slower
feed, the same thread.  Feed override, feed disable and NC stop do not act (the thread would be
spoilt): the block runs to its end [control].
::

    WAIT_ANGLE ──spindle passes SF──▶ CUTTING ──lead axis at its end point──▶ finished
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from vc.core.axis.axis import MachineAxis
from vc.core.axis.owner import Owner
from vc.core.interpolation.path import drop_axis

THREAD_SPINDLE_STANDS = 65870  # project alarm: the seed names none


@dataclass(frozen=True, slots=True)
class ThreadCommand:
    """What a G33 block asks: lead per revolution along ``lead_axis`` (geometry axis X, Y or Z)."""

    lead: float  # mm per revolution
    lead_axis: str  # geometry axis name the lead address names (I -> X, J -> Y, K -> Z)
    start_angle: float = 0.0  # SF, degrees


@dataclass(slots=True)
class ThreadSegment:
    axes: list[MachineAxis]
    starts: list[float]
    ends: list[float]
    travel_per_degree: float  # path parameter (0..1) per spindle degree
    spindle: MachineAxis
    start_position: float  # the spindle's actual position at which the thread begins (SF)
    direction: int  # +1 / -1: the spindle's sense of rotation at the start
    fraction: float = 0.0  # how much of the block is done, 0..1
    _units: list[float] = field(default_factory=list)

    @classmethod
    def plan(cls, axes: list[MachineAxis], ends: list[float], lead_delta: float, command: ThreadCommand,
             spindle: MachineAxis, chained_from: float | None = None) -> ThreadSegment:
        """``lead_delta`` is the block's travel along the lead axis (0: the lead counts along the path);
        ``chained_from``: the spindle position where the previous G33 block ended - a chain of thread
        blocks is one thread, SF counts only for its first block [control]."""
        starts = [axis.setpoint for axis in axes]
        deltas = [end - start for start, end in zip(starts, ends, strict=True)]
        along = abs(lead_delta) if lead_delta else math.sqrt(sum(delta * delta for delta in deltas))
        revolutions = along / command.lead if command.lead > 0.0 else math.inf
        direction = 1 if spindle.velocity >= 0.0 else -1
        now = spindle.actual
        angle = spindle.shown(now) % 360.0
        ahead = ((command.start_angle - angle) * direction) % 360.0
        travel = 1.0 / (revolutions * 360.0) if revolutions > 0.0 else math.inf
        for axis in axes:
            axis.take(Owner.PATH)
        start = chained_from if chained_from is not None else now + direction * ahead
        return cls(axes, starts, ends, travel, spindle, start, direction, _units=deltas)

    @property
    def finished(self) -> bool:
        return self.fraction >= 1.0

    def release_axis(self, axis: MachineAxis) -> None:
        """``axis`` leaves the thread (a retraction takes it); the others go on with the spindle."""
        drop_axis(axis, self.axes, self.starts, self.ends, self._units)

    @property
    def end_position(self) -> float:
        """The spindle position at which the block's end point is reached."""
        return self.start_position + self.direction / self.travel_per_degree

    def cycle(self, dt: float) -> None:
        """Follow the spindle: the axes stand until the start angle, then move with the spindle's turning."""
        turned = (self.spindle.actual - self.start_position) * self.direction
        fraction = min(1.0, max(0.0, turned * self.travel_per_degree))
        step = fraction - self.fraction
        self.fraction = max(self.fraction, fraction)  # a spindle turning back does not unwind the thread
        for axis, start, delta in zip(self.axes, self.starts, self._units, strict=True):
            axis.set_path_setpoint(start + delta * self.fraction, delta * max(step, 0.0) / dt if step > 0 else 0.0)
