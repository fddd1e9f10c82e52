"""Alarms of the transforms as values: the NC core raises them, the transforms only decide.

A decision function of the transforms answers a question (may the orthogonal axis be
referenced now? is there a rotary solution for this tool direction?) and returns a
:class:`TransformAlarm` or None.  ``number`` is the project alarm number the NC core raises
(the seeds name none; the texts are in vc/core/alarms.py); ``detail`` is the part of the
alarm text only the decision knows (which function conflicts, what the configuration lacks),
empty where the NC core fills in the axes and values it has itself; ``code`` is the control's
own designation where the seed prints one (Syntec ``COR-153``).

Numbers: 6582x inclined-axis control (seed 000), 6585x five-axis kinematics (seed 001).
"""

from __future__ import annotations

from dataclasses import dataclass

INCLINED_ORDER = 65820  # orthogonal axis referenced while the inclined axis is not at its reference point
INCLINED_G28_BLOCK = 65821  # G28/G30 names the inclined and the orthogonal axis in one block
INCLINED_INCOMPATIBLE = 65822  # a function that cannot run together with inclined-axis control
INCLINED_CONFIGURATION = 65824  # rotary axis, or axes with different increment systems
ROTARY_P_OUT_OF_RANGE = 65850  # Syntec COR-149: G53.1 P other than 0, 1, 2
ROTARY_NO_SOLUTION = 65851  # Syntec COR-153: no rotary solution for this tool direction
ROTARY_RANGE = 65852  # a rotary axis outside its five-axis travel range (Pr3009-3012)
FIVE_AXIS_PROGRAM = 65853  # a five-axis block the control refuses (Syntec HSHP-3551 for G43.4 L2 E / R)


@dataclass(frozen=True, slots=True)
class TransformAlarm:
    number: int  # project alarm number the NC core raises
    source: str  # seed lines
    detail: str = ""  # the alarm text's part that only the decision knows
    code: str = ""  # the control's designation where the seed gives one, e.g. "COR-153"
