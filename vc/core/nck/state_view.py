"""The state machines the NCK publishes, and where their instances are: one row each.

Each row names a state machine declared beside its State enum (``vc/core/state_machine.py`` says
how) and which part of the powered-on NCK keeps the state of each instance.  :func:`state_view`
builds the NCK's :class:`~vc.core.state_machine.StateView` from the rows; :data:`STATE_MACHINES`
lists every state machine (a procedure's variants one by one) for those who need them without an
NC running (the coverage report).  The order of the rows is the order of the reports.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import Any, Generic, TypeVar

from interfaces.signals import MODE_GROUP_INSTANCE
from vc.core.auxiliary.output import AUX_OUTPUT_STATES
from vc.core.axis.command_axis import COMMAND_AXIS_STATES
from vc.core.axis.drive_data_sets import DRIVE_DATA_SET_STATES
from vc.core.axis.index_jog import INDEX_JOG_STATES
from vc.core.axis.jog_keys import JOG_KEY_STATES
from vc.core.axis.jog_target import JOG_TARGET_STATES
from vc.core.axis.plc_axis import FC18_JOB_STATES, PLC_AXIS_TYPES
from vc.core.axis.setpoint_switchover import SETPOINT_SWITCHOVER_STATES
from vc.core.axis.software_cams import SOFTWARE_CAM_STATES
from vc.core.channel.cutting_speed import CUTTING_SPEED_STATES
from vc.core.channel.program_run import CHANNEL_STATES, PROGRAM_STATES
from vc.core.fixed_stop.fixed_stop import FIXED_STOP_STATES
from vc.core.gantry.gantry import GANTRY_STATES
from vc.core.nck.manual_retraction import MANUAL_RETRACTION_STATES
from vc.core.nck.mode_group import MODE_GROUP_STATES
from vc.core.nck.power_on import NckParts
from vc.core.referencing.referencing import REFERENCING
from vc.core.retraction.drive_esr import DRIVE_ESR_STATES
from vc.core.retraction.esr import ESR_RETRACT_STATES, ESR_STOP_STATES
from vc.core.spindle.coupling_state import COUPLING_STATES, FollowingSpindle
from vc.core.spindle.gear_change import GEAR_CHANGE_STATES
from vc.core.spindle.spindle import SPINDLE_MODES
from vc.core.state_machine import InstanceState, StateMachine, StateView, Variants, machines_of, publish

P = TypeVar("P")


class Published(Generic[P]):
    """A state machine and the parts that keep its instances: ``(instance name, part)``."""

    def __init__(self, declaration: StateMachine[P] | Variants[P],
                 instances: Callable[[NckParts], Sequence[tuple[str, P]]]):
        self.declaration = declaration
        self.instances = instances

    def publish(self, parts: NckParts) -> list[InstanceState]:
        return [publish(self.declaration, name, part) for name, part in self.instances(parts)]


PUBLISHED: tuple[Published[Any], ...] = (
    Published(MODE_GROUP_STATES, lambda nck: [(MODE_GROUP_INSTANCE, nck.mode_group)]),
    Published(CHANNEL_STATES, lambda nck: [(channel.name, channel.run) for channel in nck.channels]),
    Published(PROGRAM_STATES, lambda nck: [(channel.name, channel.run) for channel in nck.channels]),
    Published(AUX_OUTPUT_STATES, lambda nck: [(channel.name, channel.aux) for channel in nck.channels]),
    Published(CUTTING_SPEED_STATES, lambda nck: [(channel.name, channel.cutting_speed) for channel in nck.channels]),
    Published(REFERENCING, lambda nck: [(axis.name, nck.referencing.of[axis.name])
                                        for axis in nck.axes if not axis.is_spindle]),
    Published(SPINDLE_MODES, lambda nck: [(spindle.name, spindle) for spindle in nck.spindles]),
    Published(GEAR_CHANGE_STATES, lambda nck: [(spindle.name, spindle.gear_change) for spindle in nck.spindles]),
    Published(COUPLING_STATES, lambda nck: [(spindle.name, FollowingSpindle(nck.couplings.active, spindle.name))
                                            for spindle in nck.spindles]),
    Published(FIXED_STOP_STATES, lambda nck: [(fixed_stop.name, fixed_stop) for fixed_stop in nck.fixed_stops]),
    Published(DRIVE_ESR_STATES, lambda nck: [(axis.name, nck.esr.drives[axis.name]) for axis in nck.axes]),
    Published(DRIVE_DATA_SET_STATES, lambda nck: [(axis.name, axis.data_sets) for axis in nck.axes]),
    Published(SETPOINT_SWITCHOVER_STATES, lambda nck: [(drive.axes[0].name, drive) for drive in nck.shared_drives]),
    Published(ESR_RETRACT_STATES, lambda nck: [(channel.name, channel.esr) for channel in nck.channels
                                               if channel.esr is not None]),
    Published(ESR_STOP_STATES, lambda nck: [(channel.name, channel.esr) for channel in nck.channels
                                            if channel.esr is not None]),
    Published(COMMAND_AXIS_STATES, lambda nck: [(name, command) for channel in nck.channels
                                                for name, command in channel.command_axes.by_name.items()]),
    Published(PLC_AXIS_TYPES, lambda nck: [(name, plc) for channel in nck.channels
                                           for name, plc in channel.plc_axes.by_name.items()]),
    Published(FC18_JOB_STATES, lambda nck: [(name, plc) for channel in nck.channels
                                            for name, plc in channel.plc_axes.by_name.items()]),
    Published(SOFTWARE_CAM_STATES, lambda nck: [(name, cams) for name, cams in nck.software_cams.of.items()]),
    Published(INDEX_JOG_STATES, lambda nck: [(axis.name, axis.index_jog) for axis in nck.axes
                                             if axis.index_jog is not None]),
    Published(JOG_KEY_STATES, lambda nck: [(axis.name, axis.jog.keys) for axis in nck.axes if not axis.is_spindle]),
    Published(JOG_TARGET_STATES, lambda nck: list(nck.manual.jog_targets.of.items())),
    Published(MANUAL_RETRACTION_STATES, lambda nck: [(channel.name, nck.retractions[channel.name])
                                                     for channel in nck.channels]),
    Published(GANTRY_STATES, lambda nck: [(grouping.name, grouping) for grouping in nck.gantries.groupings]),
)

STATE_MACHINES: tuple[StateMachine[Any], ...] = tuple(
    machine for row in PUBLISHED for machine in machines_of(row.declaration))


def state_view(parts: NckParts) -> StateView:
    """Every instance of every published state machine of the NCK built of ``parts``."""
    return StateView([instance for row in PUBLISHED for instance in row.publish(parts)])
