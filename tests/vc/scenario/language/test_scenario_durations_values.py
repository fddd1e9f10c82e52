"""Durations and expected values as scenario files write them."""

from __future__ import annotations

import math

import pytest

from vc.input_limits import MAX_DURATION_S
from vc.scenario.language.durations import Duration, DurationError, format_seconds, parse_duration
from vc.scenario.language.values import FLOAT_TOLERANCE, ExpectedValue, ExpectedValueError, parse_expected


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


# ---------------------------------------------------------------------------------- bounds


@pytest.mark.parametrize(("written", "message"), [
    (math.nan, "nan is not a duration"),  # timeout: .nan ended in decimal.InvalidOperation
    (math.inf, "inf is not a duration"),
    ("1e400s", "'1e400s' is longer than 86400 s, the longest time a scenario may name"),
    ("1e999999999 s", "'1e999999999 s' is longer than 86400 s"),
    ("1441min", "'1441min' is longer than 86400 s"),
    (86_401, "86401 is longer than 86400 s"),
])
def test_durations_are_finite_and_bounded(written: object, message: str) -> None:
    with pytest.raises(DurationError) as caught:
        parse_duration(written)
    assert str(caught.value).startswith(message)


def test_the_longest_duration_is_accepted() -> None:
    assert parse_duration(f"{MAX_DURATION_S}s").microseconds == MAX_DURATION_S * 1_000_000
    assert parse_duration("1440 min") == parse_duration(MAX_DURATION_S)


@pytest.mark.parametrize(("written", "message"), [
    (math.inf, "inf is not a finite number"),
    (-math.inf, "-inf is not a finite number"),
    (math.nan, "nan is not a finite number"),
    (1e308, "1e+308 is beyond 1e+15"),
    (10**16, "10000000000000000 is beyond 1e+15"),
    ("1e308", "'1e308' is beyond 1e+15"),
    ("100 +- 1e400", "'1e400' is beyond 1e+15"),
    ("< -1e400", "'-1e400' is beyond 1e+15"),
    ("1" * 5000, "'11111111111111111111... (5000 characters)' is beyond 1e+15"),
])
def test_expected_values_are_finite_and_bounded(written: object, message: str) -> None:
    """``.inf`` matched every value: abs(actual - inf) <= tolerance + slack * inf is true."""
    with pytest.raises(ExpectedValueError) as caught:
        parse_expected(written)
    assert str(caught.value).startswith(message)


def test_an_actual_value_that_is_not_finite_matches_nothing() -> None:
    for expected in ("!= 0", "< 5", "> 5", "0 +- 1e15", ">= -1e15"):
        for actual in (math.nan, math.inf, -math.inf):
            assert not parse_expected(expected).matches(actual), (expected, actual)


@pytest.mark.parametrize(("written", "low", "high", "whole", "judgement"), [
    ("<= 1", 0, 1, True, "always"),  # a bool is always <= 1
    (">= 0", 0, 255, True, "always"),
    ("< 0", 0, 255, True, "never"),
    ("> 255", 0, 255, True, "never"),
    ("!= 300", 0, 255, True, "always"),
    ("!= 2.5", 0, 255, True, "always"),
    ("== 2.5", 0, 255, True, "never"),
    ("100 +- 200", 0, 255, True, "always"),
    ("0.5 +- 0.5", 0, 1, True, "always"),
    ("0.5 +- 0.4", 0, 1, True, "never"),  # no whole number within 0.1 .. 0.9
    ("300 +- 10", 0, 255, True, "never"),
    ("0 +- 1e15", -1e15, 1e15, False, "always"),
    ("< 1e15", -1e15, 1e15, False, ""),
    ("100 +- 0.001", -1e15, 1e15, False, ""),
    ("<= 1", 0, 3, True, ""),
    (1, 0, 1, True, ""),
    (256, 0, 255, True, "never"),
])
def test_whether_an_expectation_can_pass_and_fail(written: object, low: float, high: float, whole: bool,
                                                  judgement: str) -> None:
    assert parse_expected(written).judgement(low, high, whole) == judgement
