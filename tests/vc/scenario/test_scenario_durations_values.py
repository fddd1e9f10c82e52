"""Durations and expected values as scenario files write them."""

from __future__ import annotations

import pytest

from vc.scenario.durations import Duration, DurationError, format_seconds, parse_duration
from vc.scenario.values import FLOAT_TOLERANCE, ExpectedValue, ExpectedValueError, parse_expected


@pytest.mark.parametrize(("text", "microseconds"), [
    ("20ms", 20_000), ("2s", 2_000_000), ("1.5 s", 1_500_000), ("1min", 60_000_000),
    ("500us", 500), ("0.5", 500_000), (2, 2_000_000), (0.25, 250_000), ("0", 0), (" 3 ms ", 3_000),
    ("1e-3 s", 1_000), ("0.0000001 s", 1),  # below 1 us rounds up
])
def test_durations(text: object, microseconds: int) -> None:
    assert parse_duration(text).microseconds == microseconds


@pytest.mark.parametrize(("text", "message"), [
    ("5 sec", "'5 sec': unknown time unit 'sec' (use us, ms, s or min)"),
    ("soon", "'soon' is not a duration (write e.g. 20ms, 2s, 1.5 s or 1min)"),
    ("-2s", "'-2s' is not a duration (write e.g. 20ms, 2s, 1.5 s or 1min)"),
    (-2, "-2: a duration cannot be negative"),
    (True, "true is not a duration (write e.g. 20ms, 2s, 1.5 s or 1min)"),
    (None, "the time is missing (write e.g. 20ms, 2s, 1.5 s or 1min)"),
])
def test_bad_durations(text: object, message: str) -> None:
    with pytest.raises(DurationError) as caught:
        parse_duration(text)
    assert str(caught.value) == message


@pytest.mark.parametrize(("microseconds", "ipo", "cycles"), [
    (0, 2000, 0), (1, 2000, 1), (2000, 2000, 1), (2001, 2000, 2), (3000, 2000, 2), (500_000, 2000, 250),
    (100_000, 3000, 34),
])
def test_cycles_round_up(microseconds: int, ipo: int, cycles: int) -> None:
    assert Duration(microseconds).cycles(ipo) == cycles


def test_format_seconds() -> None:
    assert format_seconds(0.02) == "0.02 s"
    assert format_seconds(120) == "120 s"
    assert format_seconds(0) == "0 s"
    assert str(parse_duration("1.5 s")) == "1.5 s"


@pytest.mark.parametrize(("written", "expected", "shown"), [
    (1, ExpectedValue("==", 1), "1"),
    (True, ExpectedValue("==", 1), "1"),
    (False, ExpectedValue("==", 0), "0"),
    (99.5, ExpectedValue("+-", 99.5, FLOAT_TOLERANCE), "99.5"),
    ("100.000 +- 0.001", ExpectedValue("+-", 100.0, 0.001), "100 ± 0.001"),
    ("-5 ± 0.5", ExpectedValue("+-", -5, 0.5), "-5 ± 0.5"),
    ("< 5", ExpectedValue("<", 5), "< 5"),
    ("<= 5", ExpectedValue("<=", 5), "<= 5"),
    ("> -3.5", ExpectedValue(">", -3.5), "> -3.5"),
    (">= 5", ExpectedValue(">=", 5), ">= 5"),
    ("!= 0", ExpectedValue("!=", 0), "!= 0"),
    ("== 3", ExpectedValue("==", 3), "3"),
    ("42", ExpectedValue("==", 42), "42"),
])
def test_expected_values(written: object, expected: ExpectedValue, shown: str) -> None:
    assert parse_expected(written) == expected
    assert str(expected) == shown


def test_expected_value_matching() -> None:
    within = parse_expected("100 +- 0.001")
    assert within.matches(100.001) and within.matches(99.999) and not within.matches(100.0011)
    assert parse_expected(0.1 + 0.2).matches(0.3)
    assert not parse_expected(0.3).matches(0.3 + 1.1e-9)
    assert parse_expected("< 5").matches(4.99) and not parse_expected("< 5").matches(5)
    assert parse_expected("<= 5").matches(5)
    assert parse_expected(">= 5").matches(5) and not parse_expected("> 5").matches(5)
    assert parse_expected("!= 0").matches(1) and not parse_expected("!= 0").matches(0)
    assert parse_expected(1).matches(1.0) and not parse_expected(1).matches(0)
    assert parse_expected(1).exact == 1 and parse_expected("< 1").exact is None


@pytest.mark.parametrize("written", ["about 5", "5 +- -1", "=< 5", "", None, [1, 2]])
def test_bad_expected_values(written: object) -> None:
    with pytest.raises(ExpectedValueError):
        parse_expected(written)
