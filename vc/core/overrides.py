"""Override switches: from the interface byte to a factor (seed 003 §7.4.2, L9015-9255).

Binary coding: the byte is the percentage (1 %/bit), limited by MD12100.  Gray coding:
the byte is a switch position 1..31 and the factor comes from the machine-data table
(MD12010/12030/12050/12070).  Override not active: 100 %, the byte is ignored, except
that binary 0 and Gray position 1 are always evaluated (L9228-9237).
"""

from __future__ import annotations

from dataclasses import dataclass

# The 31 positions of a 5-bit Gray-coded override switch: position n sends n XOR (n >> 1)
# (position 1 = 00001, 2 = 00011, 3 = 00010 ... 31 = 10000), as on the control's panels.
_GRAY_TO_POSITION = {(position ^ (position >> 1)): position for position in range(1, 32)}


@dataclass(frozen=True, slots=True)
class OverrideCoding:
    gray: bool
    gray_table: tuple[float, ...]  # factor per switch position 1..31
    binary_limit: float  # MD12100

    def factor(self, raw: int, active: bool) -> float:
        """The override factor for the interface byte ``raw``."""
        if self.gray:
            position = _GRAY_TO_POSITION.get(raw & 0x1F)
            if position is None:
                return 0.0  # 00000 is no switch position (wire break): stop rather than guess
            if not active and position != 1:
                return 1.0
            return self.gray_table[position - 1]
        if raw == 0:
            return 0.0
        if not active:
            return 1.0
        return min(raw / 100.0, self.binary_limit)
