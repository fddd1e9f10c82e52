"""Checks shared by the programs' parameters (the machine file's ``plc:`` section).

Each check appends its problem to the caller's list, so that a program reports every
mistake at once when the PLC starts.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any


def seconds(parameters: Mapping[str, Any], name: str, default: float, problems: list[str]) -> float:
    """A time in seconds above 0 (``default`` when not given or wrong)."""
    value = parameters.get(name, default)
    if isinstance(value, bool) or not isinstance(value, (int, float)) or value <= 0:
        problems.append(f"plc: {name} is a time in seconds above 0, got {value!r}")
        return default
    return float(value)
