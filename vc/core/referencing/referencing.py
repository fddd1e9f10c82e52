"""Referencing of a machine axis (seed 003 chapter 4), one IPO cycle at a time.

One :class:`AxisReferencing` per axis.  It is started by a traverse key in JOG-REF or
MDA-REF, by channel-specific referencing (DB21.DBX1.0) or by G74, and drives the axis
through the phases of its measuring system.  The NC sees the reference cam only as the
PLC copies it to DB31.DBX12.7, so the PLC cycle shifts where the axis stops, as on a real
machine.  States in the manner of LinuxCNC's ``homing.c``; each says what it does and what
ends it.

Incremental measuring system with zero marks (MD34200 = 1), phases of §4.5::

    start ─MD34000=0──────────────────────────────────────────────▶ P2_ZERO_MARK
      │  ─on the cam (DB31.DBX12.7=1)──▶ P2_LEAVE_CAM
      ▼
    P1_TO_CAM ─cam rises (n latched)─▶ P1_BRAKE ─standstill─▶ P2_LEAVE_CAM
    P2_LEAVE_CAM ─cam falls, MD34050=0 (falling edge)─────────────▶ P2_ZERO_MARK
                 ─cam falls, MD34050=1 (rising edge)─▶ P2_BRAKE_OFF_CAM ─▶ P2_RETURN_TO_CAM
    P2_RETURN_TO_CAM ─cam rises─▶ P2_ZERO_MARK
    P2_ZERO_MARK ─zero mark (after the cam shift MD34092)─▶ P3_TO_POINT
    P2_ZERO_MARK ─MD34080 + MD34090 shorter than the braking distance at MD34070─▶ P3_STOP ─▶ P3_TO_POINT
    P3_TO_POINT ─at zero mark + MD34080 + MD34090─▶ SETTLE ─exact stop fine─▶ actual := MD34100[n], DONE

Distance-coded (MD34200 = 3 / 8, §4.6)::

    DC_SEARCH ─2 (or 4) marks, plausible─▶ DC_BRAKE ─▶ TO_TARGET (MD34330=0) ─▶ SETTLE ─▶ DONE
    DC_SEARCH ─cam touched / marks implausible (once)─▶ DC_REVERSE ─standstill─▶ DC_SEARCH

Absolute encoder (§4.9): calibration enabled (MD34210 = 1): no motion, MD34090 and MD34210
are written; calibrated: TO_TARGET at MD34070 (MD34330 = 0) or nothing (MD34330 = 1).
Follow-up mode (MD34104, §4.8): FOLLOW_UP waits for the slide moved from outside over a
zero mark (or the distance-coded marks).

Properties per phase (§4.5.4-4.5.6): feed override acts in phases 1 and 3; in phase 2 the
axis runs at 100 % and 0 % aborts (alarm 20005); feed stop acts in every phase; NC stop and
NC start act in phases 1 and 3 only.  In hold mode (MD11300 = 1) releasing the traverse
key brakes the axis without aborting; pressing it again continues.

The marks of a distance-coded scale are decoded in ``distance_coded``; what the reference state
of a measuring system is at power-on comes from ``buffered_positions``.

Observers see one state machine per procedure (``REFERENCING``): the phases and their transitions
differ by measuring system, so each :class:`Procedure` is declared with the states and transitions
it can take; an axis is in the procedure it started last (before its first start, the one its
active measuring system would run).
"""

from __future__ import annotations

from enum import Enum

from vc.config import md_dictionary as MD
from vc.config.machine_data import MachineData
from vc.core.alarms import AlarmList
from vc.core.axis.axis import MachineAxis
from vc.core.axis.encoder import (
    DISTANCE_CODED_MODES,
    ENC_STATE_CALIBRATED,
    ENC_STATE_CALIBRATION_ENABLED,
    MeasuringSystem,
)
from vc.core.axis.motion import braking_distance, ramp, stopping_velocity
from vc.core.axis.owner import Owner
from vc.core.nc_memory import NcMemory
from vc.core.referencing.distance_coded import decode_marks, passive_distance_coded
from vc.core.referencing.referencing_data import CycleConditions, ReferencingData
from vc.core.state_machine import Instance, StateMachine, Variants, states, transitions

ALARM_CAM_NOT_REACHED = 20000
ALARM_NO_CAM_SIGNAL = 20001
ALARM_ZERO_MARK_MISSING = 20002
ALARM_MEASURING_SYSTEM = 20003
ALARM_REFERENCE_MARK_MISSING = 20004
ALARM_APPROACH_ABORTED = 20005


