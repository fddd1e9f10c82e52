"""Gantry axes (seed 003 chapter 12): a leading axis and its synchronized followers, one IPO cycle at a time.

One :class:`GantryGrouping` per grouping of MD37100 (tens digit 0 = leading axis, 1 = following
axis, units digit = the grouping 1..8).  The program, JOG and the PLC move the leading axis only;
each following axis takes the leading axis's setpoint (L14576-14578) and its traverse keys are
ignored (L15570-15573).  The actual-value difference of each follower against the leading axis is
monitored: beyond MD37110 the warning DB31.DBX101.3 and message 10652, gone below the limit
(L14467-14476); beyond the trip limit (MD37120 synchronized, MD37130 not yet synchronized) alarm
10653 and DB31.DBX101.2, and the whole grouping stops (L14488-14501, L14588).  Referencing and
synchronization follow the seed's procedure (§12.3, L14640-14748)::

    NOT_REFERENCED ─leading axis's REF key (JOG-REF / MDA-REF), G74, channel REF─▶ LEADER_REFERENCING
    LEADER_REFERENCING ─leading axis referenced─▶ FOLLOWER_REFERENCING (each follower in turn, the
                        leading axis runs coupled, L14677-14687)
    FOLLOWER_REFERENCING ─all referenced, difference to the target <= MD37110 (> 0)─▶ SYNC_RUN
                         ─all referenced, difference beyond MD37110 (or MD37110 = 0)─▶ WAITING_FOR_START
    WAITING_FOR_START (DBX101.4 = 1) ─DBX29.4 rises in JOG-REF, no axis referencing─▶ SYNC_RUN
    SYNC_RUN ─every axis uncoupled at the target at MD34070, exact stop fine─▶ SYNCHRONIZED (DBX101.5 = 1)
    SYNCHRONIZED ─beyond the trip limit─▶ TRIPPED (alarm 10653, DBX101.2, every axis stops)
    SYNCHRONIZED ─an axis in follow-up / loses its reference─▶ WAITING_FOR_START / NOT_REFERENCED
    WAITING_FOR_START ─back in position control within MD36030, DBX29.5 = 0─▶ SYNCHRONIZED (12.3.2)
    TRIPPED ─reset─▶ WAITING_FOR_START (referenced) / NOT_REFERENCED
    any ─reset─▶ the synchronization run is cancelled: WAITING_FOR_START
    MD37140 = 1 ─power on─▶ BROKEN_UP (the axes travel on their own, nothing is monitored, L14594-14612)

The target of the synchronization run is the leading axis's reference point value MD34100 when
the run comes from referencing (L14644-14649), the leading axis's actual position when the PLC
starts it after the synchronism was lost (L14767-14786).  MD37150 bit 0 (extended monitoring,
L14517-14547): a broken-up grouping and one in follow-up are monitored as well once referenced;
a trip writes the difference into MD37135, and while MD37135 is not 0 every reset brings 10653
back.  Bit 2 suppresses message 10655.  Machines without a gantry build no grouping, and a
grouping at rest costs the cycle one test (``busy``).
"""

from __future__ import annotations

from collections.abc import Callable
from enum import Enum

from interfaces.signal_groups import GantryRequests, GantryStatus
from vc.config import md_dictionary as MD
from vc.config.machine_data import MachineData
from vc.core.alarms import AlarmList
from vc.core.axis.axis import MachineAxis
from vc.core.axis.motion import ramp, stopping_velocity
from vc.core.axis.owner import Owner
from vc.core.interface_map import SignalTable
from vc.core.nc_memory import NcMemory
from vc.core.referencing.referencing import AxisReferencing, Source
from vc.core.state_machine import Instance, StateMachine, states, transitions

ALARM_WARNING_LIMIT = 10652
ALARM_ERROR_LIMIT = 10653
ALARM_WAITING_FOR_START = 10654
ALARM_SYNCHRONIZING = 10655
EXTENDED_MONITORING, NO_SYNC_MESSAGE = 1 << 0, 1 << 2  # MD37150 bits 0 and 2


# the channel's referencing control starts a procedure: (axis, source, key direction, cycle) -> started
StartReferencing = Callable[[str, Source, int, int], bool]


