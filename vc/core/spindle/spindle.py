"""Spindles (seed 003 chapter 13): the modes of a spindle and their DB31 status.

A spindle is a machine axis with MD35000 > 0.  :class:`Spindle` owns its motion whenever it
turns on its own (owner ``SPINDLE`` of the :class:`~vc.core.axis.axis.MachineAxis`): it ramps the
speed setpoint, integrates it into the axis's position setpoint and lets the axis's loop, drive
and encoder do the rest.  In axis mode (M70) the channel's path moves it like a rotary axis.

Modes and their status bits (spec B.3, L16008-16100)::

    CONTROL (84.7) ──M40 S / M41..M45 with another gear──▶ OSCILLATION (84.6) ──16.3──▶ CONTROL
    CONTROL ──SPOS / SPOSA / M19──▶ POSITIONING (84.5) ──M3 / M4 / M5──▶ CONTROL
    CONTROL, POSITIONING ──M70 (or its axis name)──▶ AXIS (60.0 = 0) ──M3 / M4 / M5──▶ CONTROL
    (a turning spindle first brakes like M5, then position control and parameter set 0)

(A SYNCHRONOUS spindle follows a coupling's leading spindle: vc/core/spindle/coupling.py.)
Observers see the modes as ``SPINDLE_MODES``.

:class:`Spindle` keeps the modes: it takes the program's commands and the PLC's, switches the mode
and chooses the velocity command of the mode each cycle.  It owns by composition what the modes
use (each module says what it does):

``gear_change.GearChange``            the gear stages and the change dialog (oscillation mode)
``positioning.PositioningDrive``      the motion of SPOS / SPOSA / M19 (positioning mode)
``speed_control.SpeedControl``        speed limits, override, ramp, setpoint, speed monitoring (83.x)
``zero_mark.ZeroMarkSynchronisation`` synchronisation of a turning spindle with its zero mark
``signals``                           the DB31 signals it reads and writes
"""

from __future__ import annotations

from enum import Enum

from interfaces.signal_groups import SpindleEdgeRequests, SpindleSpeed, SpindleStatus
from vc.config import md_dictionary as MD
from vc.config.machine_data import MachineData
from vc.core.alarms import STOP_AXES, AlarmList
from vc.core.axis.axis import MachineAxis
from vc.core.axis.owner import Owner
from vc.core.interface_map import SignalTable
from vc.core.nc_memory import NcMemory
from vc.core.overrides import OverrideCoding
from vc.core.program.commands import SpindleCommand
from vc.core.spindle.gear_change import (
    ALARM_CATCH_UP_IMPOSSIBLE,
    ALARM_GEAR_CHANGE_NOT_POSSIBLE,
    GearChange,
    GearOutcome,
)
from vc.core.spindle.positioning import Positioning, PositioningDrive
from vc.core.spindle.signals import SpindleInputs
from vc.core.spindle.speed_control import RPM as RPM  # rev/min -> deg/s, for the spindle's callers
from vc.core.spindle.speed_control import SpeedControl
from vc.core.spindle.zero_mark import ZeroMarkSynchronisation
from vc.core.state_machine import Instance, StateMachine, states, transitions

ALARM_ZERO_MARK_MISSING = 20002  # the positioning's zero-mark search (MD34060) [control: the referencing alarm]
SUPPRESS_IN_DRY_RUN = 1 << 0  # MD35035 bit 0: no gear change in dry run
SUPPRESS_IN_PROGRAM_TEST = 1 << 1  # MD35035 bit 1: ... nor in program test


class SpindleMode(Enum):
    CONTROL = "control"
    OSCILLATION = "oscillation"
    POSITIONING = "positioning"
    AXIS = "axis"
    SYNCHRONOUS = "synchronous"  # following spindle of a coupling (84.4): vc/core/spindle/coupling.py drives it


