"""Command axes (seed 003 §9.3.2, L11211-11236): a machine axis that a synchronized action moves on
its own, ``POS[<axis>]=<position>`` at ``FA[<axis>]=<feed>``, beside the channel's path; and the
positioning axes of the part program (§9.2.2, L11000-11110), ``POS`` / ``POSA``, on the same axis
interpolator.

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

A positioning axis of the program (POSITIONING) is no single axis: it belongs to its channel
(L11044-11066).  NC stop, an alarm that stops the channel's axes and the channel's feed disable
hold it on its ramp and NC start lets it go on; its own override DB31.DBB0 and feed stop DB31.DBX4.3
act on it, the channel's override does not (L11591-11610); DB31.DBX2.2 ends it (its distance to
go deleted, L12175) and the channel's reset stops it.  Its block ends when it meets its motion-end
condition, modal per axis and kept over reset (L10112-10122; FINEA at power-on, L10193): FINEA
the exact stop fine window, COARSEA the coarse window, IPOENDA the end of its interpolation.  While
it moves, DB31.DBX76.5 says "positioning axis" (L12267) and DBD78 holds its FA (L8921).

States::

    IDLE ──POS[ax]= (the axis at rest or a command axis already)──▶ TRAVERSING ──at the end point──▶ IDLE
    TRAVERSING ──channel reset, DB31.DBX2.2 (braked with MD32300); another owner takes the axis──▶ IDLE
    TRAVERSING, IDLE ──its single-axis ESR stop or retraction──▶ ESR_STOPPED ──channel reset, DB31.DBX2.2──▶ IDLE
    IDLE, TRAVERSING ──POS / POSA of the part program──▶ POSITIONING ──at the end point──▶ IDLE
    POSITIONING ──channel reset, DB31.DBX2.2 (braked); another owner takes the axis (the block is lost)──▶ IDLE
    IDLE ──FC18 of the PLC (vc/core/axis/plc_axis.py)──▶ PLC_POSITIONING ──at the end point──▶ IDLE
    PLC_POSITIONING ──FC18 Stop, the PLC's axis reset, the channel's reset of a PLC axis (braked);
                      another owner takes the axis──▶ IDLE

A PLC axis's motion is held as its ``PlcAxis`` says (``plc_held``); the channel's reset and DB31.DBX2.2
leave it alone (the PLC axis has its own reset).  A synchronized action's POS on an axis the PLC holds
or may hold raises the alarm ``plc_refusal`` (20143, 26075, 26076).

An indexing axis with a Hirth joint (MD30505, §11.5 L14030-14060) never stops between two index
positions: NC stop, a stopping alarm, the feed disable, the channel's feed override at 0, the axis's
feed stop DB31.DBX4.3 (or its own override at 0 [INF]) let it run on at the speed it has to the next
index position ahead it can stop on (``stop_at``), where it waits for the hold to go; the channel's
reset, DB31.DBX2.2, FC18 Stop and the PLC's axis reset end its motion there (TRAVERSING to it, no
longer the program's or the PLC's).  Only an emergency stop, an alarm's rapid stop or a drive that
is not ready stop it at once (L14036-14048).

A POS on a spindle (L17574-17575) or on an axis another motion owns now (the path, JOG,
referencing, a retraction, a positioning motion of the program) is refused with alarm 20141 [control].
"""

from __future__ import annotations

from collections.abc import Callable, Iterable
from enum import Enum

from interfaces.signal_groups import PositioningAxisStatus
from vc.config import md_dictionary as MD
from vc.core.alarms import AlarmList
from vc.core.axis.axis import MachineAxis
from vc.core.axis.indexing import ON_POSITION
from vc.core.axis.motion import ramp, stopping_velocity
from vc.core.axis.owner import Owner
from vc.core.interface_map import SignalTable
from vc.core.state_machine import Instance, StateMachine, states, transitions

ALARM_ILLEGAL_AXIS_TYPE = 20141  # a command axis on a spindle or an axis in use (L17574-17575)
ALARM_SOFTWARE_LIMIT = 10720  # the end point beyond a software limit switch, as for a block [control]
_TINY = 1e-9

# The motion-end conditions of a positioning axis (L10112-10122)
MOTION_END_FINE = "FINEA"
MOTION_END_COARSE = "COARSEA"
MOTION_END_IPO = "IPOENDA"


