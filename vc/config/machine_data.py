"""Machine data as the manual names them: number, name, level, unit, default, limits.

``MdDef`` describes one machine datum (``MD32000 $MA_MAX_AX_VELO``); the dictionary of
all supported data is ``vc.config.md_dictionary``.  ``MachineData`` holds the values of
one level instance (the NCK, one channel, one axis) with the defaults filled in, and is
read by the NC core through the definitions: ``md.float(MAX_AX_VELO)``.
"""

from __future__ import annotations

import builtins
import math
import re
from collections.abc import Mapping
from dataclasses import dataclass
from enum import StrEnum

from interfaces.errors import VcError
from vc.input_limits import MAX_MAGNITUDE, MIN_MD_MAGNITUDE

MdScalar = bool | int | float | str
MdValue = MdScalar | tuple[MdScalar, ...]


class MdLevel(StrEnum):
    NCK = "N"  # general machine data $MN_
    CHANNEL = "C"  # channel-specific $MC_
    AXIS = "A"  # axis-specific $MA_

    @property
    def prefix(self) -> str:
        return f"$M{self.value}_"


class MdType(StrEnum):
    BOOL = "bool"
    INT = "int"
    FLOAT = "float"
    STR = "str"


@dataclass(frozen=True, slots=True)
class MdDef:
    """One machine datum of the manual."""

    number: int
    name: str  # without the $MN_/$MC_/$MA_ prefix, e.g. "MAX_AX_VELO"
    level: MdLevel
    type: MdType
    default: MdValue  # a tuple for array data (one value per index)
    meaning: str
    source: str  # seed line(s), or "[control]" where the seed is silent and the real control is followed
    unit: str = ""
    minimum: float | None = None
    maximum: float | None = None
    length: int = 0  # 0 = scalar; n = array with indices 0..n-1
    allowed: tuple[int, ...] = ()  # enumerations (e.g. MD30240 ENC_TYPE: 0, 1, 4)
    read_only: bool = False  # written by the control only (e.g. MD34093 REFP_CAM_MARKER_DIST)
    nonzero: str = ""  # why 0 cannot be entered ("" = it can): the control divides by it, or nothing works

    @property
    def full_name(self) -> str:
        return f"{self.level.prefix}{self.name}"

    @property
    def label(self) -> str:
        return f"MD{self.number} {self.name}"

    @property
    def is_array(self) -> bool:
        return self.length > 0


class MdValueError(VcError, ValueError):
    """A value a machine datum cannot take; the message names the datum and what it accepts."""


_NUMBER_TEXT = re.compile(r"^[-+]?(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?$")


def checked_value(md: MdDef, raw: object, index: int | None = None) -> MdScalar:
    """``raw`` (one value as read from YAML) converted to the type of ``md`` and checked.

    Numbers that YAML 1.1 leaves as text (``1e6``) are accepted; BOOL data take
    ``true``/``false`` or ``1``/``0`` as on the control; INT data take whole numbers.  A number
    is finite; a datum marked ``nonzero`` refuses 0, and no FLOAT datum takes a value closer to 0
    than ``MIN_MD_MAGNITUDE`` but 0 itself (1e-320 would turn into infinity where the control
    divides by it).  Raises :class:`MdValueError` with a message such as
    ``MD32000 MAX_AX_VELO = -5: below the minimum 0.0 mm/min``.
    """
    label = md.label if index is None else f"{md.label}[{index}]"
    value: MdScalar
    if md.type is MdType.BOOL:
        if isinstance(raw, bool):
            value = raw
        elif isinstance(raw, int) and raw in (0, 1):
            value = bool(raw)
        else:
            raise MdValueError(f"{label}: expected true/false (or 1/0), got {shown(raw)}")
        return value
    if md.type is MdType.STR:
        if not isinstance(raw, str):
            raise MdValueError(f"{label}: expected a name, got {shown(raw)}")
        return raw
    number = as_number(raw)
    if number is None:
        raise MdValueError(f"{label}: expected a number, got {shown(raw)}")
    if md.type is MdType.INT:
        if not float(number).is_integer():
            raise MdValueError(f"{label}: expected a whole number, got {shown(raw)}")
        value = int(number)
    else:
        value = float(number)
    if md.allowed and value not in md.allowed:
        choices = ", ".join(str(choice) for choice in md.allowed)
        raise MdValueError(f"{label} = {shown(raw)}: not allowed; allowed are {choices}")
    if md.minimum is not None and value < md.minimum:
        raise MdValueError(f"{label} = {shown(raw)}: below the minimum {limit_text(md, md.minimum)}")
    if md.maximum is not None and value > md.maximum:
        raise MdValueError(f"{label} = {shown(raw)}: above the maximum {limit_text(md, md.maximum)}")
    if md.nonzero and value == 0:
        raise MdValueError(f"{label} = {shown(raw)}: 0 cannot be entered ({md.nonzero})")
    if value != 0 and abs(value) < MIN_MD_MAGNITUDE:
        raise MdValueError(f"{label} = {shown(raw)}: closer to 0 than {MIN_MD_MAGNITUDE:g}, too fine for the"
                           " control to compute with")
    return value


