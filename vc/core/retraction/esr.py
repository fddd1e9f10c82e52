"""Fast retraction in G33 (LIFTFAST) and NC-controlled extended stop and retract (ESR) of a channel,
with the system variables and synchronized actions that trigger them.

Triggers (seed 003 L8215-8221, L42180-42195):

* fast retraction: NC stop DB21.DBX7.3 from the PLC [INF: the seed says "NC stop (NC/PLC interface
  signal)" and names no address], an alarm that interrupts the program (implicit NC stop), or an
  ESR trigger, while a G33 block runs with LFON;
* ESR: ``$AC_ESR_TRIGGER`` 0 -> 1 (channel) or ``$AA_ESR_TRIGGER[ax]`` 0 -> 1 (single axis), written
  by the program or by a synchronized action such as
  ``IDS=2 WHENEVER ($AC_ALARM_STAT B_AND 'H2000') > 0 DO $AC_ESR_TRIGGER=1``.

Reaction of the channel (SEQ-ESR-2, L42121-42177) per axis with ``$AA_ESR_ENABLE[ax] = 1``:

* MD37500 = 21 (retract axis): leaves the path and moves to its POLF position (POLFMASK axial,
  POLFMLIN linear) at maximum dynamics; without a POLF position in those masks it stops like a 22 [INF];
* MD37500 = 22 (stop axis): the path interpolation goes on for MD21380, then brakes to a stop within
  MD21381 (MD32300 or the deceleration that stops in MD21381, whichever is higher [control]);
* other values (0, and 10/11/12, the drive-autonomous reactions of the drive's own parameters p0888)
  take no part in the NC-controlled reaction [control].

In G33 with LFON the channel trigger is a fast retraction (DILF / ALF or LFPOS); the thread axes
that do not retract follow the spindle on for MD21380 and then brake within MD21381 as the stop
axes do ("Z keeps moving normally until it stops", L42197-42200).  With a transformation active
(the inclined-axis pair) the retract positions are program positions, provided every axis of the
transformation is ESR-enabled; otherwise its group is dissolved and its axes react as machine axes
(L42098-42104).  Under a five-axis tool path a retract axis leaves the path and the other axes go
on along it (POLF of a geometry axis is then its machine axis's position [control]).

An axis in such a reaction keeps its controller enable: alarms that would rapid-stop it (follow-up,
'H2000') wait until its reaction ends (``holds``; the real control delays the alarm reaction of ESR
axes likewise [control]).  In G33, with or without LFON, that covers the whole thread: its axes that are
not ESR-enabled and the master spindle run on with the path [control].  Couplings stay as they are: a
coupled following spindle keeps following its leading spindle while the stop axes run on and brake
(seed 003 L41545-41546).

A single axis - a command axis while a synchronized action's POS moves it (vc/core/axis/command_axis.py,
L11211-11236), or a spindle turning or positioning on its own [INF: the harness has no PLC axes] -
reacts only to its own ``$AA_ESR_TRIGGER`` with MD37510 / MD37511 (stop) or POLFA (retract), and the
channel trigger ignores it (L11505-11558, L11529-11534).  The stop ends the single axis's own
motion, not just its setpoint: what moves it (``SingleAxis``) is stopped with the brake and keeps it
stopped until a reset, so nothing that still asks for motion turns it again (L41528-41530: an
orderly stop).

``$AC_ALARM_STAT`` bits (the seed gives 'H2000' = an alarm with follow-up, L42182-42186; the others
are the project's reading of the control's alarm reactions [control])::

    bit 13 'H2000'  an alarm takes the controller enable (rapid stop, follow-up mode)
    bit  6 'H0040'  an alarm stops the axes of the channel (interpolation stop)
    bit  4 'H0010'  an alarm refuses NC start

Observers see two state machines per channel: the retract motion (``RetractPhase``: IDLE,
RETRACTING) and the stop axes (``StopPhase``: IDLE, RUNNING_ON for MD21380, BRAKING within MD21381).
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass
from enum import Enum
from typing import TYPE_CHECKING, Protocol

from vc.config import md_dictionary as MD
from vc.core.alarms import AlarmList, Reaction
from vc.core.axis.axis import MachineAxis
from vc.core.axis.command_axis import CommandAxes
from vc.core.axis.owner import Owner
from vc.core.interpolation.thread_cutting import ThreadSegment
from vc.core.program.commands import LFPOS, RetractProgramming
from vc.core.program.sync_actions import Reader, SyncAction, VariableWrite
from vc.core.retraction.drive_esr import TRIGGER_CYCLES, DriveEsr
from vc.core.retraction.drive_esr import DriveEsrReaction as DriveReaction
from vc.core.retraction.retract_motion import (
    RetractMotion,
    TransformGroup,
    direction_targets,
    machine_groups,
    retract_groups,
    retract_positions,
    through_transform,
)
from vc.core.state_machine import Instance, StateMachine, states, transitions

if TYPE_CHECKING:
    from vc.core.interpolation.path import PathSegment
    from vc.core.interpolation.tool_path import ToolPathSegment

    Interpolation = PathSegment | ToolPathSegment | ThreadSegment  # what the stop axes run on

RETRACT_AXIS = 21  # MD37500
STOP_AXIS = 22
ALARM_STAT_BITS = ((Reaction.RAPID_STOP, 1 << 13), (Reaction.STOP_AXES, 1 << 6), (Reaction.NC_START_DISABLED, 1 << 4))


class RetractPhase(Enum):
    """The retract motion of a channel's ESR or fast retraction."""

    IDLE = "no retract motion"
    RETRACTING = "the retract axes move to their POLF / LIFTFAST positions"