class CommandState(Enum):
    IDLE = "no command motion"
    TRAVERSING = "POS[ax]= of a synchronized action moves the axis"
    ESR_STOPPED = "stopped by its single-axis ESR until a reset"
    POSITIONING = "POS / POSA of the part program moves it as a positioning axis"
    PLC_POSITIONING = "FC18 of the PLC moves it as a PLC axis"


_MOVING = (CommandState.TRAVERSING, CommandState.POSITIONING, CommandState.PLC_POSITIONING)


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
        self.motion_end = MOTION_END_FINE  # FINEA / COARSEA / IPOENDA of the program, modal (L10193)
        self.lost = False  # a positioning motion another owner took: its block cannot end
        self._publish: Callable[[bool, float], None] | None = None  # DB31.DBX76.5 / DBD78
        self._published: tuple[bool, float] = (False, 0.0)
        self.plc_held = False  # a PLC axis's motion is held this cycle (set by its PlcAxis)
        self.plc_refusal = 0  # the alarm of a synchronized action's POS on an axis of the PLC; 0: allowed
        self._hirth = axis.index is not None and axis.index.hirth
        self.stop_at: float | None = None  # a Hirth axis's delayed stop: the index position it stops on
        self._run_on_speed = 0.0  # the speed it runs on at to ``stop_at``

    def publish_to(self, table: SignalTable, area: bytearray) -> None:
        """Write DB31.DBX76.5 and DBD78 of this axis into ``area`` from now on."""
        encode = table.codec(PositioningAxisStatus).encode
        self._publish = lambda positioning, feed: encode(area, PositioningAxisStatus(positioning_axis=positioning,
                                                                                     feed=feed))

    def write_status(self) -> None:
        """DB31.DBX76.5 while the program's positioning motion runs, DBD78 the FA it runs at."""
        positioning = self.state is CommandState.POSITIONING
        status = (positioning, self.motion_feed if positioning else self.feed)
        if status != self._published and self._publish is not None:
            self._published = status
            self._publish(*status)

    @property
    def busy(self) -> bool:
        """It moves, or stands stopped by its ESR: its cycle must run."""
        return self.state is not CommandState.IDLE

    # ------------------------------------------------------------------ the ESR's view (SingleAxis)
    def motion_ended(self) -> bool:
        """A positioning motion of the program has met its motion-end condition (L10112-10122)."""
        if self.state is CommandState.POSITIONING:
            return False
        if self.motion_end == MOTION_END_IPO or self.axis.at_fixed_stop:
            return True  # at a fixed stop the motion has ended there (L37775-37778)
        dyn = self.axis.dyn
        window = dyn.fine_window if self.motion_end == MOTION_END_FINE else dyn.coarse_window
        return abs(self.axis.distance_to_end_point) <= window

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
        if self.plc_refusal:
            alarms.raise_alarm(self.plc_refusal, cycle, axis.channel, axis.name, channel=axis.channel, axis=axis.name)
            return
        if axis.is_spindle or axis.owner not in (Owner.NONE, Owner.COMMAND) or self.state is CommandState.POSITIONING:
            alarms.raise_alarm(ALARM_ILLEGAL_AXIS_TYPE, cycle, axis.channel, axis.name, channel=axis.channel,
                               axis=axis.name)
            return
        minus, plus = axis.software_limits
        if axis.software_limits_active and not minus <= target <= plus:
            sign = "+" if target > plus else "-"
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
        self._aim(target)

    def program_position(self, target: float) -> None:
        """POS / POSA of the part program: the axis interpolator takes the axis to ``target`` at the
        FA in effect (the channel has waited for a POSA motion of the axis to end, and takes the
        axis from a synchronized action's command motion as from any owner)."""
        axis = self.axis
        self.target = target
        self.motion_feed = self.feed
        self.lost = False
        if self.state is not CommandState.TRAVERSING:
            self._reset_level = axis.inputs.reset_movement
        self.state = CommandState.POSITIONING
        axis.take(Owner.COMMAND)
        self._aim(target)
        self._busy()
        self.write_status()

    def plc_position(self, target: float, feed: float) -> None:
        """FC18 of the PLC: the axis interpolator takes the axis to ``target`` at ``feed`` (mm/min or
        deg/min, G94; 0: MD32060); its PlcAxis checked the axis and the end point."""
        self.target = target
        self.motion_feed = feed
        self.lost = False
        self.plc_held = False
        if self.state is CommandState.IDLE:
            self._reset_level = self.axis.inputs.reset_movement
        self.state = CommandState.PLC_POSITIONING
        self.axis.take(Owner.COMMAND)
        self._aim(target)
        self._busy()

    def _aim(self, target: float) -> None:
        """$AA_PROG_INDEX_AX_POS_NO of an indexing axis: the number of the index position at ``target``
        (0: none), until another owner takes the axis (L13779-13800).  A new motion has no delayed stop."""
        self.stop_at = None
        index = self.axis.index
        if index is not None:
            self.axis.programmed_index = index.standing_on(target, ON_POSITION)

    def reset(self) -> None:
        """The channel's reset or DB31.DBX2.2: a running motion brakes and ends, an ESR stop ends;
        a Hirth axis's motion ends on the next index position instead."""
        if self.state in _MOVING and self.axis.owner is Owner.COMMAND:
            if self._hirth and self.axis.command_velocity:
                self._stop_on_next_position()
                return
            self.axis.brake()
        self.state = CommandState.IDLE
        self.stop_at = None
        self.lost = False
        self.write_status()

    def _stop_on_next_position(self) -> None:
        """Reset of a moving Hirth axis: on to the next index position, the motion no one's any more."""
        axis = self.axis
        self.stop_at = self.target = self._next_position(1.0 if axis.command_velocity > 0.0 else -1.0)
        self.state = CommandState.TRAVERSING
        self.lost = False
        self.write_status()

    def _next_position(self, way: float) -> float:
        """The first index position ahead that the axis can stop on from the speed it has."""
        axis = self.axis
        assert axis.index is not None
        velocity = axis.command_velocity
        self._run_on_speed = abs(velocity)
        # its braking distance and one cycle's travel more: the ramp brakes only from the next cycle on
        braking = velocity * velocity / (2.0 * axis.dyn.max_accel) + abs(velocity) * self._dt
        ahead = axis.index.ahead(axis.setpoint, int(way), braking)
        if ahead is None or (ahead - self.target) * way > 0.0:
            return self.target  # its end point comes first
        return ahead

    # ------------------------------------------------------------------ the cycle
    def cycle(self, program_held: bool, channel_override_zero: bool = False) -> None:
        """One IPO cycle: DB31.DBX2.2 on its rising edge resets; then the state's own step.
        ``program_held``: NC stop, a stopping alarm or the feed disable of the channel hold a
        positioning motion of its program; the channel's feed override at 0 holds an indexing
        axis's too (L13955-13961), which the channel's override does not move otherwise."""
        level = self.axis.inputs.reset_movement
        edge, self._reset_level = level and not self._reset_level, level
        if edge and self.state is not CommandState.PLC_POSITIONING:
            self.reset()
        elif self.state is CommandState.TRAVERSING:
            self._traverse(False)
        elif self.state is CommandState.POSITIONING:
            self._traverse(program_held or (channel_override_zero and self.axis.index is not None))
        elif self.state is CommandState.PLC_POSITIONING:
            self._traverse(self.plc_held)

    def _traverse(self, program_held: bool) -> None:
        axis = self.axis
        if axis.owner is not Owner.COMMAND:
            # braked by an e-stop or an alarm, or taken by the program: a positioning block is lost;
            # a fixed stop found on the way ends the motion there (seed 003 L37306, L37775-37778)
            self.lost = self.state in (CommandState.POSITIONING, CommandState.PLC_POSITIONING) \
                and not axis.at_fixed_stop
            self.state = CommandState.IDLE
            self.write_status()
            return
        dyn, dt = axis.dyn, self._dt
        remaining = self.target - axis.setpoint
        way = 1.0 if remaining > 0.0 else -1.0
        # FA per minute in the axis's unit; MD32060 in the unit of MD32000
        feed = self.motion_feed / 60.0 if self.motion_feed else \
            axis.config.md.float(MD.POS_AX_VELO) * self._velocity_unit
        inp = axis.inputs
        # the feed stop holds it, and it never runs on into an actuated hardware limit switch (as JOG)
        # travel to fixed stop waits for the PLC's enable DB31.DBX3.1 (seed 003 L37221-37232)
        hold = program_held or inp.feed_stop or axis.fixed_stop_waits
        if self._hirth:
            if hold or axis.override == 0.0 or (self.stop_at is not None and self.state is CommandState.TRAVERSING):
                if self.stop_at is None:
                    self.stop_at = self._next_position(way)
                remaining = self.stop_at - axis.setpoint
                feed = self._run_on_speed
            else:
                self.stop_at = None
                feed = min(feed, dyn.max_velocity) * axis.override
            hold = False
        else:
            feed = min(feed, dyn.max_velocity) * axis.override
        held = hold or not axis.drive_ready or (inp.hw_limit_plus if way > 0.0 else inp.hw_limit_minus)
        speed = 0.0 if held else feed
        wanted = way * min(speed, stopping_velocity(abs(remaining), dyn.max_accel, dt))
        velocity = ramp(axis.command_velocity, wanted, dyn.max_accel, dt)
        axis.command_velocity = velocity
        axis.setpoint += velocity * dt
        if self.stop_at is not None and self.stop_at != self.target and (self.stop_at - axis.setpoint) * way <= _TINY:
            axis.setpoint = self.stop_at  # a Hirth axis stands on the index position until the hold goes
            axis.command_velocity = 0.0
        elif (self.target - axis.setpoint) * way <= _TINY:
            self.stop_at = None
            axis.setpoint = self.target  # lands exactly on its end point
            axis.release()
            positioning = self.state is CommandState.POSITIONING
            self.state = CommandState.IDLE
            if positioning:
                self.write_status()


