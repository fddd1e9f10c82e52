"""What the NC publishes for observers besides its interface signals: the states of its state
machines, its alarms and which functions its axes and channels have.

Observers (the interface coverage, and so an operator panel or the FMU's outputs) read the NC
through this module and the :class:`~vc.simulation.lockstep.Simulation` (``state_view()``,
``alarm_list``, ``functions_of()``), never through the parts of the NC core:

``StateView``          every instance of every state machine the NC declares: (machine, instance,
                       state) as names, read when asked (``vc/core/state_machine.py``)
``STATE_MACHINES``     every state machine the NC declares, without an NC running: name, title,
                       what an instance is, states with meanings, transitions with triggers
``ALARM_TEXTS``        every alarm the NC can raise, with its text and source
``PLC_USER_ALARMS``   the numbers the machine's PLC raises through DB2 (700000 ..), its texts the
                       machine file's
``AlarmList``          the NC's alarm list: present, raised (``history``), cleared and by what
                       (``Clear``)
``NcFunction``         a function an axis or a channel has or lacks at a power-on
"""

from __future__ import annotations

from enum import Enum

from vc.config.model import PLC_USER_ALARMS
from vc.core.alarms import ALARM_TEXTS, AlarmList, Clear
from vc.core.nck.state_view import STATE_MACHINES
from vc.core.state_machine import (
    Instance,
    InstanceState,
    StateInfo,
    StateMachine,
    StateReading,
    StateView,
    Transition,
)

__all__ = [
    "ALARM_TEXTS",
    "PLC_USER_ALARMS",
    "STATE_MACHINES",
    "AlarmList",
    "Clear",
    "Instance",
    "InstanceState",
    "NcFunction",
    "StateInfo",
    "StateMachine",
    "StateReading",
    "StateView",
    "Transition",
]


class NcFunction(Enum):
    """A function that only some axes or channels have."""

    SPINDLE = "spindle"  # an axis that is a spindle (MD35000 > 0)
    INCLINED_AXIS = "inclined-axis control"  # a channel whose inclined-axis control is on (seed 000)
    FIVE_AXIS = "five-axis kinematics"  # a channel with usable five-axis kinematics (seed 001)
