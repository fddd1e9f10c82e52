"""Position measuring systems: actual value, reference state, zero marks, distance-coded marks.

An encoder sees the slide's physical position; the NC's actual value is the physical
position plus an offset that referencing (or a calibrated absolute encoder) makes right.

Kinds (MD30240 ENC_TYPE, MD34200 ENC_REFP_MODE):

* incremental (ENC_TYPE 0 or 1), MD34200 = 1: equidistant zero marks.  A motor encoder
  (MD31040 = 0) gives one per motor revolution: every ``MD31030 * MD31050 / MD31060`` on a
  linear axis, every ``360 * MD31050 / MD31060`` degrees on a rotary axis; a direct
  encoder gives one per turn of a rotary axis, or every MD34300 on a linear scale.
* distance-coded (MD34200 = 3 or 8): reference marks whose spacing tells where they are.
  Layout used here, counted from the scale's first mark (``sim.zero_mark_offset``):
  mark 2k at ``k*B``, mark 2k+1 at ``k*B + B/2 + (k+1)*I`` with B = MD34300 (basic
  distance) and I = MD34310 (interval increment).  Adjacent marks are therefore
  ``B/2 + (k+1)*I`` or ``B/2 - (k+1)*I`` apart, and one measured gap identifies k: two
  crossed marks give the absolute position (seed 003 §4.6, L1376-1384).  A rotary encoder
  repeats the code every turn of the encoder (360 degrees direct, ``360 * MD31050 / MD31060``
  on the motor); B should divide that turn, as it does on real encoders.
* absolute (ENC_TYPE 4): the encoder reports its position (its zero at the slide's physical
  zero); MD34090 is the offset from the encoder's zero to machine zero, valid once
  calibrated (MD34210 = 2).

Faults the plant can inject: zero marks that are not seen (dirty or broken track) and
distance-coded marks missing in a range.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from vc.config import md_dictionary as MD
from vc.config.machine_data import MachineData
from vc.config.model import AxisConfig

ENC_TYPE_ABSOLUTE = 4
ENC_STATE_NOT_CALIBRATED = 0
ENC_STATE_CALIBRATION_ENABLED = 1  # absolute; for incremental: automatic referencing enabled
ENC_STATE_CALIBRATED = 2  # absolute; for incremental: referenced, restore at the next power-on
ENC_STATE_RESTORE = 3  # incremental: restore the buffered position without referencing
REFP_MODE_ZERO_MARK = 1
DISTANCE_CODED_MODES = (3, 8)


def travel_per_encoder_turn(axis: AxisConfig, encoder: int = 0) -> float | None:
    """Axis travel (mm or degrees) per revolution of a rotary encoder; None for a linear scale."""
    md = axis.md
    ratio = md.int(MD.DRIVE_AX_RATIO_DENOM, 0) / md.int(MD.DRIVE_AX_RATIO_NUMERA, 0)
    direct = md.bool(MD.ENC_IS_DIRECT, encoder)
    if axis.is_rotary:
        return 360.0 if direct else abs(360.0 * ratio)
    if direct or md.bool(MD.ENC_IS_LINEAR, encoder):
        return None
    return abs(md.float(MD.LEADSCREW_PITCH) * ratio)


def zero_mark_spacing(axis: AxisConfig, encoder: int = 0) -> float:
    turn = travel_per_encoder_turn(axis, encoder)
    if turn is None:
        return axis.md.float(MD.ENC_REFP_MARKER_DIST, encoder)  # a linear scale with equidistant marks
    return turn


def frequency_limit_velocity(axis: AxisConfig, encoder: int = 0) -> float:
    """Axis velocity (per second) at which the encoder's signal reaches its limit frequency MD36300.

    One signal period is a line of a rotary encoder (MD31020 lines per turn) or the grid of a
    linear scale (MD31010)."""
    md = axis.md
    turn = travel_per_encoder_turn(axis, encoder)
    if turn is None:
        return md.float(MD.ENC_FREQ_LIMIT, encoder) * md.float(MD.ENC_GRID_POINT_DIST, encoder)
    return rotary_frequency_limit_velocity(axis.md, encoder, turn)


def rotary_frequency_limit_velocity(md: MachineData, encoder: int, turn: float) -> float:
    """As :func:`frequency_limit_velocity` for a rotary encoder whose turn moves the axis by ``turn``
    (a motor encoder behind a gearbox: the spindle speed at the limit changes with the gear stage)."""
    return md.float(MD.ENC_FREQ_LIMIT, encoder) * turn / md.int(MD.ENC_RESOL, encoder)


@dataclass(frozen=True, slots=True)
class DistanceCode:
    """The distance-coded mark layout of a scale or a rotary encoder (see the module docstring).

    A scale mounted against the machine coordinates (MD34320 ENC_INVERS = 1) counts its marks
    from the first mark towards minus: ``orientation`` -1.  A rotary encoder repeats its code
    every turn (``period``, degrees of the axis), so its marks tell the position within one turn
    only (seed 003 L1653-1656); a linear scale has no period and no marks before its first.
    """

    basic: float  # B = MD34300
    increment: float  # I = MD34310
    first_mark: float  # physical position of mark 0
    orientation: int = 1  # +1: marks counted towards plus; -1: towards minus (inverted scale)
    period: float | None = None  # one encoder turn on a rotary axis; None: a linear scale

    @property
    def marks_per_period(self) -> int:
        assert self.period is not None
        return 2 * max(1, round(self.period / self.basic))

    def scale_offset(self, index: int) -> float:
        """Distance of mark ``index`` from the first mark, along the scale (or the turns of the encoder)."""
        turns = 0
        if self.period is not None:
            turns, index = divmod(index, self.marks_per_period)
        k, odd = divmod(index, 2)
        within = k * self.basic + (self.basic / 2 + (k + 1) * self.increment if odd else 0.0)
        return within + turns * self.period if self.period is not None else within

    def reading(self, index: int) -> float:
        """What the encoder knows at mark ``index``: its distance from the first mark within one turn."""
        offset = self.scale_offset(index)
        return offset % self.period if self.period is not None else offset

    def position(self, index: int) -> float:
        """Physical position of mark ``index``."""
        return self.first_mark + self.orientation * self.scale_offset(index)

    def marks_between(self, start: float, end: float) -> list[int]:
        """Indices of the marks passed moving from ``start`` to ``end`` (end included), in order of passing."""
        if start == end:
            return []
        # The search runs in scale coordinates; the test itself in physical ones, where the
        # positions were computed the same way as position() computes them (no rounding skew).
        along_low = min((start - self.first_mark) * self.orientation, (end - self.first_mark) * self.orientation)
        along_high = max((start - self.first_mark) * self.orientation, (end - self.first_mark) * self.orientation)
        forward = end > start
        found = []
        index = 2 * math.floor(along_low / self.basic) - 2
        if self.period is None:
            index = max(0, index)
        else:
            turns = math.floor(along_low / self.period)
            index = turns * self.marks_per_period + max(0, 2 * math.floor((along_low - turns * self.period)
                                                                            / self.basic) - 2)
        while self.scale_offset(index) <= along_high + self.basic:
            mark = self.position(index)
            if (start < mark <= end) if forward else (end <= mark < start):
                found.append(index)
            index += 1
        found.sort(key=self.position, reverse=not forward)
        return found

    def identify(self, gap: float, direction: int) -> int | None:
        """Index of the first of two adjacent marks crossed in ``direction`` (machine coordinates),
        from their distance.

        Moving along the scale, the first mark is the lower one; against it, the higher one.
        None if the distance fits no pair of this scale.
        """
        half = self.basic / 2
        k = round(abs(gap - half) / self.increment) - 1
        if k < 0 or abs(abs(gap - half) - (k + 1) * self.increment) > self.increment / 4:
            return None
        if (k + 1) * self.increment >= half:
            return None  # no pair of a real scale is that far from B/2
        if self.period is not None and 2 * k + 1 >= self.marks_per_period:
            return None  # more pairs than one turn of the encoder holds
        lower = 2 * k if gap > half else 2 * k + 1  # B/2 + .. follows an even mark, B/2 - .. an odd one
        return lower if direction * self.orientation > 0 else lower + 1


@dataclass(slots=True)
class MeasuringSystem:
    """One encoder of an axis (index 0 = measuring system 1, 1 = measuring system 2)."""

    index: int
    absolute: bool
    mode: int  # MD34200
    spacing: float  # zero-mark spacing (mode 1)
    zero_mark_phase: float  # physical position of one zero mark / the first distance-coded mark / encoder zero
    distance_code: DistanceCode | None
    offset: float  # NC actual value minus physical position
    referenced: bool = False
    restored: bool = False  # position restored after power-on, not referenced (DB31.DBX71.4/71.5)
    # The position is exact but its relation to the program is lost: a reference return is due
    # (not referenced, the software limits stay active) [control]
    reference_return_due: bool = False
    zero_marks_visible: bool = True  # a fault can make the zero-mark track invisible
    missing_marks: list[tuple[float, float]] = field(default_factory=list)  # physical ranges without marks
    limit_velocity: float = math.inf  # above it the signal exceeds the encoder limit frequency MD36300
    resync_velocity: float = math.inf  # MD36302: below it the encoder counts reliably again
    frequency_exceeded: bool = False  # DB31.DBX60.2 / 60.3

    @classmethod
    def for_axis(cls, axis: AxisConfig, index: int, physical: float, phase: float) -> MeasuringSystem:
        md = axis.md
        absolute = md.int(MD.ENC_TYPE, index) == ENC_TYPE_ABSOLUTE
        mode = md.int(MD.ENC_REFP_MODE, index)
        code = None
        if mode in DISTANCE_CODED_MODES:
            orientation = -1 if md.bool(MD.ENC_INVERS, index) else 1
            code = DistanceCode(md.float(MD.ENC_REFP_MARKER_DIST, index), md.float(MD.ENC_MARKER_INC, index), phase,
                                orientation, zero_mark_spacing(axis, index) if axis.is_rotary else None)
        return cls(index, absolute, mode, zero_mark_spacing(axis, index), phase, code, -physical,
                   limit_velocity=frequency_limit_velocity(axis, index),
                   resync_velocity=frequency_limit_velocity(axis, index) * md.float(MD.ENC_FREQ_LIMIT_LOW, index)
                   / 100.0)

    def actual(self, physical: float) -> float:
        return physical + self.offset

    def set_actual(self, physical: float, actual: float) -> None:
        """Synchronise: the actual value becomes ``actual`` at ``physical``; the encoder is referenced."""
        self.offset = actual - physical
        self.referenced = True
        self.restored = self.reference_return_due = False

    def lose_reference(self) -> None:
        """The position is no longer trusted: the measuring system must be referenced again."""
        self.referenced = self.restored = self.reference_return_due = False

    def require_reference_return(self) -> None:
        """The position is still exact, only its relation to the program is lost (see
        ``reference_return_due``); a measuring system that never had a position stays so."""
        if self.referenced or self.restored or self.reference_return_due:
            self.referenced = self.restored = False
            self.reference_return_due = True

    def set_turn(self, md: MachineData, turn: float) -> None:
        """A rotary motor encoder now turns once per ``turn`` of the axis (a spindle's new gear
        stage, §13.4.4): its zero marks come every ``turn`` and its limit frequency MD36300 is
        reached at another axis speed (§13.8.7)."""
        self.spacing = turn
        self.limit_velocity = rotary_frequency_limit_velocity(md, self.index, turn)
        self.resync_velocity = self.limit_velocity * md.float(MD.ENC_FREQ_LIMIT_LOW, self.index) / 100.0

    def watch_limit_frequency(self, speed: float) -> bool:
        """Above its limit frequency MD36300 the encoder loses counts and with them its reference
        (seed 003 L758-761) until the axis is below MD36302 again; True in the cycle it starts."""
        if speed > self.limit_velocity:
            if not self.frequency_exceeded:
                self.frequency_exceeded = True
                self.lose_reference()
                return True
        elif self.frequency_exceeded and speed < self.resync_velocity:
            self.frequency_exceeded = False
        return False

    def _visible(self, position: float) -> bool:
        return not any(low <= position <= high for low, high in self.missing_marks)

    def zero_mark_between(self, start: float, end: float) -> float | None:
        """Physical position of the first zero mark passed moving from ``start`` to ``end`` (end included)."""
        if start == end or self.spacing <= 0.0 or not self.zero_marks_visible:
            return None
        if end > start:
            index = math.floor((start - self.zero_mark_phase) / self.spacing) + 1
            mark = self.zero_mark_phase + index * self.spacing
            return mark if mark <= end and self._visible(mark) else None
        index = math.ceil((start - self.zero_mark_phase) / self.spacing) - 1
        mark = self.zero_mark_phase + index * self.spacing
        return mark if mark >= end and self._visible(mark) else None

    def coded_marks_between(self, start: float, end: float) -> list[float]:
        """Physical positions of the distance-coded marks passed from ``start`` to ``end``, in order."""
        if self.distance_code is None or start == end:
            return []
        code = self.distance_code
        return [p for p in (code.position(i) for i in code.marks_between(start, end)) if self._visible(p)]

    def calibrated_actual(self, physical: float, correction: float) -> float:
        """The actual value of an absolute encoder calibrated with MD34090 = ``correction``."""
        return self.absolute_reading(physical) + correction

    def absolute_reading(self, physical: float) -> float:
        """What an absolute encoder reports: its position counted from its own zero.

        The simulated absolute encoder has its zero at the physical zero of the slide, so a
        calibration with MD34090 = 0 gives actual values equal to physical positions.
        """
        return physical