SPINDLE_MODES: StateMachine[Spindle] = StateMachine(
    __name__, "spindle_mode", "Spindle modes (DB31.DBX84.3-84.7)", Instance.SPINDLE,
    states(*SpindleMode),
    transitions(("CONTROL", "OSCILLATION", "gear change"), ("POSITIONING", "OSCILLATION", "gear change"),
                ("OSCILLATION", "CONTROL", "gear changed (16.3)"),
                ("CONTROL", "POSITIONING", "SPOS / SPOSA / M19"), ("POSITIONING", "CONTROL", "M3 / M4 / M5"),
                ("CONTROL", "AXIS", "M70"), ("POSITIONING", "AXIS", "M70"), ("AXIS", "CONTROL", "M3 / M4 / M5"),
                ("AXIS", "POSITIONING", "SPOS in axis mode"),
                ("CONTROL", "SYNCHRONOUS", "COUPON: following spindle"),
                ("POSITIONING", "SYNCHRONOUS", "COUPON on a positioned spindle"),
                ("SYNCHRONOUS", "CONTROL", "COUPOF")),
    read=lambda spindle: spindle.mode)


class Spindle:
    """One spindle of a channel (see the module docstring)."""

    def __init__(self, axis: MachineAxis, table: SignalTable, area: bytearray, channel: str,
                 override_coding: OverrideCoding, feed_coding: OverrideCoding, dt: float,
                 suppress_alarm_mask: int, gear_wait_s: float, memory: NcMemory, alarms: AlarmList):
        """``memory`` and ``alarms``: where a gear stage change that recalibrates an absolute
        motor encoder writes MD34210 and raises 25022, also when a reset ends the change."""
        self.axis = axis
        self.name = axis.name
        self.number = axis.config.spindle_number
        self.channel = channel
        self.md: MachineData = axis.config.md
        self._decode_levels = table.codec(SpindleInputs).decode
        self._decode_requests = table.codec(SpindleEdgeRequests).decode
        self._encode_status = table.codec(SpindleStatus).encode
        self._encode_speed = table.codec(SpindleSpeed).encode
        self._requests = SpindleEdgeRequests()
        self._area = area
        self._dt = dt
        self.inputs = SpindleInputs()
        md = self.md
        self.gear_change = GearChange(axis, self.inputs, channel, dt, suppress_alarm_mask, gear_wait_s, memory, alarms)
        self.speed_control = SpeedControl(axis, self.gear_change, self.inputs, override_coding, feed_coding,
                                          channel, dt)
        self._positioning_drive = PositioningDrive(axis, dt)
        self._zero_mark = ZeroMarkSynchronisation(axis)
        self.mode: SpindleMode = SpindleMode.CONTROL
        self.speed = 0.0  # programmed S, rev/min
        self.direction = 0  # +1 M3, -1 M4, 0 M5 (before M3/M4 inversion by DBX17.6)
        self.positioning: Positioning | None = None
        self.position_control = md.int(MD.SPIND_DEFAULT_MODE) == 1
        self.braking_for_axis_mode = False  # M70 from rotation: braking like M5 before axis mode
        self.m_function = 0
        self.limits_unreported = False  # a suppressed change's clamping shows no 83.1 / 83.2 (L19996-20001)
        self._shown: tuple[object, ...] = ()  # the status last written, as the tuple write_outputs compares
        self._position_control_shown: bool | None = None  # what the axis was last told
        self.quiet = False  # nothing to do until an input, a command, a reset or an alarm changes
        self.held = False  # NC stop axes and spindles (DB21.DBX7.4) until NC start
        self.stopped_by_alarm = False  # an alarm's interpolation stop brakes the spindle
        self.spcon = False  # SPCON programmed: position control until SPCOF, M3/M4/M5 or reset
        self.coupling_hold = False  # leading spindle: a coupled FS's spindle stop brakes the group
        self.sync_speed_reached = False  # following spindle: the differential speed is reached (83.5)
        self.start_keys_locked = False  # manual retraction: DBX30.1 / 30.2 start nothing (L35582-35588)
        self.esr_stopped = False  # stopped by its single-axis ESR until a reset (vc/core/retraction/esr.py)
        self.constant_cutting_speed = False  # G96 / G961 set its speed (vc/core/channel/cutting_speed.py)
        self.alarm_version = -1
        self._apply_gear_data()
        self._apply_default_mode()

    # ------------------------------------------------------------------ gear data
    @property
    def suppressed_gear(self) -> int | None:
        """The stage programmed while changes were suppressed ($P_GEAR), to be caught up."""
        return self.gear_change.suppressed_gear

    @property
    def change(self) -> GearChange | None:
        """The gear change while one runs."""
        return self.gear_change if self.gear_change.state is not None else None

    def _apply_gear_data(self) -> None:
        self.gear_change.apply_parameter_set(self.parameter_set)

    @property
    def parameter_set(self) -> int:
        """The gear stage's parameter set, 0 in axis mode."""
        return 0 if self.mode is SpindleMode.AXIS and not self.braking_for_axis_mode else self.gear_change.gear

    # ------------------------------------------------------------------ inputs
    def decode_inputs(self) -> bool:
        """Take the PLC's DB31 spindle signals; True on the rising edge of DBX2.2, delete distance
        to go / spindle reset, which the spindle carries out here (the coupling has its part)."""
        self.quiet = False
        area, inp, now = self._area, self.inputs, self._requests
        self._decode_requests(area, now)
        self.gear_change.take_report(now.gear_reported)
        self._decode_levels(area, inp)
        resync = (now.resync_1, now.resync_2)
        for index, (level, before) in enumerate(zip(resync, inp.resync, strict=True)):
            if level and not before and index < len(self.axis.encoders) and self.mode is SpindleMode.CONTROL:
                # 16.4 / 16.5 rising: synchronise again at the next zero mark (L18125-18146)
                self.axis.encoders[index].referenced = False
        inp.resync = resync
        self._plc_spindle_keys(now.plc_stop, now.plc_start_cw, now.plc_start_ccw)
        reset = self.axis.inputs.reset_movement
        reset_edge = reset and not inp.reset_movement
        inp.reset_movement = reset
        if reset_edge:
            self.spindle_reset()
        return reset_edge

    def _plc_spindle_keys(self, stop: bool, start_cw: bool, start_ccw: bool) -> None:
        """The simple spindle interface DBB30: start CW / CCW with the last S, stop along the
        braking ramp (L11335, L35586-35606), on their rising edges."""
        inp = self.inputs
        if self.gear_change.state is None and self.mode in (SpindleMode.CONTROL, SpindleMode.POSITIONING):
            if stop and not inp.plc_stop:
                self.direction = 0
            elif self.start_keys_locked:
                pass
            elif start_cw and not inp.plc_start_cw:
                self.direction = 1
                self._enter_control_mode()
            elif start_ccw and not inp.plc_start_ccw:
                self.direction = -1
                self._enter_control_mode()
        inp.plc_stop, inp.plc_start_cw, inp.plc_start_ccw = stop, start_cw, start_ccw

    # ------------------------------------------------------------------ program commands
    def program(self, command: SpindleCommand, cycle: int, alarms: AlarmList, block: str,
                suppress_gear_change: bool) -> None:
        """Take the spindle part of a block (S, M3/M4/M5, M19, M40..M45, M70, SPOS, SPOSA)."""
        self.quiet = False
        if command.m_function is not None:
            self.m_function = command.m_function
        if command.speed is not None:
            self.speed = max(0.0, command.speed)
            self.show_speed(self.speed)
        if command.direction is not None:
            self.direction = {3: 1, 4: -1, 5: 0}[command.direction]
            if self.mode in (SpindleMode.POSITIONING, SpindleMode.AXIS):
                self._enter_control_mode()
        target = self.gear_change.programmed(command, suppress_gear_change)
        if target is not None:
            if command.gear == 40 and self.mode is not SpindleMode.CONTROL:
                alarms.raise_alarm(ALARM_GEAR_CHANGE_NOT_POSSIBLE, cycle, self.channel, block, self.number,
                                   channel=self.channel, axis=self.name)
            elif not suppress_gear_change:
                self._start_change(target, cycle)
            else:
                # dry run / program test: no change, the speed stays in the active stage's range, and
                # the signals of that limitation are suppressed as well (L19996-20001)
                self.limits_unreported = True
        elif command.speed is not None or command.gear is not None:
            self.limits_unreported = False
        if command.axis_mode and self.mode is not SpindleMode.AXIS:
            used = self.gear_change.for_axis_mode()
            if used is not None:
                self._start_change(used, cycle)  # MD35014: the gear of axis mode (L19886-19891)
            self._enter_axis_mode()
        if command.position is not None:
            mode, value = command.position
            self._start_positioning(Positioning(mode, value, command.wait_for_position))

    def catch_up_gear(self, cycle: int, alarms: AlarmList, block: str) -> None:
        """Dry run / program test deselected: with MD35035 bit 2 the stage programmed meanwhile is
        engaged now with the full dialog, before the block goes on (the control's REPOS, L20019-20035);
        in positioning or axis mode that is impossible: alarm 22011 (L20050-20055).  Without bit 2
        the active stage stays (L20005-20007)."""
        target = self.gear_change.catch_up_target()
        if target is None:
            return
        self.quiet = False
        if self.mode is not SpindleMode.CONTROL:
            alarms.raise_alarm(ALARM_CATCH_UP_IMPOSSIBLE, cycle, self.channel, block, self.number,
                               channel=self.channel, axis=self.name)
        elif self.gear_change.changes_to(target):
            self.limits_unreported = False
            self._start_change(target, cycle)

    def needs_gear_change(self, command: SpindleCommand) -> bool:
        """The block would change the gear stage (M41..M45 or S with M40)."""
        return self.gear_change.requested(command) is not None

    # ------------------------------------------------------------------ block change
    @property
    def holds_motion(self) -> bool:
        """The block's gear change or transition to axis mode is not finished yet (L18540-18548)."""
        if self.gear_change.state is not None:
            return True
        return self.mode is SpindleMode.AXIS and self.axis.owner is Owner.SPINDLE

    @property
    def holds_block_end(self) -> bool:
        """SPOS / M19 until the spindle stands on its target (60.6, §13.8.8)."""
        return self.positioning is not None and self.positioning.holds_block_end(self.axis)

    def positioned_or_stopped(self) -> bool:
        """WAITS: on the position of SPOS / SPOSA / M19, or standing after M5; a spindle turning
        with M3 / M4 or coupled has nothing to wait for [control]."""
        if self.positioning is not None:
            return self.positioning.reached(self.axis)
        if self.mode is SpindleMode.CONTROL and self.direction == 0:
            return self.stationary()
        return True

    # ------------------------------------------------------------------ single-axis ESR (vc/core/retraction/esr.py)
    @property
    def is_single_axis(self) -> bool:
        """Moves on its own, as the single axis of ``$AA_ESR_TRIGGER`` (seed 003 L11491-11527): not in axis
        mode, where the channel's path moves it, nor as the following spindle of a coupling, which only
        stopping its leading spindle stops (L11390-11392)."""
        return self.mode not in (SpindleMode.AXIS, SpindleMode.SYNCHRONOUS)

    def esr_stop(self) -> None:
        """The extended stop of the single axis (MD37500 = 22, L11541-11548) brakes it, or its retraction
        (21, POLFA) takes it: its own motion ends as under an alarm's rapid stop - the direction is
        deleted, S stays, a positioning is dropped (L16215-16217) - and it stays stopped, whatever is
        commanded, until the channel's reset or its own DB31.DBX2.2 (L11442-11468: the reset ends a
        stopped single axis) [control]."""
        self.quiet = False
        self.esr_stopped = True
        self.direction = 0
        if self.mode is SpindleMode.POSITIONING:
            self._enter_control_mode()  # the positioning is aborted (as by a reset, L16672-16686)

    # ------------------------------------------------------------------ coupling (vc/core/spindle/coupling.py)
    def enter_synchronous_mode(self) -> None:
        """The spindle becomes the following spindle of a coupling: its own motion ends."""
        self.quiet = False
        self.positioning = None
        self.braking_for_axis_mode = False
        self.mode = SpindleMode.SYNCHRONOUS
        self.axis.resting = False

    def leave_synchronous_mode(self, speed: float) -> None:
        """COUPOF: the spindle turns on with ``speed`` (rev/min, signed) as M3/M4 S (L22234-22256)."""
        self.quiet = False
        self.mode = SpindleMode.CONTROL
        self.direction = (1 if speed > 0 else -1) if speed else 0
        if self.inputs.invert_m3_m4:
            self.direction = -self.direction
        self.speed = abs(speed)
        self.show_speed(self.speed)
        self.sync_speed_reached = False
        axis = self.axis
        axis.disable_by_coupling = None
        if axis.owner is Owner.COUPLING:
            axis.owner = Owner.SPINDLE  # the spindle ramps on from the coupled speed
        self._apply_gear_data()
        axis.resting = False

    def set_position_control(self, on: bool) -> None:
        self.quiet = False
        self.position_control = on

    def program_position_control(self, on: bool) -> None:
        """SPCON / SPCOF: position control in speed-control mode (L22100, L23918-23921)."""
        self.spcon = on
        if self.mode in (SpindleMode.CONTROL, SpindleMode.SYNCHRONOUS):
            self.set_position_control(on or self.mode is SpindleMode.SYNCHRONOUS)

    def show_constant_cutting_speed(self, on: bool) -> None:
        """DB31.DBX84.0: the channel's G96 / G961 sets this spindle's speed."""
        self.constant_cutting_speed = on
        self.quiet = False

    def show_speed(self, speed: float) -> None:
        self._encode_speed(self._area, SpindleSpeed(s_value=speed))

    # ------------------------------------------------------------------ modes
    def _enter_control_mode(self) -> None:
        self.mode = SpindleMode.CONTROL
        self.braking_for_axis_mode = False
        self.positioning = None
        self.position_control = self.md.int(MD.SPIND_DEFAULT_MODE) == 1 or self.spcon
        self._apply_gear_data()
        self.axis.resting = False

    def _enter_axis_mode(self) -> None:
        """M70: brake like M5, then position control and the parameter set of axis mode
        (L16083-16086; the steps of the implicit M70: stop the spindle, then position control
        and the parameter set, L17425-17433)."""
        self.direction = 0
        self.positioning = None
        self.mode = SpindleMode.AXIS
        self.braking_for_axis_mode = self.axis.owner is Owner.SPINDLE  # still turning
        if not self.braking_for_axis_mode:
            self._axis_mode_reached()
        self.axis.resting = False

    def _axis_mode_reached(self) -> None:
        self.braking_for_axis_mode = False
        self.position_control = True
        self._apply_gear_data()

    def enter_retraction(self) -> None:
        """Manual retraction of a thread or tapping block: the spindle in position control again
        (axis mode), moved with the tool axis (seed 003 L35497-35500)."""
        self.quiet = False
        self._enter_axis_mode()

    def reset(self, program_end: bool) -> None:
        """Channel reset or M2 / M30: MD35040 = 0 brakes and forgets S and the direction
        (L16196-16214); a running change ends and the reported gear is taken (L18694-18698)."""
        self.quiet = False
        if self.gear_change.state is not None:
            self._end_gear_change()
        if self.positioning is not None and not self.positioning.done:
            self._enter_control_mode()  # a running positioning is aborted (L16672-16686)
        self.gear_change.reset()
        self.held = False
        if not program_end:
            self.esr_stopped = False  # a reset ends the single-axis ESR stop; the program's end does not
        self.spcon = False  # [control] reset ends SPCON like the other modal spindle functions
        if not self.md.int(MD.SPIND_ACTIVE_AFTER_RESET):
            self.direction = 0
            self.speed = 0.0
            self.limits_unreported = False
        default_mask = self.md.int(MD.SPIND_DEFAULT_ACT_MASK)
        if default_mask == 2 and program_end:
            self._apply_default_mode()

    def program_start(self) -> None:
        """A part program starts: the NC reads the PLC's actual stage; 0 = disengaged means the next
        change is made with the full dialog (L18758-18766)."""
        self.quiet = False
        self.gear_change.dialog_forced = self.gear_change.changes_enabled and self.inputs.gear_reported == 0
        if self.md.int(MD.SPIND_DEFAULT_ACT_MASK) >= 1:
            self._apply_default_mode()

    def _apply_default_mode(self) -> None:
        mode = self.md.int(MD.SPIND_DEFAULT_MODE)
        if mode == 3:
            self._enter_axis_mode()
        elif mode == 2:
            self.mode = SpindleMode.POSITIONING
            self.position_control = True
        elif self.mode is not SpindleMode.CONTROL:
            self._enter_control_mode()

    def spindle_reset(self) -> None:
        """DB31.DBX2.2: stop, delete S and the direction, abort positioning and a gear change
        (L16212-16214, L16676-16678, L18646); a single-axis ESR stop ends (L11442-11468)."""
        self.quiet = False
        if self.gear_change.state is not None:
            self._end_gear_change()
        self.direction = 0
        self.speed = 0.0
        self.esr_stopped = False
        if self.mode is SpindleMode.POSITIONING:
            self._enter_control_mode()

    def nc_stop(self) -> None:
        """DB21.DBX7.4 NC stop axes and spindles: the spindle stops until NC start, but not
        during a gear change (L18627-18655)."""
        self.quiet = False
        if self.gear_change.state is None:
            self.held = True

    def nc_start(self) -> None:
        self.quiet = False
        self.held = False

    def emergency_stop(self) -> None:
        """A fast stop deletes the direction but keeps S (L16215-16217)."""
        self.quiet = False
        self.direction = 0
        self.positioning = None

    # ------------------------------------------------------------------ gear change (gear_change.py)
    def _start_change(self, target: int, cycle: int) -> None:
        self.gear_change.start(target, cycle, self.mode in (SpindleMode.POSITIONING, SpindleMode.AXIS))
        self._follow_gear_change()

    def _gear_change_cycle(self, cycle: int, alarms: AlarmList) -> float | None:
        """The velocity the gear change commands this cycle (None: it does not command)."""
        command = self.gear_change.cycle(cycle, alarms, self.stationary(), self.position_control, self.positioning,
                                         self.speed_control.last_rotation)
        self._follow_gear_change()
        return command

    def _follow_gear_change(self) -> None:
        """The mode the gear change asks for."""
        outcome = self.gear_change.outcome
        if outcome is GearOutcome.DIALOG:
            self._enter_oscillation_mode()
        elif outcome is GearOutcome.TO_POSITION:
            position = self.gear_change.change_position()
            self._start_positioning(Positioning("DC", position, True, programmed=False), for_change=True)
        elif outcome is GearOutcome.ABORTED:
            self.positioning = None
            self._enter_control_mode()
            self.direction = 0
        elif outcome is GearOutcome.CHANGED:
            self._gear_changed()

    def _enter_oscillation_mode(self) -> None:
        """The dialog opens: oscillation mode (84.6); at the change position a motor encoder keeps
        position control (L19577-19587)."""
        with_motor_encoder = not self.md.bool(MD.ENC_IS_DIRECT, self.axis.encoder.index)
        fixed_position = self.gear_change.at_position
        if self.mode is not SpindleMode.POSITIONING or not fixed_position:
            self.positioning = None
        self.mode = SpindleMode.OSCILLATION
        self.position_control = fixed_position and with_motor_encoder
        self.axis.resting = False

    def _end_gear_change(self) -> None:
        """A reset ends the change: the gear the PLC reports becomes active (L18694-18698)."""
        self.gear_change.finish(self.inputs.gear_reported, None, 0)
        self._follow_gear_change()

    def _gear_changed(self) -> None:
        """Control mode with the new gear's data; after a change from positioning or axis mode M5
        (L18657-18675)."""
        self.positioning = None
        if self.gear_change.stops_spindle:
            self.direction = 0
        self.mode = SpindleMode.CONTROL
        self.position_control = self.md.int(MD.SPIND_DEFAULT_MODE) == 1
        self._apply_gear_data()
        self.axis.resting = False

    # ------------------------------------------------------------------ positioning (positioning.py)
    def _start_positioning(self, positioning: Positioning, for_change: bool = False) -> None:
        index = self.axis.encoder.index
        inp = self.inputs
        if (inp.resync_for_positioning_1, inp.resync_for_positioning_2)[index]:
            self.axis.encoder.referenced = False  # 17.4 / 17.5: synchronise again while positioning (L18035)
        self.positioning = positioning
        if not for_change:
            self.direction = 0
        self.mode = SpindleMode.POSITIONING
        self.axis.resting = False

    def _positioning_cycle(self) -> float | None:
        """The velocity command of the running positioning (the drive's ``planned``: not to be
        ramped again)."""
        positioning = self.positioning
        assert positioning is not None
        if positioning.done:
            return None
        speed = self.speed_control
        limit = speed.positioning_speed() * RPM * speed.override()  # the override acts (L16690)
        drive = self._positioning_drive
        command = drive.step(positioning, limit, speed.position_control_acceleration())
        if drive.position_control is not None:
            self.position_control = drive.position_control
        return command

    # ------------------------------------------------------------------ the cycle
    def cycle(self, cycle: int, alarms: AlarmList, channel_in_reset: bool, esr_run_on: bool = False) -> None:
        """Synchronise, run the mode, ramp the speed and drive the axis; monitor; outputs.
        ``esr_run_on``: a G33 thread on this spindle runs on for MD21380 through the alarms' stop."""
        axis = self.axis
        self.alarm_version = alarms.version
        self._zero_mark.cycle()
        if channel_in_reset and self.gear_change.accept_reported_gear():
            self._apply_gear_data()
        self._positioning_drive.planned = False
        command: float | None
        if self.gear_change.state is not None:
            command = self._gear_change_cycle(cycle, alarms)
            if command is None and self.positioning is not None and not self.positioning.done:
                command = self._positioning_cycle()
        elif self.mode is SpindleMode.POSITIONING and self.positioning is not None:
            command = self._positioning_cycle()
            if self._positioning_drive.zero_mark_missing:
                self._positioning_drive.zero_mark_missing = False
                alarms.raise_alarm(ALARM_ZERO_MARK_MISSING, cycle, self.channel, self.name,
                                   channel=self.channel, axis=self.name)
                self._enter_control_mode()  # the positioning is aborted: the spindle brakes
                self.direction = 0
        elif self.mode is SpindleMode.CONTROL:
            command = self._control_speed()
        elif self.braking_for_axis_mode:
            command = 0.0  # M70 from rotation: brake along the ramp of the mode, like M5
        elif self.mode is SpindleMode.SYNCHRONOUS:
            command = None  # the coupling drives the following spindle
        else:
            command = None
        self.stopped_by_alarm = bool(alarms.reactions(self.channel) & STOP_AXES) and not esr_run_on
        stopped = self.inputs.rapid_stop or self.held or self.stopped_by_alarm or self.esr_stopped or \
            not axis.drive_ready or axis.disabled
        if stopped and command is not None:
            command = 0.0
        if command is not None and axis.owner in (Owner.NONE, Owner.SPINDLE):
            positioned = self.positioning is not None and self.positioning.done
            self.speed_control.drive(command, self._positioning_drive.planned, self.position_control, positioned)
        if self.braking_for_axis_mode and axis.owner is not Owner.SPINDLE:
            self._axis_mode_reached()  # stands (or another owner took the axis): axis mode proper
        self.speed_control.monitor(cycle, alarms)
        self.write_outputs()
        # quiet: stands, nothing asked of it, no input changed: the NCK skips it until an input, a
        # command, a reset or an alarm changes (most cycles of most spindles)
        self.quiet = (self.gear_change.settled and (self.positioning is None or self.positioning.done)
                      and (self.direction == 0 or self.mode is SpindleMode.AXIS) and axis.velocity == 0.0
                      and axis.command_velocity == 0.0 and axis.owner is Owner.NONE)

    def _control_speed(self) -> float:
        """Speed control: S x override within the gear's limits, in the programmed direction."""
        inp = self.inputs
        programmed = 0.0 if inp.delete_s else self.speed
        direction = -self.direction if inp.invert_m3_m4 else self.direction
        wanted = programmed * self.speed_control.override()
        held = self.axis.inputs.feed_stop or self.coupling_hold
        return self.speed_control.setpoint(direction, wanted, held, self.position_control)

    def stationary(self) -> bool:
        return self.speed_control.stationary()

    # ------------------------------------------------------------------ monitoring and status
    def speed_reached(self) -> bool:
        """83.5 (see :meth:`SpeedControl.reached`); a following spindle's differential speed."""
        if self.mode is SpindleMode.SYNCHRONOUS:
            return self.sync_speed_reached  # the differential speed (L23507-23511)
        direction = -self.direction if self.inputs.invert_m3_m4 else self.direction
        return self.speed_control.reached(self.mode is SpindleMode.CONTROL, direction)

    def in_position(self) -> bool:
        """85.5: after SPOS / SPOSA / M19 while synchronised, in exact stop fine, on the target;
        only for the function "spindle positioning", not at the gear-change position (L17059-17068)."""
        positioning = self.positioning
        return positioning is not None and self.mode is SpindleMode.POSITIONING and positioning.in_position(self.axis)

    def write_outputs(self) -> None:
        """The DB31 status of the spindle, written when it changed; the axis follows the position control."""
        change, speed, mode = self.gear_change, self.speed_control, self.mode
        dialog = change.dialog_open
        limits_shown = mode is SpindleMode.CONTROL and not self.limits_unreported
        gear = change.target if dialog else change.acknowledged_gear
        limited, raised, reached = speed.limited and limits_shown, speed.raised and limits_shown, self.speed_reached()
        clockwise, in_position = self.axis.velocity > self.axis.dyn.standstill_velocity, self.in_position()
        # a plain tuple first: compared every cycle, the status is built (by keyword) only when it changed
        shown = (gear, dialog, speed.at_chuck_limit, limited, raised, reached, clockwise, mode, in_position,
                 self.m_function, self.parameter_set, self.constant_cutting_speed)
        if shown != self._shown:
            self._shown = shown
            self._encode_status(self._area, SpindleStatus(
                requested_gear=gear, change_gear=dialog, speed_limit_exceeded=speed.at_chuck_limit,
                setpoint_limited=limited, setpoint_raised=raised, speed_reached=reached, clockwise=clockwise,
                control_mode=mode is SpindleMode.CONTROL, oscillation_mode=mode is SpindleMode.OSCILLATION,
                positioning_mode=mode is SpindleMode.POSITIONING, spindle_mode=mode is not SpindleMode.AXIS,
                in_position=in_position, m_function=self.m_function, parameter_set=self.parameter_set,
                constant_cutting_speed=self.constant_cutting_speed))
        if self.position_control != self._position_control_shown:
            self._position_control_shown = self.position_control
            self.axis.position_control = self.position_control
            self.axis.resting = False
