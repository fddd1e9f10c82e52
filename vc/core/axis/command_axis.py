"""Command axes (seed 003 §9.3.2, L11211-11236): a machine axis that a synchronized action moves on
its own, ``POS[<axis>]=<position>`` at ``FA[<axis>]=<feed>``, beside the channel's path.

Its axis interpolator (L11195-11205) runs a straight line (G01) to the end point at FA (mm/min or
deg/min; without FA at MD32060 POS_AX_VELO, L11592-11594; at most MD32000), times the axis's own
feed override DB31.DBB0 (L11597-11599, L12172-12173), ramped with MD32300 (L11624-11627) and
stopping exactly on its end point; the axis's feed stop DB31.DBX4.3 holds it, and it goes only away
from an actuated hardware limit switch.  An FA written while
the axis moves changes its feed; FA for the next motion lasts until the program ends (L11595) or
the channel is reset, a running motion keeps its feed.

While it moves it is a *single axis*, independent of the channel's program: NC stop, the channel's
alarms and the program's end do not stop it (L11215-11227); the reset of its channel does
(L24176-24178), and so does the axis's DB31.DBX2.2 (delete distance to go of a positioning axis,
L12175; the axis reset of a single axis, L11442-11468).  An emergency stop, an alarm's rapid stop or
a program block that moves the axis takes the axis from it, as from every motion owner.  Its
extended stop (``$AA_ESR_TRIGGER``, vc/core/retraction/esr.py) keeps it stopped until one of those
resets: a POS of a synchronized action that goes on firing does not move it again.

States::

    IDLE ──POS[ax]= (the axis at rest or a command axis already)──▶ TRAVERSING ──at the end point──▶ IDLE
    TRAVERSING ──channel reset, DB31.DBX2.2 (braked with MD32300); another owner takes the axis──▶ IDLE
    TRAVERSING, IDLE ──its single-axis ESR stop or retraction──▶ ESR_STOPPED ──channel reset, DB31.DBX2.2──▶ IDLE

A POS on a spindle (L17574-17575) or on an axis another motion owns now (the path, JOG,
referencing, a retraction) is refused with alarm 20141 [control].
"""

from __future__ import annotations

from collections.abc import Callable, Iterable
from enum import Enum

from vc.config import md_dictionary as MD
from vc.core.alarms import AlarmList
from vc.core.axis.axis import MachineAxis
from vc.core.axis.motion import ramp, stopping_velocity
from vc.core.axis.owner import Owner
from vc.core.state_machine import Instance, StateMachine, states, transitions

ALARM_ILLEGAL_AXIS_TYPE = 20141  # a command axis on a spindle or an axis in use (L17574-17575)
ALARM_SOFTWARE_LIMIT = 10720  # the end point beyond a software limit switch, as for a block [control]
_TINY = 1e-9


class CommandState(Enum):
    IDLE = "no command motion"
    TRAVERSING = "POS[ax]= of a synchronized action moves the axis"
    ESR_STOPPED = "stopped by its single-axis ESR until a reset"


