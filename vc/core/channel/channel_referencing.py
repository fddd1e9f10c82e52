"""Channel-specific referencing (seed 003 §4.3): DB21.DBX1.0 in JOG-REF or MDA-REF references the
channel's axes in the order of MD34110 (ascending; equal numbers together; 0 and -1 take no part)
and reports DB21.DBX33.0 while it runs.

One group of axes at a time::

    idle ──DB21.DBX1.0 (channel in reset)──▶ group started ──every axis of it DONE──▶ next group
    a procedure aborted (alarm, reset), or the order rule refusing a start ──▶ idle
"""

from __future__ import annotations

from collections.abc import Sequence

from vc.config import md_dictionary as MD
from vc.core.alarms import STOP_AXES, AlarmList
from vc.core.axis.axis import MachineAxis
from vc.core.channel.referencing_control import ReferencingControl
from vc.core.referencing.referencing import Source, State


class ChannelReferencing:
    def __init__(self, name: str, axes: Sequence[MachineAxis], referencing: ReferencingControl, alarms: AlarmList):
        self.name = name
        self._axes = axes
        self._referencing = referencing
        self._alarms = alarms
        self.groups: list[list[str]] = []  # groups still to do, MD34110 order
        self._group_started = False

    @property
    def active(self) -> bool:
        return bool(self.groups)

    def start(self) -> None:
        """DB21.DBX1.0: reference the channel's axes in the order of MD34110 (seed 003 L667-683)."""
        if self.groups:
            return
        numbers: dict[int, list[str]] = {}
        for axis in self._axes:
            number = axis.config.md.int(MD.REFP_CYCLE_NR)
            if not axis.is_spindle and number > 0:
                numbers.setdefault(number, []).append(axis.name)
        self.groups = [numbers[number] for number in sorted(numbers)]
        self._group_started = False

    def cancel(self) -> None:
        """Reset: the groups not yet done are not referenced."""
        self.groups = []

    def cycle(self, cycle: int) -> None:
        """The running group: start its axes, then wait until they are referenced."""
        group = self.groups[0]
        procedures = [self._referencing.of[name] for name in group]
        if not self._group_started:
            for name, procedure in zip(group, procedures, strict=True):
                if not procedure.active and not self._referencing.start(name, Source.CHANNEL, 0, cycle):
                    if self._alarms.reactions(self.name) & STOP_AXES:
                        self.groups = []  # the order rule (or another alarm) ends it
                    return  # wait for the enables
            self._group_started = True
            return
        if any(procedure.state is State.IDLE for procedure in procedures):
            self.groups = []  # aborted (alarm or reset): the channel referencing ends
            return
        if all(procedure.state is State.DONE for procedure in procedures):
            self.groups.pop(0)
            self._group_started = False
