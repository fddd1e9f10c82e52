"""The travel to fixed stop words of a block (seed 003 L37132-37160): ``FXS[ax]=1`` / ``=0``,
``FXST[ax]=<percent>``, ``FXSW[ax]=<width>``, into the block plan for the channel's fixed stops
(vc/core/fixed_stop/).  A value out of range raises 12080 (FXS only 0 or 1; FXST 0 .. 800 %, FXSW
not negative [control]), a name that is no axis of the channel 12550.
"""

from __future__ import annotations

from vc.core.program.commands import FixedStopWords
from vc.core.program.decoder import BlockDecoder
from vc.core.program.program import Assignment

FIXED_STOP_WORDS = ("FXS", "FXST", "FXSW")
MAX_TORQUE_PERCENT = 800.0  # SD43510 [control]


def fixed_stop_word(decoder: BlockDecoder, item: Assignment) -> None:
    value = item.value
    machine_axis = decoder.machine_axis(item.index)
    if machine_axis is None:
        decoder.unknown(f"{item.name}[{item.index}]")
        return
    valid = isinstance(value, float) and (
        value in (0.0, 1.0) if item.name == "FXS"
        else 0.0 <= value <= MAX_TORQUE_PERCENT if item.name == "FXST" else value >= 0.0)
    if not valid or not isinstance(value, float):
        decoder.fail(12080, decoder.channel.name, decoder.block.label, f"{item.name}[{item.index}]={value}")
        return
    words = decoder.plan.fixed_stop.setdefault(machine_axis, FixedStopWords())
    if item.name == "FXS":
        words.switch = int(value)
    elif item.name == "FXST":
        words.torque = value
    else:
        words.window = value