def limit_text(md: MdDef, limit: float) -> str:
    """A limit of ``md`` with its unit, as messages show it (``0.0 mm/min``, ``15``)."""
    text = str(int(limit)) if md.type is MdType.INT else str(float(limit))
    return f"{text} {md.unit}" if md.unit else text


def shown(raw: object) -> str:
    """A value from a YAML file as a message quotes it (a number too large for :func:`as_number` says so)."""
    beyond = f" (beyond {MAX_MAGNITUDE:g})" if _too_large(raw) else ""
    if isinstance(raw, bool):
        return "true" if raw else "false"
    if isinstance(raw, str):
        return f"'{raw}'{beyond}"
    if isinstance(raw, (int, float)):
        return f"{raw}{beyond}"
    if raw is None:
        return "nothing (null)"
    if isinstance(raw, list):
        return "a list"
    if isinstance(raw, dict):
        return "a mapping"
    return str(raw)


def _too_large(raw: object) -> bool:
    if isinstance(raw, str) and _NUMBER_TEXT.match(raw.strip()):
        raw = float(raw)
    return isinstance(raw, (int, float)) and not isinstance(raw, bool) and abs(raw) > MAX_MAGNITUDE


def as_number(raw: object) -> int | float | None:
    """A number from YAML (also ``1e6``, which YAML 1.1 reads as text) of at most MAX_MAGNITUDE,
    else None: ``"1e400"`` would be infinite, and nothing in a machine file is that large."""
    if isinstance(raw, bool):
        return None
    number: int | float
    if isinstance(raw, (int, float)):
        number = raw
    elif isinstance(raw, str) and _NUMBER_TEXT.match(raw.strip()):
        number = float(raw)
    else:
        return None
    return number if math.isfinite(number) and abs(number) <= MAX_MAGNITUDE else None


_INDEX_SHIFT = 20  # a float's cache key: the MD number (below 2^20) with its array index + 1 above it


class MachineData:
    """Values of one level instance (NCK, a channel or an axis), defaults filled in."""

    __slots__ = ("_floats", "_values", "owner")

    def __init__(self, owner: str, values: Mapping[int, MdValue]):
        self.owner = owner
        self._values = dict(values)
        # the values are fixed once loaded (a change makes a new instance: with_values), so a float
        # asked for once is kept: the IPO cycle asks for the same gear-stage data every cycle
        self._floats: dict[builtins.int, builtins.float] = {}

    def value(self, md: MdDef) -> MdValue:
        try:
            return self._values[md.number]
        except KeyError:
            return md.default

    def float(self, md: MdDef, index: int | None = None) -> builtins.float:
        key = md.number if index is None else md.number | (index + 1) << _INDEX_SHIFT if index >= 0 else -1
        known = self._floats.get(key)
        if known is not None:
            return known
        value = self._indexed(md, index)
        assert isinstance(value, (int, float)) and not isinstance(value, str)
        number = float(value)
        if key >= 0:
            self._floats[key] = number
        return number

    def int(self, md: MdDef, index: builtins.int | None = None) -> builtins.int:
        value = self._indexed(md, index)
        assert isinstance(value, (int, bool))
        return int(value)

    def bool(self, md: MdDef, index: builtins.int | None = None) -> builtins.bool:
        return bool(self._indexed(md, index))

    def str(self, md: MdDef, index: builtins.int | None = None) -> builtins.str:
        return str(self._indexed(md, index))

    def floats(self, md: MdDef) -> tuple[builtins.float, ...]:
        value = self.value(md)
        assert isinstance(value, tuple)
        return tuple(float(v) for v in value)

    def items(self) -> list[tuple[builtins.int, MdValue]]:
        return sorted(self._values.items())

    def with_values(self, values: Mapping[builtins.int, MdValue]) -> MachineData:
        merged = dict(self._values)
        merged.update(values)
        return MachineData(self.owner, merged)

    def _indexed(self, md: MdDef, index: builtins.int | None) -> MdScalar:
        value = self.value(md)
        if isinstance(value, tuple):
            return value[0 if index is None else index]
        return value
