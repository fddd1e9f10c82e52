"""Override switches: interface byte -> factor (seed 003 §7.4.2, L9015-9255; spec B.4.17).

Binary: 1 %/bit, 0 .. 200 %, limited by MD12100.  Gray: the byte is a 5-bit switch position
1..31, the factor comes from the MD table (MD12010/12030/12050/12070), index 0 = position 1.
Override not active: 100 %, the byte is ignored, except binary 0 (always 0 %) and Gray
position 1 (always the MD value of position 1) (L9228-9237).
"""

from __future__ import annotations

import pytest

from vc.config import md_dictionary as MD
from vc.core.overrides import OverrideCoding

_DEFAULT = MD.OVR_FACTOR_FEEDRATE.default  # the control's default factors per switch position
assert isinstance(_DEFAULT, tuple) and len(_DEFAULT) == 31
FEED_TABLE: tuple[float, ...] = tuple(float(factor) for factor in _DEFAULT)


def binary(limit: float = 1.2) -> OverrideCoding:
    return OverrideCoding(False, FEED_TABLE, limit)


def gray(table: tuple[float, ...] | None = None) -> OverrideCoding:
    return OverrideCoding(True, table or FEED_TABLE, 1.2)


def gray_code(position: int) -> int:
    """The code a 31-position Gray switch sends in position 1..31.

    The SINUMERIK override switch (e.g. HT 2, 840Di sl commissioning manual 7.7.2.2) sends
    00001 in its first position, then 00011, 00010, 00110, 00111, ... (reflected binary code
    of the position number): position n = n XOR (n >> 1).  The code 00000 is no position.
    """
    return position ^ (position >> 1)


# ------------------------------------------------------------------------------ binary


@pytest.mark.parametrize(("raw", "factor"), [(0, 0.0), (1, 0.01), (2, 0.02), (3, 0.03), (4, 0.04),
                                             (50, 0.5), (100, 1.0), (110, 1.1), (120, 1.2)])
def test_binary_is_one_percent_per_bit(raw: int, factor: float) -> None:
    assert binary().factor(raw, True) == pytest.approx(factor)


@pytest.mark.parametrize(("raw", "limit", "factor"), [(200, 1.2, 1.2), (121, 1.2, 1.2), (200, 2.0, 2.0),
                                                      (150, 2.0, 1.5), (150, 1.0, 1.0), (80, 1.0, 0.8)])
def test_binary_override_is_limited_by_md12100(raw: int, limit: float, factor: float) -> None:
    assert binary(limit).factor(raw, True) == pytest.approx(factor)


@pytest.mark.parametrize("raw", [1, 50, 100, 150, 200])
def test_inactive_binary_override_is_100_percent(raw: int) -> None:
    assert binary().factor(raw, False) == 1.0


def test_inactive_binary_override_at_zero_is_still_zero() -> None:
    # "exception: binary 0 is always evaluated -> 0 %" (L9228-9237): 0 % acts as a feed disable.
    assert binary().factor(0, False) == 0.0


# ------------------------------------------------------------------------------ Gray


def test_gray_codes_of_the_switch_positions_are_those_of_the_real_switch() -> None:
    assert [format(gray_code(n), "05b") for n in (1, 2, 3, 4, 5, 6, 7, 8, 31)] == [
        "00001", "00011", "00010", "00110", "00111", "00101", "00100", "01100", "10000"]


def test_every_gray_position_selects_its_md_table_entry() -> None:
    # A table with a distinct factor per position shows which entry was used: position n -> n/100.
    table = tuple(n / 100 for n in range(1, 32))
    coding = gray(table)
    factors = [round(coding.factor(gray_code(position), True), 6) for position in range(1, 32)]
    assert factors == [round(position / 100, 6) for position in range(1, 32)]


def test_gray_default_table_positions_1_19_and_31() -> None:
    # MD12030 defaults: position 1 = 0 %, position 19 = 100 %, position 31 = 120 %.
    coding = gray()
    assert coding.factor(gray_code(1), True) == 0.0
    assert coding.factor(gray_code(19), True) == 1.0
    assert coding.factor(gray_code(31), True) == 1.2


@pytest.mark.parametrize("position", [2, 10, 19, 31])
def test_inactive_gray_override_is_100_percent(position: int) -> None:
    table = tuple(n / 100 for n in range(1, 32))
    assert gray(table).factor(gray_code(position), False) == 1.0


def test_inactive_gray_override_in_position_1_is_the_md_value_of_position_1() -> None:
    # L9228-9237: Gray position 1 is always evaluated; its MD value (should be 0) is used.
    table = (0.05, *(n / 100 for n in range(2, 32)))
    assert gray(table).factor(gray_code(1), False) == pytest.approx(0.05)


def test_gray_uses_only_the_five_switch_bits() -> None:
    table = tuple(n / 100 for n in range(1, 32))
    coding = gray(table)
    for position in (2, 7, 20):
        code = gray_code(position)
        assert coding.factor(0b11100000 | code, True) == coding.factor(code, True)
