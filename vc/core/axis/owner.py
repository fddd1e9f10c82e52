"""Who moves an axis: one motion owner at a time gives the axis its position setpoint.

Motion owners::

    NONE ──key held in JOG──▶ JOG ──key released, stopped──▶ NONE
    NONE ──block with this axis──▶ PATH ──block end──▶ NONE
    NONE ──referencing started──▶ REF ──referenced, aborted──▶ NONE
    NONE ──spindle turns (M3/M4, SPOS, oscillation)──▶ SPINDLE ──stands──▶ NONE
    any ──e-stop, enable removed, hardware limit──▶ BRAKE ──standstill──▶ NONE
    PATH / NONE ──fast retraction, ESR retract──▶ RETRACT ──at the retract position──▶ NONE
    NONE ──POS[ax]= of a synchronized action──▶ COMMAND ──at its end point──▶ NONE
"""

from __future__ import annotations

from enum import Enum


class Owner(Enum):
    NONE = "none"
    JOG = "jog"
    PATH = "path"
    REF = "ref"
    BRAKE = "brake"
    SPINDLE = "spindle"  # a spindle turning, oscillating or positioning on its own (vc/core/spindle/spindle.py)
    COUPLING = "coupling"  # the following spindle of a coupling (vc/core/spindle/coupling.py)
    # the orthogonal axis carried along by its inclined axis (vc/core/transforms/inclined_axis_control.py)
    TRANSFORM = "transform"
    RETRACT = "retract"  # a retract motion at maximum dynamics (LIFTFAST, ESR: vc/core/retraction/retract_motion.py)
    COMMAND = "command"  # a command axis, moved on its own by a synchronized action (vc/core/axis/command_axis.py)
