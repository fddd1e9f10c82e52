"""A machine axis or spindle: setpoint, position control loop, drive, encoder, monitoring.

Per IPO cycle the axis gets a position setpoint from whoever owns its motion (the
channel's path interpolation, JOG, a braking ramp), filters it (axial jerk filter where
configured), closes the position loop (Kv, speed feedforward), moves the simulated drive
(first-order lag with the equivalent speed-control time constant MD32810) and the slide,
reads the encoder, monitors, and writes its DB31 status bits.

Internal units: mm, mm/s, mm/s^2 for linear axes; degrees, deg/s, deg/s^2 for rotary
axes and spindles (``dynamics``: the machine data converted once).  One motion owner at a
time gives the setpoint (``owner``: the diagram).

Measuring systems: one or two (MD30200); DB31.DBX1.5 / 1.6 select which one is active.
With neither selected the axis is "parked": no actual value, no position control.

The axis owns its functions' pieces: ``PositionLoop`` (Kv, feedforward, symmetrising and the
drive's lag: ``position_loop``), ``AxisJog`` (JOG with the traverse keys and the handwheel, the
software limit switches in JOG: ``jog``), ``DrfOffset`` (the DRF offset in AUTO / MDA: ``drf``);
its DB31 signals are the groups ``AxisInputs`` (``signals``) and ``AxisStatus``
(``interfaces.signal_groups``).  The cycle itself (the slide, the encoder, enables, exact stop and
standstill monitoring, the status bits) stays here, on the axis's own attributes:
``control_cycle`` runs every IPO cycle for every moving axis.
"""

from __future__ import annotations

import dataclasses
from typing import Protocol

from interfaces.signal_groups import AxisStatus
from vc.config import md_dictionary as MD
from vc.config.model import AxisConfig
from vc.core.alarms import AlarmList
from vc.core.axis.drf import DrfOffset
from vc.core.axis.drive_data_sets import DriveDataSets
from vc.core.axis.drive_messages import DriveMessages
from vc.core.axis.dynamics import CoupledLoop, dynamics_of, jerk_filter_of
from vc.core.axis.encoder import MeasuringSystem
from vc.core.axis.holding_brake import HoldingBrakeSignals
from vc.core.axis.index_jog import IndexJog
from vc.core.axis.indexing import IndexPositions
from vc.core.axis.jog import FREE_JOG, AxisJog, JogLimits
from vc.core.axis.jog_keys import CONTINUOUS_JOG, JogSelection
from vc.core.axis.motion import ramp
from vc.core.axis.owner import Owner
from vc.core.axis.parameter_sets import ServoParameterSets
from vc.core.axis.position_loop import PositionLoop
from vc.core.axis.rotary import modulo_range_of
from vc.core.axis.signals import AxisInputs
from vc.core.interface_map import SignalTable

_TINY = 1e-9
POSITIONING_AXIS_ONLY = 1 << 8  # MD30460 bit 8 (seed 003 L10843-10858)


class Obstacle(Protocol):
    """Something the slide can run into (the plant's fixed stop: vc/plant/fixed_stop.py)."""

    def hold(self, previous: float, position: float, force_percent: float) -> float:
        """Where the slide that moved from ``previous`` to ``position`` stands, the drive pushing
        with ``force_percent`` of its maximum force."""


