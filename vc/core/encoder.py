"""The position measuring system of an axis: actual value, reference state, zero marks.

The encoder sees the slide's physical position.  The NC's actual value is the physical
position plus an offset that only referencing makes meaningful: an incremental encoder
starts at 0 wherever the slide stands at power-on (not referenced); a calibrated absolute
encoder (MD30240 = 4, MD34210 = 2) is referenced at once (seed 003 §4.9, §4.10).

Zero marks: one per encoder revolution.  A motor encoder (MD31040 = 0) on a linear axis
turns once per ``MD31030 * MD31050 / MD31060`` of travel; a rotary axis or spindle once
per ``360 * MD31050 / MD31060`` degrees; a direct encoder on a rotary axis once per turn.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from vc.config import md_dictionary as MD
from vc.config.model import AxisConfig

ENC_TYPE_ABSOLUTE = 4
ENC_STATE_CALIBRATED = 2


def zero_mark_spacing(axis: AxisConfig) -> float:
    md = axis.md
    ratio = md.int(MD.DRIVE_AX_RATIO_DENOM, 0) / md.int(MD.DRIVE_AX_RATIO_NUMERA, 0)
    if axis.is_rotary:
        return 360.0 if md.bool(MD.ENC_IS_DIRECT) else abs(360.0 * ratio)
    return abs(md.float(MD.LEADSCREW_PITCH) * ratio)


@dataclass(slots=True)
class Encoder:
    spacing: float  # distance between two zero marks
    zero_mark_phase: float  # physical position of one zero mark
    offset: float  # NC actual value minus physical position
    referenced: bool

    @classmethod
    def at_power_on(cls, axis: AxisConfig, physical: float) -> Encoder:
        absolute_calibrated = (axis.md.int(MD.ENC_TYPE) == ENC_TYPE_ABSOLUTE
                               and axis.md.int(MD.ENC_REFP_STATE) == ENC_STATE_CALIBRATED)
        # A calibrated absolute encoder knows the machine zero (MD34090 offset); an incremental
        # encoder counts from 0 wherever the slide stands at power-on.
        offset = axis.md.float(MD.REFP_MOVE_DIST_CORR) if absolute_calibrated else -physical
        return cls(zero_mark_spacing(axis), axis.sim.zero_mark_offset, offset, absolute_calibrated)

    def actual(self, physical: float) -> float:
        return physical + self.offset

    def zero_mark_between(self, start: float, end: float) -> float | None:
        """Physical position of the first zero mark passed moving from ``start`` to ``end`` (end included)."""
        if start == end or self.spacing <= 0.0:
            return None
        if end > start:
            index = math.floor((start - self.zero_mark_phase) / self.spacing) + 1
            mark = self.zero_mark_phase + index * self.spacing
            return mark if mark <= end else None
        index = math.ceil((start - self.zero_mark_phase) / self.spacing) - 1
        mark = self.zero_mark_phase + index * self.spacing
        return mark if mark >= end else None

    def set_actual(self, physical: float, actual: float) -> None:
        """Synchronise: the actual value becomes ``actual`` at the current physical position."""
        self.offset = actual - physical
        self.referenced = True
