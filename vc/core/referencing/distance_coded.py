"""Distance-coded reference marks (seed 003 §4.6, L1404-1437, L1653-1670, L1727-1780): the
position the marks crossed give, and the passive scale that references itself by crossing them.

``decode_marks`` turns 2 (or 4, MD34200 = 8) marks crossed in one direction into the actual value
at the first of them, mapped into the modulo range where the axis has one
(``modulo_reference_position``); the referencing procedure of the active measuring system uses
it, and so does ``PassiveMarkWatcher`` for a passive distance-coded scale (MD30242 = 2) while the
axis moves for any reason.
"""

from __future__ import annotations

from vc.config import md_dictionary as MD
from vc.config.machine_data import MachineData
from vc.core.axis.axis import MachineAxis
from vc.core.axis.encoder import DISTANCE_CODED_MODES, MeasuringSystem

MISC_MODULO_REFERENCE = 1 << 1  # MD30455 bit 1: distance-coded rotary reference into the modulo range
PASSIVE_REFERENCED_BY_MARKS = 2  # MD30242: a passive encoder, not independent


def passive_distance_coded(axis: MachineAxis, encoder: MeasuringSystem, md: MachineData) -> bool:
    """A passive distance-coded measuring system that references itself by crossing its marks
    (MD30242 = 2, MD34200 = 3 or 8; seed 003 L1727-1780, L5931-5943)."""
    return (encoder is not axis.encoder and encoder.mode in DISTANCE_CODED_MODES
            and md.int(MD.ENC_IS_INDEPENDENT, encoder.index) == PASSIVE_REFERENCED_BY_MARKS)


class PassiveMarkWatcher:
    """Watches a passive distance-coded scale while the axis moves for any reason; once it has
    crossed its marks (2 or 4, in one direction) the scale knows its position: referenced.

    The seed's sequence (L1766-1780): first the active system is referenced (60.4 = 1, 60.5 = 0),
    then traversing the marks references the passive one; so the watcher counts marks only
    while the active system is referenced."""

    def __init__(self, axis: MachineAxis, encoder: MeasuringSystem, md: MachineData):
        self.axis = axis
        self.encoder = encoder
        self._md = md
        self._last = axis.physical
        self._direction = 0
        self._marks: list[float] = []

    def cycle(self) -> None:
        encoder, physical = self.encoder, self.axis.physical
        moved_from, self._last = self._last, physical
        if encoder.referenced or physical == moved_from or encoder is self.axis.encoder:
            return
        if not self.axis.encoder.referenced:
            self._marks = []
            return
        direction = 1 if physical > moved_from else -1
        if direction != self._direction:
            self._direction, self._marks = direction, []
        for mark in encoder.coded_marks_between(moved_from, physical):
            self._marks.append(mark)
            if len(self._marks) == (4 if encoder.mode == 8 else 2):
                value = decode_marks(encoder, self._marks, direction, self._md)
                if value is not None:
                    encoder.set_actual(self._marks[0], value)
                self._marks = []
                return


def decode_marks(encoder: MeasuringSystem, marks: list[float], direction: int, md: MachineData) -> float | None:
    """The actual value at the first of ``marks`` (crossed in ``direction``), or None if they do not fit."""
    code = encoder.distance_code
    assert code is not None
    first = code.identify(abs(marks[1] - marks[0]), direction)
    if first is None:
        return None
    step = 1 if direction * code.orientation > 0 else -1
    for number, mark in enumerate(marks):
        expected = code.position(first + number * step) - code.position(first)
        if abs(expected - (mark - marks[0])) > code.increment / 4:
            return None  # the 4-mark plausibility check (MD34200 = 8)
    # The scale reads its distance from its first mark; counted against the machine coordinates
    # (MD34320) it enters the actual value with a minus sign (seed 003 L1404-1407, L1431-1437).
    value = code.orientation * code.reading(first) + md.float(MD.REFP_MOVE_DIST_CORR, encoder.index)
    return modulo_reference_position(value, md)


def modulo_reference_position(value: float, md: MachineData) -> float:
    """A rotary encoder knows its position within one turn only; on a modulo rotary axis
    (MD30310) or with MD30455 bit 1 the NC maps it into the modulo range MD30330/MD30340
    (seed 003 L1653-1670).  Elsewhere the value stands as decoded."""
    if not md.bool(MD.IS_ROT_AX):
        return value
    if not (md.bool(MD.ROT_IS_MODULO) or md.int(MD.MISC_FUNCTION_MASK) & MISC_MODULO_REFERENCE):
        return value
    start, size = md.float(MD.MODULO_RANGE_START), md.float(MD.MODULO_RANGE)
    return start + (value - start) % size
