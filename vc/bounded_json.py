"""JSON read within the limits of :mod:`vc.input_limits`: session recordings and coverage files.

Python's :func:`json.loads` takes what the standard leaves open and more: ``NaN`` and
``Infinity``, whole numbers of any length (converting 5,000 digits raises ``ValueError``, not a
``JSONDecodeError``), numbers such as ``1e999`` that become infinite, and nesting until the
interpreter's recursion limit (``RecursionError``).  :func:`loads` refuses each of them as a
:class:`JsonProblem` with its line and column, like a syntax error: a whole number has at most
``MAX_INTEGER_DIGITS`` digits, every number is finite, and arrays and objects nest at most
``MAX_JSON_NESTING`` deep.
"""

from __future__ import annotations

import json
import math
from typing import Any

from interfaces.errors import VcError
from vc.input_limits import MAX_INTEGER_DIGITS, MAX_JSON_NESTING


class JsonProblem(VcError, ValueError):
    """Text that is not JSON within the limits: the message and its 1-based line and column."""

    def __init__(self, message: str, line: int = 1, column: int = 1):
        super().__init__(message)
        self.message = message
        self.line = line
        self.column = column


class _Refused(VcError, ValueError):
    """A value a hook of the decoder refuses (the decoder passes it on unchanged)."""


def _whole(text: str) -> int:
    if len(text.lstrip("-")) > MAX_INTEGER_DIGITS:
        raise _Refused(f"a whole number of {len(text.lstrip('-')):,} digits (at most {MAX_INTEGER_DIGITS})")
    return int(text)


def _real(text: str) -> float:
    value = float(text)
    if not math.isfinite(value):
        raise _Refused(f"the number {text[:24]} is not finite")
    return value


def _constant(text: str) -> float:
    raise _Refused(f"{text} is not a number JSON knows (numbers must be finite)")


def loads(text: str) -> Any:
    """The value of the JSON ``text``; raises :class:`JsonProblem`."""
    try:
        value = json.loads(text, parse_int=_whole, parse_float=_real, parse_constant=_constant)
    except json.JSONDecodeError as error:
        raise JsonProblem(f"not JSON: {error.msg}", error.lineno, error.colno) from None
    except _Refused as error:
        raise JsonProblem(str(error)) from None
    except RecursionError:
        raise JsonProblem(f"arrays and objects nested more than {MAX_JSON_NESTING} deep") from None
    if _nesting(value) > MAX_JSON_NESTING:
        raise JsonProblem(f"arrays and objects nested more than {MAX_JSON_NESTING} deep")
    return value


def _nesting(value: Any) -> int:
    """How deep arrays and objects lie inside one another (without recursing)."""
    deepest = 0
    pending = [(value, 1)]
    while pending:
        item, depth = pending.pop()
        if isinstance(item, dict):
            children = list(item.values())
        elif isinstance(item, list):
            children = item
        else:
            continue
        deepest = max(deepest, depth)
        if depth <= MAX_JSON_NESTING:
            pending.extend((child, depth + 1) for child in children)
    return deepest
