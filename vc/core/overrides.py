"""Override switches: from the interface byte to a factor (seed 003 §7.4.2, L9015-9255).

Binary coding: the byte is the percentage (1 %/bit), limited by MD12100.  Gray coding:
the byte is a switch position 1..31 and the factor comes from the machine-data table
(MD12010/12030/12050/12070).  Override not active: 100 %, the byte is ignored, except
that binary 0 and Gray position 1 are always evaluated (L9228-9237).
"""

from __future__ import annotations

from dataclasses import dataclass

# Gray code of the 31 switch positions, position n = gray(n - 1): the standard reflected
# binary code a 5-bit Gray switch produces.
_GRAY_TO_POSITION = {(index ^ (index >> 1)): index + 1 for index in range(31)}


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
                return 0.0
            if not active and position != 1:
                return 1.0
            return self.gray_table[position - 1]
        if raw == 0:
            return 0.0
        if not active:
            return 1.0
        return min(raw / 100.0, self.binary_limit)
