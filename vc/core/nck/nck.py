"""The NCK: one deterministic IPO cycle at a time.

``Nck.step(plc_side)`` is the only way time advances.  Its body is the order of
operations of one IPO cycle::

    latch PLC->NC signals -> edges -> NCK functions (emergency stop)
    -> mode group and channel commands (reset, NC start/stop, mode, REF)
    -> program interpreter and path interpolation (incl. channel referencing, G74)
    -> JOG or, in JOG-REF / MDA-REF, referencing with the traverse keys
    -> referencing procedures -> position control, drive, encoder, monitoring
    -> reactions to new alarms -> NC->PLC outputs

The NCK owns its own process image of all interface data blocks.  It reads the PLC's
outputs from ``plc_side`` at the start of the cycle (only when that image changed) and
writes its outputs into its own image at the end; a link moves those bytes to the PLC.
No I/O, no wall clock, no global state: same configuration and same inputs give the
same outputs, byte for byte.  What the control keeps over power-off (machine data it
writes, buffered positions) is an :class:`NcMemory` handed in by whoever powers it on.
"""

from __future__ import annotations

import math
from collections.abc import Callable

from interfaces.image import ProcessImage
from interfaces.signals import Catalog, Direction, InstanceKind, expand
from vc.config import md_dictionary as MD
from vc.config.model import MachineConfig, machine_ipo_cycle_us
from vc.core.alarms import STOP_AXES, Alarm, AlarmList, Clear, Reaction
from vc.core.axis.axis import AxisSignals, MachineAxis, Owner
from vc.core.axis.handwheel import GEOMETRY_AXES, Handwheels, HandwheelSignals
from vc.core.channel.channel import Channel, ChannelSignals, ChannelState, Mode
from vc.core.channel.referencing_control import ReferencingControl
from vc.core.interface_map import SignalTable
from vc.core.nc_memory import NcMemory
from vc.core.nck.alarm_area import AlarmArea
from vc.core.nck.manual_retraction import ManualRetraction, RetractionSignals
from vc.core.nck.mode_group import ModeGroup, ModeGroupSignals
from vc.core.overrides import OverrideCoding
from vc.core.referencing.referencing import buffer_at_power_off, encoder_slip, restore_at_power_on
from vc.core.retraction.dc_link import DcLink
from vc.core.retraction.drive_esr import DriveEsr, DriveEsrSignals
from vc.core.retraction.esr import ChannelEsr, NckEsr
from vc.core.spindle.coupling import Couplings, CouplingSignals
from vc.core.spindle.polygon import PolygonTurning
from vc.core.spindle.spindle import Spindle, SpindleSignals
from vc.core.transforms.inclined_axis_control import InclinedAxisControl, inclined_axis_control

EMERGENCY_STOP_ALARM = 3000
PLC_SIGN_OF_LIFE_ALARM = 2000
PLC_NOT_STARTED_ALARM = 2001


class NckSignals:
    def __init__(self, table: SignalTable):
        self.emergency_stop = table.bit("basic.out.emergencyStop")
        self.emergency_stop_ack = table.bit("basic.out.emergencyStopAck")
        self.emergency_stop_active = table.bit("basic.in.emergencyStopActive")
        self.nc_ready = table.bit("basic.in.ncReady")
        self.alarm_active = table.bit("basic.in.alarmActive")
        self.digital_inputs = table.field("basic.out.setDigitalInputs")  # $A_IN[1..8]


class HmiSignals:
    """The operator panel's DB19, as far as the NC's functions depend on it."""

    def __init__(self, table: SignalTable):
        self.display_wcs = table.bit("basic.out.displayWcsValues")  # DB19.DBX0.7: 1 WCS, 0 MCS