class MachineAxis:
    """One machine axis or spindle of the simulated control."""

    def __init__(self, config: AxisConfig, table: SignalTable, area: bytearray, dt: float, channel: str,
                 physical: float | None = None):
        self.config = config
        self.name = config.name
        self.area_key = f"DB{config.db}"
        self.channel = channel
        self.dyn = dynamics_of(config)
        self.modulo_range = modulo_range_of(config)
        self.index = IndexPositions.of(config)  # an indexing axis's positions (MD30500), else None
        self.programmed_index = 0  # $AA_PROG_INDEX_AX_POS_NO: the index position a POS / FC18 motion goes to
        # MD30460 bit 8: a positioning axis / auxiliary spindle only (no path axis, no thread; the decoder)
        self.positioning_only = bool(config.md.int(MD.BASE_FUNCTION_MASK) & POSITIONING_AXIS_ONLY)
        self._decode = table.codec(AxisInputs).decode
        self._encode = table.codec(AxisStatus).encode
        self._area = area
        self._dt = dt
        self.inputs = AxisInputs()
        self.physical = config.sim.start_position if physical is None else physical
        phases = (config.sim.zero_mark_offset, config.sim.zero_mark_offset_2)
        self.encoders = [MeasuringSystem.for_axis(config, index, self.physical, phases[index])
                         for index in range(max(1, config.md.int(MD.NUM_ENCS)))]
        self.active_encoder: int | None = 0  # until the PLC selects (power-on: measuring system 1)
        self._lowest_limit_velocity = min(encoder.limit_velocity for encoder in self.encoders)
        self._frequency_exceeded_somewhere = False
        self.actual = self.encoder.actual(self.physical)
        self.external_velocity = 0.0  # the slide moved by hand while the servo is off (physical units/s)
        self.pulses_cancelled = False  # the power unit cancelled the pulses (DC link below 0.9 x r0208)
        self.line_up_ready = False  # the drive line-up (infeed) reports ready: the plant's Drives.ready
        self.setpoint = self.actual  # interpolated position setpoint (before the jerk filter)
        self.command_velocity = 0.0  # velocity of the interpolated setpoint, signed, per second
        self.velocity = 0.0  # actual velocity of the slide, signed, per second
        self.owner = Owner.NONE
        self.servo_on = False
        self.follow_up = False
        self.override = 1.0
        self._brake_decel = 0.0
        self._servo_off_countdown = -1  # cycles until the controller enable is removed after a rapid stop
        self._tracking = False  # enable lost in motion: the setpoint follows the slide until the enable returns
        self._motion_end_cycle = 0  # cycles since the interpolator reached its end point
        self._fine_reached = True
        self.at_software_limit = 0  # -1 / +1 while resting on the minus / plus software limit switch
        self.jog = AxisJog(dt)  # the traverse keys and the handwheel in JOG
        # JOG of an indexing axis to its index positions, once it is referenced (L13405-13407)
        self.index_jog = IndexJog(self.index, dt) if self.index is not None else None
        self.loop = PositionLoop(dt, self.actual, jerk_filter_of(config, self.dyn, dt, self.actual))
        self.resting = False  # at rest and no input changed since: the cycle may skip the axis
        self.coordinate_shift = 0.0  # the sum of every shift(): the NC coordinates against the first ones
        self._status = -1  # the status bits last written, one bit each (none yet)
        self.is_spindle = config.is_spindle
        # DB31.DBX61.5: a spindle in speed control runs without position control (L16163-16167)
        self.position_control = not config.is_spindle
        self.axis_mode = False  # a spindle in axis mode (M70) is programmed like a rotary axis
        # a coupled following spindle takes the leading spindle's disable instead of its own (L23212-23230)
        self.disable_by_coupling: bool | None = None
        # overlaid motion added behind the interpolator (a coupled helix axis): the machine position
        # moves, the programmed one does not until the overlay is folded in (seed 002 L77-81)
        self.overlay = 0.0
        self.overlay_velocity = 0.0
        self.disturbance_velocity = 0.0  # a load the drive must hold against (plant fault), per second
        # a part clamped in this spindle and another: the slide is held at k x the other's position + offset
        self.clamp: tuple[MachineAxis, float, float] | None = None
        # DRF (AUTO / MDA, DB21.DBX0.3): the handwheel's offset in the MCS, overlaid on the path (part of
        # ``overlay``), and the distance of it still to travel; it outlives reset and program end (L36426)
        self.drf = DrfOffset(dt)
        # travel to fixed stop (vc/core/fixed_stop/): the drive's torque limit in percent of its maximum
        # (None: not limited), and while it stands at the stop the NC holds it there (no monitoring,
        # DBX2.1 / 1.3 do not act); ``obstacle``: what the slide runs into (the plant's fixed stop)
        self.torque_limit: float | None = None
        self.at_fixed_stop = False
        self.fixed_stop_waits = False  # FXS selected, its motion waits for the PLC's enable DBX3.1 (L37221-37232)
        self.obstacle: Obstacle | None = None
        self.blocked = False  # the slide stood against the obstacle in the last cycle: the motor pushes
        # the drive's messages DB31.DBX94.x / 95.0 (vc/core/axis/drive_messages.py): only a drive that reports them
        self.messages: DriveMessages | None = None
        # the servo parameter set the PLC selects (DB31.DBX9.0-9.2, MD35590 = 1 / 2): only on such an axis
        self.parameter_sets: ServoParameterSets | None = None
        # the drive's data sets and integrator (DB31.DBX21.0-21.6 / 93.0-93.6, drive_data_sets.py)
        self.data_sets = DriveDataSets(table, area, dt)
        # the motor's holding brake (DB31.DBX20.5 / 92.5, holding_brake.py): only an axis that has one
        self.holding_brake: HoldingBrakeSignals | None = None
        HoldingBrakeSignals.declare(table)
        self._table = table
        # setpoint switchover (setpoint_switchover.py): an axis sharing its drive with others is position
        # controlled only while it has the drive's control (DB31.DBX96.5); an axis with a drive of its own has
        self.drive_control = True

    # ------------------------------------------------------------------ inputs
    def decode_inputs(self) -> None:
        """The PLC changed its outputs: read this axis's DB31 signals."""
        inp = self.inputs
        self._decode(self._area, inp)
        inp.select_encoder(len(self.encoders))
        self.resting = False
        sets = self.parameter_sets
        if sets is not None:
            kv = sets.decode()
            if kv is not None:
                self.set_loop_gain(kv)
        self.data_sets.decode()
        if self.holding_brake is not None:
            self.holding_brake.decode()
        if inp.encoder_selected != self.active_encoder:
            self._select_encoder(inp.encoder_selected)

    def fit_holding_brake(self, brake: Obstacle) -> HoldingBrakeSignals:
        """The plant's holding brake on this axis's motor: it holds the slide (the axis's obstacle)
        and takes the PLC's order and gives its feedback through the signals returned."""
        self.obstacle = brake
        self.holding_brake = HoldingBrakeSignals(self._table, self._area)
        return self.holding_brake

    @property
    def disabled(self) -> bool:
        return self.inputs.disable if self.disable_by_coupling is None else self.disable_by_coupling

    def add_overlay(self, distance: float, velocity: float) -> None:
        self.overlay += distance
        self.overlay_velocity = velocity
        self.resting = False

    def fold_overlay(self) -> None:
        """The overlaid distance becomes part of the programmed position (nothing moves); the DRF
        offset stays overlaid."""
        self.setpoint += self.overlay - self.drf.offset
        self.overlay = self.drf.offset
        self.overlay_velocity = self.drf.velocity
        self.resting = False

    def add_drf_travel(self, distance: float) -> None:
        """Handwheel pulses with DRF: the DRF offset grows by ``distance`` (sign = direction); not
        for an axis with a Hirth joint, as the handwheel in JOG (seed 003 L14074, L14081)."""
        if self.index is not None and self.index.hirth:
            return
        self.drf.add_travel(distance)
        self.resting = False

    def drf_cycle(self, stopped: bool) -> None:
        """The DRF offset's travel, one IPO cycle (``DrfOffset.step``), overlaid on whatever the path does."""
        drf = self.drf
        step = drf.step(stopped, self.dyn.max_accel, self.dyn.drf_velocity)
        self.add_overlay(step, drf.velocity)

    def delete_drf_offset(self) -> None:
        """DRFOF: the DRF offset is deleted and the axis does not move (seed 003 L36470-36490): the
        offset becomes part of the programmed position, as a folded overlay does; a DRF travel still
        to go is dropped."""
        drf = self.drf
        if not (drf.offset or drf.moving):
            return
        self.setpoint += drf.offset
        self.overlay -= drf.offset
        self.overlay_velocity -= drf.velocity
        drf.clear()
        self.resting = False

    @property
    def drf_moving(self) -> bool:
        return self.drf.moving

    @property
    def drf_offset(self) -> float:
        """The DRF offset in the MCS (part of ``overlay``); a coupling's DRF adds to it."""
        return self.drf.offset

    @drf_offset.setter
    def drf_offset(self, offset: float) -> None:
        self.drf.offset = offset

    def _select_encoder(self, selected: int | None) -> None:
        """Measuring-system switch-over: the new actual value is taken over, nothing moves."""
        self.active_encoder = selected
        if selected is None:
            return  # parked: the last actual value stands, position control is off
        new_actual = self.encoders[selected].actual(self.physical)
        self.shift(new_actual - self.actual)

    @property
    def encoder(self) -> MeasuringSystem:
        """The active measuring system (the last one while parked)."""
        return self.encoders[self.active_encoder if self.active_encoder is not None else 0]

    def stand_at(self, actual: float) -> None:
        """Power-on: the axis stands still at ``actual``; every setpoint stage agrees with it."""
        self.actual = self.setpoint = actual
        self.loop.hold_at(actual)
        self.resting = False

    def shift(self, delta: float) -> None:
        """Move the NC coordinates by ``delta`` (the actual value system was set anew)."""
        if delta == 0.0:
            return
        self.coordinate_shift += delta
        self.actual += delta
        self.setpoint += delta
        self.loop.shift(delta)
        self.resting = False

    def synchronise(self, encoder: MeasuringSystem, physical: float, actual: float) -> None:
        """Referencing done: ``encoder`` reads ``actual`` at the physical position ``physical``."""
        encoder.set_actual(physical, actual)
        if encoder is self.encoder:
            self.shift(encoder.actual(self.physical) - self.actual)
        self.resting = False
    @property
    def drive_ready(self) -> bool:
        """Controller and pulse enable present, a measuring system active and the drive's control (a
        drive shared with other axes, setpoint switchover): position control possible."""
        return self.inputs.controller_enable and self.inputs.pulse_enable and self.active_encoder is not None \
            and not self.pulses_cancelled and not self.data_sets.pulses_cancelled and self.drive_control

    @property
    def _drive_held_at_stop(self) -> bool:
        """At the fixed stop the controller enable does not act (seed 003 L37292-37298)."""
        return self.inputs.pulse_enable and self.active_encoder is not None and not self.pulses_cancelled \
            and not self.data_sets.pulses_cancelled

    def hold_at_fixed_stop(self, setpoint: float) -> None:
        """The fixed stop is detected: the path's rest is deleted and the setpoint stands at
        ``setpoint``, the threshold MD37030 beyond the stop, so that the drive keeps pushing with
        its torque limit (seed 003 L37306-37308, L37345-37349)."""
        self.release()
        self.setpoint = setpoint
        self.resting = False

    def leave_fixed_stop(self) -> None:
        """Deselected or aborted: no torque limit, position control where the slide stands
        (seed 003 L37446-37449, L37402-37406)."""
        self.torque_limit = None
        if self.owner is Owner.NONE:
            self.setpoint = self.actual
            self.loop.hold_at(self.actual)
        self.resting = False

    @property
    def drive_enabled(self) -> bool:
        """DB31.DBX92.7 "drive ready": the line-up is ready, the PLC enables the pulses (DBX21.7) and
        the controller (DBX2.1), and neither the power unit (DC link) nor the NC (the controller
        enable it removes after a rapid stop) has taken the enable away.  The drive reports it,
        whatever the measuring systems do [control]."""
        inp = self.inputs
        return self.line_up_ready and inp.pulse_enable and inp.controller_enable and not self.pulses_cancelled \
            and not self.data_sets.pulses_cancelled and self._servo_off_countdown != 0

    def set_line_up_ready(self, ready: bool) -> None:
        self.line_up_ready = ready
        self.resting = False  # the status bits change

    @property
    def referenced(self) -> bool:
        return self.encoder.referenced

    @property
    def software_limits_active(self) -> bool:
        """After referencing, and also with a restored position (seed 003 L2777-2778) or one that
        is exact but waits for a reference return (``require_reference_return``)."""
        encoder = self.encoder
        return (encoder.referenced or encoder.restored or encoder.reference_return_due) and not self.is_spindle \
            and (self.modulo_range is None or self.inputs.modulo_limit_enable)

    @property
    def software_limits(self) -> tuple[float, float]:
        """MD36100 / MD36110 in the NC's coordinates, MD36120 / MD36130 in their place while the PLC selects
        the 2nd software limit switches (DB31.DBX12.2 / 12.3).  A modulo rotary axis has them only with
        DB31.DBX12.4 (L12780-12800): the limits are modulo positions, the range from the minus to
        the plus limit (across the range end where minus > plus, L12900-12905) is the turn nearest to
        the setpoint, divided from the next in the middle of the forbidden gap between them [INF]."""
        dyn, inp = self.dyn, self.inputs
        # DB31.DBX12.2 / 12.3: the 2nd software limit switch MD36120 / MD36130 in place of the 1st
        limit_minus = dyn.limit_minus_2 if inp.limit_switch_2_minus else dyn.limit_minus
        limit_plus = dyn.limit_plus_2 if inp.limit_switch_2_plus else dyn.limit_plus
        if self.modulo_range is None:
            return limit_minus, limit_plus
        size = self.modulo_range[1]
        allowed = (limit_plus - limit_minus) % size
        gap = size - allowed
        low = self.setpoint - (self.setpoint - limit_plus - gap / 2.0) % size + gap / 2.0
        return low, low + allowed

    @property
    def following_error(self) -> float:
        """Position setpoint at the position controller minus actual value."""
        return self.loop.setpoint - self.actual

    @property
    def lag_per_velocity(self) -> float:
        """Following error per unit of a constant velocity (s): ``PositionLoop.lag_per_velocity``."""
        return self.loop.lag_per_velocity(self.dyn)

    @property
    def coupled_loop(self) -> CoupledLoop | None:
        """The position loop a synchronous spindle coupling sets in place of the axis's own."""
        return self.loop.coupled

    @coupled_loop.setter
    def coupled_loop(self, loop: CoupledLoop | None) -> None:
        self.loop.set_coupled(self.dyn, loop)

    @property
    def distance_to_end_point(self) -> float:
        """Interpolated end point minus actual value: what the exact stop windows measure
        (seed 003 §13.8.8: the windows are counted from the target position)."""
        return self.setpoint + self.overlay - self.actual

    @property
    def display_velocity(self) -> float:
        return self.velocity * self.dyn.display_velocity_factor

    def shown(self, position: float) -> float:
        """A position as the NC shows it: on a modulo rotary axis (MD30310) inside the modulo
        range MD30340 .. MD30340 + MD30330.  The NC itself counts on without a jump, so a move
        across the range end stays one continuous move."""
        if self.modulo_range is None:
            return position
        start, size = self.modulo_range
        return start + (position - start) % size

    @property
    def at_rest(self) -> bool:
        """No motion commanded and the setpoint has arrived."""
        return self.owner is Owner.NONE and self.command_velocity == 0.0

    # ------------------------------------------------------------------ motion owners
    def take(self, owner: Owner) -> None:
        self.owner = owner
        if owner is not Owner.COMMAND:
            self.programmed_index = 0  # $AA_PROG_INDEX_AX_POS_NO: no longer on its way to an index position
        self._motion_end_cycle = 0
        self.resting = False

    def release(self) -> None:
        """The owner has finished: the setpoint stands still at its end point."""
        self.owner = Owner.NONE
        self.command_velocity = 0.0
        self._motion_end_cycle = 0

    def brake(self, decel: float | None = None) -> None:
        """Stop the setpoint on a ramp, whatever owns the axis (e-stop, enable removed, limit switch)."""
        self._brake_decel = self.dyn.max_accel if decel is None else decel
        self.take(Owner.BRAKE)

    @property
    def rapid_stopping(self) -> bool:
        """Braking on the rapid-stop ramp (MD36610): alarm reaction, emergency stop, enable removed."""
        return self.owner is Owner.BRAKE and self._brake_decel == self.dyn.rapid_stop_decel

    def rapid_stop(self, then_servo_off: bool) -> None:
        self.brake(self.dyn.rapid_stop_decel)
        if then_servo_off and self._servo_off_countdown < 0:
            self._servo_off_countdown = max(1, round(self.dyn.servo_disable_delay / self._dt))

    def set_path_setpoint(self, position: float, velocity: float) -> None:
        self.setpoint = position
        self.command_velocity = velocity

    def add_handwheel_travel(self, distance: float) -> None:
        """Handwheel pulses in JOG: ``distance`` more to travel (sign = direction); not for an axis
        with a Hirth joint (seed 003 L14074)."""
        if self.index is not None and self.index.hirth:
            return
        self.jog.add_handwheel_travel(distance)
        self.resting = False

    @property
    def handwheel_rest(self) -> float:
        """JOG: the handwheel's distance still to travel."""
        return self.jog.handwheel_rest

    def jog_cycle(self, allowed: bool, channel_feed_disable: bool, limits: JogLimits = FREE_JOG,
                  selection: JogSelection = CONTINUOUS_JOG) -> None:
        """JOG with the traverse keys (continuous or incremental as ``selection`` says), or the
        handwheel's travel, one IPO cycle; a referenced indexing axis jogs to its index positions
        (whatever increment is selected, L13463-13465)."""
        if self.index_jog is not None and self.referenced and not self.jog.handwheel_rest:
            self.index_jog.cycle(self, allowed, channel_feed_disable, limits, selection.increment != 0.0)
        else:
            self.jog.cycle(self, allowed, channel_feed_disable, limits, selection)

    def _brake_cycle(self) -> None:
        velocity = ramp(self.command_velocity, 0.0, self._brake_decel, self._dt)
        self.command_velocity = velocity
        self.setpoint += velocity * self._dt
        if velocity == 0.0:
            self.release()

    # ------------------------------------------------------------------ control loop
    def control_cycle(self, cycle: int, alarms: AlarmList) -> bool:
        """Position loop, drive, encoder, monitoring and status bits for one IPO cycle.

        Returns False when the axis was at rest and nothing changed (its outputs stand).
        """
        if self.owner is Owner.BRAKE:
            self._brake_cycle()
        if self.resting and self.command_velocity == 0.0 and self.owner is Owner.NONE \
                and not self.external_velocity and not self.disturbance_velocity and not self.overlay_velocity \
                and self.clamp is None:
            return False
        self._update_servo_state(cycle, alarms)
        dt = self._dt
        loop = self.loop
        drive_velocity_before = loop.drive_velocity
        if self.servo_on:
            if loop.close(self.dyn, self.setpoint + self.overlay, self.actual, self.command_velocity):
                # Settled below the measuring resolution: the slide stands on the setpoint.
                self.physical += loop.setpoint - self.actual
        else:
            # No position control: the drive brakes on its own ramp and the slide stops.
            loop.drive_velocity = ramp(loop.drive_velocity, 0.0, self.dyn.rapid_stop_decel, dt)
        if self.disabled and not self.at_fixed_stop:
            # Axis disable: the setpoints do not reach the drive; the NC shows the setpoint as actual value.
            loop.drive_velocity = 0.0
            self.velocity = self.command_velocity
            self.actual = loop.setpoint if self.servo_on else self.actual
        else:
            slide_velocity = loop.drive_velocity + self.disturbance_velocity if self.servo_on \
                else loop.drive_velocity + self.external_velocity
            previous = self.physical
            self.physical += slide_velocity * dt
            if self.obstacle is not None:
                force = 0.0 if not self.servo_on else 100.0 if self.torque_limit is None else self.torque_limit
                held = self.obstacle.hold(previous, self.physical, force)
                self.blocked = held != self.physical
                if self.blocked:
                    self.physical = held
                    slide_velocity = (held - previous) / dt
                    loop.drive_velocity = 0.0  # the motor is blocked
            self.velocity = slide_velocity
            if self.clamp is not None:
                other, ratio, offset = self.clamp
                self.physical = ratio * other.physical + offset  # the part holds it, whatever the drive does
                self.velocity = ratio * other.velocity
            if self.active_encoder is not None:
                self.actual = self.encoder.actual(self.physical)
        if not self.servo_on and (self.follow_up or self._tracking):
            self.setpoint = self.actual
            loop.hold_at(self.actual)
            self.command_velocity = 0.0
        if abs(self.velocity) > self._lowest_limit_velocity or self._frequency_exceeded_somewhere:
            self._monitor_encoder_frequency(cycle, alarms)
        self._monitor(cycle, alarms)
        messages = self.messages
        if messages is not None:
            messages.update(self.velocity, loop.speed_setpoint if self.servo_on else 0.0,
                            (loop.drive_velocity - drive_velocity_before) / dt, self.servo_on, self.torque_limit,
                            self.blocked and self.servo_on)
        self._write_outputs()
        return True

    def _update_servo_state(self, cycle: int, alarms: AlarmList) -> None:
        inp = self.inputs
        if self._servo_off_countdown > 0:
            self._servo_off_countdown -= 1
        forced_off = self._servo_off_countdown == 0
        wanted = (self.drive_ready or (self.at_fixed_stop and self._drive_held_at_stop)) and not forced_off
        if self.servo_on and not wanted and not forced_off:
            moving = self.command_velocity != 0.0 or abs(self.velocity) > self.dyn.standstill_velocity
            if moving:
                alarms.raise_alarm(21612, cycle, self.channel, self.name, channel=self.channel, axis=self.name)
                self._tracking = True  # the NC cannot hold a moving setpoint: it follows the braking slide
            self.brake(self.dyn.rapid_stop_decel)
        # Enable returns: take the present position (follow-up), or return to the held setpoint.
        if not self.servo_on and wanted and (self.follow_up or self._tracking
                                             or (self.owner is Owner.NONE and inp.follow_up_mode)):
            self.setpoint = self.actual
            self.loop.hold_at(self.actual)
        if wanted:
            self._tracking = False
        self.servo_on = wanted
        self.follow_up = not wanted and (inp.follow_up_mode or forced_off or not self.drive_control)

    def set_encoder_turn(self, encoder: MeasuringSystem, turn: float) -> None:
        """A rotary motor encoder now turns once per ``turn`` of the axis (``MeasuringSystem.set_turn``)."""
        encoder.set_turn(self.config.md, turn)
        self._lowest_limit_velocity = min(each.limit_velocity for each in self.encoders)

    def set_speed_control(self, on: bool) -> None:
        """Position control off (``on``) or back on: the position loop takes over where the slide is,
        not where the setpoint ran ahead of it."""
        loop = self.loop
        if loop.speed_control and not on:
            self.setpoint = loop.setpoint = loop.model_position = self.actual
            if loop.jerk_filter:
                loop.jerk_filter.reset(self.actual)
        loop.speed_control = on

    def set_loop_gain(self, kv: float) -> None:
        """The servo gain of the active parameter set (MD32200[n], e.g. a spindle's gear stage)."""
        if kv != self.dyn.kv:
            self.dyn = dataclasses.replace(self.dyn, kv=kv)

    def restore_servo(self) -> None:
        """After an acknowledged emergency stop: the NC gives the controller enable back."""
        self._servo_off_countdown = -1
        self.resting = False

    def _monitor_encoder_frequency(self, cycle: int, alarms: AlarmList) -> None:
        """Above its limit frequency MD36300 an encoder loses counts: the measuring system loses
        its reference (seed 003 L758-761: G74 again) and shows DB31.DBX60.2 / 60.3.  On an axis the
        active one raises alarm 21610 [control]; a spindle resynchronises (L21129-21180)."""
        speed = abs(self.velocity)
        for encoder in self.encoders:
            if encoder.watch_limit_frequency(speed) and encoder is self.encoder and not self.is_spindle:
                alarms.raise_alarm(21610, cycle, self.channel, self.name, encoder.index + 1,
                                   channel=self.channel, axis=self.name)
        self._frequency_exceeded_somewhere = any(encoder.frequency_exceeded for encoder in self.encoders)

    def preset_actual(self, value: float) -> None:
        """PRESETON: the actual value becomes ``value`` where the axis stands; every measuring
        system is moved with it and loses its reference (seed 003 L758-761, L2007, L2045)."""
        delta = value - self.actual
        for encoder in self.encoders:
            encoder.offset += delta
            encoder.lose_reference()
        self.resting = False  # the status bits change
        self.shift(delta)

    def require_reference_return(self) -> None:
        """The machine position is still exact, only its relation to the program is lost: the axis
        shows itself unreferenced (DB31.DBX60.4 / 60.5 = 0, NC start locked by MD20700) until it is
        referenced again, and its software limits stay active [control]."""
        for encoder in self.encoders:
            encoder.require_reference_return()
        self.resting = False  # the status bits change

    def _monitor(self, cycle: int, alarms: AlarmList) -> None:
        dyn = self.dyn
        error = abs(self.setpoint + self.overlay - self.actual)  # exact stop windows count from the end point
        interpolation_done = self.owner is Owner.NONE and self.command_velocity == 0.0
        if self.at_fixed_stop:
            self.resting = False  # held against the stop: no exact stop or standstill monitoring (L37771-37773)
            return
        if not self.servo_on and not self.follow_up and not self._tracking and self.position_control:
            # held without controller enable (no follow-up mode): the standstill monitoring watches the
            # slide, e.g. a vertical axis sagging on an open brake; 25040, then follow-up (L14921-14925)
            self._fine_reached = False
            if error > dyn.standstill_tolerance:
                alarms.raise_alarm(25040, cycle, self.name, channel=self.channel, axis=self.name)
                self._tracking = True
        elif interpolation_done and self.servo_on and not self.disabled:
            self._motion_end_cycle += 1
            elapsed = self._motion_end_cycle * self._dt
            if error <= dyn.fine_window:
                self._fine_reached = True
            elif not self._fine_reached and elapsed > dyn.positioning_time:
                alarms.raise_alarm(25080, cycle, self.name, channel=self.channel, axis=self.name)
            # DB31.DBX2.3 "clamping in progress": the clamping monitor (MD36050, alarm 26000) takes the
            # standstill monitor's place, as the clamp may push the axis further [control]
            clamping = self.inputs.clamping
            tolerance = dyn.clamp_tolerance if clamping else dyn.standstill_tolerance
            if self._fine_reached and elapsed > dyn.standstill_delay and error > tolerance:
                alarms.raise_alarm(26000 if clamping else 25040, cycle, self.name, channel=self.channel,
                                   axis=self.name)
        else:
            self._fine_reached = False
        if self.at_software_limit:
            self.jog.monitor_software_limit(self, cycle, alarms)
        # At rest when nothing moves: the next cycles can skip the loop until an input changes.
        loop = self.loop
        self.resting = (interpolation_done and self.velocity == 0.0 and loop.drive_velocity == 0.0
                             and loop.setpoint == self.setpoint + self.overlay and error <= dyn.fine_window
                             and (loop.jerk_filter is None or loop.jerk_filter.settled(self.setpoint, 0.0))
                             and self._servo_off_countdown <= 0 and not self.at_software_limit)

    def _write_outputs(self) -> None:
        dyn = self.dyn
        error = abs(self.setpoint + self.overlay - self.actual)  # exact stop windows count from the end point
        no_motion = self.owner is Owner.NONE and self.command_velocity == 0.0
        first = self.encoders[0]
        second = self.encoders[1] if len(self.encoders) > 1 else None
        exact_coarse = no_motion and error <= dyn.coarse_window
        exact_fine = no_motion and error <= dyn.fine_window
        # "stationary" is the actual speed below MD36060, whoever owns the axis (a coupled FS,
        # a path axis held by feed stop), as long as nothing commands it to move
        stationary = self.command_velocity == 0.0 and abs(self.velocity) <= dyn.standstill_velocity
        position_control = self.servo_on and self.position_control
        referenced_2 = second is not None and second.referenced
        restored_2 = second is not None and second.restored
        frequency_exceeded_2 = second is not None and second.frequency_exceeded
        command_plus = self.command_velocity > _TINY
        command_minus = self.command_velocity < -_TINY
        # DB31.DBX74.4: the limits of a modulo rotary axis act (DBX12.4 and referenced, L12936-12946)
        modulo_limit_active = self.inputs.modulo_limit_enable and self.modulo_range is not None and \
            self.software_limits_active
        # DB31.DBX76.6: an indexing axis stands on an index position within MD36010 (L13823-13829),
        # once it is referenced [INF: the seed counts index positions only then, L13405-13407]
        index_in_position = self.index is not None and exact_fine and self.referenced and \
            self.index.standing_on(self.actual, dyn.fine_window) > 0
        drive_enabled = self.drive_enabled
        # the bits as one number first: compared every cycle, without building anything; the status
        # is built (by keyword) only when it changed
        status = (exact_coarse | exact_fine << 1 | stationary << 2 | position_control << 3 | self.follow_up << 4
                  | first.referenced << 5 | referenced_2 << 6 | first.restored << 7 | restored_2 << 8
                  | first.frequency_exceeded << 9 | frequency_exceeded_2 << 10 | self.disabled << 11
                  | command_plus << 12 | command_minus << 13 | drive_enabled << 14 | modulo_limit_active << 15
                  | index_in_position << 16)
        if status == self._status:
            return
        self._status = status
        self._encode(self._area, AxisStatus(
            exact_coarse=exact_coarse, exact_fine=exact_fine, stationary=stationary, position_control=position_control,
            follow_up_active=self.follow_up, referenced_1=first.referenced, referenced_2=referenced_2,
            restored_1=first.restored, restored_2=restored_2, frequency_exceeded_1=first.frequency_exceeded,
            frequency_exceeded_2=frequency_exceeded_2, disabled=self.disabled, command_plus=command_plus,
            command_minus=command_minus, drive_enabled=drive_enabled, modulo_limit_active=modulo_limit_active,
            index_in_position=index_in_position))