class State(Enum):
    BROKEN_UP = "broken up (MD37140 = 1): the axes travel on their own, nothing is monitored"
    NOT_REFERENCED = "coupled, not referenced: the followers take the leading axis's setpoint"
    LEADER_REFERENCING = "part 1: the leading axis references, the followers run coupled"
    FOLLOWER_REFERENCING = "part 2: a following axis references, the leading axis runs coupled"
    WAITING_FOR_START = "referenced, not synchronized: waiting for DB31.DBX29.4 (DBX101.4 = 1, message 10654)"
    SYNC_RUN = "part 3: every axis travels uncoupled to the target position (message 10655)"
    SYNCHRONIZED = "synchronized (DBX101.5 = 1): coupled, the difference monitored against MD37110 / MD37120"
    TRIPPED = "beyond the trip limit: alarm 10653, DBX101.2, the grouping stands until reset"


def _state(grouping: GantryGrouping) -> State:
    return grouping.state


GANTRY_STATES: StateMachine[GantryGrouping] = StateMachine(
    __name__, "gantry", "Gantry grouping: referencing, synchronization and monitoring (seed 003 chapter 12)",
    Instance.AXIS, states(*State),
    transitions(("NOT_REFERENCED", "LEADER_REFERENCING", "the leading axis starts referencing"),
                ("LEADER_REFERENCING", "FOLLOWER_REFERENCING", "the leading axis is referenced"),
                ("LEADER_REFERENCING", "NOT_REFERENCED", "referencing aborted (reset, REF left, an alarm)"),
                ("FOLLOWER_REFERENCING", "NOT_REFERENCED", "referencing aborted (reset, REF left, an alarm)"),
                ("FOLLOWER_REFERENCING", "SYNC_RUN", "all referenced, the difference within MD37110"),
                ("FOLLOWER_REFERENCING", "WAITING_FOR_START", "all referenced, the difference beyond MD37110"),
                ("WAITING_FOR_START", "SYNC_RUN", "DB31.DBX29.4 of the leading axis in JOG-REF"),
                ("WAITING_FOR_START", "SYNCHRONIZED", "automatic synchronization: back in position control"
                 " within MD36030, DBX29.5 = 0"),
                ("WAITING_FOR_START", "LEADER_REFERENCING", "the leading axis is referenced again"),
                ("SYNC_RUN", "SYNCHRONIZED", "every axis at the target"),
                ("SYNC_RUN", "WAITING_FOR_START", "reset, an alarm"),
                ("SYNCHRONIZED", "TRIPPED", "the difference beyond MD37120"),
                ("WAITING_FOR_START", "TRIPPED", "the difference beyond MD37130"),
                ("NOT_REFERENCED", "TRIPPED", "the difference beyond MD37130"),
                ("LEADER_REFERENCING", "TRIPPED", "the difference beyond MD37130"),
                ("FOLLOWER_REFERENCING", "TRIPPED", "the difference beyond MD37130"),
                ("SYNCHRONIZED", "WAITING_FOR_START", "an axis in follow-up: the synchronism is lost"),
                ("SYNCHRONIZED", "LEADER_REFERENCING", "the leading axis is referenced again"),
                ("SYNCHRONIZED", "NOT_REFERENCED", "an axis lost its reference (PRESET, parked)"),
                ("TRIPPED", "WAITING_FOR_START", "reset, every axis referenced"),
                ("TRIPPED", "NOT_REFERENCED", "reset, an axis not referenced"),
                ("BROKEN_UP", "TRIPPED", "extended monitoring (MD37150 bit 0): the difference beyond MD37120")),
    read=_state)

_RUNNING = (State.LEADER_REFERENCING, State.FOLLOWER_REFERENCING, State.SYNC_RUN)
_COUPLED = (State.NOT_REFERENCED, State.LEADER_REFERENCING, State.WAITING_FOR_START, State.SYNCHRONIZED)


def gantry_type(md: MachineData) -> tuple[int, bool]:
    """MD37100 of an axis: (grouping 1..8 or 0, whether the axis follows)."""
    value = md.int(MD.GANTRY_AXIS_TYPE)
    return value % 10, value >= 10


