"""The NCK's reactions to alarms: rapid stop and follow-up, and the controller enable given back.

An axis alarm whose reaction is a rapid stop takes the axis out of position control (servo off);
when the last such alarm is cleared (reset), the NC gives the axis its controller enable back.  The
reactions run after extended stop and retract in the IPO cycle: an axis whose channel or drive is
retracting or stopping in a controlled way keeps doing that first, and its rapid stop waits
(seed 003 L41550-41556: the drive retracts autonomously even when the NC fails) [control].
Emergency stop has its own function in the NCK and is not handled here.
"""

from __future__ import annotations

from vc.core.alarms import AlarmList, Reaction
from vc.core.axis.axis import MachineAxis
from vc.core.channel.channel import Channel
from vc.core.retraction.esr import NckEsr
from vc.core.spindle.polygon import PolygonTurning

EMERGENCY_STOP_ALARM = 3000
AXIS_BRAKES_ITSELF_ALARM = 21612  # controller enable reset while moving: the axis brakes on its own


class AlarmReactions:
    def __init__(self, alarms: AlarmList, axes: list[MachineAxis], axes_by_name: dict[str, MachineAxis],
                 channels_by_name: dict[str, Channel], esr: NckEsr, polygons: list[PolygonTurning]):
        self.alarms = alarms
        self.axes = axes
        self.axes_by_name = axes_by_name
        self.channels_by_name = channels_by_name
        self.esr = esr
        self.polygons = polygons
        self._alarm_count = 0  # alarms of the history already reacted to
        self._servo_held_by_alarm: set[str] = set()  # axes an alarm took the controller enable from
        self._servo_check_version = -1
        self._rapid_stop_waiting: set[str] = set()  # axes whose alarm reaction waits for their ESR reaction

    def react(self, emergency_stop: bool) -> None:
        """React to the alarms raised since the last cycle; give back the controller enable of the axes
        no alarm holds any more (the emergency stop's acknowledgement gives back every enable)."""
        history = self.alarms.history
        if self.polygons and len(history) > self._alarm_count:
            for polygon in self.polygons:
                polygon.alarms_raised(history[self._alarm_count:])
        for alarm in history[self._alarm_count:]:
            if Reaction.RAPID_STOP not in alarm.reaction or alarm.number in (AXIS_BRAKES_ITSELF_ALARM,
                                                                              EMERGENCY_STOP_ALARM):
                continue  # 21612 brakes on its own; the emergency stop has its own function
            for axis in (self.axes_by_name[alarm.axis],) if alarm.axis else self.axes:
                if self._in_esr_reaction(axis):
                    self._rapid_stop_waiting.add(axis.name)  # the retract / stop comes first [control]
                    continue
                axis.rapid_stop(then_servo_off=True)
                self._servo_held_by_alarm.add(axis.name)
        for name in sorted(self._rapid_stop_waiting) if self._rapid_stop_waiting else ():
            axis = self.axes_by_name[name]
            if not self._in_esr_reaction(axis):
                self._rapid_stop_waiting.discard(name)
                if any(Reaction.RAPID_STOP in alarm.reaction for alarm in self.alarms.present):
                    axis.rapid_stop(then_servo_off=True)
                    self._servo_held_by_alarm.add(name)
        self._alarm_count = len(history)
        if self._servo_held_by_alarm and self.alarms.version != self._servo_check_version \
                and not emergency_stop:  # the e-stop acknowledgement gives every enable back
            self._servo_check_version = self.alarms.version
            holding = set()
            for alarm in self.alarms.present:
                if Reaction.RAPID_STOP in alarm.reaction:
                    holding |= {alarm.axis} if alarm.axis else set(self.axes_by_name)
            for name in sorted(self._servo_held_by_alarm - holding):
                self.axes_by_name[name].restore_servo()
            self._servo_held_by_alarm &= holding

    def _in_esr_reaction(self, axis: MachineAxis) -> bool:
        """The NC-controlled reaction of its channel or its drive's own reaction runs: the drive
        retracts autonomously even when the NC fails (seed 003 L41550-41556)."""
        drive = self.esr.drives.get(axis.name)
        if drive is not None and drive.reacting:
            return True
        channel = self.channels_by_name.get(axis.channel)
        return channel is not None and channel.esr is not None and channel.esr.holds(axis.name)
