"""The index positions of an indexing axis (seed 003 chapter 11, from L13374).

An indexing axis (MD30500 INDEX_AX_ASSIGN_POS_TAB > 0) has numbered index positions: those of an
index position table of the NC (MD10910 / MD10930, as many as MD10900 / MD10920; number 1 the
table's first entry, L14131-14142), or equidistant ones (MD30500 = 3: from MD30503 at the spacing
MD30501 / MD30502, on a modulo axis MD30330 / MD30502, L14200-14300).  Number n of equidistant
positions stands at ``offset + (n - 1) x spacing`` [INF: the seed numbers them 1 .. m on a modulo axis
and "..., -1, 0, 1, ..." on a linear one without saying where 1 lies; the first position is 1 as in
a table].  On a modulo axis the positions lie in its range and repeat every turn; after the last
the next in the positive direction is the first (L13586-13592).

The program's coded positions (L13833-13868)::

    CAC(i)   absolute: to index position i, the way chosen as AC        linear and rotary axes
    CACP(i)  absolute, positive direction (as ACP)                      rotary axes
    CACN(i)  absolute, negative direction (as ACN)                      rotary axes
    CDC(i)   absolute, the shorter way (as DC)                          rotary axes
    CIC(i)   incremental: i positions on from the one the axis stands on, its sign the direction

Between two positions CIC(1) goes to the next higher, CIC(-1) to the next lower, CIC(0) does not
move (L13896-13904); on a modulo axis CIC counts round the turn without whole turns (L13890-13893).
A coded position written for an axis that is no indexing axis raises 17500, a number that names
no index position 17510 [control: the seed names no alarm].

"In position" (DB31.DBX76.6, L13823-13829): the axis stands still on an index position within its
exact stop fine window MD36010.  JOG (vc/core/axis/jog.py) stops an indexing axis on an index
position once its measuring system is referenced (L13405-13490); ``IndexPositions.ahead`` finds it.
"""

from __future__ import annotations

import math

from vc.config import md_dictionary as MD
from vc.config.model import AxisConfig, IndexDivision
from vc.core.axis import rotary

ALARM_NOT_AN_INDEXING_AXIS = 17500  # [control]
ALARM_HIRTH_NOT_AN_INDEX_POSITION = 17501  # [control]: "indexing axis with Hirth joint is active"
ALARM_HIRTH_NOT_REFERENCED = 17503  # [control]: "indexing axis with Hirth joint and axis not referenced"
ALARM_INVALID_INDEX = 17510  # [control]
ON_POSITION = 1e-6  # mm or degrees: an end point that lies on an index position
CODED_POSITIONS = {"CAC": "AC", "CACP": "ACP", "CACN": "ACN", "CDC": "DC", "CIC": "IC"}
MAX_CODED_POSITION = 59  # L13868: 0 .. 59


