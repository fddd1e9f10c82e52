"""The end point of a rotary axis's absolute and incremental values (seed 003 chapter 10).

A rotary axis with modulo (MD30310 = 1, L12700-12740) counts on without limit inside the NC: its
position is only shown inside the modulo range MD30340 .. MD30340 + MD30330 (``MachineAxis.shown``).
A program's absolute value is a position inside that range and the way to it is chosen from where
the axis stands (L12980-13070):

* ``AC(v)``: positive when v lies above the axis's modulo position, negative when below;
* G90 ``C=v``: the same, or the shortest way with MD30455 bit 2 (L12758-12766);
* ``ACP(v)`` / ``ACN(v)``: in the positive / negative direction;
* ``DC(v)``: the shortest way, positive when both are 180 degrees (L13046-13048);
* ``IC(v)``, G91: v is the way itself, any size, its sign the direction (L13083-13100).

A rotary axis without modulo (L13110-13180) goes to ``AC(v)`` as a linear axis does, any value;
``DC(v)`` (0 .. 359.999) takes the shortest way as on a modulo axis.  Refused: ACP / ACN without
modulo (16810 / 16820), DC on a linear axis (16800), a modulo position outside the range (16830).
"""

from __future__ import annotations

from vc.config import md_dictionary as MD
from vc.config.model import AxisConfig

ALARM_DC_NOT_ALLOWED = 16800  # L13164
ALARM_ACP_NOT_ALLOWED = 16810  # L13123
ALARM_ACN_NOT_ALLOWED = 16820  # L13123-13124
ALARM_WRONG_MODULO_POSITION = 16830  # L13150-13152
MISC_G90_SHORTEST_WAY = 1 << 2  # MD30455 bit 2: G90 on a modulo axis positions as DC (L12758-12766)
ROTARY_MODES = ("DC", "ACP", "ACN")
_FULL_TURN = 360.0


def modulo_range_of(config: AxisConfig) -> tuple[float, float] | None:
    """(MD30340 start, MD30330 size) of a modulo rotary axis, None for any other axis."""
    md = config.md
    if config.is_rotary and md.bool(MD.ROT_IS_MODULO):
        return md.float(MD.MODULO_RANGE_START), md.float(MD.MODULO_RANGE)
    return None


def end_point(config: AxisConfig, start: float, mode: str, value: float) -> tuple[float, int]:
    """The NC's end point of ``value`` written with ``mode`` ("AC", "IC", "DC", "ACP", "ACN", or
    "G90" for a plain absolute value) for an axis that stands at ``start``, and 0; or (start, the
    alarm number)."""
    if mode == "IC":
        return start + value, 0
    modulo = modulo_range_of(config)
    if modulo is None:
        if mode in ("AC", "G90"):
            return value, 0
        if mode == "DC" and config.is_rotary:
            return _to_position(start, (0.0, _FULL_TURN), value, "DC")
        alarms = {"DC": ALARM_DC_NOT_ALLOWED, "ACP": ALARM_ACP_NOT_ALLOWED}
        return start, alarms.get(mode, ALARM_ACN_NOT_ALLOWED)
    if mode == "G90":
        mode = "DC" if config.md.int(MD.MISC_FUNCTION_MASK) & MISC_G90_SHORTEST_WAY else "AC"
    return _to_position(start, modulo, value, mode)


def _to_position(start: float, modulo: tuple[float, float], value: float, mode: str) -> tuple[float, int]:
    begin, size = modulo
    if not begin <= value < begin + size:
        return start, ALARM_WRONG_MODULO_POSITION
    here = begin + (start - begin) % size
    if mode == "AC":
        way = value - here
    elif mode == "ACP":
        way = (value - here) % size
    elif mode == "ACN":
        way = -((here - value) % size)
    else:  # DC: the shorter way, positive on a tie
        way = (value - here) % size
        if way > size / 2.0:
            way -= size
    return start + way, 0
