"""The one bit-level access to data-block bytes, as the NC (vc/core/interface_map), the PLC runtime
(plc_stub/io) and the typed image (interfaces/image) use it: S7 bit order, big-endian words."""

from __future__ import annotations

from hypothesis import given
from hypothesis import strategies as st

from interfaces.bit_access import Bit, Field, read_field, write_field
from interfaces.signals import SignalType


def test_a_bit_is_its_mask_in_one_byte() -> None:
    area = bytearray(4)
    Bit(2, 1 << 4).put(area, True)  # DBX2.4
    assert area == bytearray([0, 0, 0x10, 0]) and Bit(2, 0x10).get(area)
    Bit(2, 1 << 4).put(area, False)
    assert area == bytearray(4)


def test_a_bits_field_lies_inside_its_byte_from_its_lowest_bit() -> None:
    area = bytearray([0b1111_1111])
    Field(0, 1, 3, SignalType.BITS).put(area, 0b010)  # bits 1..3
    assert area[0] == 0b1111_0101
    assert Field(0, 1, 3, SignalType.BITS).get(area) == 0b010


def test_words_and_double_words_are_big_endian() -> None:
    area = bytearray(6)
    Field(0, 0, 16, SignalType.WORD).put(area, 0x1234)
    Field(2, 0, 32, SignalType.DWORD).put(area, 0xDEADBEEF)
    assert area == bytes.fromhex("1234deadbeef")
    assert read_field(area, 2, 0, 32) == 0xDEADBEEF


@given(st.binary(min_size=4, max_size=4), st.integers(0, 3), st.integers(0, 7), st.integers(1, 8),
       st.integers(0, 0xFFFF_FFFF))
def test_a_write_changes_only_its_bits_and_reads_back_cut_to_its_width(
        before: bytes, byte: int, shift: int, width: int, value: int) -> None:
    width = min(width, 8 - shift)
    area = bytearray(before)
    write_field(area, byte, shift, width, value)
    mask = ((1 << width) - 1) << shift
    assert read_field(area, byte, shift, width) == value & ((1 << width) - 1)
    assert area[byte] & ~mask & 0xFF == before[byte] & ~mask & 0xFF
    assert [b for k, b in enumerate(area) if k != byte] == [b for k, b in enumerate(before) if k != byte]
