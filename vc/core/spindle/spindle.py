"""Spindles (seed 003 chapter 13): modes, speed, positioning, gear stages, monitoring, DB31 status.

A spindle is a machine axis with MD35000 > 0.  :class:`Spindle` owns its motion whenever it
turns on its own (owner ``SPINDLE`` of the :class:`~vc.core.axis.axis.MachineAxis`): it ramps the
speed setpoint, integrates it into the axis's position setpoint and lets the axis's loop, drive
and encoder do the rest.  In axis mode (M70) the channel's path moves it like a rotary axis.

Modes and their status bits (spec B.3, L16008-16100)::

    CONTROL (84.7) ──M40 S / M41..M45 with another gear──▶ OSCILLATION (84.6) ──16.3──▶ CONTROL
    CONTROL ──SPOS / SPOSA / M19──▶ POSITIONING (84.5) ──M3 / M4 / M5──▶ CONTROL
    CONTROL, POSITIONING ──M70 (or its axis name)──▶ AXIS (60.0 = 0) ──M3 / M4 / M5──▶ CONTROL
    (a turning spindle first brakes like M5, then position control and parameter set 0)

Speed (§13.8): set speed = S x spindle override (DBB19, or the axis override DBB0 with
DBX17.0), clamped to the gear's MD35130 and MD35100 (83.1) and raised to its MD35140 (83.2,
speed control only); ramps with MD35200 (speed control) or MD35210 (position control) of the
gear.  83.5 when the actual speed is within MD35150 x the set speed (always with MD35150 = 0);
83.0 and alarm 22100 above MD35100 x (1 + MD35150); 61.4 with no setpoint and the actual
speed below MD36060 (the axis reports it).

Positioning (§13.2.5): from rotation the spindle brakes to MD35300 keeping its direction; an
unsynchronised spindle turns on (from standstill in the direction MD35350, or the ACP / ACN
direction) until it passes a zero mark; then position control (61.5) brakes onto the target
with MD35210; ACP / ACN against the rotation brake to a stop first and reverse.  85.5 "in
position" while synchronised, within exact stop fine and on the programmed position (SPOS,
SPOSA, M19 only, not at the gear-change position).

Synchronisation: a turning spindle whose encoder is not referenced takes the zero mark it
passes: there its actual value is MD34100[n] - direction x (MD34080 + MD34090), the relation
axis referencing uses between the mark and the reference point (L18011-18025).
"""

from __future__ import annotations

import struct
from enum import Enum

from vc.config import md_dictionary as MD
from vc.config.machine_data import MachineData, MdDef
from vc.core.alarms import STOP_AXES, AlarmList
from vc.core.axis.axis import MachineAxis, Owner
from vc.core.axis.motion import ramp
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
from vc.core.spindle.signals import SpindleSignals as SpindleSignals  # the NCK builds them with the spindles

RPM = 6.0  # rev/min -> deg/s
REV_S2 = 360.0  # rev/s^2 -> deg/s^2
ALARM_CHUCK_SPEED = 22100
ALARM_ZERO_MARK_MISSING = 20002  # the positioning's zero-mark search (MD34060) [control: the referencing alarm]
POSITION_CONTROL_RESERVE = 0.9  # the speed a position-controlled spindle may use (L16747-16750)
SUPPRESS_IN_DRY_RUN = 1 << 0  # MD35035 bit 0: no gear change in dry run
SUPPRESS_IN_PROGRAM_TEST = 1 << 1  # MD35035 bit 1: ... nor in program test


class SpindleMode(Enum):
    CONTROL = "control"
    OSCILLATION = "oscillation"
    POSITIONING = "positioning"
    AXIS = "axis"
    SYNCHRONOUS = "synchronous"  # following spindle of a coupling (84.4): vc/core/spindle/coupling.py drives it