class Source(Enum):
    KEY = "traverse key (JOG-REF / MDA-REF)"
    CHANNEL = "channel-specific referencing"
    G74 = "G74"


class State(Enum):
    IDLE = "idle"
    P1_TO_CAM = "phase 1: to the reference cam"
    P1_BRAKE = "phase 1: braking on the cam"
    P2_LEAVE_CAM = "phase 2: leaving the cam"
    P2_BRAKE_OFF_CAM = "phase 2: braking off the cam"
    P2_RETURN_TO_CAM = "phase 2: back to the cam"
    P2_ZERO_MARK = "phase 2: waiting for the zero mark"
    P3_STOP = "phase 3: stopping after the zero mark (reference point too close)"
    P3_TO_POINT = "phase 3: to the reference point"
    DC_SEARCH = "distance-coded: crossing reference marks"
    DC_REVERSE = "distance-coded: reversing"
    DC_BRAKE = "distance-coded: braking after the marks"
    TO_TARGET = "to the reference position"
    SETTLE = "settling in exact stop fine"
    FOLLOW_UP = "follow-up: waiting for the slide to cross the marks"
    DONE = "referenced"


class Procedure(Enum):
    """The procedure an axis references with: a state machine of its own for observers."""

    INCREMENTAL_CAM = "incremental measuring system with reference cam (MD34200 = 1, MD34000 = 1)"
    INCREMENTAL_NO_CAM = "incremental measuring system without reference cam (MD34000 = 0)"
    DISTANCE_CODED = "distance-coded reference marks (MD34200 = 3 / 8)"
    ABSOLUTE = "absolute encoder (MD30240 = 4)"
    FOLLOW_UP = "in follow-up mode (MD34104 = 1)"


_ABORT = "abort: reset, an alarm, the traverse key or REF taken away"
S = State


def _procedure(procedure: Procedure, members: tuple[State, ...],
               *steps: tuple[str, str, str]) -> StateMachine[AxisReferencing]:
    return StateMachine(__name__, f"referencing.{procedure.name.lower()}", f"Referencing, {procedure.value}",
                        Instance.AXIS, states(*members), transitions(*steps), read=_state)


def _state(referencing: AxisReferencing) -> State:
    return referencing.state