class GantryGrouping:
    """One gantry grouping: its leading axis, its followers and their state (the module docstring)."""

    def __init__(self, number: int, leader: MachineAxis, followers: list[MachineAxis],
                 referencing: dict[str, AxisReferencing], start_referencing: StartReferencing, table: SignalTable,
                 areas: dict[str, bytearray], memory: NcMemory, dt: float, alarms: AlarmList):
        self.number = number
        self.name = leader.name  # the instance: the grouping is known by its leading axis
        self.leader = leader
        self.followers = followers
        self.axes = [leader, *followers]
        self._referencing = referencing
        self._start_referencing = start_referencing
        self._areas = areas
        self._memory = memory
        self._dt = dt
        self._alarms = alarms
        self._decode = table.codec(GantryRequests).decode
        self._encode = table.codec(GantryStatus).encode
        self.inputs = GantryRequests()
        md = leader.config.md
        self.warning_limit = md.float(MD.GANTRY_POS_TOL_WARNING)
        self.error_limit = md.float(MD.GANTRY_POS_TOL_ERROR)
        self.reference_limit = md.float(MD.GANTRY_POS_TOL_REF)
        self.function_mask = md.int(MD.GANTRY_FUNCTION_MASK)
        self.broken_up = md.bool(MD.GANTRY_BREAK_UP)
        self.state = State.BROKEN_UP if self.broken_up else State.NOT_REFERENCED
        # each follower's setpoint against the leading axis's while coupled (0 once synchronized)
        self.offsets = {axis.name: axis.setpoint - leader.setpoint for axis in followers}
        self.differences = {axis.name: 0.0 for axis in followers}  # actual value against the leading axis
        self.warning = {axis.name: False for axis in followers}
        self.cut_off = {axis.name: False for axis in followers}
        self._target = 0.0
        self._from_referencing = False  # the next synchronization run comes from referencing (target MD34100)
        self._follower_referencing: MachineAxis | None = None
        self._start_was = False
        # each axis's coordinate shift seen (referencing sets the actual value anew: nothing moves)
        self._shifts = {axis.name: axis.coordinate_shift for axis in self.axes}
        self._written: dict[str, int] = {}
        self.busy = True  # something to do this cycle: the first cycle publishes the power-on state
        self.write_outputs()

    # ------------------------------------------------------------------ inputs
    def decode_inputs(self, axis: MachineAxis) -> None:
        """The PLC changed DB31 of ``axis``: the leading axis's gantry signals; a coupled follower's
        traverse keys are ignored (L15570-15573)."""
        self.busy = True
        if axis is self.leader:
            self._decode(self._areas[axis.name], self.inputs)
        elif self.state is not State.BROKEN_UP:
            axis.inputs.key_plus = axis.inputs.key_minus = False

    # ------------------------------------------------------------------ before position control
    def couple(self, cycle: int, reference_function: bool, any_referencing: bool) -> None:
        """The state's transitions on the inputs, then the setpoints: the followers take the leading
        axis's (the leading axis a referencing follower's), or the synchronization run moves every axis."""
        self._follow_shifts()
        state = self.state
        if state is State.BROKEN_UP or state is State.TRIPPED:
            self._start_was = self.inputs.start_sync_run
            return
        leader_referencing = self._referencing[self.leader.name]
        if leader_referencing.active and state is not State.LEADER_REFERENCING:
            self._enter(State.LEADER_REFERENCING)
        elif state is State.LEADER_REFERENCING and not leader_referencing.active:
            if self.leader.referenced:
                self._next_follower(cycle)
            else:
                self._enter(State.NOT_REFERENCED)
        elif state is State.FOLLOWER_REFERENCING:
            follower = self._follower_referencing
            if follower is not None and not self._referencing[follower.name].active:
                if follower.referenced:
                    self._next_follower(cycle)
                else:
                    self._enter(State.NOT_REFERENCED)
        elif state in (State.WAITING_FOR_START, State.SYNCHRONIZED) and not all(a.referenced for a in self.axes):
            self._enter(State.NOT_REFERENCED)
        elif state is State.WAITING_FOR_START:
            start = self.inputs.start_sync_run and not self._start_was
            if start and reference_function and not any_referencing:
                self._start_sync_run(cycle, self._target if self._from_referencing else self.leader.actual)
        self._start_was = self.inputs.start_sync_run
        self._setpoints(cycle)

    def _follow_shifts(self) -> None:
        """An axis whose actual value was set anew (referenced) keeps standing: the coupling's offsets
        take the shift over."""
        leader = self.leader
        leader_shift = leader.coordinate_shift - self._shifts[leader.name]
        self._shifts[leader.name] = leader.coordinate_shift
        for follower in self.followers:
            shift = follower.coordinate_shift - self._shifts[follower.name]
            self._shifts[follower.name] = follower.coordinate_shift
            if shift != leader_shift:
                self.offsets[follower.name] += shift - leader_shift

    def _setpoints(self, cycle: int) -> None:
        state = self.state
        leader = self.leader
        if state is State.SYNC_RUN:
            self._sync_run_cycle(cycle)
            return
        if state is State.FOLLOWER_REFERENCING:
            follower = self._follower_referencing
            if follower is not None and follower.owner is Owner.REF and leader.owner is Owner.NONE:
                leader.setpoint = follower.setpoint - self.offsets[follower.name]  # the leading axis runs along
                leader.command_velocity = follower.command_velocity
                leader.resting = False
        for follower in self.followers:
            # a stop of one axis stops the grouping (L14588): a follower braking on its own (a reaction
            # of its own) brakes the leading axis, whose braking setpoint the other followers take
            if follower.owner is Owner.BRAKE and leader.owner is not Owner.BRAKE and leader.command_velocity:
                leader.brake()
            if follower.owner is Owner.NONE and follower is not self._follower_referencing:
                setpoint = leader.setpoint + self.offsets[follower.name]
                if setpoint != follower.setpoint or follower.command_velocity != leader.command_velocity:
                    follower.setpoint = setpoint
                    follower.command_velocity = leader.command_velocity
                    follower.resting = False

    # ------------------------------------------------------------------ referencing and synchronization
    def _enter(self, state: State) -> None:
        self.state = state
        self.busy = True
        if state is not State.SYNC_RUN:
            self._alarms.clear(ALARM_SYNCHRONIZING, axis=self.leader.name)
        if state is not State.WAITING_FOR_START:
            self._alarms.clear(ALARM_WAITING_FOR_START, axis=self.leader.name)
        if state is State.LEADER_REFERENCING:
            self._recouple()
        if state is State.NOT_REFERENCED:
            self._follower_referencing = None
            self._recouple()

    def _recouple(self) -> None:
        """Coupled with the followers where they stand (not synchronized)."""
        for follower in self.followers:
            self.offsets[follower.name] = follower.setpoint - self.leader.setpoint

    def _next_follower(self, cycle: int) -> None:
        """Part 2: the next follower not referenced references; the leading axis runs coupled (L14677-14687)."""
        for follower in self.followers:
            if not follower.referenced:
                self._recouple()
                if self._start_referencing(follower.name, Source.CHANNEL, 0, cycle):
                    self._follower_referencing = follower
                    self.state = State.FOLLOWER_REFERENCING
                    self.busy = True
                else:
                    self._enter(State.NOT_REFERENCED)
                return
        self._follower_referencing = None
        self._all_referenced(cycle)

    def _all_referenced(self, cycle: int) -> None:
        """Part 3: each follower's actual value against the leading axis's reference position (L14689-14748)."""
        leader_md = self._memory.view(self.leader.name, self.leader.config.md)
        self._target = leader_md.float(MD.REFP_SET_POS, 0)
        self._from_referencing = True
        # "the actual-value difference between the leading and the following axes" (L14697)
        difference = max(abs(follower.actual - self.leader.actual) for follower in self.followers)
        if self.warning_limit > 0.0 and difference <= self.warning_limit:
            self._start_sync_run(cycle, self._target)
        else:
            self._wait_for_start(cycle)

    def _wait_for_start(self, cycle: int) -> None:
        self._enter(State.WAITING_FOR_START)
        self._recouple()
        self._alarms.raise_alarm(ALARM_WAITING_FOR_START, cycle, self.leader.channel, self.number,
                                 channel=self.leader.channel, axis=self.leader.name)

    def _start_sync_run(self, cycle: int, target: float) -> None:
        self._enter(State.SYNC_RUN)
        self._target = target
        for axis in self.axes:
            if axis.owner is not Owner.REF:
                axis.take(Owner.REF)
        if not self.function_mask & NO_SYNC_MESSAGE:
            self._alarms.raise_alarm(ALARM_SYNCHRONIZING, cycle, self.leader.channel, self.number,
                                     channel=self.leader.channel, axis=self.leader.name)

    def _sync_run_cycle(self, cycle: int) -> None:
        """Every axis uncoupled to the target at its MD34070 (L14705-14722); synchronized once all stand."""
        arrived = True
        for axis in self.axes:
            if axis.owner is not Owner.REF:
                self._wait_for_start(cycle)  # a reaction (alarm, e-stop) took an axis: the run is cancelled
                return
            speed = self._memory.view(axis.name, axis.config.md).float(MD.REFP_VELO_POS) / 60.0
            if not _approach(axis, self._target, speed * axis.override, self._dt) \
                    or abs(axis.distance_to_end_point) > axis.dyn.fine_window:
                arrived = False
        if arrived:
            for axis in self.axes:
                axis.release()
            self._synchronized()

    def _synchronized(self) -> None:
        self._enter(State.SYNCHRONIZED)
        self._from_referencing = False
        for follower in self.followers:
            self.offsets[follower.name] = 0.0
            follower.setpoint = self.leader.setpoint
            follower.resting = False

    def _automatic_sync(self) -> bool:
        """12.3.2: back from follow-up into position control, within the standstill tolerance MD36030 of
        each follower and DBX29.5 not set: synchronized again without a run (L14906-14944)."""
        if self.inputs.disable_sync or self._from_referencing:
            return False
        for axis in self.axes:
            if not axis.servo_on or axis.follow_up:
                return False
        return all(abs(follower.actual - self.leader.actual) <= follower.dyn.standstill_tolerance
                   for follower in self.followers)

    # ------------------------------------------------------------------ after position control
    def monitor(self, cycle: int) -> None:
        """The actual-value difference of each follower: warning and trip limit; the synchronism lost
        in follow-up; then the status bits."""
        state = self.state
        leader = self.leader
        extended = bool(self.function_mask & EXTENDED_MONITORING) and all(a.referenced for a in self.axes)
        if state is State.SYNCHRONIZED and any(axis.follow_up for axis in self.axes):
            self._enter(State.WAITING_FOR_START)  # follow-up: the synchronism is lost (L14908-14912)
            self._recouple()
            state = self.state
        elif state is State.WAITING_FOR_START and self._automatic_sync():
            self._synchronized()  # on this cycle's servo states and actual values
            state = self.state
        monitored = state in _COUPLED or state is State.FOLLOWER_REFERENCING or \
            (extended and state is State.BROKEN_UP)
        limit = self.error_limit if state is State.SYNCHRONIZED or state is State.BROKEN_UP \
            else self.reference_limit
        tripped = False
        for follower in self.followers:
            name = follower.name
            # against the leading axis as coupled: its actual value once synchronized (L14395-14398)
            difference = follower.actual - leader.actual - self.offsets[name]
            self.differences[name] = difference
            warning = monitored and state is not State.BROKEN_UP and 0.0 < self.warning_limit < abs(difference)
            if warning != self.warning[name]:
                self.warning[name] = warning
                if warning:
                    self._alarms.raise_alarm(ALARM_WARNING_LIMIT, cycle, follower.channel, name,
                                             channel=follower.channel, axis=name)
                else:
                    self._alarms.clear(ALARM_WARNING_LIMIT, axis=name)
            if monitored and 0.0 < limit < abs(difference):
                self.cut_off[name] = tripped = True
                if extended:
                    self._memory.write(name, MD.GANTRY_ACT_POS_TOL_ERROR, difference, None, follower.config.md)
        if tripped:
            self._trip(cycle)
        self.write_outputs()
        self.busy = self.state in _RUNNING or not self.at_rest

    @property
    def at_rest(self) -> bool:
        """No axis of the grouping moves or is moved: the grouping has nothing to do."""
        return all(axis.resting and axis.owner is Owner.NONE for axis in self.axes)

    def _trip(self, cycle: int) -> None:
        """Alarm 10653 (the mode group stops, L14496-14501) and every axis of the grouping stops (L14588)."""
        if self.state is State.SYNC_RUN:
            for axis in self.axes:
                axis.release()
        self._enter(State.TRIPPED)
        name = next(f.name for f in self.followers if self.cut_off[f.name])
        self._alarms.raise_alarm(ALARM_ERROR_LIMIT, cycle, self.leader.channel, name, channel=self.leader.channel)
        for axis in self.axes:
            axis.rapid_stop(then_servo_off=False)

    def reset(self, cycle: int) -> None:
        """Channel or mode-group reset: the synchronization run is cancelled, a trip acknowledged; with
        the extended monitoring a difference kept in MD37135 brings 10653 back (L14532-14547)."""
        self.busy = True
        if self.function_mask & EXTENDED_MONITORING:
            for follower in self.followers:
                kept = self._memory.view(follower.name, follower.config.md).float(MD.GANTRY_ACT_POS_TOL_ERROR)
                if kept:
                    self._alarms.raise_alarm(ALARM_ERROR_LIMIT, cycle, self.leader.channel, follower.name,
                                             channel=self.leader.channel)
                    self._enter(State.TRIPPED)
                    return
        for follower in self.followers:
            self.cut_off[follower.name] = False
        if self.state is State.SYNC_RUN:
            for axis in self.axes:
                if axis.owner is Owner.REF:
                    axis.brake()
            self._wait_for_start(cycle)
        elif self.state is State.TRIPPED:
            if self.broken_up:
                self._enter(State.BROKEN_UP)
            elif all(axis.referenced for axis in self.axes):
                self._from_referencing = False
                self._wait_for_start(cycle)
            else:
                self._enter(State.NOT_REFERENCED)

    # ------------------------------------------------------------------ outputs
    def write_outputs(self) -> None:
        """DB31.DBX101.2-101.7 of every axis of the grouping, when they changed."""
        state = self.state
        sync_ok = state is State.SYNCHRONIZED
        ready = state is State.WAITING_FOR_START
        for axis in self.axes:
            leading = axis is self.leader
            warning = not leading and self.warning[axis.name]
            cut_off = not leading and self.cut_off[axis.name]
            bits = cut_off | warning << 1 | (leading and ready) << 2 | (leading and sync_ok) << 3 | leading << 4
            if self._written.get(axis.name) == bits:
                continue
            self._written[axis.name] = bits
            self._encode(self._areas[axis.name], GantryStatus(
                cut_off_limit=cut_off, warning_limit=warning, sync_run_ready=leading and ready,
                sync_ok=leading and sync_ok, leading=leading, gantry=True))


