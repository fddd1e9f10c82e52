"""PLC axes (seed 003 §9.3.2, §9.7; L11211-11490, L12145-12565): a machine axis of a channel that the
PLC moves on its own through FC18 SINU_TraversePosAxis, or takes from the channel altogether.

FC18 (L12269-12290) starts the axis as a concurrent positioning axis of its channel: G01 at FRate
(G94, mm/min or deg/min; 0: MD32060), exact stop fine at its end (G09), on the axis's own
interpolator (``CommandAxis``, state ``PLC_POSITIONING``).  Funct 5 (positioning axis; 0 as 5) takes
Pos in mm or degrees and Mode as the way (AC, IC, DC, ACP, ACN); Funct 4 indexes an indexing axis
(§11.2.3, L13522-13530): Pos is the number of an index position and Mode the program's coded way
(CAC, CIC, CDC, CACP, CACN; vc/core/axis/indexing.py).  An axis the program does not move
becomes a PLC axis with the request (L12221-12222: DB31.DBX68.7).  Its channel's NC stop holds it and
NC start lets it go on, the channel's reset aborts it (L12320-12330); the channel's feed disable holds
it unless MD30460 bit 6 (L12191-12210), and DB21.DBX36.3 leaves it out with bit 7.

With DB31.DBX28.7 the PLC takes the axis from its channel (L11237-11253: only an axis the program
does not move; until then DBX68.4 says the new type is requested): DBX63.1.  The channel's NC stop
and reset no longer act on it (L12332-12390); DBX30.0 stops it on its ramp (DBX63.2), DBX28.2 lets
it go on, DBX28.1 resets it: a motion ends, DBX63.0 says so until the next start (L11442-11467).
DBX28.7 = 0 gives it back (L11282-11315): a motion still running is stopped and the axis reset.

MD30460 bit 4: the axis is the PLC's alone, bit 5: it is assigned to the PLC for good and starts as
a neutral axis (DBX68.6, L12219-12222).  A program (or a synchronized action) that names such an axis
raises 26075 / 26076 (L12215-12217); a synchronized action's POS on an axis the PLC holds 20143
(L11231-11235); a program block that names an axis the PLC holds waits until the PLC gives it back,
the control's implicit GET [control].

The axis's type towards the PLC (DB31.DBB68, DBX63.1)::

    CHANNEL, NEUTRAL ──FC18 Start (the program does not move it)──▶ PLC (DBX68.7)
    PLC ──the FC18 motion is over (in position, stopped, failed)──▶ CHANNEL (NEUTRAL with MD30460 bit 5)
    CHANNEL, NEUTRAL, PLC ──DBX28.7 = 1 (the program does not move it)──▶ PLC_CONTROLLED (DBX63.1, 68.7)
    PLC_CONTROLLED ──DBX28.7 = 0 (a motion stops, the axis is reset)──▶ CHANNEL (NEUTRAL with bit 5)

FC18's job (its outputs Active, InPos, Error, State)::

    IDLE, IN_POSITION, FAILED ──Start──▶ TRAVERSING (or FAILED: refused, State says why)
    TRAVERSING ──NC stop (PLC), DBX30.0, the feed disable, a stopping alarm of the channel──▶ HELD
    HELD ──NC start, DBX28.2, the hold gone──▶ TRAVERSING
    TRAVERSING ──in the exact stop fine window of its end point──▶ IN_POSITION
    TRAVERSING, HELD ──channel reset (PLC), DBX28.1, DB21.DBX6.2, DBX28.7 = 0, another owner took it──▶ FAILED (30)
    TRAVERSING, HELD ──FC18 Stop──▶ IDLE (braked, the rest of the way deleted)
    IN_POSITION, FAILED ──DBX28.1──▶ IDLE

The function at rest costs nothing: the channel runs it only while a PLC request came in or a job
runs (``PlcAxes.active``).
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from enum import Enum

from interfaces.signal_groups import PlcAxisRequests, PlcAxisStatus
from vc.config import md_dictionary as MD
from vc.core.axis.command_axis import CommandAxis, CommandState
from vc.core.axis.indexing import ALARM_HIRTH_NOT_AN_INDEX_POSITION, ALARM_HIRTH_NOT_REFERENCED, ALARM_INVALID_INDEX
from vc.core.axis.owner import Owner
from vc.core.axis.rotary import (
    ALARM_ACN_NOT_ALLOWED,
    ALARM_ACP_NOT_ALLOWED,
    ALARM_DC_NOT_ALLOWED,
    ALARM_WRONG_MODULO_POSITION,
    end_point,
)
from vc.core.interface_map import SignalTable
from vc.core.state_machine import Instance, StateMachine, states, transitions

# MD30460 BASE_FUNCTION_MASK (L12181-12218)
PLC_ONLY = 1 << 4
PLC_FOR_GOOD = 1 << 5
FEED_DISABLE_IGNORED = 1 << 6
NOT_IN_ALL_AXES_STATIONARY = 1 << 7

ALARM_PLC_ONLY = 26075
ALARM_PLC_FOR_GOOD = 26076
ALARM_COMMAND_ON_PLC_AXIS = 20143  # a synchronized action's POS on an axis the PLC holds (L11231-11235)

# FC18 Funct: the functions of an axis the NC takes (the spindle's 1-3 are not built) [control]
FUNCT_INDEXING_AXIS = 4  # Pos is an index position's number (seed 003 §11.2.3)
FUNCT_POSITIONING_AXIS = 5
FUNCTIONS = (0, FUNCT_INDEXING_AXIS, FUNCT_POSITIONING_AXIS)  # 0: a PLC that leaves DBB34 alone, as 5

# FC18 Mode -> the way of the end point (vc/core/axis/rotary.py); of an indexing axis the coded way
FC18_MODES = ("AC", "IC", "DC", "ACP", "ACN")
FC18_INDEX_MODES = ("CAC", "CIC", "CDC", "CACP", "CACN")

# FC18 State, the error numbers (after the real block's list; the seed prints none) [control]
ERROR_PARAMETERS = 1  # Funct not 4 / 5 (4 on no indexing axis), Mode not 0..4, Pos or FRate not a number
ERROR_ABORTED = 30  # the motion was aborted: channel reset, axis reset, DB21.DBX6.2, control given back, axis taken
ERROR_PROGRAM_MOVES_AXIS = 40  # the NC moves the axis (its program, JOG, referencing ...): the start is refused
ERROR_WRONG_POSITION = 100  # outside the modulo range (16830); no such index position (17510); Hirth (17501, 17503)
ERROR_NEGATIVE_FEED = 110
ERROR_NO_SHORTEST_PATH = 125  # DC on a linear axis (16800)
ERROR_NO_ABSOLUTE_PLUS = 126  # ACP without modulo (16810)
ERROR_NO_ABSOLUTE_MINUS = 127  # ACN without modulo (16820)
ERROR_LIMIT_PLUS = 130  # the end point beyond the software limit switch plus
ERROR_LIMIT_MINUS = 131
_WAY_ERRORS = {ALARM_DC_NOT_ALLOWED: ERROR_NO_SHORTEST_PATH, ALARM_ACP_NOT_ALLOWED: ERROR_NO_ABSOLUTE_PLUS,
               ALARM_ACN_NOT_ALLOWED: ERROR_NO_ABSOLUTE_MINUS, ALARM_WRONG_MODULO_POSITION: ERROR_WRONG_POSITION,
               ALARM_INVALID_INDEX: ERROR_WRONG_POSITION,  # "number of index positions too high" [control]
               ALARM_HIRTH_NOT_AN_INDEX_POSITION: ERROR_WRONG_POSITION,  # a Hirth axis off its positions [INF]
               ALARM_HIRTH_NOT_REFERENCED: ERROR_WRONG_POSITION}  # [INF]


class AxisType(Enum):
    CHANNEL = "an axis of its channel (DBX68.0-68.3 its channel)"
    NEUTRAL = "a neutral axis: neither the program's nor the PLC's (DBX68.6)"
    PLC = "a PLC axis: FC18 moves it, the channel's NC stop and reset act on it (DBX68.7)"
    PLC_CONTROLLED = "controlled by the PLC (DBX28.7 -> DBX63.1): the channel's stop and reset do not act"


class Job(Enum):
    IDLE = "no FC18 motion (none yet, stopped by FC18 Stop, or the axis reset)"
    TRAVERSING = "FC18's motion runs (Active)"
    HELD = "FC18's motion is held: NC stop, axis stop DBX30.0 (DBX63.2), feed disable, a stopping alarm"
    IN_POSITION = "the motion ended in the exact stop fine window (InPos)"
    FAILED = "refused or aborted (Error, State the number)"


_MOVING = (Job.TRAVERSING, Job.HELD)


class PlcAxis:
    """One axis of a channel as the PLC sees it (see the module docstring)."""

    def __init__(self, command: CommandAxis, channel_number: int, table: SignalTable, area: bytearray):
        self.command = command
        self.axis = command.axis
        self.name = command.axis.name
        self._channel_number = channel_number
        self._area = area
        requests = table.codec(PlcAxisRequests)
        self._decode = requests.decode
        # the bytes of its requests (DBX28.x .. DBD40): the other bytes of DB31 change far more often
        self._first = min(accessor.byte for accessor in requests.accessors)
        self._end = max(accessor.byte + max(1, accessor.width_bits // 8) for accessor in requests.accessors)
        self._raw = bytes(self._end - self._first)
        self._encode = table.codec(PlcAxisStatus).encode
        self.inputs = PlcAxisRequests()
        self._last = PlcAxisRequests()  # the requests as last evaluated: their edges
        mask = self.axis.config.md.int(MD.BASE_FUNCTION_MASK)
        self.mask = mask
        self.home = AxisType.NEUTRAL if mask & PLC_FOR_GOOD else AxisType.CHANNEL
        self.type = self.home
        self.job = Job.IDLE
        self.error_number = 0
        self.reset_done = False
        self.axis_stopped = False  # DBX30.0 stopped it, until DBX28.2 (DBX63.2)
        self.nc_stopped = False  # the channel's NC stop holds a PLC axis until NC start
        self.new_type_requested = False  # DBX28.7 waits for the program to leave the axis (DBX68.4)
        self.pending = False  # a request came in: the channel runs the cycle
        self.start_acknowledged = False  # FC18's Start taken: its feedback belongs to it (DBX104.3)
        self._published: tuple[object, ...] | None = None
        self._set_refusal()
        self.write_status()

    # ------------------------------------------------------------------ what others ask
    @property
    def busy(self) -> bool:
        return self.pending or self.job in _MOVING or self.new_type_requested

    @property
    def held_by_plc(self) -> bool:
        """The PLC has the axis: a program block that names it waits (the implicit GET)."""
        return self.type in (AxisType.PLC, AxisType.PLC_CONTROLLED)

    @property
    def program_alarm(self) -> int:
        """The alarm a program block that names the axis raises: 26075 (bit 4), 26076 (bit 5), or 0."""
        if self.mask & PLC_ONLY:
            return ALARM_PLC_ONLY
        return ALARM_PLC_FOR_GOOD if self.mask & PLC_FOR_GOOD else 0

    @property
    def left_out_of_stationary(self) -> bool:
        """MD30460 bit 7: DB21.DBX36.3 does not wait for this axis while the PLC has it."""
        return bool(self.mask & NOT_IN_ALL_AXES_STATIONARY) and self.held_by_plc

    def decode_inputs(self) -> bool:
        """The axis's DB31 changed; True when its requests did (the cycle must look at them)."""
        raw = bytes(self._area[self._first:self._end])
        if raw == self._raw:
            return False
        self._raw = raw
        self._decode(self._area, self.inputs)
        self.pending = True
        return True

    def channel_reset(self) -> None:
        """The channel's reset aborts FC18's motion of a PLC axis; a PLC-controlled axis keeps it."""
        if self.type is AxisType.PLC and self.job in _MOVING:
            self._abort(ERROR_ABORTED)
        self.nc_stopped = False

    def channel_stop(self) -> None:
        """NC stop of the channel holds the motion of a PLC axis (not of a PLC-controlled one)."""
        if self.type is AxisType.PLC and self.job in _MOVING:
            self.nc_stopped = True

    def channel_start(self) -> None:
        self.nc_stopped = False

    # ------------------------------------------------------------------ the cycle
    def cycle(self, feed_disable: bool, alarm_stop: bool) -> None:
        """Before the channel's command axes run: the requests' edges, then the job's own step;
        it hands the command axis whether its motion is held this cycle."""
        if self.pending:
            self.pending = False
            self._requests()
        if self.new_type_requested:
            self._take_control()
        if self.job is Job.TRAVERSING or self.job is Job.HELD:
            self._moving(feed_disable, alarm_stop)
        self.write_status()

    def _requests(self) -> None:
        inp, last = self.inputs, self._last
        self._last = PlcAxisRequests(request_plc_control=inp.request_plc_control, axis_reset=inp.axis_reset,
                                     resume=inp.resume, axis_stop=inp.axis_stop, start=inp.start, stop=inp.stop)
        if inp.request_plc_control and self.type is not AxisType.PLC_CONTROLLED:
            self.new_type_requested = True
        elif not inp.request_plc_control:
            self.new_type_requested = False
            if self.type is AxisType.PLC_CONTROLLED:
                self._give_back()
        if self.type in (AxisType.PLC, AxisType.PLC_CONTROLLED):
            if inp.axis_stop and not last.axis_stop and self.job in _MOVING:
                self.axis_stopped = True  # use case 2 (L11345-11396)
            if inp.resume and not last.resume:
                self.axis_stopped = False  # use case 3 (L11402-11440)
            if inp.axis_reset and not last.axis_reset:
                self._axis_reset()  # use case 4 (L11442-11467)
        if inp.stop and not last.stop and self.job in _MOVING:
            self._brake()
            self.job = Job.IDLE
            self._job_over()
        if inp.start and not last.start and self.job not in _MOVING:
            self._start()
        self.start_acknowledged = inp.start

    def delete_distance_to_go(self) -> bool:
        """The channel's DB21.DBX6.2 aborts the motion of a PLC axis or a PLC-controlled one (use
        case 1, L11339-11343); the PLC learns of the abort as from DBX28.1, which the seed likens
        to it (L11452): FC18 Error, State 30.  True if a motion ended."""
        if self.type is AxisType.CHANNEL or self.type is AxisType.NEUTRAL or self.job not in _MOVING:
            return False
        self._abort(ERROR_ABORTED)
        self.write_status()
        return True

    def _take_control(self) -> None:
        """DBX28.7: granted once the program does not move the axis (L11240-11253, L11271-11272)."""
        if self.axis.owner is Owner.PATH or self.command.state is CommandState.POSITIONING:
            return  # DBX68.4 stays until the program leaves the axis
        self.new_type_requested = False
        self.type = AxisType.PLC_CONTROLLED
        self.reset_done = False
        self._set_refusal()

    def _give_back(self) -> None:
        """DBX28.7 = 0 (L11282-11315): a motion stops, the axis is reset and belongs to the NC again."""
        if self.job in _MOVING:
            self._abort(ERROR_ABORTED)
        self.axis_stopped = False
        self.reset_done = False
        self.type = self.home
        self._set_refusal()

    def _axis_reset(self) -> None:
        if self.job in _MOVING:
            self._abort(ERROR_ABORTED)
        elif self.job is not Job.IDLE:
            self.job = Job.IDLE
            self.error_number = 0
        self.axis_stopped = False
        self.reset_done = True

    def _start(self) -> None:
        """FC18's Start edge: the end point from Mode and Pos, the checks, then the axis interpolator."""
        inp, axis = self.inputs, self.axis
        self.reset_done = False
        self.axis_stopped = False
        self.nc_stopped = False
        if axis.owner not in (Owner.NONE, Owner.COMMAND) or self.command.state is not CommandState.IDLE:
            self._fail(ERROR_PROGRAM_MOVES_AXIS)  # the program, JOG, referencing or a synchronized action moves it
            return
        indexing = inp.function == FUNCT_INDEXING_AXIS
        if inp.function not in FUNCTIONS or inp.mode >= len(FC18_MODES) or (indexing and axis.index is None) \
                or not math.isfinite(inp.position) or not math.isfinite(inp.feedrate):
            self._fail(ERROR_PARAMETERS)
            return
        if inp.feedrate < 0.0:
            self._fail(ERROR_NEGATIVE_FEED)
            return
        if indexing:
            target, alarm = self._index_end_point(inp.mode, inp.position)
        else:
            target, alarm = end_point(axis.config, axis.setpoint, FC18_MODES[inp.mode], inp.position)
        if not alarm and axis.index is not None:
            alarm = axis.index.hirth_refusal(target, axis.referenced)  # a Hirth axis: its positions only
        if alarm:
            self._fail(_WAY_ERRORS[alarm])
            return
        minus, plus = axis.software_limits
        if axis.software_limits_active and not minus <= target <= plus:
            self._fail(ERROR_LIMIT_PLUS if target > plus else ERROR_LIMIT_MINUS)
            return
        if self.type is not AxisType.PLC_CONTROLLED:
            self.type = AxisType.PLC  # a concurrent positioning axis becomes a PLC axis (L12221-12222)
            self._set_refusal()
        self.error_number = 0
        self.job = Job.TRAVERSING
        self.command.plc_position(target, inp.feedrate)

    def _index_end_point(self, mode: int, number: float) -> tuple[float, int]:
        """Funct 4 (seed 003 §11.2.3, L13522-13530): Pos is the number of an index position, Mode the
        coded way of the program (CAC, CIC, CDC, CACP, CACN; vc/core/axis/indexing.py)."""
        axis = self.axis
        assert axis.index is not None
        return axis.index.coded_end_point(axis.config, axis.setpoint, FC18_INDEX_MODES[mode], number,
                                          axis.dyn.fine_window)

    def _moving(self, feed_disable: bool, alarm_stop: bool) -> None:
        """TRAVERSING / HELD: the holds of this cycle; the end of the motion."""
        command = self.command
        if command.state is not CommandState.PLC_POSITIONING:
            if command.lost:
                self._abort(ERROR_ABORTED)  # an e-stop or an alarm's rapid stop took the axis
            elif abs(self.axis.distance_to_end_point) <= self.axis.dyn.fine_window:
                self.job = Job.IN_POSITION  # exact stop fine (G09, L12277)
                self._job_over()
            return
        held = self.axis_stopped or (feed_disable and not self.mask & FEED_DISABLE_IGNORED)
        if self.type is AxisType.PLC:
            held = held or self.nc_stopped or alarm_stop
        command.plc_held = held
        self.job = Job.HELD if held else Job.TRAVERSING

    def _brake(self) -> None:
        if self.command.state is CommandState.PLC_POSITIONING:
            self.command.reset()

    def _abort(self, number: int) -> None:
        self._brake()
        self._fail(number)

    def _fail(self, number: int) -> None:
        self.job = Job.FAILED
        self.error_number = number
        self._job_over()

    def _job_over(self) -> None:
        """A PLC axis (not a PLC-controlled one) goes back to its channel or neutral."""
        self.axis_stopped = False
        self.nc_stopped = False
        if self.type is AxisType.PLC:
            self.type = self.home
            self._set_refusal()

    def _set_refusal(self) -> None:
        """What a synchronized action's POS on the axis raises (CommandAxis.position)."""
        self.command.plc_refusal = self.program_alarm or (ALARM_COMMAND_ON_PLC_AXIS if self.held_by_plc else 0)

    # ------------------------------------------------------------------ outputs
    def write_status(self) -> None:
        plc = self.held_by_plc
        status = (self.reset_done, self.type, self.axis_stopped and self.job is Job.HELD, self.new_type_requested,
                  self.job, self.error_number, self.start_acknowledged)
        if status == self._published:
            return
        self._published = status
        self._encode(self._area, PlcAxisStatus(
            reset_done=self.reset_done, plc_controlled=self.type is AxisType.PLC_CONTROLLED,
            stopped=self.axis_stopped and self.job is Job.HELD, channel_number=self._channel_number,
            new_type_requested=self.new_type_requested, changeover_possible=not self.mask & PLC_ONLY,
            neutral=self.type is AxisType.NEUTRAL, plc_axis=plc, active=self.job in _MOVING,
            in_position=self.job is Job.IN_POSITION, error=self.job is Job.FAILED, error_number=self.error_number,
            start_acknowledged=self.start_acknowledged))


