"""Durations in scenario files: ``20ms``, ``2s``, ``1.5 s``, ``1min``, or a bare number of seconds.

A duration is kept as a whole number of microseconds (exact for every text a user writes,
down to 1 us) and turned into IPO cycles only when the cycle length is known, rounding up:
``wait: 3ms`` with a 2 ms IPO cycle waits 2 cycles, and a non-zero duration always takes at
least one cycle.  A duration is finite and at most ``MAX_DURATION_S`` (:mod:`vc.input_limits`):
``1e400s`` would otherwise make a timeout that never ends.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass
from decimal import ROUND_CEILING, Decimal, InvalidOperation

from interfaces.errors import VcError
from vc.input_limits import MAX_DURATION_S

_UNIT_US: dict[str, int] = {"us": 1, "ms": 1_000, "s": 1_000_000, "min": 60_000_000}
_PATTERN = re.compile(r"^\s*(?P<number>[0-9]*\.?[0-9]+(?:[eE][-+]?[0-9]+)?)\s*(?P<unit>[a-z]*)\s*$")


class DurationError(VcError, ValueError):
    """A text or value that is not a duration; the message says what is accepted."""


@dataclass(frozen=True, slots=True, order=True)
class Duration:
    microseconds: int

    @property
    def seconds(self) -> float:
        return self.microseconds / 1e6

    def cycles(self, ipo_cycle_us: int) -> int:
        """IPO cycles needed to let this much time pass (rounded up; 0 only for a zero duration)."""
        return -(-self.microseconds // ipo_cycle_us)

    def __str__(self) -> str:
        return format_seconds(self.seconds)


def parse_duration(value: object) -> Duration:
    """``20ms``, ``2s``, ``1.5 s``, ``1min``, ``500us`` or a number of seconds (``0.5``)."""
    if value is None:
        raise DurationError("the time is missing (write e.g. 20ms, 2s, 1.5 s or 1min)")
    if isinstance(value, bool):
        raise DurationError(f"{str(value).lower()} is not a duration (write e.g. 20ms, 2s, 1.5 s or 1min)")
    if isinstance(value, float) and not math.isfinite(value):
        raise DurationError(f"{value} is not a duration (write e.g. 20ms, 2s, 1.5 s or 1min)")
    if isinstance(value, (int, float)):
        number, unit = Decimal(repr(value)), "s"
    else:
        match = _PATTERN.match(str(value))
        if match is None:
            raise DurationError(f"{_shown(value)} is not a duration (write e.g. 20ms, 2s, 1.5 s or 1min)")
        try:
            number = Decimal(match.group("number"))
        except InvalidOperation:  # pragma: no cover - the pattern admits only decimal numbers
            raise DurationError(f"{_shown(value)} is not a duration") from None
        unit = match.group("unit") or "s"
        if unit not in _UNIT_US:
            raise DurationError(f"{_shown(value)}: unknown time unit '{unit}' (use us, ms, s or min)")
    if number < 0:
        raise DurationError(f"{_shown(value)}: a duration cannot be negative")
    if number > Decimal(MAX_DURATION_S * _UNIT_US["s"] // _UNIT_US[unit]):  # exact, and before any arithmetic
        raise DurationError(f"{_shown(value)} is longer than {format_seconds(MAX_DURATION_S)}, the longest time"
                            " a scenario may name")
    try:
        microseconds = (number * _UNIT_US[unit]).to_integral_value(rounding=ROUND_CEILING)
    except ArithmeticError:  # decimal's Underflow and the like, for exponents such as 1e-999999999
        raise DurationError(f"{_shown(value)} is not a duration the harness can count in microseconds") from None
    return Duration(int(microseconds))


def format_seconds(seconds: float) -> str:
    """A time for people: ``0.02 s``, ``1.5 s``, ``120 s`` (no trailing zeros)."""
    text = f"{seconds:.6f}".rstrip("0").rstrip(".")
    return f"{text or '0'} s"


def _shown(value: object) -> str:
    return f"'{value}'" if isinstance(value, str) else str(value)
