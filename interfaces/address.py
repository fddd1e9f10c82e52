"""Absolute S7-style addresses of the NC/PLC interface and the plant I/O.

Grammar (case-insensitive, printed canonically in upper case)::

    DB<n>.DBX<byte>.<bit>    one bit of a data block          DB31.DBX60.4
    DB<n>.DBB<byte>          one byte                         DB21.DBB4
    DB<n>.DBW<byte>          16-bit word, big-endian (S7)     DB21.DBW68
    DB<n>.DBD<byte>          32-bit double word, big-endian   DB31.DBD88
    I<byte>.<bit> / Q<byte>.<bit>     plant input / output bit
    IB<byte> / IW<byte> / ID<byte>    plant input byte / word / double word (same for Q)

An address names a location only; what it means (bool, bits field, real...) is the
business of the signal that lives there (``interfaces.signals``).
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from typing import Literal

from interfaces.errors import VcError

Width = Literal["X", "B", "W", "D"]

_WIDTH_BYTES: dict[str, int] = {"X": 1, "B": 1, "W": 2, "D": 4}

_DB_PATTERN = re.compile(r"^DB(\d+)\.DB([XBWD])(\d+)(?:\.(\d+))?$")
_IO_PATTERN = re.compile(r"^([IQ])([BWD]?)(\d+)(?:\.(\d+))?$")


class AddressError(VcError, ValueError):
    """A text that is not a valid absolute address."""


@dataclass(frozen=True, slots=True, order=True)
class Address:
    """One absolute location: a data block bit/byte/word/dword or a plant I/O point."""

    area: str  # "DB", "I" or "Q"
    db: int  # data block number; 0 for I and Q
    byte: int
    bit: int  # 0..7 for width "X"; -1 otherwise
    width: str  # "X", "B", "W" or "D"

    @classmethod
    def parse(cls, text: str) -> Address:
        """Parse ``DB31.DBX60.4``, ``DB21.DBB4``, ``I0.3``, ``QB2`` ... (case-insensitive)."""
        cleaned = text.strip().upper().replace(" ", "")
        match = _DB_PATTERN.match(cleaned)
        if match:
            db_text, width, byte_text, bit_text = match.groups()
            return cls._checked("DB", int(db_text), int(byte_text), bit_text, width, text)
        match = _IO_PATTERN.match(cleaned)
        if match:
            area, width_letter, byte_text, bit_text = match.groups()
            return cls._checked(area, 0, int(byte_text), bit_text, width_letter or "X", text)
        raise AddressError(
            f"'{text}' is not an address (expected e.g. DB31.DBX60.4, DB21.DBB4, DB31.DBD88, I0.3, QB2)"
        )

    @classmethod
    def _checked(
        cls, area: str, db: int, byte: int, bit_text: str | None, width: str, original: str
    ) -> Address:
        if width == "X":
            if bit_text is None:
                raise AddressError(f"'{original}' names a bit but has no bit number (e.g. .4)")
            bit = int(bit_text)
            if bit > 7:
                raise AddressError(f"'{original}': bit number {bit} is outside 0..7")
            return cls(area, db, byte, bit, "X")
        if bit_text is not None:
            raise AddressError(f"'{original}': a byte, word or double word address takes no bit number")
        return cls(area, db, byte, -1, width)

    @classmethod
    def bit_in_db(cls, db: int, byte: int, bit: int) -> Address:
        return cls("DB", db, byte, bit, "X")

    @property
    def size(self) -> int:
        """Number of bytes this address spans."""
        return _WIDTH_BYTES[self.width]

    @property
    def is_bit(self) -> bool:
        return self.width == "X"

    @property
    def area_key(self) -> str:
        """Key of the byte area in a process image: ``DB31``, ``I`` or ``Q``."""
        return f"DB{self.db}" if self.area == "DB" else self.area

    def in_db(self, db: int) -> Address:
        """The same location in another instance of the data block (DB31 -> DB33)."""
        return Address(self.area, db, self.byte, self.bit, self.width)

    def bit_address(self, bit_offset: int) -> Address:
        """The bit ``bit_offset`` places above this bit (for multi-bit fields such as DBX16.0..16.2)."""
        absolute = self.byte * 8 + self.bit + bit_offset
        return Address(self.area, self.db, absolute // 8, absolute % 8, "X")

    def __str__(self) -> str:
        if self.area == "DB":
            head = f"DB{self.db}.DB{self.width}{self.byte}"
            return f"{head}.{self.bit}" if self.is_bit else head
        if self.is_bit:
            return f"{self.area}{self.byte}.{self.bit}"
        return f"{self.area}{self.width}{self.byte}"


def is_address(text: str) -> bool:
    """True if ``text`` parses as an absolute address."""
    try:
        Address.parse(text)
    except AddressError:
        return False
    return True