class StopPhase(Enum):
    """The stop axes of a channel's ESR (and the thread axes of an ESR in G33 with LFON)."""

    IDLE = "no stop reaction"
    RUNNING_ON = "the path runs on for MD21380"
    BRAKING = "the stop axes brake within MD21381"


ESR_RETRACT_STATES: StateMachine[ChannelEsr] = StateMachine(
    __name__, "esr.retract", "Fast retraction and NC-controlled ESR retract of a channel", Instance.CHANNEL,
    states(*RetractPhase),
    transitions(("IDLE", "RETRACTING", "$AC_ESR_TRIGGER, LIFTFAST in G33, POLFA"),
                ("RETRACTING", "IDLE", "at the retract positions")),
    read=lambda esr: esr.retract_phase)

ESR_STOP_STATES: StateMachine[ChannelEsr] = StateMachine(
    __name__, "esr.stop", "NC-controlled ESR stop axes of a channel (MD21380, MD21381)", Instance.CHANNEL,
    states(*StopPhase),
    transitions(("IDLE", "RUNNING_ON", "$AC_ESR_TRIGGER (a stop axis, or G33 with LFON)"),
                ("IDLE", "BRAKING", "$AC_ESR_TRIGGER with MD21380 = 0"),
                ("RUNNING_ON", "BRAKING", "MD21380 elapsed"), ("BRAKING", "IDLE", "the stop axes stand")),
    read=lambda esr: esr.stop_phase)


class NckEsr:
    """NC-wide part: ``$AN_ESR_TRIGGER``, the digital NCK inputs ``$A_IN[n]`` and the drives."""

    def __init__(self, drives: dict[str, DriveEsr]):
        self.drives = drives
        self.generators = [drive for drive in drives.values() if drive.threshold > 0.0]  # may buffer the DC link
        self._speed_watchers = [drive for drive in drives.values() if drive.watches_speed]
        self.trigger = False  # $AN_ESR_TRIGGER
        self._trigger_cycles = 0
        self._reacting = False  # a drive is in its reaction: the drives need their cycle
        self.inputs = 0  # $A_IN[1..8]: DB10.DBB1, set by the PLC [control]

    def cycle(self) -> None:
        for drive in self._speed_watchers:
            drive.watch_speed()
        self._trigger_cycles = self._trigger_cycles + 1 if self.trigger else 0
        if self._trigger_cycles < TRIGGER_CYCLES and not self._reacting:
            return  # nothing can start and nothing runs
        self._reacting = False
        for drive in self.drives.values():
            drive.cycle(self._trigger_cycles)
            self._reacting = self._reacting or drive.reaction is DriveReaction.REACTING