_PROCEDURES: dict[Procedure, StateMachine[AxisReferencing]] = {
    Procedure.INCREMENTAL_CAM: _procedure(
        Procedure.INCREMENTAL_CAM,
        (S.IDLE, S.P1_TO_CAM, S.P1_BRAKE, S.P2_LEAVE_CAM, S.P2_BRAKE_OFF_CAM, S.P2_RETURN_TO_CAM, S.P2_ZERO_MARK,
         S.P3_STOP, S.P3_TO_POINT, S.SETTLE, S.DONE),
        ("IDLE", "P1_TO_CAM", "start off the cam"), ("IDLE", "P2_LEAVE_CAM", "start on the cam"),
        ("DONE", "P1_TO_CAM", "a referenced axis referenced again"),
        ("P1_TO_CAM", "P1_BRAKE", "the cam rises"), ("P1_BRAKE", "P2_LEAVE_CAM", "standstill on the cam"),
        ("P2_LEAVE_CAM", "P2_ZERO_MARK", "the cam falls, MD34050 = 0"),
        ("P2_LEAVE_CAM", "P2_BRAKE_OFF_CAM", "the cam falls, MD34050 = 1"),
        ("P2_LEAVE_CAM", "P1_TO_CAM", "the cam fell before creep speed: phase 1 again"),
        ("P2_BRAKE_OFF_CAM", "P2_RETURN_TO_CAM", "standstill off the cam"),
        ("P2_RETURN_TO_CAM", "P2_ZERO_MARK", "the cam rises"),
        ("P2_ZERO_MARK", "P3_TO_POINT", "zero mark"),
        ("P2_ZERO_MARK", "P3_STOP", "zero mark, reference point within the braking distance"),
        ("P3_STOP", "P3_TO_POINT", "standstill"), ("P3_TO_POINT", "SETTLE", "at the reference point"),
        ("SETTLE", "DONE", "exact stop fine: referenced"),
        ("P1_TO_CAM", "IDLE", f"{_ABORT}, 20000"), ("P1_BRAKE", "IDLE", f"{_ABORT}, 20001"),
        ("P2_LEAVE_CAM", "IDLE", f"{_ABORT}, 20005"), ("P2_ZERO_MARK", "IDLE", f"{_ABORT}, 20002"),
        ("P3_TO_POINT", "IDLE", _ABORT)),
    Procedure.INCREMENTAL_NO_CAM: _procedure(
        Procedure.INCREMENTAL_NO_CAM, (S.IDLE, S.P2_ZERO_MARK, S.P3_STOP, S.P3_TO_POINT, S.SETTLE, S.DONE),
        ("IDLE", "P2_ZERO_MARK", "start"), ("P2_ZERO_MARK", "P3_TO_POINT", "zero mark"),
        ("P2_ZERO_MARK", "P3_STOP", "zero mark, reference point within the braking distance"),
        ("P3_STOP", "P3_TO_POINT", "standstill"), ("P3_TO_POINT", "SETTLE", "at the reference point"),
        ("SETTLE", "DONE", "exact stop fine: referenced"), ("P2_ZERO_MARK", "IDLE", f"{_ABORT}, 20002"),
        ("P3_TO_POINT", "IDLE", _ABORT)),
    Procedure.DISTANCE_CODED: _procedure(
        Procedure.DISTANCE_CODED, (S.IDLE, S.DC_SEARCH, S.DC_REVERSE, S.DC_BRAKE, S.TO_TARGET, S.SETTLE, S.DONE),
        ("IDLE", "DC_SEARCH", "start"), ("DC_SEARCH", "DC_BRAKE", "2 (4) plausible marks"),
        ("DC_SEARCH", "DC_REVERSE", "the cam at the end of the range, or implausible marks"),
        ("DC_REVERSE", "DC_SEARCH", "standstill: the other way"), ("DC_BRAKE", "TO_TARGET", "standstill, MD34330 = 0"),
        ("DC_BRAKE", "DONE", "standstill, MD34330 = 1: referenced"), ("TO_TARGET", "SETTLE", "at the target"),
        ("SETTLE", "DONE", "exact stop fine: referenced"), ("DC_SEARCH", "IDLE", f"{_ABORT}, 20003, 20004"),
        ("TO_TARGET", "IDLE", _ABORT)),
    Procedure.ABSOLUTE: _procedure(
        Procedure.ABSOLUTE, (S.IDLE, S.TO_TARGET, S.SETTLE, S.DONE),
        ("IDLE", "TO_TARGET", "start, calibrated, MD34330 = 0"),
        ("IDLE", "DONE", "calibration without motion (MD34210 = 1), or MD34330 = 1"),
        ("TO_TARGET", "SETTLE", "at the reference position"), ("SETTLE", "DONE", "exact stop fine: referenced"),
        ("TO_TARGET", "IDLE", _ABORT)),
    Procedure.FOLLOW_UP: _procedure(
        Procedure.FOLLOW_UP, (S.IDLE, S.FOLLOW_UP, S.DONE),
        ("IDLE", "FOLLOW_UP", "start in follow-up mode"), ("FOLLOW_UP", "DONE", "the slide crossed the marks"),
        ("FOLLOW_UP", "IDLE", "follow-up mode ended"), ("DONE", "FOLLOW_UP", "G74 on a referenced axis")),
}

REFERENCING: Variants[AxisReferencing] = Variants(
    "referencing", tuple(_PROCEDURES.values()), lambda referencing: _PROCEDURES[referencing.procedure])


_PHASE = {
    State.P1_TO_CAM: 1, State.P1_BRAKE: 1,
    State.P2_LEAVE_CAM: 2, State.P2_BRAKE_OFF_CAM: 2, State.P2_RETURN_TO_CAM: 2, State.P2_ZERO_MARK: 2,
    State.P3_STOP: 3, State.P3_TO_POINT: 3, State.SETTLE: 3,
    State.DC_SEARCH: 1, State.DC_REVERSE: 1, State.DC_BRAKE: 1, State.TO_TARGET: 3,
}