class IndexPositions:
    """The numbered index positions of one indexing axis, in the NC's coordinates."""

    def __init__(self, division: IndexDivision, modulo: tuple[float, float] | None, hirth: bool = False):
        self.hirth = hirth  # MD30505: a Hirth joint locks the axis on its positions (§11.3.2.2)
        self.table = division.table
        self.offset = division.offset
        self.spacing = division.spacing
        self.count = division.count if not division.table else len(division.table)
        self.bounded = bool(division.table) or modulo is not None  # linear equidistant: unbounded
        self.modulo = modulo

    @classmethod
    def of(cls, config: AxisConfig) -> IndexPositions | None:
        if config.indexing is None:
            return None
        return cls(config.indexing, rotary.modulo_range_of(config), config.md.bool(MD.HIRTH_IS_ACTIVE))

    # ------------------------------------------------------------------ numbers and positions
    def position(self, number: int) -> float | None:
        """Where index position ``number`` lies (in the modulo range on a modulo axis); None: no such."""
        if self.table:
            return self.table[number - 1] if 1 <= number <= self.count else None
        if self.modulo is not None and not 1 <= number <= self.count:
            return None
        return self.offset + (number - 1) * self.spacing

    def _here(self, position: float) -> float:
        """``position`` inside the modulo range (a modulo axis), else itself."""
        if self.modulo is None:
            return position
        begin, size = self.modulo
        return begin + (position - begin) % size

    def _equidistant_number(self, position: float) -> float:
        """The (fractional) number of the equidistant positions at ``position``."""
        return (self._here(position) - self.offset) / self.spacing + 1.0

    def standing_on(self, position: float, window: float) -> int:
        """The number of the index position within ``window`` of ``position``, 0: none."""
        here = self._here(position)
        if not self.table:
            number = round(self._equidistant_number(position))
            if self.modulo is not None:
                number = (number - 1) % self.count + 1
            found = self.position(number)
            return number if found is not None and self._distance(here, found) <= window else 0
        return next((n for n, p in enumerate(self.table, start=1) if self._distance(here, p) <= window), 0)

    def _distance(self, here: float, index_position: float) -> float:
        gap = abs(here - index_position)
        if self.modulo is not None:
            gap = min(gap, self.modulo[1] - gap)
        return gap

    def below(self, position: float) -> int:
        """The number of the highest index position at or below ``position`` (its modulo position on a
        modulo axis); 0 below the first (L13920-13930)."""
        here = self._here(position)
        if not self.table:
            return math.floor(self._equidistant_number(position) + 1e-9)
        return sum(1 for p in self.table if p <= here)

    def reached(self, position: float, window: float, halfway: bool) -> int:
        """``$AA_ACT_INDEX_AX_POS_NO`` (L13618-13680, L13808-13820): the number of the index position
        last reached or passed at ``position``.  MD10940 bit 0 = 0: a position counts from the edge of
        its exact stop fine window ``window`` on its lower side, the same edge whichever way the axis
        travels (reached going up, left going down); bit 0 = 1 (``halfway``): from half the way to it.
        On a modulo axis before the first position of the turn: the last; on a linear table below
        its first: 0 [INF]."""
        if halfway:
            return self._nearest(position)
        number = self.below(position + window)
        if self.modulo is not None and number < 1:
            return self.count
        return number

    def _nearest(self, position: float) -> int:
        here = self._here(position)
        if not self.table:
            number = round(self._equidistant_number(position))
            return (number - 1) % self.count + 1 if self.modulo is not None else number
        distances = [self._distance(here, p) for p in self.table]
        return distances.index(min(distances)) + 1

    # ------------------------------------------------------------------ the program's coded positions
    def coded_end_point(self, config: AxisConfig, start: float, word: str, value: float,
                        window: float) -> tuple[float, int]:
        """The end point of ``CAC(i)`` (``word`` one of CODED_POSITIONS) for an axis that stands at
        ``start``, and 0; or (start, the alarm number)."""
        if value != round(value):
            return start, ALARM_INVALID_INDEX
        number = round(value)
        if word != "CIC":
            if not 0 <= number <= MAX_CODED_POSITION:
                return start, ALARM_INVALID_INDEX
            target = self.position(number)
            if target is None:
                return start, ALARM_INVALID_INDEX
            return rotary.end_point(config, start, CODED_POSITIONS[word], target)
        if number == 0:
            return start, 0  # CIC(0): no motion (L13904)
        at = self.standing_on(start, window)
        if at:
            goal = at + number
        else:  # between two positions: CIC(1) the next higher, CIC(-1) the next lower (L13898-13902)
            lower = self.below(start)
            goal = lower + number if number > 0 else lower + 1 + number
        if self.modulo is not None:
            goal = (goal - 1) % self.count + 1  # round the turn, no whole turns (L13890-13893)
            target = self.position(goal)
            assert target is not None
            return rotary.end_point(config, start, "ACP" if number > 0 else "ACN", target)
        target = self.position(goal)
        if target is None:
            return start, ALARM_INVALID_INDEX
        return target, 0

    def hirth_refusal(self, end: float, referenced: bool) -> int:
        """The alarm a motion of a Hirth axis to ``end`` raises before it moves, 0 if none: its
        measuring system must be referenced (L13750-13757, 17503), and it may go to its index
        positions only: the Hirth joint locks it there alone (L13740-13747, 17501) [control]."""
        if not self.hirth:
            return 0
        if not referenced:
            return ALARM_HIRTH_NOT_REFERENCED
        return 0 if self.standing_on(end, ON_POSITION) else ALARM_HIRTH_NOT_AN_INDEX_POSITION

    # ------------------------------------------------------------------ JOG
    def ahead(self, position: float, direction: int, beyond: float) -> float | None:
        """The NC position of the first index position in ``direction`` at least ``beyond`` away
        from ``position``; None where there is none (past a table's end on a linear axis)."""
        here = self._here(position)
        shift = position - here  # NC position = position in the range + shift
        edge = here + direction * beyond
        if not self.table:
            raw = self._equidistant_number(edge) - 1.0
            steps = math.ceil(raw - 1e-9) if direction > 0 else math.floor(raw + 1e-9)
            target = self.offset + steps * self.spacing
            return target + shift
        if self.modulo is None:
            candidates = [p for p in self.table if (p - edge) * direction >= -1e-9]
            if not candidates:
                return None
            return min(candidates) if direction > 0 else max(candidates)
        # a modulo axis: the table in the turn of ``edge`` and the next turn that way; after the last
        # position comes the first (L13586-13592)
        begin, size = self.modulo
        turn = math.floor((edge - begin) / size) * size
        candidates = [p + turn + k * size for k in (0, direction) for p in self.table
                      if (p + turn + k * size - edge) * direction >= -1e-9]
        return (min(candidates) if direction > 0 else max(candidates)) + shift
