"""Which referencing runs when: traverse keys, channel-specific referencing, G74, aborts.

The NCK holds one :class:`ReferencingControl`.  It owns the :class:`AxisReferencing` of every
axis (spindles synchronise on their own, chapter 13), starts procedures from the traverse
keys in JOG-REF and MDA-REF (the key of the MD34010 direction; either key for distance-coded
systems), gives each running procedure its cycle conditions (feed stop, NC stop, the held
key) and aborts them on reset or when REF is left.

Inclined-axis control (seed 000): the orthogonal axis may start its reference return only
while the inclined axis stands at its reference point (ZPx = 1); otherwise alarm 65820 and the
orthogonal axis does not start (seed 000 L62-66, L321, L375, L380).  This holds for the keys,
G74 and channel-specific referencing alike.  The pairs are those of the channels' active
inclined-axis controls (``order_inclined_pairs``): a control that MD62800-62808 switch off, or
that alarm 65824 leaves off, imposes no order.
"""

from __future__ import annotations

from collections.abc import Sequence

from vc.config import md_dictionary as MD
from vc.config.model import MachineConfig
from vc.core.alarms import AlarmList
from vc.core.axis.axis import MachineAxis
from vc.core.kinematics.inclined_axis import reference_order_alarm
from vc.core.nc_memory import NcMemory
from vc.core.referencing.distance_coded import PassiveMarkWatcher, passive_distance_coded
from vc.core.referencing.referencing import AxisReferencing, Source
from vc.core.referencing.referencing_data import CycleConditions
from vc.core.transforms.inclined_axis_control import InclinedAxisControl, at_reference_point


class ReferencingControl:
    def __init__(self, machine: MachineConfig, axes: Sequence[MachineAxis], memory: NcMemory, dt: float,
                 alarms: AlarmList):
        hold_mode = machine.nck.bool(MD.JOG_INC_MODE_LEVELTRIGGRD)
        self._alarms = alarms
        self.of: dict[str, AxisReferencing] = {
            axis.name: AxisReferencing(axis, memory, hold_mode, dt, alarms) for axis in axes if not axis.is_spindle
        }
        self._axes = {axis.name: axis for axis in axes}
        self._running: list[AxisReferencing] = []  # procedures started and not yet ended
        self._keys = {name: (True, True) for name in self.of}  # as if held: a key must be pressed anew
        self._keys_followed: set[str] = set()  # channels whose keys are followed (REF allows them)
        self._key_direction = {name: 0 for name in self.of}
        self._nc_stopped: set[str] = set()  # axes held by NC stop until NC start (phases 1 and 3)
        self.passive_watchers = [
            PassiveMarkWatcher(axis, encoder, memory.view(axis.name, axis.config.md))
            for axis in axes for encoder in axis.encoders
            if passive_distance_coded(axis, encoder, memory.view(axis.name, axis.config.md))
        ]
        # orthogonal axis -> the inclined-axis control whose inclined axis must be at its reference point
        self._inclined_before: dict[str, InclinedAxisControl] = {}

    def order_inclined_pairs(self, controls: Sequence[InclinedAxisControl]) -> None:
        """The active inclined-axis controls, once the NCK has built them."""
        self._inclined_before = {control.orthogonal.name: control for control in controls}

    @property
    def any_active(self) -> bool:
        return bool(self._running)

    def start(self, axis: str, source: Source, direction: int, cycle: int) -> bool:
        """Start referencing ``axis``; False if it cannot start now (order, enable, wrong key)."""
        control = self._inclined_before.get(axis)
        if control is not None:
            parameters = control.parameters
            alarm = reference_order_alarm(parameters, parameters.orthogonal_axis, at_reference_point(control.inclined))
            if alarm is not None:
                channel = self._axes[axis].channel
                self._alarms.raise_alarm(alarm.number, cycle, channel, axis, control.inclined.name, channel=channel,
                                         axis=axis)
                return False
        procedure = self.of[axis]
        started = procedure.start(source, direction)
        if started:
            self._key_direction[axis] = direction
            if procedure.active and procedure not in self._running:
                self._running.append(procedure)
        return started

    def traverse_keys(self, channel: str, axes: Sequence[MachineAxis], allowed: bool, cycle: int) -> None:
        """JOG-REF / MDA-REF: a traverse key starts referencing of its axis (rising edge).

        Outside REF the keys are not followed; a key already held when REF comes must be
        pressed anew to start referencing.
        """
        if not allowed:
            if channel in self._keys_followed:
                self._keys_followed.discard(channel)
                for axis in axes:
                    if axis.name in self._keys:
                        self._keys[axis.name] = (True, True)
            return
        self._keys_followed.add(channel)
        for axis in axes:
            procedure = self.of.get(axis.name)
            if procedure is None:
                continue
            plus, minus = axis.inputs.key_plus, axis.inputs.key_minus
            was_plus, was_minus = self._keys[axis.name]
            self._keys[axis.name] = (plus, minus)
            if procedure.active:
                continue
            direction = 1 if plus and not was_plus else (-1 if minus and not was_minus else 0)
            if direction:
                self.start(axis.name, Source.KEY, direction, cycle)

    def run(self, cycle: int, channel_feed_disable: dict[str, bool],
            channel_nc_stop: dict[str, tuple[bool, bool, bool]]) -> None:
        """One cycle of every running procedure (before the axes' control loops).

        ``channel_nc_stop`` per channel: (NC stop edge, NC stop level, NC start edge).  NC stop
        acts in phases 1 and 3 only and holds the axis until NC start (seed 003 L1044, L1339).
        """
        for procedure in list(self._running):
            if not procedure.active:
                self._running.remove(procedure)
                self._nc_stopped.discard(procedure.axis.name)
                continue
            axis = procedure.axis
            key = self._key_direction[axis.name]
            stop_edge, stop_level, start_edge = channel_nc_stop.get(axis.channel, (False, False, False))
            if stop_edge and procedure.phase in (1, 3):
                self._nc_stopped.add(axis.name)
            elif start_edge and not stop_level:
                self._nc_stopped.discard(axis.name)
            conditions = CycleConditions(
                feed_stop=axis.inputs.feed_stop or channel_feed_disable.get(axis.channel, False),
                nc_stop=axis.name in self._nc_stopped and procedure.phase in (1, 3),
                key_held=(axis.inputs.key_plus if key > 0 else axis.inputs.key_minus) if key else False,
            )
            procedure.cycle(cycle, conditions)
            if not procedure.active:
                self._running.remove(procedure)
                self._nc_stopped.discard(axis.name)

    def abort_channel(self, channel: str) -> None:
        """Channel or mode-group reset: unfinished axes stay unreferenced (seed 003 L614-626)."""
        for procedure in self.of.values():
            if procedure.axis.channel == channel:
                procedure.abort()

    def abort_key_started(self) -> None:
        """REF was left: referencing started with the keys ends."""
        for procedure in self.of.values():
            if procedure.source is Source.KEY:
                procedure.abort()