class Spindle:
    """One spindle of a channel (see the module docstring)."""

    def __init__(self, axis: MachineAxis, signals: SpindleSignals, area: bytearray, channel: str,
                 override_coding: OverrideCoding, feed_coding: OverrideCoding, dt: float,
                 suppress_alarm_mask: int, gear_wait_s: float, memory: NcMemory, alarms: AlarmList):
        """``memory`` and ``alarms``: where a gear stage change that recalibrates an absolute
        motor encoder writes MD34210 and raises 25022, also when a reset ends the change."""
        self.axis = axis
        self.name = axis.name
        self.number = axis.config.spindle_number
        self.channel = channel
        self.md: MachineData = axis.config.md
        self._signals = signals
        self._area = area
        self._override_coding = override_coding
        self._feed_coding = feed_coding
        self._dt = dt
        self.inputs = SpindleInputs()
        md = self.md
        self.gear_change = GearChange(axis, self.inputs, channel, dt, suppress_alarm_mask, gear_wait_s, memory, alarms)
        self._positioning_drive = PositioningDrive(axis, md, dt)
        self.mode = SpindleMode.CONTROL
        self.speed = 0.0  # programmed S, rev/min
        self.direction = 0  # +1 M3, -1 M4, 0 M5 (before M3/M4 inversion by DBX17.6)
        self.positioning: Positioning | None = None
        self.position_control = md.int(MD.SPIND_DEFAULT_MODE) == 1
        self.braking_for_axis_mode = False  # M70 from rotation: braking like M5 before axis mode
        self.m_function = 0
        self.last_rotation = 0  # direction of the last rotation, for the oscillation start
        self.set_speed = 0.0  # after override and limits, rev/min (monitoring)
        self.limited = False
        self.raised = False
        self.limits_unreported = False  # a suppressed change's clamping shows no 83.1 / 83.2 (L19996-20001)
        self.at_chuck_limit = False
        self._last_physical = axis.physical
        self._status: tuple[object, ...] = ()
        self._planned = False  # the positioning's command is a planned profile, not a ramp target
        self.quiet = False  # nothing to do until an input, a command, a reset or an alarm changes
        self.held = False  # NC stop axes and spindles (DB21.DBX7.4) until NC start
        self.stopped_by_alarm = False  # an alarm's interpolation stop brakes the spindle
        self.spcon = False  # SPCON programmed: position control until SPCOF, M3/M4/M5 or reset
        self.speed_cap: float | None = None  # leading spindle: the coupled FS's limit over the ratio
        self.acceleration_cap: float | None = None  # leading spindle: the coupled FS's acceleration over the ratio
        self.coupling_hold = False  # leading spindle: a coupled FS's spindle stop brakes the group
        self.sync_speed_reached = False  # following spindle: the differential speed is reached (83.5)
        self.acceleration_override: float | None = None  # deg/s^2 while polygon turning sets the ramp
        self.start_keys_locked = False  # manual retraction: DBX30.1 / 30.2 start nothing (L35582-35588)
        self.alarm_version = -1
        self._apply_gear_data()
        if md.int(MD.SPIND_DEFAULT_MODE) == 3:
            self._enter_axis_mode()
        elif md.int(MD.SPIND_DEFAULT_MODE) == 2:
            self.mode = SpindleMode.POSITIONING
            self.position_control = True

    # ------------------------------------------------------------------ gear data
    @property
    def gear(self) -> int:
        """The active gear stage (its parameter set and limits)."""
        return self.gear_change.gear

    @property
    def suppressed_gear(self) -> int | None:
        """The stage programmed while changes were suppressed ($P_GEAR), to be caught up."""
        return self.gear_change.suppressed_gear

    @property
    def change(self) -> GearChange | None:
        """The gear change while one runs."""
        return self.gear_change if self.gear_change.state is not None else None

    def _gear_float(self, md_def: MdDef) -> float:
        return self.gear_change.gear_float(md_def)

    def _apply_gear_data(self) -> None:
        """The gear's (or axis mode's) parameter set: Kv, and with a motor encoder the zero-mark
        spacing of the new ratio (§13.4.4, L18960-18995) and the spindle speed at which the
        encoder reaches its limit frequency MD36300 (§13.8.7: a motor speed, the same in every
        gear stage)."""
        axis, md = self.axis, self.md
        index = self.parameter_set
        axis.set_loop_gain(md.float(MD.POSCTRL_GAIN, min(index, 5)))
        for encoder in axis.encoders:
            if not md.bool(MD.ENC_IS_DIRECT, encoder.index):
                ratio = md.int(MD.DRIVE_AX_RATIO_DENOM, index) / md.int(MD.DRIVE_AX_RATIO_NUMERA, index)
                axis.set_encoder_turn(encoder, abs(360.0 * ratio))

    @property
    def parameter_set(self) -> int:
        return 0 if self.mode is SpindleMode.AXIS and not self.braking_for_axis_mode else self.gear

    @property
    def max_speed(self) -> float:
        """Largest set speed of the active gear (rev/min): MD35130, the chuck MD35100, MD32000.

        Under position control 10 % is kept as control reserve: 90 % of that and of the active
        encoder's limit frequency, and MD35135 of the gear when set (L16747-16750, L16834-16838,
        L18226-18228)."""
        limit = min(self._gear_float(MD.GEAR_STEP_MAX_VELO_LIMIT), self.md.float(MD.SPIND_VELO_LIMIT),
                    self.md.float(MD.MAX_AX_VELO))
        if self.speed_cap is not None:
            limit = min(limit, self.speed_cap)
        if not self.position_control:
            return limit
        if self.axis.active_encoder is not None:
            limit = min(limit, self.axis.encoder.limit_velocity / RPM)
        limit *= POSITION_CONTROL_RESERVE
        position_control_limit = self._gear_float(MD.GEAR_STEP_PC_MAX_VELO_LIMIT)
        return min(limit, position_control_limit) if position_control_limit > 0.0 else limit

    # ------------------------------------------------------------------ inputs
    def decode_inputs(self) -> bool:
        """Take the PLC's DB31 spindle signals; True on the rising edge of DBX2.2, delete distance
        to go / spindle reset, which the spindle carries out here (the coupling has its part)."""
        self.quiet = False
        area, sig, inp = self._area, self._signals, self.inputs
        self.gear_change.take_report(sig.gear_reported.get(area))
        inp.gear_done = sig.gear_done.get(area)
        inp.delete_s = sig.delete_s.get(area)
        inp.use_feed_override = sig.use_feed_override.get(area)
        inp.invert_m3_m4 = sig.invert_m3_m4.get(area)
        inp.oscillation_by_plc = sig.oscillation_by_plc.get(area)
        inp.oscillation_enable = sig.oscillation_enable.get(area)
        inp.oscillation_cw = sig.oscillation_cw.get(area)
        inp.oscillation_ccw = sig.oscillation_ccw.get(area)
        inp.override_raw = sig.override.get(area)
        inp.rapid_stop = sig.rapid_stop.get(area)
        resync = (sig.resync[0].get(area), sig.resync[1].get(area))
        for index, (now, before) in enumerate(zip(resync, inp.resync, strict=True)):
            if now and not before and index < len(self.axis.encoders) and self.mode is SpindleMode.CONTROL:
                # 16.4 / 16.5 rising: synchronise again at the next zero mark (L18125-18146)
                self.axis.encoders[index].referenced = False
        inp.resync = resync
        inp.resync_for_positioning = (sig.resync_for_positioning[0].get(area),
                                      sig.resync_for_positioning[1].get(area))
        self._plc_spindle_keys(sig.plc_stop.get(area), sig.plc_start_cw.get(area), sig.plc_start_ccw.get(area))
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

    def override(self) -> float:
        axis = self.axis
        if self.inputs.use_feed_override:
            return self._feed_coding.factor(axis.inputs.override_raw, axis.inputs.override_active)
        return self._override_coding.factor(self.inputs.override_raw, axis.inputs.override_active)

    # ------------------------------------------------------------------ program commands
    def program(self, command: SpindleCommand, cycle: int, alarms: AlarmList, block: str,
                suppress_gear_change: bool) -> None:
        """Take the spindle part of a block (S, M3/M4/M5, M19, M40..M45, M70, SPOS, SPOSA)."""
        self.quiet = False
        if command.m_function is not None:
            self.m_function = command.m_function
        if command.speed is not None:
            self.speed = max(0.0, command.speed)
            struct.pack_into(">f", self._area, self._signals.s_value, self.speed)  # DBD88 (L17367)
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
        positioning = self.positioning
        if positioning is None or not positioning.wait:
            return False
        if not positioning.done:
            return True
        return abs(self.axis.distance_to_end_point) > self.axis.dyn.coarse_window

    def positioned_or_stopped(self) -> bool:
        """WAITS: on the position of SPOS / SPOSA / M19, or standing after M5; a spindle turning
        with M3 / M4 or coupled has nothing to wait for [control]."""
        positioning = self.positioning
        if positioning is not None:
            return positioning.done and abs(self.axis.distance_to_end_point) <= self.axis.dyn.fine_window
        if self.mode is SpindleMode.CONTROL and self.direction == 0:
            return self.stationary()
        return True

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

    def show_speed(self, speed: float) -> None:
        struct.pack_into(">f", self._area, self._signals.s_value, speed)  # DBD88 (L17367)

    def positioning_speed(self) -> float:
        """MD35300 of the active gear, rev/min."""
        return self._gear_float(MD.SPIND_POSCTRL_VELO)

    def coupled_acceleration(self) -> float:
        """The acceleration of a coupled FS's own motion (position control ramp), deg/s^2."""
        return self._gear_float(MD.GEAR_STEP_POSCTRL_ACCEL) * REV_S2

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

    @property
    def in_axis_mode(self) -> bool:
        return self.mode is SpindleMode.AXIS

    def reset(self, program_end: bool) -> None:
        """Channel reset or M2 / M30: MD35040 = 0 brakes and forgets S and the direction
        (L16196-16214); a running change ends and the reported gear is taken (L18694-18698)."""
        self.quiet = False
        if self.gear_change.state is not None:
            self._end_gear_change()
        if self.positioning is not None and not self.positioning.done:
            self._enter_control_mode()  # a running positioning is aborted (L16672-16686)
        self.gear_change.automatic_gear = True
        self.gear_change.suppressed_gear = None
        self.held = False
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
        (L16212-16214, L16676-16678, L18646)."""
        self.quiet = False
        if self.gear_change.state is not None:
            self._end_gear_change()
        self.direction = 0
        self.speed = 0.0
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
        change = self.gear_change
        change.start(target, cycle, self.mode in (SpindleMode.POSITIONING, SpindleMode.AXIS))
        if change.outcome is GearOutcome.DIALOG:
            self._enter_oscillation_mode()
        else:
            position = change.change_position()
            self._start_positioning(Positioning("DC", position, True, programmed=False), for_change=True)

    def _gear_change_cycle(self, cycle: int, alarms: AlarmList) -> float | None:
        """The velocity the gear change commands this cycle (None: it does not command), and the
        mode it asks for."""
        change = self.gear_change
        command = change.cycle(cycle, alarms, self.stationary(), self.position_control, self.positioning,
                               self.last_rotation)
        outcome = change.outcome
        if outcome is GearOutcome.DIALOG:
            self._enter_oscillation_mode()
        elif outcome is GearOutcome.ABORTED:
            self.positioning = None
            self._enter_control_mode()
            self.direction = 0
        elif outcome is GearOutcome.CHANGED:
            self._gear_changed()
        return command

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
        self._gear_changed()

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
        if self.inputs.resync_for_positioning[index]:
            self.axis.encoder.referenced = False  # 17.4 / 17.5: synchronise again while positioning (L18035)
        self.positioning = positioning
        if not for_change:
            self.direction = 0
        self.mode = SpindleMode.POSITIONING
        self.axis.resting = False

    def _positioning_cycle(self) -> float | None:
        """The velocity command of the running positioning; ``self._planned`` tells the drive not
        to ramp it again."""
        positioning = self.positioning
        assert positioning is not None
        if positioning.done:
            return None
        limit = self._gear_float(MD.SPIND_POSCTRL_VELO) * RPM * self.override()  # override acts (L16690)
        accel = self._gear_float(MD.GEAR_STEP_POSCTRL_ACCEL) * REV_S2
        drive = self._positioning_drive
        command = drive.step(positioning, limit, accel)
        if drive.position_control is not None:
            self.position_control = drive.position_control
        self._planned = drive.planned
        return command

    # ------------------------------------------------------------------ the cycle
    def cycle(self, cycle: int, alarms: AlarmList, channel_in_reset: bool, esr_run_on: bool = False) -> None:
        """Synchronise, run the mode, ramp the speed and drive the axis; monitor; outputs.
        ``esr_run_on``: a G33 thread on this spindle runs on for MD21380 through the alarms' stop."""
        axis = self.axis
        self.alarm_version = alarms.version
        self._synchronise()
        if channel_in_reset and self.gear_change.accept_reported_gear():
            self._apply_gear_data()
        self._planned = False
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
        stopped = self.inputs.rapid_stop or self.held or self.stopped_by_alarm or \
            not axis.drive_ready or axis.disabled
        if stopped and command is not None:
            command = 0.0
        if command is not None and axis.owner in (Owner.NONE, Owner.SPINDLE):
            self._drive(command)
        if self.braking_for_axis_mode and axis.owner is not Owner.SPINDLE:
            self._axis_mode_reached()  # stands (or another owner took the axis): axis mode proper
        self._monitor(cycle, alarms)
        self.write_outputs()
        # quiet: stands, nothing asked of it, no input changed: the NCK skips it until an input, a
        # command, a reset or an alarm changes (most cycles of most spindles)
        self.quiet = (self.gear_change.settled and (self.positioning is None or self.positioning.done)
                      and (self.direction == 0 or self.mode is SpindleMode.AXIS) and axis.velocity == 0.0
                      and axis.command_velocity == 0.0 and axis.owner is Owner.NONE)

    def _control_speed(self) -> float:
        """Speed control: S x override within the gear's limits, in the programmed direction."""
        inp, axis = self.inputs, self.axis
        programmed = 0.0 if inp.delete_s else self.speed
        direction = -self.direction if inp.invert_m3_m4 else self.direction
        override = self.override()
        wanted = programmed * override
        maximum = self.max_speed
        minimum = self._gear_float(MD.GEAR_STEP_MIN_VELO_LIMIT)
        stopped = direction == 0 or wanted == 0.0 or axis.inputs.feed_stop or self.coupling_hold
        self.limited = direction != 0 and wanted > maximum
        self.raised = not stopped and 0.0 < wanted < minimum
        set_speed = 0.0 if stopped else min(max(wanted, minimum), maximum)
        self.set_speed = set_speed
        return direction * set_speed * RPM

    def _drive(self, command: float) -> None:
        """Ramp toward ``command`` (deg/s) and move the setpoint; own the axis while it moves."""
        axis = self.axis
        if self._planned:
            velocity = command  # positioning planned its own profile
        else:
            velocity = ramp(axis.command_velocity, command, self._acceleration(command), self._dt)
        if velocity == 0.0 and axis.command_velocity == 0.0:
            if axis.owner is Owner.SPINDLE:
                axis.release()
            return
        if axis.owner is Owner.NONE:
            axis.take(Owner.SPINDLE)
        axis.command_velocity = velocity
        axis.setpoint += velocity * self._dt
        if velocity:
            self.last_rotation = 1 if velocity > 0 else -1
        if velocity == 0.0 and self.positioning is not None and self.positioning.done:
            axis.release()

    def _acceleration(self, command: float) -> float:
        if self.acceleration_override is not None:
            return self.acceleration_override
        if self.gear_change.brakes_into_oscillation:
            return self.gear_change.oscillation.accel  # braking into / during oscillation (L18372-18374)
        if self.position_control:
            accel = self._gear_float(MD.GEAR_STEP_POSCTRL_ACCEL) * REV_S2
        else:
            accel = self._gear_float(MD.GEAR_STEP_SPEEDCTRL_ACCEL) * REV_S2
        accel *= self.acceleration_reduction(self.axis.command_velocity)
        return accel if self.acceleration_cap is None else min(accel, self.acceleration_cap)

    def acceleration_reduction(self, velocity: float) -> float:
        """The share of the acceleration left at ``velocity`` (deg/s) by the kinked characteristic
        MD35220 / MD35230 / MD35242 (seed 003 L23797-23810), for speeding up and braking alike.
        Above the speed point, a share of the gear stage's MD35130 [control], the acceleration falls
        to 1 - MD35230 at MD35130 and stays there: at once (0, constant), along a hyperbola through
        both ends (1, the seed's default) [INF] or along a straight line (2)."""
        factor = self.md.float(MD.ACCEL_REDUCTION_FACTOR)
        top = self._gear_float(MD.GEAR_STEP_MAX_VELO_LIMIT)
        point = self.md.float(MD.ACCEL_REDUCTION_SPEED_POINT) * top
        speed = abs(velocity) / RPM
        if factor <= 0.0 or speed <= point:
            return 1.0
        kind = self.md.int(MD.ACCEL_REDUCTION_TYPE)
        share = min((speed - point) / (top - point), 1.0)  # of the way from the point to MD35130
        if kind == 0:
            return 1.0 - factor
        if kind == 2:
            return 1.0 - factor * share
        return 1.0 / (1.0 + factor / (1.0 - factor) * share)

    def stationary(self) -> bool:
        axis = self.axis
        return axis.command_velocity == 0.0 and abs(axis.velocity) <= axis.dyn.standstill_velocity

    def _synchronise(self) -> None:
        """An unsynchronised turning spindle takes the zero mark it passed (§13.3); an absolute
        encoder is referenced by its calibration instead (§4.9), and one that lost it stays
        unreferenced until it is calibrated again (seed 003 L2025-2040)."""
        axis = self.axis
        physical, before = axis.physical, self._last_physical
        self._last_physical = physical
        encoder = axis.encoder
        if encoder.referenced or encoder.frequency_exceeded or physical == before or axis.active_encoder is None \
                or encoder.absolute:
            return
        mark = encoder.zero_mark_between(before, physical)
        if mark is None:
            return
        md, index = self.md, encoder.index
        direction = 1 if physical > before else -1
        offset = md.float(MD.REFP_MOVE_DIST, index) + md.float(MD.REFP_MOVE_DIST_CORR, index)
        value = md.float(MD.REFP_SET_POS, self._reference_value_index()) - direction * offset
        axis.synchronise(encoder, mark, value)

    def _reference_value_index(self) -> int:
        """DB31.DBX2.4..2.7 select one of the four reference values MD34100[0..3]."""
        selection = self.axis.inputs.ref_point_selection
        for index in range(4):
            if selection & (1 << index):
                return index
        return 0

    # ------------------------------------------------------------------ monitoring and status
    def _monitor(self, cycle: int, alarms: AlarmList) -> None:
        """83.0 and alarm 22100 above the chuck speed (L20932-21020)."""
        actual = abs(self.axis.velocity) / RPM
        limit = self.md.float(MD.SPIND_VELO_LIMIT) * (1.0 + self.md.float(MD.SPIND_DES_VELO_TOL))
        self.at_chuck_limit = actual > limit
        if self.at_chuck_limit:
            alarms.raise_alarm(ALARM_CHUCK_SPEED, cycle, self.channel, "", self.number,
                               channel=self.channel, axis=self.name)

    def speed_reached(self) -> bool:
        """83.5: actual speed within MD35150 x set speed; always with MD35150 = 0 (L20840-20858)."""
        if self.mode is SpindleMode.SYNCHRONOUS:
            return self.sync_speed_reached  # the differential speed (L23507-23511)
        tolerance = self.md.float(MD.SPIND_DES_VELO_TOL)
        if tolerance == 0.0:
            return True
        if self.mode is not SpindleMode.CONTROL:
            return False
        axis = self.axis
        actual = axis.velocity / RPM
        direction = -self.direction if self.inputs.invert_m3_m4 else self.direction
        wanted = direction * self.set_speed
        if wanted == 0.0:
            return self.stationary()
        return abs(actual - wanted) <= tolerance * abs(wanted)

    def in_position(self) -> bool:
        """85.5: after SPOS / SPOSA / M19 while synchronised, in exact stop fine, on the target;
        only for the function "spindle positioning", not at the gear-change position (L17059-17068)."""
        positioning, axis = self.positioning, self.axis
        return (positioning is not None and positioning.programmed and positioning.done
                and self.mode is SpindleMode.POSITIONING
                and axis.encoder.referenced and axis.owner is Owner.NONE
                and abs(axis.distance_to_end_point) <= axis.dyn.fine_window)

    def write_outputs(self) -> None:
        change = self.gear_change
        dialog = change.dialog_open
        requested = change.target if dialog else change.acknowledged_gear
        direction_shown = 1 if self.axis.velocity > self.axis.dyn.standstill_velocity else 0
        status = (
            requested, dialog, self.at_chuck_limit,
            self.limited and self.mode is SpindleMode.CONTROL and not self.limits_unreported,
            self.raised and self.mode is SpindleMode.CONTROL and not self.limits_unreported,
            self.speed_reached(), direction_shown,
            self.mode, self.in_position(), self.m_function, self.parameter_set, self.position_control,
        )
        if status == self._status:
            return
        position_control_changed = not self._status or self._status[-1] != self.position_control
        self._status = status
        area, sig = self._area, self._signals
        sig.requested_gear.put(area, requested)
        sig.change_gear.put(area, dialog)
        sig.speed_limit_exceeded.put(area, self.at_chuck_limit)
        sig.setpoint_limited.put(area, bool(status[3]))
        sig.setpoint_raised.put(area, bool(status[4]))
        sig.speed_reached.put(area, bool(status[5]))
        sig.clockwise.put(area, bool(direction_shown))
        sig.control_mode.put(area, self.mode is SpindleMode.CONTROL)
        sig.oscillation_mode.put(area, self.mode is SpindleMode.OSCILLATION)
        sig.positioning_mode.put(area, self.mode is SpindleMode.POSITIONING)
        sig.spindle_mode.put(area, self.mode is not SpindleMode.AXIS)
        sig.in_position.put(area, bool(status[8]))
        sig.m_function.put(area, self.m_function)
        sig.parameter_set.put(area, self.parameter_set)
        if position_control_changed:
            self.axis.position_control = self.position_control
            self.axis.resting = False