COMMAND_AXIS_STATES: StateMachine[CommandAxis] = StateMachine(
    __name__, "command_axis", "Command axis: POS[ax]= of a synchronized action, a single axis (seed 003 §9.3.2);"
    " a positioning axis of the program (§9.2.2)",
    Instance.AXIS, states(*CommandState),
    transitions(("IDLE", "TRAVERSING", "POS[ax]= of a synchronized action"),
                ("TRAVERSING", "IDLE", "at its end point; channel reset, DB31.DBX2.2; another owner took it"),
                ("TRAVERSING", "ESR_STOPPED", "its single-axis ESR stop or retraction"),
                ("IDLE", "ESR_STOPPED", "its ESR stop after the motion ended within MD37510"),
                ("ESR_STOPPED", "IDLE", "the channel's reset, DB31.DBX2.2"),
                ("IDLE", "POSITIONING", "POS / POSA of the part program"),
                ("TRAVERSING", "POSITIONING", "POS / POSA of the part program takes the axis"),
                ("POSITIONING", "IDLE", "at its end point; channel reset, DB31.DBX2.2; another owner took it"),
                ("IDLE", "PLC_POSITIONING", "FC18 Start of the PLC"),
                ("PLC_POSITIONING", "IDLE", "at its end point; FC18 Stop, the PLC's axis reset, the channel's reset"
                 " of a PLC axis; another owner took it")),
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
            if command.state in (CommandState.TRAVERSING, CommandState.POSITIONING):
                command.motion_feed = feed
            command.write_status()

    def cycle(self, program_held: bool, channel_override_zero: bool = False) -> None:
        active = False
        for command in self.by_name.values():
            if command.busy:
                command.cycle(program_held, channel_override_zero)
                active = active or command.busy
        self.active = active

    def program_ended(self) -> None:
        """Program end or reset: the programmed FA no longer counts (L11595)."""
        for command in self.by_name.values():
            command.feed = 0.0
            command.write_status()

    # ------------------------------------------------------------------ the program's positioning axes
    def program_position(self, name: str, target: float) -> None:
        """POS[name]= / POSA[name]= of the channel's program (the decoder checked the axis)."""
        self.by_name[name].program_position(target)

    def positioning(self, name: str) -> bool:
        """The program's positioning motion of ``name`` runs (a POSA the program must wait for)."""
        command = self.by_name.get(name)
        return command is not None and command.state is CommandState.POSITIONING

    def motion_ended(self, names: Iterable[str]) -> bool:
        """Every axis of ``names`` has met its motion-end condition."""
        return all(self.by_name[name].motion_ended() for name in names)

    def any_positioning(self) -> bool:
        return self.active and any(command.state is CommandState.POSITIONING for command in self.by_name.values())

    def lost(self, names: Iterable[str]) -> bool:
        """A positioning motion of ``names`` was taken by another owner (an alarm's rapid stop)."""
        return any(self.by_name[name].lost for name in names)

    def set_motion_end(self, name: str, condition: str) -> None:
        self.by_name[name].motion_end = condition

    def reset(self) -> None:
        """The channel's reset stops its command axes (L24176-24178); a PLC axis has its own reset."""
        for command in self.by_name.values():
            if command.busy and command.state is not CommandState.PLC_POSITIONING:
                command.reset()