class CommandAxis:
    """One machine axis as a command axis (see the module docstring)."""

    def __init__(self, axis: MachineAxis, dt: float, busy: Callable[[], None]):
        self.axis = axis
        self._dt = dt
        self._busy = busy  # tells the channel's command axes to run their cycle
        # mm/min -> mm/s; for a rotary axis MD32060 is rev/min (as MD32000) and FA deg/min
        self._velocity_unit = 6.0 if axis.config.is_rotary else 1.0 / 60.0
        self.state = CommandState.IDLE
        self.target = 0.0
        self.feed = 0.0  # FA[ax] in mm/min (deg/min) for the next motion; 0: MD32060
        self.motion_feed = 0.0  # the running motion's
        self._reset_level = False  # DB31.DBX2.2 as last seen, for its rising edge

    @property
    def busy(self) -> bool:
        """It moves, or stands stopped by its ESR: its cycle must run."""
        return self.state is not CommandState.IDLE

    # ------------------------------------------------------------------ the ESR's view (SingleAxis)
    @property
    def is_single_axis(self) -> bool:
        """A single axis while its command motion runs (L11523-11527)."""
        return self.state is CommandState.TRAVERSING

    def esr_stop(self) -> None:
        """Its extended stop brakes it (or its retraction takes it): it stays stopped until a reset."""
        self.state = CommandState.ESR_STOPPED
        self._reset_level = self.axis.inputs.reset_movement
        self._busy()

    # ------------------------------------------------------------------ commands
    def position(self, target: float, cycle: int, alarms: AlarmList) -> None:
        """POS[ax]=target from a synchronized action."""
        axis = self.axis
        if self.state is CommandState.ESR_STOPPED:
            return  # stopped by its ESR until a reset
        if axis.is_spindle or axis.owner not in (Owner.NONE, Owner.COMMAND):
            alarms.raise_alarm(ALARM_ILLEGAL_AXIS_TYPE, cycle, axis.channel, axis.name, channel=axis.channel,
                               axis=axis.name)
            return
        if axis.software_limits_active and not axis.dyn.limit_minus <= target <= axis.dyn.limit_plus:
            sign = "+" if target > axis.dyn.limit_plus else "-"
            alarms.raise_alarm(ALARM_SOFTWARE_LIMIT, cycle, axis.channel, axis.name, f"POS[{axis.name}]", sign,
                               channel=axis.channel, axis=axis.name)
            return
        if self.state is CommandState.IDLE and axis.owner is Owner.NONE and axis.setpoint == target:
            return  # there already (a WHENEVER action repeats its POS every cycle)
        self.target = target
        if self.state is CommandState.IDLE:
            self._reset_level = axis.inputs.reset_movement
            self.motion_feed = self.feed
        self.state = CommandState.TRAVERSING
        self._busy()
        if axis.owner is Owner.NONE:
            axis.take(Owner.COMMAND)

    def reset(self) -> None:
        """The channel's reset or DB31.DBX2.2: a running motion brakes and ends, an ESR stop ends."""
        if self.state is CommandState.TRAVERSING and self.axis.owner is Owner.COMMAND:
            self.axis.brake()
        self.state = CommandState.IDLE

    # ------------------------------------------------------------------ the cycle
    def cycle(self) -> None:
        """One IPO cycle: DB31.DBX2.2 on its rising edge resets; then the state's own step."""
        level = self.axis.inputs.reset_movement
        edge, self._reset_level = level and not self._reset_level, level
        if edge:
            self.reset()
        elif self.state is CommandState.TRAVERSING:
            self._traverse()

    def _traverse(self) -> None:
        axis = self.axis
        if axis.owner is not Owner.COMMAND:
            self.state = CommandState.IDLE  # braked by an e-stop or an alarm, or taken by the program
            return
        dyn, dt = axis.dyn, self._dt
        remaining = self.target - axis.setpoint
        way = 1.0 if remaining > 0.0 else -1.0
        # FA per minute in the axis's unit; MD32060 in the unit of MD32000
        feed = self.motion_feed / 60.0 if self.motion_feed else \
            axis.config.md.float(MD.POS_AX_VELO) * self._velocity_unit
        inp = axis.inputs
        # the feed stop holds it, and it never runs on into an actuated hardware limit switch (as JOG)
        held = inp.feed_stop or not axis.drive_ready or (inp.hw_limit_plus if way > 0.0 else inp.hw_limit_minus)
        speed = 0.0 if held else min(feed, dyn.max_velocity) * axis.override
        wanted = way * min(speed, stopping_velocity(abs(remaining), dyn.max_accel, dt))
        velocity = ramp(axis.command_velocity, wanted, dyn.max_accel, dt)
        axis.command_velocity = velocity
        axis.setpoint += velocity * dt
        if (self.target - axis.setpoint) * way <= _TINY:
            axis.setpoint = self.target  # lands exactly on its end point
            axis.release()
            self.state = CommandState.IDLE


COMMAND_AXIS_STATES: StateMachine[CommandAxis] = StateMachine(
    __name__, "command_axis", "Command axis: POS[ax]= of a synchronized action, a single axis (seed 003 §9.3.2)",
    Instance.AXIS, states(*CommandState),
    transitions(("IDLE", "TRAVERSING", "POS[ax]= of a synchronized action"),
                ("TRAVERSING", "IDLE", "at its end point; channel reset, DB31.DBX2.2; another owner took it"),
                ("TRAVERSING", "ESR_STOPPED", "its single-axis ESR stop or retraction"),
                ("IDLE", "ESR_STOPPED", "its ESR stop after the motion ended within MD37510"),
                ("ESR_STOPPED", "IDLE", "the channel's reset, DB31.DBX2.2")),
    read=lambda command: command.state)


class CommandAxes:
    """The command axes of one channel: every machine axis of it that is no spindle."""

    def __init__(self, channel: str, axes: Iterable[MachineAxis], alarms: AlarmList, dt: float):
        self.channel = channel
        self.by_name = {axis.name: CommandAxis(axis, dt, self._busy) for axis in axes if not axis.is_spindle}
        self._alarms = alarms
        self.active = False  # a command axis moves or stands stopped by its ESR: the channel runs cycle()

    def _busy(self) -> None:
        self.active = True

    def position(self, name: str, target: float, cycle: int) -> None:
        """POS[name]=target; a spindle has no command axis here: refused like one in use."""
        command = self.by_name.get(name)
        if command is None:
            self._alarms.raise_alarm(ALARM_ILLEGAL_AXIS_TYPE, cycle, self.channel, name, channel=self.channel,
                                     axis=name)
            return
        command.position(target, cycle, self._alarms)

    def set_feed(self, name: str, feed: float) -> None:
        """FA[name]=feed (mm/min or deg/min): for the next motion, and for the running one."""
        command = self.by_name.get(name)
        if command is not None:
            command.feed = feed
            if command.state is CommandState.TRAVERSING:
                command.motion_feed = feed

    def cycle(self) -> None:
        active = False
        for command in self.by_name.values():
            if command.busy:
                command.cycle()
                active = active or command.busy
        self.active = active

    def program_ended(self) -> None:
        """Program end or reset: the programmed FA no longer counts (L11595)."""
        for command in self.by_name.values():
            command.feed = 0.0

    def reset(self) -> None:
        """The channel's reset stops its command axes (L24176-24178)."""
        for command in self.by_name.values():
            if command.busy:
                command.reset()