class Nck:
    def __init__(self, machine: MachineConfig, catalog: Catalog, memory: NcMemory | None = None,
                 physical: dict[str, float] | None = None):
        """Power on.  ``memory`` is what the control kept from before; ``physical`` where the
        slides stand now (default: the start positions of the machine file)."""
        self.machine = machine
        self.memory = memory if memory is not None else NcMemory()
        self.cycle_us = machine_ipo_cycle_us(machine)
        self.dt = self.cycle_us / 1_000_000
        self.cycle = 0
        expanded = expand(catalog, machine.layout)
        self.catalog = expanded
        self.image = ProcessImage(expanded.area_sizes)
        self.plc_to_nc_ranges = expanded.byte_ranges(Direction.PLC_TO_NC)
        self.nc_to_plc_ranges = expanded.byte_ranges(Direction.NC_TO_PLC)
        self._seen_version = -1
        self.alarms = AlarmList()
        self._alarm_count = 0
        self._servo_held_by_alarm: set[str] = set()  # axes an alarm took the controller enable from
        self._servo_check_version = -1
        # every catalogue signal the NC reads or writes, by its catalogue symbol: the signals it models
        self.signals_used: set[str] = set()
        used = self.signals_used
        self._nck_signals = NckSignals(SignalTable(catalog, InstanceKind.NCK, used))
        self._nck_area = self.image.area("DB10")
        self._alarm_area = AlarmArea(SignalTable(catalog, InstanceKind.ALARMS, used), self.image.area("DB100"),
                                     {channel.name: channel.number for channel in machine.channels},
                                     {axis.name: axis.number for axis in machine.axes})
        self._alarm_area_version = -1
        self._hmi_signals = HmiSignals(SignalTable(catalog, InstanceKind.HMI, used))
        self.handwheels = Handwheels()
        self._handwheel_signals = HandwheelSignals(SignalTable(catalog, InstanceKind.AXIS, used))
        geometry_table = SignalTable(catalog, InstanceKind.CHANNEL, used)
        self._geometry_handwheel_signals = tuple(HandwheelSignals(geometry_table, f"geoAxis{number}.out.")
                                                 for number in range(1, GEOMETRY_AXES + 1))
        self._geometry_handwheel_shown = geometry_table.field("geoAxis1.in.handwheelAssignedNumber")
        self._drf_requested = geometry_table.bit("basic.out.handwheelOffsetDrf")  # DB21.DBX0.3
        self._drf_shown = geometry_table.bit("basic.in.handwheelOvrActive")  # DB21.DBX33.3
        # what the handwheel outputs depend on (mode, PLC data): they are written only when it changed
        self._handwheel_outputs_for: object = None
        self._drf_active: dict[str, bool] = {}
        self._drf_travelling: set[str] = set()  # axes with DRF travel to go (most cycles: none)
        self.mode_group = ModeGroup(ModeGroupSignals(SignalTable(catalog, InstanceKind.MODE_GROUP, used)),
                                    self.image.area("DB11"))
        axis_signals = AxisSignals(SignalTable(catalog, InstanceKind.AXIS, used))
        channel_of_axis = {axis: channel.name for channel in machine.channels for axis in channel.axes}
        positions = physical or {}
        self.axes = [
            MachineAxis(axis, axis_signals, self.image.area(f"DB{axis.db}"), self.dt,
                        channel_of_axis.get(axis.name, ""), positions.get(axis.name))
            for axis in machine.axes
        ]
        self.axes_by_name = {axis.name: axis for axis in self.axes}
        for axis in self.axes:
            restore_at_power_on(axis, self.memory, self.alarms)
        self.referencing = ReferencingControl(machine, self.axes, self.memory, self.dt, self.alarms)
        nck = machine.nck
        feed_coding = OverrideCoding(nck.bool(MD.OVR_FEED_IS_GRAY_CODE), nck.floats(MD.OVR_FACTOR_FEEDRATE),
                                     nck.float(MD.OVR_FACTOR_LIMIT_BIN))
        rapid_coding = OverrideCoding(nck.bool(MD.OVR_RAPID_IS_GRAY_CODE), nck.floats(MD.OVR_FACTOR_RAPID_TRA),
                                      nck.float(MD.OVR_FACTOR_LIMIT_BIN))
        self._axis_coding = OverrideCoding(nck.bool(MD.OVR_AX_IS_GRAY_CODE), nck.floats(MD.OVR_FACTOR_AX_SPEED),
                                           nck.float(MD.OVR_FACTOR_LIMIT_BIN))
        channel_table = SignalTable(catalog, InstanceKind.CHANNEL, used)
        channel_signals = ChannelSignals(channel_table)
        self.channels = [
            Channel(channel, channel_signals, self.image.area(f"DB{channel.db}"),
                    [self.axes_by_name[name] for name in channel.axes], self.alarms, feed_coding, rapid_coding,
                    self.dt, self.referencing)
            for channel in machine.channels
        ]
        self.channels_by_name = {channel.name: channel for channel in self.channels}
        self.inclined_axes: list[InclinedAxisControl] = []  # GSK inclined-axis control (seed 000) per channel
        for channel in self.channels:
            inclined = inclined_axis_control(channel.config, channel.axes_by_name, channel_table,
                                             self.image.area(f"DB{channel.config.db}"), self.dt, self.alarms)
            if inclined is not None:
                channel.inclined = inclined
                self.inclined_axes.append(inclined)
        self.referencing.order_inclined_pairs(self.inclined_axes)
        retraction_signals = RetractionSignals(SignalTable(catalog, InstanceKind.CHANNEL, used))
        self.retractions = {channel.name: ManualRetraction(channel, self.memory, retraction_signals,
                                                           self.image.area(f"DB{channel.config.db}"),
                                                           nck.int(MD.JOG_MODE_MASK))
                            for channel in self.channels}
        self.mode_group.power_on(self._power_on_mode())
        spindle_signals = SpindleSignals(SignalTable(catalog, InstanceKind.AXIS, used))
        spindle_coding = OverrideCoding(nck.bool(MD.OVR_SPIND_IS_GRAY_CODE), nck.floats(MD.OVR_FACTOR_SPIND_SPEED),
                                        nck.float(MD.OVR_FACTOR_LIMIT_BIN))
        self.spindles: list[Spindle] = []
        for channel in self.channels:
            for axis in channel.axes:
                if axis.is_spindle:
                    spindle = Spindle(axis, spindle_signals, self.image.area(f"DB{axis.config.db}"), channel.name,
                                      spindle_coding, self._axis_coding, self.dt, nck.int(MD.SUPPRESS_ALARM_MASK),
                                      nck.float(MD.GEAR_CHANGE_WAIT_TIME), self.memory, self.alarms)
                    channel.spindles[axis.name] = spindle
                    self.spindles.append(spindle)
        self._spindle_of = {spindle.name: spindle for spindle in self.spindles}
        self.couplings = Couplings(list(machine.channels), self._spindle_of,
                                   CouplingSignals(SignalTable(catalog, InstanceKind.AXIS, used)),
                                   {spindle.name: self.image.area(f"DB{spindle.axis.config.db}")
                                    for spindle in self.spindles}, self.dt, self.alarms)
        drive_signals = DriveEsrSignals(SignalTable(catalog, InstanceKind.AXIS, used))
        self.esr = NckEsr({axis.name: DriveEsr(axis, drive_signals, self.image.area(f"DB{axis.config.db}"), self.dt,
                                               self._parameter_set_of(axis.name))
                           for axis in self.axes})
        self.dc_link = DcLink(machine.dc_link, self.dt) if machine.dc_link is not None else None
        for channel in self.channels:
            geometry = {name: axis for name, axis in zip(channel.config.geometry_names, channel.config.geometry_axes,
                                                           strict=True) if axis}
            channel.esr = ChannelEsr(channel.name, channel.axes_by_name, self.alarms, self.dt, self.esr, geometry)
            channel.esr.other_variables = (self.couplings.variable_reader(channel.spindle_indices()),
                                           channel.write_coupling_variable)
        self._rapid_stop_waiting: set[str] = set()  # axes whose alarm reaction waits for their ESR reaction
        self.polygons: list[PolygonTurning] = []
        for channel in self.channels:
            channel.couplings = self.couplings
            polygon = PolygonTurning(channel.config, self.couplings, channel.spindles, channel.axes_by_name)
            if polygon.configured:
                channel.polygon = polygon
                self.polygons.append(polygon)
        for spindle in self.spindles:
            spindle.write_outputs()  # the power-on state
        self.emergency_stop = False
        self._plc_life: int | None = None  # the PLC's last sign of life; None while no PLC is attached
        self._plc_started = False  # the sign of life has changed once: the PLC scans
        self._plc_timeout_cycles = max(1, round(machine.nck.float(MD.PLC_CYCLIC_TIMEOUT) / self.dt))
        self._plc_startup_cycles = max(1, round(machine.nck.float(MD.PLC_RUNNINGUP_TIMEOUT) / self.dt))
        self._plc_deadline: float = math.inf  # the cycle after which the missing sign of life is an alarm
        self._emergency_stop_level = False
        self._emergency_stop_ack = False
        self._hw_limits = {axis.name: (False, False) for axis in self.axes}
        for axis in self.axes:
            axis.control_cycle(0, self.alarms)  # publish the power-on state
        self._last_status = self._status_signature()
        self._write_status()
        for channel in self.channels:
            channel.write_axis_summary()
        for retraction in self.retractions.values():
            retraction.write_outputs()

    def _parameter_set_of(self, axis: str) -> Callable[[], int]:
        """The active parameter set of ``axis``: a spindle's gear stage, else the first."""
        spindle = self._spindle_of.get(axis)
        if spindle is None:
            return lambda: 0
        return lambda: spindle.parameter_set

    def _power_on_mode(self) -> Mode:
        """MD10720 of the mode group (0 AUTOMATIC, 3 MDA, 7 JOG; the sub-modes count as JOG [control]);
        MD10721 = 1 selects JOG when a channel has retract data (seed 003 L35366-35378)."""
        nck = self.machine.nck
        if nck.int(MD.OPERATING_MODE_EXTENDED, 0) == 1 and any(r.data for r in self.retractions.values()):
            return Mode.JOG
        return {0: Mode.AUTO, 3: Mode.MDA}.get(nck.int(MD.OPERATING_MODE_DEFAULT, 0), Mode.JOG)

    # ------------------------------------------------------------------ the IPO cycle
    def step(self, plc_side: ProcessImage) -> None:
        """Advance one IPO cycle with the PLC's outputs as they are in ``plc_side``."""
        self.cycle += 1
        if plc_side.version != self._seen_version:
            self._seen_version = plc_side.version
            changed = self._latch(plc_side)
            if changed:
                self._decode_inputs(changed)
        self._emergency_stop_function()
        if self.cycle > self._plc_deadline:
            self.alarms.raise_alarm(PLC_SIGN_OF_LIFE_ALARM if self._plc_started else PLC_NOT_STARTED_ALARM,
                                    self.cycle)
        self._mode_group_and_channel_commands()
        for channel in self.channels:
            channel.program_cycle(self.cycle)
        self._manual_functions()
        for retraction in self.retractions.values():
            retraction.follow()
        alarm_version = self.alarms.version
        for spindle in self.spindles:
            if not spindle.quiet or spindle.alarm_version != alarm_version or spindle.axis.velocity:
                channel = self.channels_by_name[spindle.channel]
                spindle.cycle(self.cycle, self.alarms, channel.state is ChannelState.RESET,
                              channel.esr_run_on_spindle == spindle.axis.name)
        if self.couplings.active:
            self.couplings.cycle(self.cycle)
        for watcher in self.referencing.passive_watchers:
            watcher.cycle()
        if self.referencing.any_active:
            self.referencing.run(self.cycle, {c.name: c.inputs.feed_disable for c in self.channels},
                                 {c.name: (c.edges.nc_stop, c.inputs.nc_stop or c.inputs.nc_stop_all, c.edges.nc_start)
                                  for c in self.channels})
        for inclined in self.inclined_axes:
            inclined.follow()  # a manual motion of the inclined axis carries the orthogonal one along
        moved = False
        for axis in self.axes:
            if axis.resting and axis.owner is Owner.NONE:
                continue  # nothing moves and no input changed: its outputs stand
            if axis.control_cycle(self.cycle, self.alarms):
                moved = True
        self.couplings.monitor(self.cycle)
        self._extended_stop_and_retract()
        dc_link = self.dc_link
        if dc_link is not None and (not dc_link.supply_on or not dc_link.charged):
            self._dc_link_cycle(dc_link)
        self._react_to_new_alarms()
        status = self._status_signature()
        if status != self._last_status:
            self._last_status = status
            self._write_status()
        if moved:
            for channel in self.channels:
                channel.write_axis_summary()
        for channel in self.channels:
            channel.clear_edges()
        for retraction in self.retractions.values():
            retraction.write_outputs()
        self.mode_group.reset_edge = False

    # ------------------------------------------------------------------ inputs
    def _latch(self, plc_side: ProcessImage) -> set[str]:
        """Copy the PLC->NC bytes that changed; return the data blocks they belong to."""
        changed: set[str] = set()
        areas, sources = self.image.areas, plc_side.areas
        for key, start, stop in self.plc_to_nc_ranges:
            incoming = sources[key][start:stop]
            if incoming != areas[key][start:stop]:
                areas[key][start:stop] = incoming
                changed.add(key)
        return changed

    def _decode_inputs(self, changed: set[str]) -> None:
        if "DB10" in changed:
            sig, area = self._nck_signals, self._nck_area
            self._emergency_stop_level = sig.emergency_stop.get(area)
            self._emergency_stop_ack = sig.emergency_stop_ack.get(area)
            self.esr.inputs = sig.digital_inputs.get(area)
        if "DB11" in changed:
            self.mode_group.decode_inputs()
        if "DB19" in changed:
            wcs = self._hmi_signals.display_wcs.get(self.image.area("DB19"))
            for retraction in self.retractions.values():
                retraction.wcs_shown = wcs
        for channel in self.channels:
            if channel.area_key in changed:
                channel.decode_inputs()
        for axis in self.axes:
            if axis.area_key in changed:
                axis.decode_inputs()
                axis.override = self._axis_coding.factor(axis.inputs.override_raw, axis.inputs.override_active)
                self._hardware_limit_switches(axis)
                spindle = self._spindle_of.get(axis.name)
                if spindle is not None:
                    if spindle.decode_inputs():
                        self.couplings.reset_movement(axis.name)  # DB31.DBX2.2 on its rising edge
                    self.couplings.decode_inputs(axis.name)

    def _hardware_limit_switches(self, axis: MachineAxis) -> None:
        """An actuated hardware limit switch stops the axis and raises alarm 21614 (on its edge)."""
        was_minus, was_plus = self._hw_limits[axis.name]
        minus, plus = axis.inputs.hw_limit_minus, axis.inputs.hw_limit_plus
        self._hw_limits[axis.name] = (minus, plus)
        for edge, sign in ((minus and not was_minus, "-"), (plus and not was_plus, "+")):
            if edge:
                self.alarms.raise_alarm(21614, self.cycle, axis.channel, axis.name, sign,
                                        channel=axis.channel, axis=axis.name)
                if axis.dyn.brake_rapid_at_limit_switch:
                    axis.brake(axis.dyn.rapid_stop_decel)
                else:
                    axis.brake()

    # ------------------------------------------------------------------ NCK functions
    def _emergency_stop_function(self) -> None:
        """DB10.DBX56.1: alarm 3000, rapid stop of every axis, then the controller enable is removed.

        Leaving the emergency-stop state needs the button released (56.1 = 0), the
        acknowledgement DB10.DBX56.2 and a reset (channel or mode group).
        """
        if self._emergency_stop_level and not self.emergency_stop:
            self.emergency_stop = True
            self.alarms.raise_alarm(EMERGENCY_STOP_ALARM, self.cycle)
            for axis in self.axes:
                axis.rapid_stop(then_servo_off=True)
            for spindle in self.spindles:
                spindle.emergency_stop()
            for polygon in self.polygons:
                polygon.cancel()  # the emergency stop ends polygon turning (seed 002 L134)
            for channel in self.channels:
                channel.stop()
            return
        if self.emergency_stop and not self._emergency_stop_level and self._emergency_stop_ack:
            reset_requested = self.mode_group.reset_edge or any(c.edges.reset for c in self.channels)
            if reset_requested:
                self.emergency_stop = False
                self.alarms.clear(EMERGENCY_STOP_ALARM, how=Clear.EMERGENCY_STOP_ACK)
                for axis in self.axes:
                    axis.restore_servo()

    def _mode_group_and_channel_commands(self) -> None:
        mode_group = self.mode_group
        had_reference_function = mode_group.reference_function
        if mode_group.update(any(channel.is_active for channel in self.channels)):
            for channel in self.channels:
                channel.mode_changed()
        if had_reference_function and not mode_group.reference_function:
            self.referencing.abort_key_started()
        for channel in self.channels:
            edges = channel.edges
            retraction = self.retractions[channel.name]
            reset = edges.reset or mode_group.reset_edge
            if reset:
                retraction.keep_data()  # before the reset forgets the block (seed 003 L35306-35309)
            retraction.commands(mode_group.mode, mode_group.reference_function, reset)
            for spindle in channel.spindles.values():
                spindle.start_keys_locked = retraction.active
            if reset:
                channel.reset(self.cycle)
                self.referencing.abort_channel(channel.name)
                continue
            if edges.reference_start and mode_group.reference_function and mode_group.mode is not Mode.AUTO \
                    and not self.emergency_stop:
                channel.start_channel_referencing(self.cycle)
            if edges.nc_stop or channel.inputs.nc_stop or channel.inputs.nc_stop_all:
                channel.stop()
                if channel.inputs.nc_stop_all:
                    for spindle in channel.spindles.values():
                        spindle.nc_stop()
            if edges.nc_start and not self.emergency_stop:
                was_in_reset = channel.state is ChannelState.RESET
                channel.nc_start(self.cycle, mode_group.mode, mode_group.reference_function)
                if was_in_reset and channel.is_active:
                    retraction.program_started()
                for spindle in channel.spindles.values():
                    spindle.nc_start()

    def _manual_functions(self) -> None:
        """JOG with the traverse keys, or in JOG-REF / MDA-REF referencing with them."""
        mode_group = self.mode_group
        reference_keys = mode_group.reference_function and mode_group.mode in (Mode.JOG, Mode.MDA)
        jog_mode = mode_group.mode is Mode.JOG and not mode_group.reference_function
        keys_followed = reference_keys or jog_mode
        pulses = self.handwheels.pulses() if self.handwheels.any_turning else {}
        drf_mode = mode_group.mode in (Mode.AUTO, Mode.MDA) and not mode_group.reference_function
        outputs_for = (mode_group.mode, mode_group.reference_function, self._seen_version)
        refresh_outputs = outputs_for != self._handwheel_outputs_for
        self._handwheel_outputs_for = outputs_for
        for channel in self.channels:
            axes_stopped = self.emergency_stop or bool(self.alarms.reactions(channel.name) & STOP_AXES)
            allowed = keys_followed and not channel.is_active and not axes_stopped
            if pulses and allowed and jog_mode:
                self._handwheel_pulses(channel, pulses)
            if refresh_outputs:
                self._show_geometry_handwheel(channel)
                self._show_drf(channel, drf_mode)
            self._drf(channel, pulses, axes_stopped)
            self.referencing.traverse_keys(channel.name, channel.axes, allowed and reference_keys, self.cycle)
            feed_disable = channel.inputs.feed_disable
            jog_allowed = allowed and jog_mode
            retraction = self.retractions[channel.name]
            inclined = channel.inclined
            for axis in channel.axes:
                if axis.is_spindle and axis.name in self.couplings.active:
                    inputs = axis.inputs
                    direction = (1 if inputs.key_plus else -1) if jog_allowed and inputs.key_plus != inputs.key_minus \
                        else 0
                    self.couplings.jog(axis.name, direction, inputs.feed_stop or feed_disable)
                # outside JOG only a jog that is still running out needs its cycle; in JOG an axis at
                # rest needs it only when a key or its handwheel asks it to move (limits cost time)
                inputs = axis.inputs
                asked = jog_allowed and (inputs.key_plus != inputs.key_minus or axis.handwheel_rest != 0.0)
                if (asked or axis.owner is Owner.JOG) and not axis.is_spindle:
                    limits = retraction.jog_limits(axis)
                    if inclined is not None:
                        limits = limits.and_(inclined.jog_limits(axis))
                    limits = limits.and_(channel.stroke_jog_limits(axis, self.cycle))  # G22, stroke limit 3
                    axis.jog_cycle(jog_allowed, feed_disable, limits)

    def _handwheel_pulses(self, channel: Channel, pulses: dict[int, int]) -> None:
        """Hand this cycle's pulses of the turning handwheels to the axes the PLC assigned them to
        (DB31.DBX4.0..4.2, or the geometry axes' DB21.DBX12.0..2 / 16.0..2 / 20.0..2), by the
        increment it selects for them; spindles take none."""
        receivers = self._handwheel_receivers(channel, pulses)
        counted = {(number, axis.name) for number, axis in self.retractions[channel.name].handwheel_priority(
            [(number, axis) for number, axis, _ in receivers])}
        for number, axis, per_detent in receivers:
            if (number, axis.name) in counted and pulses[number] and per_detent and not axis.is_spindle:
                axis.add_handwheel_travel(pulses[number] * per_detent)

    def _show_drf(self, channel: Channel, drf_mode: bool) -> None:
        """DB21.DBX33.3: DRF requested (DB21.DBX0.3) in AUTO or MDA."""
        area = self.image.area(channel.area_key)
        active = drf_mode and self._drf_requested.get(area)
        self._drf_active[channel.name] = active
        if self._drf_shown.get(area) != active:
            self._drf_shown.put(area, active)

    def _drf(self, channel: Channel, pulses: dict[int, int], axes_stopped: bool) -> None:
        """DRF (seed 003 §16.13.3, L36409-36506): in AUTO and MDA with DB21.DBX0.3 the pulses of a
        handwheel assigned to a machine axis (DB31.DBX4.0..4.2, not to a geometry axis: L36419) build
        up the axis's DRF offset, travelled overlaid on the path; DB21.DBX33.3 acknowledges it.  On a
        coupled following spindle they move the relation as overlaid motion (L22011-22015); an
        uncoupled spindle takes none [control]."""
        if pulses and self._drf_active[channel.name] and not axes_stopped:
            signals = self._handwheel_signals
            for axis in channel.axes:
                axis_area = self.image.area(axis.area_key)
                assigned, per_detent = signals.assigned(axis_area), signals.increment(axis_area)
                detents = sum(count for number, count in pulses.items() if assigned & (1 << (number - 1)))
                if not (detents and per_detent):
                    continue
                if axis.is_spindle:
                    self.couplings.drf(axis.name, detents * per_detent)
                else:
                    axis.add_drf_travel(detents * per_detent)
                    self._drf_travelling.add(axis.name)
        if not self._drf_travelling:
            return
        for axis in channel.axes:
            if axis.name in self._drf_travelling:
                axis.drf_cycle(axes_stopped or axis.inputs.feed_stop or channel.inputs.feed_disable
                               or not axis.drive_ready)
                if not axis.drf_moving:
                    self._drf_travelling.discard(axis.name)

    def _show_geometry_handwheel(self, channel: Channel) -> None:
        """DB21.DBX40.0..2: the handwheel assigned to geometry axis 1, as the PLC selects it (L34189-34193);
        the seed prints no such bits for geometry axes 2 and 3."""
        area = self.image.area(channel.area_key)
        assigned = self._geometry_handwheel_signals[0].assigned(area) if channel.config.geometry_axes[0] else 0
        if self._geometry_handwheel_shown.get(area) != assigned:
            self._geometry_handwheel_shown.put(area, assigned)

    def _handwheel_receivers(self, channel: Channel, pulses: dict[int, int]) -> list[tuple[int, MachineAxis, float]]:
        """(handwheel, machine axis, its travel per detent) of every assignment of a turning handwheel."""
        receivers: list[tuple[int, MachineAxis, float]] = []
        signals = self._handwheel_signals
        for axis in channel.axes:
            area = self.image.area(axis.area_key)
            assigned = signals.assigned(area)
            if assigned:
                receivers += [(number, axis, signals.increment(area)) for number in pulses
                              if assigned & (1 << (number - 1))]
        area = self.image.area(channel.area_key)
        inclined = channel.inclined
        for geometry, name in zip(self._geometry_handwheel_signals, channel.config.geometry_axes, strict=False):
            assigned = geometry.assigned(area) if name else 0
            if assigned:
                axis = channel.axes_by_name[name]
                per_detent = geometry.increment(area) * (inclined.geometry_travel(axis) if inclined else 1.0)
                receivers += [(number, axis, per_detent) for number in pulses if assigned & (1 << (number - 1))]
        return receivers

    def turn_handwheel(self, number: int, detents: int, cycles: int) -> None:
        """The operator turns handwheel ``number`` (1..3) by ``detents`` over ``cycles`` IPO cycles."""
        self.handwheels.turn(number, detents, cycles)

    def _extended_stop_and_retract(self) -> None:
        """Synchronized actions (after this cycle's alarms, before their reactions), the channels'
        reaction to $AC_ESR_TRIGGER, then the drives' own reaction to $AN_ESR_TRIGGER."""
        for channel in self.channels:
            esr = channel.esr
            assert esr is not None
            if esr.actions:
                esr.run_actions(self.cycle)
            channel.esr_trigger(self.cycle)  # returns at once unless a trigger rose
        self.esr.cycle()

    def _dc_link_cycle(self, dc_link: DcLink) -> None:
        """The link without supply (the generators buffer it), or precharging on it: the power units
        cancel their pulses when it falls below 0.9 x r0208 and take them back once it is charged."""
        cancelled = dc_link.pulses_cancelled
        dc_link.cycle(self.esr.generators)
        if dc_link.pulses_cancelled != cancelled:
            for axis in self.axes:
                axis.pulses_cancelled = dc_link.pulses_cancelled
                axis.resting = False

    def supply(self, on: bool) -> None:
        """The line supply of the drive line-up fails (or returns): the DC link is on its own."""
        if self.dc_link is not None:
            self.dc_link.supply_on = on

    def _in_esr_reaction(self, axis: MachineAxis) -> bool:
        """The NC-controlled reaction of its channel or its drive's own reaction runs: the drive
        retracts autonomously even when the NC fails (seed 003 L41550-41556)."""
        drive = self.esr.drives.get(axis.name)
        if drive is not None and drive.reacting:
            return True
        channel = self.channels_by_name.get(axis.channel)
        return channel is not None and channel.esr is not None and channel.esr.holds(axis.name)

    def _react_to_new_alarms(self) -> None:
        """Axis alarms whose reaction is a rapid stop put the axis into follow-up (servo off);
        when the last of them is cleared (reset), the NC gives the axis its controller enable back."""
        history = self.alarms.history
        if self.polygons and len(history) > self._alarm_count:
            for polygon in self.polygons:
                polygon.alarms_raised(history[self._alarm_count:])
        for alarm in history[self._alarm_count:]:
            if Reaction.RAPID_STOP not in alarm.reaction or alarm.number in (21612, EMERGENCY_STOP_ALARM):
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
                and not self.emergency_stop:  # the e-stop acknowledgement gives every enable back
            self._servo_check_version = self.alarms.version
            holding = set()
            for alarm in self.alarms.present:
                if Reaction.RAPID_STOP in alarm.reaction:
                    holding |= {alarm.axis} if alarm.axis else set(self.axes_by_name)
            for name in sorted(self._servo_held_by_alarm - holding):
                self.axes_by_name[name].restore_servo()
            self._servo_held_by_alarm &= holding

    # ------------------------------------------------------------------ outputs
    def _status_signature(self) -> tuple[object, ...]:
        """What the NCK, mode-group and channel outputs depend on besides the axes."""
        mode_group = self.mode_group
        return (self.alarms.version, self.emergency_stop, mode_group.mode, mode_group.reference_function,
                [(channel.state, channel.program_state, channel.reference_active) for channel in self.channels])

    def _write_status(self) -> None:
        present = self.alarms.present
        if self.alarms.version != self._alarm_area_version:
            self._alarm_area_version = self.alarms.version
            self._alarm_area.write(self.alarms)
        sig, area = self._nck_signals, self._nck_area
        sig.emergency_stop_active.put(area, self.emergency_stop)
        sig.nc_ready.put(area, True)
        sig.alarm_active.put(area, bool(present))
        self.mode_group.write_outputs(ready=True)
        for channel in self.channels:
            channel_alarms = [a for a in present if a.channel in ("", channel.name)] if present else []
            with_stop = any(Reaction.STOP_AXES in a.reaction for a in channel_alarms)
            channel.write_status(bool(channel_alarms), with_stop)

    # ------------------------------------------------------------------ power off, plant faults
    def plc_sign_of_life(self, counter: int) -> None:
        """The PLC's sign of life as the link sees it (a number that changes with every scan).
        Once a PLC is attached the NC watches it: no change within MD10120 of power-on raises
        alarm 2001, later no change for longer than MD10100 alarm 2000 (axes stop, NC start
        disabled, cleared by a reset when the PLC scans again)."""
        if self._plc_life is None:
            self._plc_life = counter
            self._plc_deadline = float(self._plc_startup_cycles)
        elif counter != self._plc_life:
            self._plc_life = counter
            self._plc_started = True
            self._plc_deadline = float(self.cycle + self._plc_timeout_cycles)

    def power_off(self) -> NcMemory:
        """Switch off: buffer what the control keeps, and hand its memory to the next power-on."""
        for retraction in self.retractions.values():
            retraction.keep_data()  # power failure during a thread (seed 003 L35306-35309)
        for axis in self.axes:
            buffer_at_power_off(axis, self.memory)
        return self.memory

    def program_position(self, axis: str) -> float:
        """The absolute (program) position the NC shows for ``axis``: Cartesian for the pair of an
        inclined-axis control (seed 000 L38-41), else the machine position."""
        for inclined in self.inclined_axes:
            position = inclined.program_position(axis)
            if position is not None:
                return position
        item = self.axes_by_name[axis]
        return item.shown(item.actual - item.drf_offset)  # the DRF offset is not shown (L36423)

    def physical_positions(self) -> dict[str, float]:
        return {axis.name: axis.physical for axis in self.axes}

    def encoder_slip(self, axis: str, encoder: int, amount: float) -> None:
        """A fault of the machine: the measuring system miscounts by ``amount``."""
        encoder_slip(self.axes_by_name[axis], encoder, amount, self.memory, self.alarms)

    def drive_line_up(self, ready: bool) -> None:
        """The drive line-up (the infeed) reports ready or not (the plant's Drives.ready): the
        drives show it in DB31.DBX92.7."""
        for axis in self.axes:
            axis.set_line_up_ready(ready)

    def drive_blocked(self, axis: str) -> None:
        """A fault of the machine: the drive of ``axis`` reports its motor blocked (a part twisted
        between two chucks holds it); the alarm's rapid stop takes the axis out of position control."""
        item = self.axes_by_name[axis]
        self.alarms.raise_alarm(207900, self.cycle, axis, channel=item.channel, axis=axis)
        item.resting = False

    # ------------------------------------------------------------------ operator access (HMI)
    def load_mda(self, channel: str, text: str) -> None:
        self.channels_by_name[channel].mda_text = text

    def select_program(self, channel: str, name: str, text: str) -> None:
        self.channels_by_name[channel].selected_program = (name, text)

    def acknowledge(self, kind: Clear = Clear.CANCEL) -> None:
        """The operator's acknowledge key for alarms cleared with CANCEL."""
        self.alarms.clear_on((kind,))

    def present_alarms(self) -> list[Alarm]:
        return list(self.alarms.present)
