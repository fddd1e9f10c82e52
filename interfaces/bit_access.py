"""Bit-level access to the bytes of a data block: the one implementation the NC, the PLC runtime
and the typed process image share.

The convention is S7's, stated once: a bool is bit 0..7 of one byte; a field of a few bits lies
inside one byte from its lowest bit up (a gear stage in DB31.DBX16.0..16.2); a byte is the byte;
words and double words are big-endian over 2 or 4 bytes.  An accessor is resolved once from the
catalogue (byte, bit, width) and then works on the bytes directly, which keeps an IPO cycle and a
PLC scan cheap.  Values are unsigned; REAL values are the typed image's business
(:mod:`interfaces.image`).
"""

from __future__ import annotations

from dataclasses import dataclass

from interfaces.signals import SignalType


def read_field(area: bytes | bytearray, byte: int, shift: int, width_bits: int) -> int:
    """The unsigned value of ``width_bits`` bits from bit ``shift`` of ``byte`` (a field inside one
    byte) or, for 16 and 32 bits, of the big-endian word or double word at ``byte``."""
    if width_bits <= 8:
        return (area[byte] >> shift) & ((1 << width_bits) - 1)
    return int.from_bytes(area[byte : byte + width_bits // 8], "big")


def write_field(area: bytearray, byte: int, shift: int, width_bits: int, value: int) -> None:
    """Write the unsigned ``value`` where :func:`read_field` reads it; bits beyond the width are cut."""
    if width_bits <= 8:
        mask = ((1 << width_bits) - 1) << shift
        area[byte] = (area[byte] & ~mask & 0xFF) | ((value << shift) & mask)
    else:
        size = width_bits // 8
        area[byte : byte + size] = (value & ((1 << (8 * size)) - 1)).to_bytes(size, "big")


@dataclass(frozen=True, slots=True)
class Bit:
    byte: int
    mask: int

    def get(self, area: bytearray) -> bool:
        return bool(area[self.byte] & self.mask)

    def put(self, area: bytearray, value: bool) -> None:
        if value:
            area[self.byte] |= self.mask
        else:
            area[self.byte] &= ~self.mask & 0xFF


@dataclass(frozen=True, slots=True)
class Field:
    """An unsigned bits field, a byte, a word or a double word (big-endian) inside one DB."""

    byte: int
    shift: int
    width_bits: int
    type: SignalType

    def get(self, area: bytearray) -> int:
        return read_field(area, self.byte, self.shift, self.width_bits)

    def put(self, area: bytearray, value: int) -> None:
        write_field(area, self.byte, self.shift, self.width_bits, value)