PLC_AXIS_TYPES: StateMachine[PlcAxis] = StateMachine(
    __name__, "plc_axis", "PLC axis: the axis's type towards the PLC (DB31.DBB68, DBX63.1; seed 003 §9.7)",
    Instance.AXIS, states(*AxisType),
    transitions(("CHANNEL", "PLC", "FC18 Start, the program does not move the axis"),
                ("NEUTRAL", "PLC", "FC18 Start"),
                ("PLC", "CHANNEL", "the FC18 motion is over"),
                ("PLC", "NEUTRAL", "the FC18 motion is over (MD30460 bit 5)"),
                ("CHANNEL", "PLC_CONTROLLED", "DB31.DBX28.7, the program does not move the axis"),
                ("NEUTRAL", "PLC_CONTROLLED", "DB31.DBX28.7"),
                ("PLC", "PLC_CONTROLLED", "DB31.DBX28.7"),
                ("PLC_CONTROLLED", "CHANNEL", "DB31.DBX28.7 = 0"),
                ("PLC_CONTROLLED", "NEUTRAL", "DB31.DBX28.7 = 0 (MD30460 bit 5)")),
    read=lambda plc: plc.type)

FC18_JOB_STATES: StateMachine[PlcAxis] = StateMachine(
    __name__, "fc18_job", "FC18 SINU_TraversePosAxis: the PLC's positioning job of the axis (seed 003 §9.7.1)",
    Instance.AXIS, states(*Job),
    transitions(("IDLE", "TRAVERSING", "FC18 Start"), ("IN_POSITION", "TRAVERSING", "FC18 Start"),
                ("FAILED", "TRAVERSING", "FC18 Start"),
                ("IDLE", "FAILED", "FC18 Start refused"), ("IN_POSITION", "FAILED", "FC18 Start refused"),
                ("TRAVERSING", "HELD", "NC stop, DBX30.0, feed disable, a stopping alarm"),
                ("HELD", "TRAVERSING", "NC start, DBX28.2, the hold gone"),
                ("TRAVERSING", "IN_POSITION", "in the exact stop fine window"),
                ("TRAVERSING", "FAILED", "channel reset, DBX28.1, DB21.DBX6.2, DBX28.7 = 0, the axis taken"),
                ("HELD", "FAILED", "channel reset, DBX28.1, DB21.DBX6.2, DBX28.7 = 0, the axis taken"),
                ("TRAVERSING", "IDLE", "FC18 Stop"), ("HELD", "IDLE", "FC18 Stop"),
                ("IN_POSITION", "IDLE", "DBX28.1"), ("FAILED", "IDLE", "DBX28.1")),
    read=lambda plc: plc.job)


