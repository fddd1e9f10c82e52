"""The travel to fixed stop words of a block (seed 003 L37132-37160): ``FXS[ax]=1`` / ``=0``,
``FXST[ax]=<percent>``, ``FXSW[ax]=<width>``, into the block plan for the channel's fixed stops
(vc/core/fixed_stop/).  A value out of range raises 12080 (FXS only 0 or 1; FXST 0 .. 800 %, FXSW
not negative [control]), a name that is no axis of the channel 12550.
"""

from __future__ import annotations

from vc.core.program.commands import FixedStopWords
from vc.core.program.decoder import BlockDecoder
from vc.core.program.program import Assignment
from vc.core.program.sync_actions import FIXED_STOP_WORDS, VariableWrite

__all__ = ["FIXED_STOP_WORDS", "fixed_stop_action", "fixed_stop_word"]

MAX_TORQUE_PERCENT = 800.0  # SD43510 [control]


def _checked(decoder: BlockDecoder, name: str, index: str, value: object) -> tuple[str, float] | None:
    """The word's machine axis and value; None after 12550 (no axis of the channel) or 12080."""
    machine_axis = decoder.machine_axis(index)
    if machine_axis is None:
        decoder.unknown(f"{name}[{index}]")
        return None
    valid = isinstance(value, float) and (
        value in (0.0, 1.0) if name == "FXS"
        else 0.0 <= value <= MAX_TORQUE_PERCENT if name == "FXST" else value >= 0.0)
    if not valid or not isinstance(value, float):
        decoder.fail(12080, decoder.channel.name, decoder.block.label, f"{name}[{index}]={value}")
        return None
    return machine_axis, value


def fixed_stop_action(decoder: BlockDecoder, name: str, index: str, value: float) -> VariableWrite | None:
    """``DO FXS[Y]=1`` / ``FXST[Y]=30`` / ``FXSW[Y]=1`` of a synchronized action (L37125-37131,
    L38047-38110), with the axis as a machine axis; checked as in a block."""
    checked = _checked(decoder, name, index, value)
    return None if checked is None else VariableWrite(name, *checked)


def fixed_stop_word(decoder: BlockDecoder, item: Assignment) -> None:
    checked = _checked(decoder, item.name, item.index, item.value)
    if checked is None:
        return
    machine_axis, value = checked
    words = decoder.plan.fixed_stop.setdefault(machine_axis, FixedStopWords())
    if item.name == "FXS":
        words.switch = int(value)
    elif item.name == "FXST":
        words.torque = value
    else:
        words.window = value