class SingleAxis(Protocol):
    """What moves a single axis on its own (a command axis: vc/core/axis/command_axis.py; a spindle:
    vc/core/spindle/spindle.py), as the ESR sees it."""

    @property
    def is_single_axis(self) -> bool:
        """It moves on its own now, not with the channel's path or a coupling (L11525-11527)."""
        ...

    def esr_stop(self) -> None:
        """The extended stop brakes it, or the retraction takes it: its own motion ends, and it stays
        stopped until a reset."""
        ...


@dataclass(slots=True)
class _StopAxes:
    """The stop axes of a running ESR: the path goes on until ``brake_at``, then stops by ``stopped_by``."""

    brake_at: int
    stopped_by: int
    braking_time: float
    braked: bool = False  # a single axis's brake has been applied

    @classmethod
    def after(cls, cycle: int, delay: float, braking_time: float, dt: float) -> _StopAxes:
        """Triggered in ``cycle``: on for ``delay`` (MD21380 / MD37510), braked within ``braking_time``."""
        return cls(cycle + round(delay / dt), cycle + round((delay + braking_time) / dt), braking_time)

    def deceleration(self, axis: MachineAxis, dt: float) -> float:
        """MD32300, or what stops the axis within the braking time if that is more [control]."""
        return max(axis.dyn.max_accel, abs(axis.command_velocity) / max(self.braking_time, dt))