def _approach(axis: MachineAxis, target: float, speed: float, dt: float) -> bool:
    """Position the setpoint of ``axis`` on ``target`` at ``speed``; True once it stands there."""
    accel = axis.dyn.max_accel
    velocity = axis.command_velocity
    distance = target - axis.setpoint
    if velocity and (distance == 0.0 or (distance > 0) != (velocity > 0)):
        new = ramp(velocity, 0.0, accel, dt)
    else:
        direction = 1 if distance > 0 else -1
        new = direction * min(ramp(abs(velocity), speed, accel, dt), stopping_velocity(abs(distance), accel, dt))
    axis.command_velocity = new
    axis.setpoint += new * dt
    axis.resting = False
    if abs(target - axis.setpoint) <= 1e-9 and new == 0.0:
        axis.setpoint = target
        return True
    return False


class Gantries:
    """Every gantry grouping of the machine (none on most machines: then nothing runs)."""

    def __init__(self, axes: list[MachineAxis], referencing: dict[str, AxisReferencing],
                 start_referencing: StartReferencing, table: SignalTable, areas: dict[str, bytearray],
                 memory: NcMemory, dt: float, alarms: AlarmList):
        table.codec(GantryRequests)  # the signals are modelled on every machine: without a grouping they stay 0
        table.codec(GantryStatus)
        leaders: dict[int, MachineAxis] = {}
        followers: dict[int, list[MachineAxis]] = {}
        for axis in axes:
            number, follows = gantry_type(axis.config.md)
            if not number or axis.is_spindle:
                continue
            if follows:
                followers.setdefault(number, []).append(axis)
            elif number not in leaders:
                leaders[number] = axis
        self.groupings = [GantryGrouping(number, leaders[number], followers[number], referencing, start_referencing,
                                         table, areas, memory, dt, alarms)
                          for number in sorted(leaders) if followers.get(number)]
        self.of: dict[str, GantryGrouping] = {axis.name: grouping for grouping in self.groupings
                                              for axis in grouping.axes}

    def couple(self, cycle: int, reference_function: bool, any_referencing: bool) -> None:
        for grouping in self.groupings:
            if grouping.busy or not grouping.at_rest:
                grouping.busy = True
                grouping.couple(cycle, reference_function, any_referencing)

    def monitor(self, cycle: int) -> None:
        for grouping in self.groupings:
            if grouping.busy:
                grouping.monitor(cycle)

    def reset(self, channel: str, cycle: int) -> None:
        for grouping in self.groupings:
            if grouping.leader.channel == channel:
                grouping.reset(cycle)