class AxisReferencing:
    def __init__(self, axis: MachineAxis, memory: NcMemory, hold_mode: bool, dt: float, alarms: AlarmList):
        self.axis = axis
        self._memory = memory
        self._hold_mode = hold_mode
        self._dt = dt
        self._alarms = alarms
        self.state = State.IDLE
        self.source = Source.KEY
        self._data = self._read_data()
        self.procedure: Procedure = self._configured_procedure()  # the procedure started last (observers read it)
        self._direction = 1  # direction of the present motion of the procedure
        self._search_direction = 1
        self._selection = 0  # index into MD34100, latched at the cam
        self._last_physical = axis.physical
        self._edge_physical = 0.0  # where the cam edge was seen (phase 2)
        self._start_physical = 0.0  # where the present search started (distance monitoring)
        self._zero_mark = 0.0
        self._target = 0.0  # NC coordinates (phase 3 / TO_TARGET)
        self._target_actual = 0.0  # actual value at the reference point
        self._marks: list[float] = []
        self._search_speed = 0.0  # distance-coded search velocity (MD34040, halved after implausible marks)
        self._next_speed = 0.0  # the search velocity after a reversal
        self._cycle = 0
        self._implausible = 0
        self._restart_phase_1 = False
        self._calibrating = False  # an absolute encoder referenced by its zero mark: MD34090 is written

    # ------------------------------------------------------------------ machine data
    @property
    def md(self) -> MachineData:
        return self._memory.view(self.axis.name, self.axis.config.md)

    def _read_data(self) -> ReferencingData:
        return ReferencingData.of(self.axis, self.md, self._hold_mode, self._encoder_index())

    def _encoder_index(self) -> int:
        return self.axis.active_encoder or 0

    @property
    def encoder(self) -> MeasuringSystem:
        return self.axis.encoders[self._encoder_index()]

    def _configured_procedure(self) -> Procedure:
        """The procedure the active measuring system references with (follow-up aside)."""
        encoder = self.encoder
        if encoder.mode in DISTANCE_CODED_MODES:
            return Procedure.DISTANCE_CODED
        if encoder.absolute:
            return Procedure.ABSOLUTE
        return Procedure.INCREMENTAL_CAM if self._data.with_cam else Procedure.INCREMENTAL_NO_CAM

    @property
    def active(self) -> bool:
        return self.state not in (State.IDLE, State.DONE)

    @property
    def phase(self) -> int:
        """The phase whose properties apply (override, NC stop): §4.5.4-4.5.6, §4.6.5."""
        phase = _PHASE.get(self.state, 0)
        if phase == 3 and self.encoder.mode in DISTANCE_CODED_MODES and self._data.with_cam:
            return 2  # distance-coded with a cam: the travel to the target behaves like phase 2 (L1633-1646)
        return phase

    # ------------------------------------------------------------------ start and abort
    def start(self, source: Source, key_direction: int = 0) -> bool:
        """Begin referencing; returns False if the axis cannot start (no enable, wrong key)."""
        axis = self.axis
        if self.active or axis.is_spindle:
            return False
        data = self._data = self._read_data()
        encoder = self.encoder
        md = self.md
        index = self._encoder_index()
        distance_coded = encoder.mode in DISTANCE_CODED_MODES
        if source is Source.KEY and not distance_coded and key_direction != data.direction:
            return False  # the direction enable MD34010 decides which key starts referencing
        self.source = source
        self._selection = self._selected_value()
        self._implausible = 0
        self._marks = []
        self._calibrating = False
        self._last_physical = axis.physical
        if axis.follow_up and data.in_follow_up:
            if encoder.referenced and source is not Source.G74:
                return False  # a referenced system is referenced again in follow-up only with G74 (L1892-1896)
            self.procedure = Procedure.FOLLOW_UP
            self._begin(State.FOLLOW_UP, take=False)
            self._direction = key_direction or data.direction
            return True
        if not axis.drive_ready:
            return False
        axis.delete_drf_offset()  # phase 1 deletes the axis's DRF offset (seed 003 L36497)
        if encoder.absolute:
            return self._start_absolute(md, index)
        encoder.referenced = False
        if distance_coded:
            direction = key_direction or data.direction
            if data.with_cam and axis.inputs.ref_cam:
                direction = -data.direction  # on the cam at the end of the range: away from it (L1526-1535)
            self.procedure = Procedure.DISTANCE_CODED
            self._search(direction, data.creep_velocity)
            return True
        self._start_zero_mark_procedure()
        return True

    def _start_zero_mark_procedure(self) -> None:
        data = self._data
        self.procedure = Procedure.INCREMENTAL_CAM if data.with_cam else Procedure.INCREMENTAL_NO_CAM
        if not data.with_cam:
            self._enter_zero_mark_search(self._direction_of_search())
        elif self.axis.inputs.ref_cam:
            self._begin(State.P2_LEAVE_CAM)  # case 2: already on the cam
        else:
            self._start_physical = self.axis.physical
            self._begin(State.P1_TO_CAM)

    def _start_absolute(self, md: MachineData, index: int) -> bool:
        state = md.int(MD.ENC_REFP_STATE, index)
        encoder = self.encoder
        value = self._data.set_positions[self._selection]
        if state == ENC_STATE_CALIBRATION_ENABLED and md.int(MD.ENC_REFP_MODE, index) == 0:
            # §4.9.3: the axis does not move; the NC computes MD34090 and marks the encoder calibrated
            self._write_calibration(value - encoder.absolute_reading(self.axis.physical))
            self.axis.synchronise(encoder, self.axis.physical, value)
            self.procedure = Procedure.ABSOLUTE
            self.state = State.DONE
            return True
        if state == ENC_STATE_CALIBRATED:
            # The encoder is read anew: after PRESETON the actual value was set by hand (L758-761).
            physical = self.axis.physical
            self.axis.synchronise(encoder, physical, encoder.calibrated_actual(
                physical, md.float(MD.REFP_MOVE_DIST_CORR, index)))
            self.procedure = Procedure.ABSOLUTE
            if self._data.stop_at_target:
                self.state = State.DONE  # §4.9.6: MD34330 = 1, referencing ends at once
                return True
            self._target = value
            self._target_actual = value
            self._begin(State.TO_TARGET)
            return True
        if md.int(MD.ENC_REFP_MODE, index) == 1:
            # §4.9.5: calibration with the zero mark of a BERO or substitute zero mark
            self._calibrating = True
            encoder.referenced = False
            self._start_zero_mark_procedure()
            return True
        return False  # not calibrated and calibration not enabled: MD34210 must be set first

    def _write_calibration(self, offset: float) -> None:
        index = self._encoder_index()
        config_md = self.axis.config.md
        self._memory.write(self.axis.name, MD.REFP_MOVE_DIST_CORR, offset, index, config_md)
        self._memory.write(self.axis.name, MD.ENC_REFP_STATE, ENC_STATE_CALIBRATED, index, config_md)

    def abort(self, alarm: int = 0) -> None:
        """Reset, an alarm or leaving REF: the axis brakes and stays (or becomes) unreferenced."""
        if not self.active:
            return
        if alarm:
            self._alarms.raise_alarm(alarm, self._cycle, self.axis.channel, self.axis.name,
                                     channel=self.axis.channel, axis=self.axis.name)
        if self.axis.owner is Owner.REF:
            self.axis.brake()
        self.state = State.IDLE

    def _begin(self, state: State, take: bool = True) -> None:
        self.state = state
        if take and self.axis.owner is not Owner.REF:
            self.axis.take(Owner.REF)

    def _selected_value(self) -> int:
        """DB31.DBX2.4..2.7 select reference point value 1..4; none selected = value 1."""
        bits = self.axis.inputs.ref_point_selection
        for index in range(4):
            if bits & (1 << index):
                return index
        return 0

    def _direction_of_search(self) -> int:
        """Zero-mark search direction: against MD34010 for the falling cam edge, with it for the rising one."""
        data = self._data
        return data.direction if data.rising_edge else -data.direction

    # ------------------------------------------------------------------ the cycle
    def cycle(self, cycle: int, conditions: CycleConditions) -> None:
        """One IPO cycle of the procedure; runs before the axis's control loop."""
        state = self.state
        if state in (State.IDLE, State.DONE):
            return
        self._cycle = cycle
        axis = self.axis
        physical = axis.physical
        moved_from, self._last_physical = self._last_physical, physical
        if state is State.FOLLOW_UP:
            self._follow_up(moved_from, physical)
            return
        if axis.owner is not Owner.REF:
            self.state = State.IDLE  # a reaction (e-stop, limit switch, enable lost) took the axis
            return
        data = self._data
        phase = self.phase
        hold = conditions.feed_stop or not axis.drive_ready or (conditions.nc_stop and phase in (1, 3)) or \
            (self.source is Source.KEY and data.hold_mode and not conditions.key_held)
        override = axis.override if phase in (1, 3) else 1.0
        if phase == 2 and axis.override == 0.0:
            self.abort(ALARM_APPROACH_ABORTED)  # §4.5.5: override 0 % aborts phase 2 (L1252-1254)
            return
        handler = _HANDLERS[state]
        handler(self, moved_from, physical, hold, override)

    # ------------------------------------------------------------------ motion
    def _run(self, direction: int, speed: float, hold: bool) -> None:
        """Ramp toward ``direction * speed`` (0 while held) with the axis acceleration."""
        axis = self.axis
        velocity = ramp(axis.command_velocity, 0.0 if hold else direction * speed, axis.dyn.max_accel, self._dt)
        axis.command_velocity = velocity
        axis.setpoint += velocity * self._dt

    def _brake(self) -> bool:
        """Brake to standstill; True once standing."""
        self._run(0, 0.0, True)
        return self.axis.command_velocity == 0.0

    def _approach(self, target: float, speed: float, hold: bool) -> bool:
        """Position the setpoint on ``target``; braking first (and overshooting) if it cannot stop in time.

        True once the setpoint stands on the target.
        """
        axis = self.axis
        accel, dt = axis.dyn.max_accel, self._dt
        velocity = axis.command_velocity
        distance = target - axis.setpoint
        if hold or (velocity and (distance == 0.0 or (distance > 0) != (velocity > 0))):
            new = ramp(velocity, 0.0, accel, dt)  # held, or moving away from the target: stop first
        else:
            direction = 1 if distance > 0 else -1
            limit = stopping_velocity(abs(distance), accel, dt)
            if abs(velocity) - accel * dt > limit + 1e-12:
                new = ramp(velocity, 0.0, accel, dt)  # too fast to stop in time: brake, come back after
            else:
                new = direction * min(ramp(abs(velocity), speed, accel, dt), limit)
        axis.command_velocity = new
        axis.setpoint += new * dt
        if abs(target - axis.setpoint) <= 1e-9 and new == 0.0:
            axis.setpoint = target
            return True
        if abs(target - axis.setpoint) <= 1e-12:
            axis.setpoint = target
        return False

    # ------------------------------------------------------------------ incremental: phases 1-3
    def _p1_to_cam(self, moved_from: float, physical: float, hold: bool, override: float) -> None:
        """Phase 1: travel in the MD34010 direction at MD34020 until the PLC reports the cam."""
        data = self._data
        if self.axis.inputs.ref_cam:
            self._selection = self._selected_value()  # latched when the cam is reached (L1323-1326)
            self.state = State.P1_BRAKE
            self._p1_brake(moved_from, physical, hold, override)
            return
        if abs(physical - self._start_physical) > data.max_cam_distance:
            self.abort(ALARM_CAM_NOT_REACHED)
            return
        self._run(data.direction, data.search_velocity * override, hold)

    def _p1_brake(self, moved_from: float, physical: float, hold: bool, override: float) -> None:
        """Phase 1: brake to standstill on the cam (at least s_min, so phase 2 can leave it at creep speed)."""
        if self._brake():
            if not self.axis.inputs.ref_cam:
                self.abort(ALARM_NO_CAM_SIGNAL)  # braked beyond the cam: no cam for phase 2
                return
            self.state = State.P2_LEAVE_CAM

    def _p2_leave_cam(self, moved_from: float, physical: float, hold: bool, override: float) -> None:
        """Phase 2: leave the cam against MD34010 (MD34040 for the falling edge, MD34020 for the rising one)."""
        data = self._data
        speed = data.search_velocity if data.rising_edge else data.creep_velocity
        if not self.axis.inputs.ref_cam:
            if data.rising_edge:
                self.state = State.P2_BRAKE_OFF_CAM
                return
            if not self._speed_reached(data.creep_velocity):
                self._restart_phase_1_from_here()  # left the cam before creep speed: restart (L1109-1115)
                return
            self._edge_physical = physical
            self._enter_zero_mark_search(-data.direction)
            return
        self._run(-data.direction, speed, hold)

    def _p2_brake_off_cam(self, moved_from: float, physical: float, hold: bool, override: float) -> None:
        """Phase 2, rising edge: brake to standstill after leaving the cam."""
        if self._brake():
            self.state = State.P2_RETURN_TO_CAM

    def _p2_return_to_cam(self, moved_from: float, physical: float, hold: bool, override: float) -> None:
        """Phase 2, rising edge: back to the cam at MD34040; the rising cam edge starts the zero-mark search."""
        data = self._data
        if self.axis.inputs.ref_cam:
            if not self._speed_reached(data.creep_velocity):
                self._restart_phase_1_from_here()
                return
            self._edge_physical = physical
            self._enter_zero_mark_search(data.direction)
            return
        self._run(data.direction, data.creep_velocity, hold)

    def _enter_zero_mark_search(self, direction: int) -> None:
        self._search_direction = direction
        self._start_physical = self.axis.physical
        if not self._data.with_cam:
            self._edge_physical = self.axis.physical
        self._begin(State.P2_ZERO_MARK)

    def _p2_zero_mark(self, moved_from: float, physical: float, hold: bool, override: float) -> None:
        """Phase 2: constant creep velocity until the next zero mark after the cam shift MD34092."""
        data = self._data
        direction = self._search_direction
        mark = self.encoder.zero_mark_between(moved_from, physical)
        shifted = (mark - self._edge_physical) * direction >= data.cam_shift - 1e-12 if mark is not None else False
        if mark is not None and shifted:
            self._zero_mark = mark
            if data.with_cam:
                self._memory.write(self.axis.name, MD.REFP_CAM_MARKER_DIST, abs(mark - self._edge_physical),
                                   self._encoder_index(), self.axis.config.md)
            reference_point = mark + direction * data.move_distance
            self._target = reference_point + self.encoder.offset
            self._target_actual = data.set_positions[self._selection]
            if data.move_distance < braking_distance(data.positioning_velocity, self.axis.dyn.max_accel):
                # L1341-1351: MD34080 + MD34090 shorter than the braking distance at MD34070 (or the
                # reference point behind): the axis stops after the zero mark, then travels to the point.
                self.state = State.P3_STOP
                return
            self.state = State.P3_TO_POINT
            self._p3_to_point(moved_from, physical, hold, 1.0)
            return
        if abs(physical - self._edge_physical) > data.max_marker_distance:
            self.abort(ALARM_ZERO_MARK_MISSING)
            return
        self._run(direction, data.creep_velocity, hold)

    def _p3_stop(self, moved_from: float, physical: float, hold: bool, override: float) -> None:
        """Phase 3, special case: brake to standstill after the zero mark before positioning."""
        if self._brake():
            self.state = State.P3_TO_POINT

    def _p3_to_point(self, moved_from: float, physical: float, hold: bool, override: float) -> None:
        """Phase 3: travel MD34080 + MD34090 from the zero mark at MD34070 and stop there."""
        if self._approach(self._target, self._data.positioning_velocity * override, hold):
            self.state = State.SETTLE

    def _to_target(self, moved_from: float, physical: float, hold: bool, override: float) -> None:
        """Distance-coded / absolute: travel to the reference position MD34100 at MD34070."""
        if self._approach(self._target, self._data.positioning_velocity * override, hold):
            self.state = State.SETTLE

    def _settle(self, moved_from: float, physical: float, hold: bool, override: float) -> None:
        """Stand in exact stop fine, then set the actual value: the axis is referenced."""
        axis = self.axis
        if abs(axis.distance_to_end_point) > axis.dyn.fine_window:
            return
        encoder = self.encoder
        reference_physical = self._target - encoder.offset  # where the setpoint stands, in physical terms
        if self._calibrating:
            self._write_calibration(self._target_actual - encoder.absolute_reading(reference_physical))
        axis.synchronise(encoder, reference_physical, self._target_actual)
        self._finish()

    def _finish(self) -> None:
        axis = self.axis
        encoder = self.encoder
        encoder.referenced = True
        encoder.restored = encoder.reference_return_due = False
        if self._data.sync_encoders:
            for other in axis.encoders:
                if other is not encoder and not passive_distance_coded(axis, other, self.md):
                    other.set_actual(axis.physical, encoder.actual(axis.physical))  # MD34102 (§4.7)
        index = self._encoder_index()
        if not encoder.absolute and self.md.int(MD.ENC_REFP_STATE, index) == ENC_STATE_CALIBRATION_ENABLED:
            # automatic referencing enabled: now referenced, restored at the next power-on (§4.10.2)
            self._memory.write(axis.name, MD.ENC_REFP_STATE, ENC_STATE_CALIBRATED, index, axis.config.md)
        if axis.owner is Owner.REF:
            axis.release()
        self.state = State.DONE

    def _speed_reached(self, wanted: float) -> bool:
        return abs(self.axis.command_velocity) >= wanted * (1.0 - self._data.velocity_tolerance) - 1e-9

    def _restart_phase_1_from_here(self) -> None:
        """The cam edge came before the phase-2 speed: phase 1 again, from off the cam (seed L1109-1115)."""
        self._start_physical = self.axis.physical
        self.state = State.P1_TO_CAM

    # ------------------------------------------------------------------ distance-coded
    def _search(self, direction: int, speed: float) -> None:
        self._direction = direction
        self._search_speed = speed
        self._marks = []
        self._start_physical = self.axis.physical
        self._begin(State.DC_SEARCH)

    def _dc_search(self, moved_from: float, physical: float, hold: bool, override: float) -> None:
        """Cross 2 (MD34200 = 3) or 4 (MD34200 = 8) reference marks at MD34040; then the position is known."""
        data = self._data
        if data.with_cam and self.axis.inputs.ref_cam and self._direction == data.direction:
            self._reverse(data.creep_velocity)  # touched the cam at the end of the range: the other way
            return
        for mark in self.encoder.coded_marks_between(moved_from, physical):
            if self._marks and abs(mark - self._marks[-1]) > 2 * self.md.float(MD.ENC_REFP_MARKER_DIST,
                                                                              self._encoder_index()):
                self._implausible_marks()
                return
            self._marks.append(mark)
            if len(self._marks) == (4 if self.encoder.mode == 8 else 2):
                if not self._decode_marks():
                    self._implausible_marks()
                    return
                self.state = State.DC_BRAKE
                return
        if abs(physical - self._start_physical) > data.max_marker_distance:
            self.abort(ALARM_REFERENCE_MARK_MISSING)
            return
        self._run(self._direction, self._search_speed * override, hold)

    def _implausible_marks(self) -> None:
        """Marks too far apart or inconsistent: reverse at half MD34040 once; the second time alarm 20003."""
        self._implausible += 1
        if self._implausible >= 2:
            self.abort(ALARM_MEASURING_SYSTEM)
            return
        self._reverse(self._data.creep_velocity / 2)

    def _reverse(self, speed: float) -> None:
        self._next_speed = speed
        self.state = State.DC_REVERSE

    def _dc_reverse(self, moved_from: float, physical: float, hold: bool, override: float) -> None:
        """Brake, then search again in the other direction."""
        if self._brake():
            self._search(-self._direction, self._next_speed)

    def _decode_marks(self) -> bool:
        """Absolute position from the crossed marks; False if they do not fit the scale."""
        value = decode_marks(self.encoder, self._marks, self._direction, self.md)
        if value is None:
            return False
        encoder = self.encoder
        encoder.offset = value - self._marks[0]  # the actual value system is synchronised (L1570-1572)
        if encoder is self.axis.encoder:
            self.axis.shift(encoder.actual(self.axis.physical) - self.axis.actual)
        return True

    def _dc_brake(self, moved_from: float, physical: float, hold: bool, override: float) -> None:
        """The axis stops after the marks; then to the target point MD34100 unless MD34330 = 1."""
        if not self._brake():
            return
        if self._data.stop_at_target:
            self._finish()
            return
        self._target = self._target_actual = self._data.set_positions[self._selection]
        self.state = State.TO_TARGET

    # ------------------------------------------------------------------ follow-up
    def _follow_up(self, moved_from: float, physical: float) -> None:
        """§4.8: the slide is moved from outside (servo off); crossing the marks references the encoder."""
        encoder = self.encoder
        data = self._data
        if not self.axis.follow_up:
            self.state = State.IDLE  # follow-up cancelled: the procedure ends, not referenced (L1884-1890)
            return
        if physical == moved_from:
            return
        direction = 1 if physical > moved_from else -1
        if encoder.mode in DISTANCE_CODED_MODES:
            self._direction = direction
            for mark in encoder.coded_marks_between(moved_from, physical):
                self._marks.append(mark)
                if len(self._marks) == (4 if encoder.mode == 8 else 2):
                    if self._decode_marks():
                        self._finish()
                    else:
                        self._marks = []
                    return
            return
        zero_mark = encoder.zero_mark_between(moved_from, physical)
        if zero_mark is None:
            return
        reference_point = zero_mark + direction * data.move_distance
        self.axis.synchronise(encoder, reference_point, data.set_positions[self._selection])
        self._finish()


_HANDLERS = {
    State.P1_TO_CAM: AxisReferencing._p1_to_cam,
    State.P1_BRAKE: AxisReferencing._p1_brake,
    State.P2_LEAVE_CAM: AxisReferencing._p2_leave_cam,
    State.P2_BRAKE_OFF_CAM: AxisReferencing._p2_brake_off_cam,
    State.P2_RETURN_TO_CAM: AxisReferencing._p2_return_to_cam,
    State.P2_ZERO_MARK: AxisReferencing._p2_zero_mark,
    State.P3_STOP: AxisReferencing._p3_stop,
    State.P3_TO_POINT: AxisReferencing._p3_to_point,
    State.TO_TARGET: AxisReferencing._to_target,
    State.SETTLE: AxisReferencing._settle,
    State.DC_SEARCH: AxisReferencing._dc_search,
    State.DC_REVERSE: AxisReferencing._dc_reverse,
    State.DC_BRAKE: AxisReferencing._dc_brake,
}