class PlcAxes:
    """The PLC axes of one channel: every axis of it that is no spindle."""

    def __init__(self) -> None:
        self.by_name: dict[str, PlcAxis] = {}
        self.active = False  # a request came in or a job runs: the channel runs cycle()
        self.restricted = False  # an axis a program block must not name or must wait for (none on most machines)
        self._bit7 = False  # an axis with MD30460 bit 7

    def add(self, plc: PlcAxis) -> None:
        """At power-on: one axis of the channel."""
        self.by_name[plc.name] = plc
        self.restricted = self.restricted or bool(plc.program_alarm)
        self._bit7 = self._bit7 or bool(plc.mask & NOT_IN_ALL_AXES_STATIONARY)

    @property
    def any_left_out(self) -> bool:
        """An axis with MD30460 bit 7 is the PLC's now: DB21.DBX36.3 leaves it out."""
        return self._bit7 and any(plc.left_out_of_stationary for plc in self.by_name.values())

    def left_out(self, name: str) -> bool:
        plc = self.by_name.get(name)
        return plc is not None and plc.left_out_of_stationary

    def decode_inputs(self, name: str) -> None:
        plc = self.by_name.get(name)
        if plc is not None and plc.decode_inputs():
            self.active = True

    def cycle(self, feed_disable: bool, alarm_stop: bool) -> None:
        active = False
        for plc in self.by_name.values():
            if plc.busy:
                plc.cycle(feed_disable, alarm_stop)
                active = active or plc.busy
        self.active = active
        self.restricted = any(plc.program_alarm or plc.held_by_plc for plc in self.by_name.values())

    def reset(self) -> None:
        for plc in self.by_name.values():
            plc.channel_reset()
            plc.write_status()

    def stop(self) -> None:
        for plc in self.by_name.values():
            plc.channel_stop()

    def delete_distance_to_go(self) -> None:
        """DB21.DBX6.2's rising edge: the PLC axes' motions end (L11339-11343)."""
        for plc in self.by_name.values():
            plc.delete_distance_to_go()

    def start(self) -> None:
        for plc in self.by_name.values():
            plc.channel_start()

    def block_refusal(self, names: Iterable[str]) -> tuple[str, int] | None:
        """The first axis of ``names`` a program block may not name and its alarm (26075 / 26076);
        (axis, 0) for an axis the PLC holds: the block waits."""
        waiting: tuple[str, int] | None = None
        for name in sorted(names):
            plc = self.by_name.get(name)
            if plc is None:
                continue
            if plc.program_alarm:
                return name, plc.program_alarm
            if plc.held_by_plc and waiting is None:
                waiting = name, 0
        return waiting