class ChannelEsr:
    """Trigger variables, synchronized actions and the retract / stop reaction of one channel."""

    def __init__(self, name: str, axes: dict[str, MachineAxis], alarms: AlarmList, dt: float, nck: NckEsr,
                 geometry: dict[str, str], single_axes: Mapping[str, SingleAxis], command_axes: CommandAxes):
        self.name = name
        self.axes = axes
        self._single_axes = single_axes  # what may move the channel's axes on their own (spindles, command axes)
        self.command_axes = command_axes  # POS[ax]= / FA[ax]= of a synchronized action move them
        self._alarms = alarms
        self._dt = dt
        self.nck = nck
        self._geometry = geometry  # geometry axis name -> machine axis
        self.liftfast = 0.0  # $AC_LIFTFAST
        self.trigger = False  # $AC_ESR_TRIGGER
        self.channel_trigger_pending = False  # its rising edge, for the channel to react in this cycle
        self.axis_trigger: dict[str, bool] = dict.fromkeys(axes, False)  # $AA_ESR_TRIGGER
        self.single_axis_retract: dict[str, tuple[int, float]] = {}  # POLFA: axis -> (type, value)
        self.actions: dict[int, SyncAction] = {}
        # the system variables of other functions (the couplings'): their reader and writer
        self.other_variables: tuple[Reader, Callable[[VariableWrite, int], None]] | None = None
        self.motion: RetractMotion | None = None
        self._stop: _StopAxes | None = None
        self._now = 0  # the IPO cycle of the reaction's last step (or its start): where the stop axes are
        self._single_stops: dict[str, _StopAxes] = {}
        self.protected: set[str] = set()  # axes whose alarm reaction waits for their ESR reaction

    # ------------------------------------------------------------------ variables
    def enabled(self, axis: str) -> bool:
        """$AA_ESR_ENABLE[ax]: one enable for the NC-controlled reaction and the drive's own (L41782-41792,
        L42173-42177), kept by the axis's drive."""
        drive = self.nck.drives.get(axis)
        return drive is not None and drive.enabled

    def read(self, name: str, index: str) -> float:
        """A system variable for a synchronized action's condition; KeyError if unknown."""
        if name == "$AC_ALARM_STAT":
            reactions = self._alarms.reactions(self.name)
            return float(sum(bit for reaction, bit in ALARM_STAT_BITS if reactions & reaction.value))
        if name == "$A_IN" and index.isdigit() and 1 <= int(index) <= 8:
            return float(self.nck.inputs >> (int(index) - 1) & 1)
        if name == "$AC_LIFTFAST":
            return self.liftfast
        if name == "$AC_ESR_TRIGGER":
            return float(self.trigger)
        if name == "$AN_ESR_TRIGGER":
            return float(self.nck.trigger)
        axis = self._geometry.get(index, index)
        if name == "$AA_ESR_STAT" and axis in self.nck.drives:
            return float(self.nck.drives[axis].status)
        if name == "$AA_ESR_ENABLE" and axis in self.axes:
            return float(self.enabled(axis))
        if self.other_variables is not None:
            return self.other_variables[0](name, index)
        raise KeyError(name)

    def _synchronized_read(self, name: str, index: str) -> float:
        """``read`` for a synchronized action: $P_ variables are part-program only (L22383-22385 for
        $P_COUP_OFFS); the control refuses them there as a name not defined (12550) [control]."""
        if name.upper().startswith("$P_"):
            raise KeyError(name)
        return self.read(name, index)

    def write(self, write: VariableWrite, cycle: int) -> None:
        """A program assignment or a synchronized action's action, its axis a machine axis of the channel
        (the interpreter maps X to X1 and refuses the others with 12550); a trigger acts on its rising edge."""
        value = bool(write.value)
        if write.name == "$AC_LIFTFAST":
            self.liftfast = write.value
        elif write.name == "$AN_ESR_TRIGGER":
            self.nck.trigger = value
        elif write.name == "$AC_ESR_TRIGGER":
            rising, self.trigger = value and not self.trigger, value
            if rising:
                self.channel_trigger_pending = True
        elif write.name == "$AA_ESR_ENABLE":
            self.nck.drives[write.index].set_enable(value)
        elif write.name == "$AA_ESR_TRIGGER":
            rising, self.axis_trigger[write.index] = value and not self.axis_trigger[write.index], value
            if rising:
                self._single_axis_reaction(write.index, cycle)
        elif write.name == "POS":
            self.command_axes.position(write.index, write.value, cycle)
        elif write.name == "FA":
            self.command_axes.set_feed(write.index, write.value)
        elif self.other_variables is not None:
            self.other_variables[1](write, cycle)

    def add_actions(self, actions: list[SyncAction]) -> None:
        for action in actions:
            self.actions[action.number] = action

    def program_ended(self) -> None:
        """Reset / program end: the modal synchronized actions (ID=) end, the static ones (IDS=) stay;
        the channel and axis triggers go back to 0, so the next 1 is an edge again [control]."""
        self.actions = {number: action for number, action in self.actions.items() if action.static}
        self.command_axes.program_ended()
        self.trigger = False
        self.channel_trigger_pending = False
        self.axis_trigger = dict.fromkeys(self.axis_trigger, False)

    def run_actions(self, cycle: int) -> None:
        """The synchronized actions of this IPO cycle; a condition on an unknown variable raises 12550
        and ends the action (its writes were checked when the block was decoded)."""
        for number, action in list(self.actions.items()):
            try:
                due = action.due(self._synchronized_read)
            except KeyError as error:
                self._alarms.raise_alarm(12550, cycle, self.name, f"ID={number}", str(error),
                                         channel=self.name)
                del self.actions[number]
                continue
            if due:
                for write in action.actions:
                    self.write(write, cycle)

    def single_axis_retract_command(self, axis: str, kind: int, value: float | None) -> None:
        """POLFA(ax, type[, value]); without a value the last one stays (L11560-11578)."""
        if kind == 0:
            self.single_axis_retract.pop(axis, None)
            return
        previous = self.single_axis_retract.get(axis, (kind, 0.0))[1]
        self.single_axis_retract[axis] = (kind, previous if value is None else value)

    # ------------------------------------------------------------------ reactions
    @property
    def running(self) -> bool:
        return self.motion is not None or self._stop is not None or bool(self._single_stops)

    @property
    def retract_phase(self) -> RetractPhase:
        return RetractPhase.IDLE if self.motion is None else RetractPhase.RETRACTING

    @property
    def stop_phase(self) -> StopPhase:
        """Whether the stop axes run on (MD21380) or brake (MD21381); IDLE without a stop reaction."""
        stop = self._stop
        if stop is None:
            return StopPhase.IDLE
        return StopPhase.RUNNING_ON if self._now < stop.brake_at else StopPhase.BRAKING

    def path_runs_on(self, cycle: int) -> bool:
        """The stop axes' delay MD21380: the path goes on whatever holds it."""
        return self._stop is not None and cycle < self._stop.brake_at

    def start_channel_reaction(self, cycle: int, candidates: list[str], segment: Interpolation | None,
                               retract: RetractProgramming, delays: tuple[float, float],
                               transform: TransformGroup | None) -> None:
        """$AC_ESR_TRIGGER: retract axes to POLF, the path (with the stop axes) on for MD21380.

        ``transform``: the active transformation; unless all its axes are ESR-enabled its group is
        dissolved and its axes react as machine axes (seed 003 L42098-42104)."""
        # spindles, and the axes that are single axes at the trigger, take no part (L11529-11534)
        enabled = [name for name in candidates if self.enabled(name) and not self.axes[name].is_spindle
                   and not self._is_single_axis(name)]
        thread = segment if isinstance(segment, ThreadSegment) else None
        thread_axes = {axis.name for axis in thread.axes} if thread is not None else set()
        if transform is not None and not all(self.enabled(name) for name in transform.machine_axes):
            transform = None
        retracting = [name for name in enabled if self.axes[name].config.md.int(MD.ESR_REACTION) == RETRACT_AXIS]
        groups = retract_groups(retract, self.axes, retracting, transform)
        moving = {axis.name for group in groups for axis in group}
        if segment is not None:
            for name in moving:
                segment.release_axis(self.axes[name])
        self.motion = RetractMotion(groups) if groups else None
        self._stop = _StopAxes.after(cycle, *delays, self._dt)
        self._now = cycle
        self.protected = moving | set(enabled)
        if thread is not None:
            # the thread is one interpolation group with its master spindle: the path that runs on for
            # MD21380 is the thread, so its axes that are not ESR-enabled and the spindle stay in it, and
            # a rapid stop waits for them as for the enabled ones - braking them alone would cut the
            # thread (a group is kept whole or not at all, as the transformation's, L42098-42104) [control]
            self.protected |= thread_axes | {thread.spindle.name}

    def start_liftfast(self, retract: RetractProgramming, plane: str, thread: ThreadSegment,
                       default_distance: float, transform: TransformGroup | None,
                       esr: tuple[int, tuple[float, float]] | None) -> None:
        """G33 with LFON interrupted: retract (DILF/ALF or LFPOS).  The thread axes that stay stop at
        MD32300 at once (NC stop, an alarm), or, for an ESR trigger (``esr``: its cycle and MD21380 /
        MD21381), follow the spindle on for MD21380 and then brake within MD21381, as the stop axes
        of an ESR do (L42121-42128, L42197-42200)."""
        if retract.target_mode == LFPOS:
            groups = retract_groups(retract, self.axes, [name for name in self.axes if not self.axes[name].is_spindle],
                                    transform)
        else:
            where = retract_positions(self.axes, transform)
            distance = default_distance if retract.distance is None else retract.distance
            targets = direction_targets(retract.direction, distance, plane, self._geometry, where)
            groups = machine_groups(through_transform([targets] if targets else [], transform), self.axes)
        moving = {axis for group in groups for axis in group}
        for axis in moving:
            thread.release_axis(axis)
        if esr is None:
            for axis in thread.axes:
                axis.brake()  # the thread axis stops at its maximum acceleration
        else:
            cycle, delays = esr
            self._stop = _StopAxes.after(cycle, *delays, self._dt)
            self._now = cycle
        self.motion = RetractMotion(groups) if groups else None
        self.protected = {axis.name for axis in moving}
        if esr is not None:
            # the run-on and braking of the thread axes are the ESR's too, and they follow the master
            # spindle: it turns on with them ("Z keeps moving normally until it stops", L42197-42200) [control]
            self.protected |= {axis.name for axis in thread.axes} | {thread.spindle.name}
        self.liftfast = 1.0

    def _is_single_axis(self, name: str) -> bool:
        single = self._single_axes.get(name)
        return single is not None and single.is_single_axis

    def _single_axis_reaction(self, name: str, cycle: int) -> None:
        """$AA_ESR_TRIGGER[ax]: only a single axis (a command axis moving, a spindle on its own) with
        $AA_ESR_ENABLE reacts."""
        if not self._is_single_axis(name) or not self.enabled(name):
            return  # not a single axis at the trigger: ignored (L11523-11527)
        single = self._single_axes[name]
        axis = self.axes[name]
        md = axis.config.md
        reaction = md.int(MD.ESR_REACTION)
        if reaction == RETRACT_AXIS and name in self.single_axis_retract:
            kind, value = self.single_axis_retract[name]
            group = {axis: value if kind == 1 else axis.setpoint + value}
            if self.motion is None:
                self.motion = RetractMotion([group])
            else:
                self.motion.add(group)  # the running retractions go on as they are
            self.protected.add(name)
            single.esr_stop()  # its own motion ends: it stands at the retract position afterwards
        elif reaction in (RETRACT_AXIS, STOP_AXIS):
            self._single_stops[name] = _StopAxes.after(cycle, md.float(MD.AX_ESR_DELAY_TIME1),
                                                       md.float(MD.AX_ESR_DELAY_TIME2), self._dt)
            self.protected.add(name)

    def cycle(self, cycle: int, segment: Interpolation | None) -> None:
        """One IPO cycle of the running reaction: the retract motions, and after MD21380 the path
        (``segment``: the block's path, tool path or thread) starts braking."""
        self._now = cycle
        if self.motion is not None:
            self.motion.cycle(self._dt)
            if self.motion.finished:
                self.motion = None
        stop = self._stop
        if stop is not None:
            if cycle == stop.brake_at and segment is not None:
                if isinstance(segment, ThreadSegment):
                    for axis in segment.axes:
                        axis.brake(stop.deceleration(axis, self._dt))
                else:
                    segment.accel = max(segment.accel, segment.velocity / max(stop.braking_time, self._dt))
            if cycle >= stop.stopped_by and (segment is None or all(axis.command_velocity == 0.0
                                                                    for axis in segment.axes)):
                self._stop = None
        for name, single in list(self._single_stops.items()):
            axis = self.axes[name]
            # at or after brake_at: with MD37510 = 0 a trigger written by a block comes after this
            # cycle's reaction, so brake_at has passed when the reaction sees it first
            if not single.braked and cycle >= single.brake_at:
                single.braked = True
                axis.brake(single.deceleration(axis, self._dt))
                self._single_axes[name].esr_stop()  # its own motion ends too: nothing turns it again
            if cycle >= single.stopped_by and axis.command_velocity == 0.0:
                del self._single_stops[name]
        if not self.running:
            self.protected = set()

    def holds(self, axis: str) -> bool:
        """The axis's alarm reaction (rapid stop, controller enable off) waits for its ESR reaction."""
        return axis in self.protected and self.axes[axis].owner in (Owner.RETRACT, Owner.PATH, Owner.BRAKE,
                                                                    Owner.SPINDLE, Owner.COUPLING, Owner.COMMAND)
