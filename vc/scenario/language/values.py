"""Expected values in ``expect`` mappings.

=====================  =================================================
written                passes when the actual value ...
=====================  =================================================
``1``, ``true``        equals it exactly (whole numbers and yes/no)
``99.5``               is within 1e-9 of it (a decimal number)
``"100 +- 0.001"``     lies in 100 - 0.001 .. 100 + 0.001, bounds included (also ``±``)
``"< 5"``, ``"<= 5"``  is below / at most 5
``"> 5"``, ``">= 5"``  is above / at least 5
``"!= 0"``, ``"== 3"`` differs from / equals the number
=====================  =================================================

Numbers are finite and at most ``MAX_MAGNITUDE`` (:mod:`vc.input_limits`): ``.inf`` would match
every value within "tolerance" (the distance is infinite, and so is the allowance), and a
NaN would make ``!=`` hold for ever.  An actual value that is not finite matches nothing.
Whether an expectation can fail at all for a given quantity (``"<= 1"`` on a bool, a
tolerance covering a byte's whole range) is :meth:`ExpectedValue.judgement` against the
quantity's range.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass

from interfaces.errors import VcError
from vc.input_limits import MAX_MAGNITUDE

FLOAT_TOLERANCE = 1e-9
ROUNDING_SLACK = 1e-12  # relative; far below any tolerance a machine is measured with

_NUMBER = r"[-+]?(?:[0-9]+(?:\.[0-9]*)?|\.[0-9]+)(?:[eE][-+]?[0-9]+)?"
_WITHIN = re.compile(rf"^\s*(?P<value>{_NUMBER})\s*(?:\+-|\+/-|±)\s*(?P<tolerance>{_NUMBER})\s*$")
_COMPARE = re.compile(rf"^\s*(?P<op>==|!=|<=|>=|<|>)\s*(?P<value>{_NUMBER})\s*$")
_PLAIN = re.compile(rf"^\s*(?P<value>{_NUMBER})\s*$")


class ExpectedValueError(VcError, ValueError):
    """A text that is not an expected value."""


@dataclass(frozen=True, slots=True)
class ExpectedValue:
    op: str  # "==", "!=", "<", "<=", ">", ">=", or "+-" (within a tolerance)
    value: int | float
    tolerance: float = 0.0

    def matches(self, actual: float) -> bool:
        if not math.isfinite(actual):
            return False
        op, value = self.op, self.value
        if op == "+-":  # bounds included, with slack for binary rounding (100.001 - 100 > 0.001)
            return abs(actual - value) <= self.tolerance + ROUNDING_SLACK * max(1.0, abs(value))
        if op == "==":
            return actual == value
        if op == "!=":
            return actual != value
        if op == "<":
            return actual < value
        if op == "<=":
            return actual <= value
        if op == ">":
            return actual > value
        return actual >= value

    @property
    def exact(self) -> int | None:
        """The whole number this expects exactly, if it does (for checks against a signal's range)."""
        return self.value if self.op == "==" and isinstance(self.value, int) else None

    def judgement(self, low: float, high: float, whole: bool) -> str:
        """For a quantity whose values lie in ``low .. high`` (only whole numbers if ``whole``):
        "" if this expectation can both pass and fail there, else "always" or "never" (it holds
        for every value there, or for none)."""
        op, value = self.op, self.value
        if op == "+-":
            allowance = self.tolerance + ROUNDING_SLACK * max(1.0, abs(value))
            lowest, highest = value - allowance, value + allowance
            if whole:
                lowest, highest = math.ceil(lowest), math.floor(highest)
            if lowest <= low and high <= highest:
                return "always"
            return "never" if highest < lowest or highest < low or high < lowest else ""
        takes = low <= value <= high and (not whole or float(value).is_integer())  # the quantity can be value
        holds = {"<": (high < value, value <= low), "<=": (high <= value, value < low),
                 ">": (value < low, high <= value), ">=": (value <= low, high < value),
                 "==": (low == high == value, not takes), "!=": (not takes, low == high == value)}
        always, never = holds[op]
        return "always" if always else ("never" if never else "")

    def __str__(self) -> str:
        if self.op == "+-":
            if self.tolerance == FLOAT_TOLERANCE:
                return _number(self.value)
            return f"{_number(self.value)} ± {_number(self.tolerance)}"
        if self.op == "==":
            return _number(self.value)
        return f"{self.op} {_number(self.value)}"


def parse_expected(value: object) -> ExpectedValue:
    """An expected value from YAML: a number, true/false, or a text as in the module docstring."""
    if isinstance(value, bool):
        return ExpectedValue("==", int(value))
    if isinstance(value, int):
        return ExpectedValue("==", _checked(value))
    if isinstance(value, float):
        return ExpectedValue("+-", _checked(value), FLOAT_TOLERANCE)
    if isinstance(value, str):
        match = _WITHIN.match(value)
        if match:
            tolerance = float(_to_number(match.group("tolerance")))
            if tolerance < 0:
                raise ExpectedValueError(f"'{value}': the tolerance after +- cannot be negative")
            return ExpectedValue("+-", _to_number(match.group("value")), tolerance)
        match = _COMPARE.match(value)
        if match:
            return ExpectedValue(match.group("op"), _to_number(match.group("value")))
        match = _PLAIN.match(value)
        if match:
            number = _to_number(match.group("value"))
            if isinstance(number, int):
                return ExpectedValue("==", number)
            return ExpectedValue("+-", number, FLOAT_TOLERANCE)
    raise ExpectedValueError(
        f"{value!r} is not an expected value (write a number, true/false, \"100 +- 0.001\","
        " \"< 5\", \">= 5\" or \"!= 0\")"
    )


def _to_number(text: str) -> int | float:
    number: int | float = float(text)
    if not abs(number) <= MAX_MAGNITUDE:
        shown = text if len(text) <= 24 else f"{text[:20]}... ({len(text)} characters)"
        raise ExpectedValueError(f"'{shown}' is beyond {MAX_MAGNITUDE:g}, the largest number an expectation may hold")
    if text.lstrip("+-").isdigit():
        number = int(text)
    return number


def _checked(number: int | float) -> int | float:
    """A number from YAML as an expected value: finite and at most MAX_MAGNITUDE."""
    if not (math.isfinite(number) and abs(number) <= MAX_MAGNITUDE):
        raise ExpectedValueError(f"{number} is beyond {MAX_MAGNITUDE:g}, the largest number an expectation may hold"
                                 if math.isfinite(number) else f"{number} is not a finite number")
    return number


def _number(value: float) -> str:
    if isinstance(value, int):
        return str(value)
    return f"{value:.9g}" if abs(value) < 1e15 else repr(value)


def format_value(value: float, unit: str = "") -> str:
    """An actual value for messages: whole numbers as such, others with up to 9 significant digits;
    followed by its ``unit`` when it has one (``600.0 rev/min``)."""
    if isinstance(value, int):
        shown = str(value)
    elif value.is_integer() and abs(value) < 1e15:
        shown = f"{value:.1f}"
    else:
        shown = f"{value:.9g}"
    return f"{shown} {unit}" if unit else shown
