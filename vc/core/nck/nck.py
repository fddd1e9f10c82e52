"""The NCK: one deterministic IPO cycle at a time.

``Nck.step(plc_side)`` is the only way NC time advances.  Its body is the list of the cycle's
phases, in the manner of LinuxCNC's ``emcmotController``; each phase is a method that keeps its
own skip-guards (most of the machine rests in most cycles).  Why each comes where it does:

1. **latch inputs**: copy the PLC's bytes that changed since the last cycle and decode them.
   Everything below sees one consistent set of PLC signals for the whole cycle, as the real NC
   reads the interface once per cycle.
2. **NCK functions**: the emergency stop (DB10.DBX56.1) and the PLC's sign of life (alarms
   2000 / 2001).  They come before any command, because they decide whether a command may start
   a motion at all.
3. **mode group and channel commands**: reset, NC stop, NC start, mode changes, REF start of the
   channel.  A reset must act before the programs run this cycle; a start before the program can
   take its first block.
4. **programs**: each channel's interpreter and interpolation (incl. channel referencing G74).
   They set the axes' and spindles' set-points before the manual functions, which take only the
   axes no program owns.
5. **manual functions**: JOG with the traverse keys, handwheels, DRF, referencing with the
   traverse keys in JOG-REF / MDA-REF, then manual retraction following what moved.
6. **spindles and couplings**: spindle modes and gear stage changes on their new commands, then
   the couplings, whose following spindles take their leading spindles' new set-points.
7. **referencing**: passive watchers (zero marks seen while moving), then the running
   referencing procedures; they command their axes before position control moves them.
8. **position control**: the drives changing a data set over (a motor changeover cancels the
   pulses the axis's servo state sees in this cycle), the inclined-axis controls carry the
   orthogonal axis along a manual motion, the gantry followers take their leading axes' setpoints
   (only while a grouping's axis moves or its referencing runs), every axis that moves or was commanded runs its control
   loop, drive and encoder, then travel to fixed stop detects its stop and watches its window
   (only while one is selected), and the couplings and the gantry groupings monitor their
   synchronism on the new actual values, and the software cams of the axes whose cams are active set their signals.
9. **extended stop and retract**: synchronized actions, the channels' and the drives' ESR
   reactions, the DC link.  After position control, so that a trigger of this cycle sees this
   cycle's positions; before the alarm reactions, which must not cut off a retraction.
10. **alarm reactions**: rapid stop and follow-up for the alarms raised this cycle, the controller
    enable given back when the last one is cleared.
11. **outputs**: the NCK, mode-group and channel status when it changed, the channels' axis
    summary when an axis moved, the auxiliary function slots when a batch came or went, the edges
    of this cycle cleared.

Between two steps the composed machine tells the NCK of every PLC cycle (``plc_cycle_done``):
the handshake of the auxiliary functions counts the PLC's cycles, not the NC's.

The NCK owns its own process image of all interface data blocks.  It reads the PLC's outputs from
``plc_side`` at the start of the cycle (only when that image changed) and writes its outputs into
its own image; a link moves those bytes to the PLC.  No I/O, no wall clock, no global state: same
configuration and same inputs give the same outputs, byte for byte.  What the control keeps over
power-off (machine data it writes, buffered positions) is an :class:`NcMemory` handed in by whoever
powers it on; the parts are built by :mod:`vc.core.nck.power_on`.
"""

from __future__ import annotations

import math

from interfaces.image import ProcessImage
from interfaces.signal_groups import NckRequests, NckStatus
from interfaces.signals import Catalog, Direction, expand
from vc.config import md_dictionary as MD
from vc.config.model import MachineConfig, machine_ipo_cycle_us
from vc.core.alarms import Alarm, AlarmList, Clear, Reaction
from vc.core.axis.axis import MachineAxis
from vc.core.axis.drive_messages import AMBIENT_TEMPERATURE
from vc.core.axis.owner import Owner
from vc.core.axis.setpoint_switchover import SharedDrive
from vc.core.channel.program_run import ChannelState, Mode, ProgramState
from vc.core.nc_memory import NcMemory
from vc.core.nck.alarm_reactions import EMERGENCY_STOP_ALARM, AlarmReactions
from vc.core.nck.power_on import power_on
from vc.core.nck.state_view import state_view
from vc.core.referencing.buffered_positions import buffer_at_power_off, encoder_slip
from vc.core.retraction.dc_link import DcLink
from vc.core.state_machine import StateView

PLC_SIGN_OF_LIFE_ALARM = 2000
PLC_NOT_STARTED_ALARM = 2001


class _StatusSeen:
    """What the NCK, mode-group and channel status bits were last written for."""

    def __init__(self, alarms_version: int, emergency_stop: bool, mode: Mode, reference_function: bool,
                 channels: list[tuple[ChannelState, ProgramState, bool]]):
        self.alarms_version = alarms_version
        self.emergency_stop = emergency_stop
        self.mode = mode
        self.reference_function = reference_function
        self.channels = channels  # per channel: state, program state, channel-specific referencing active


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
        self._latch_side: ProcessImage | None = None  # the PLC side the pieces below were bound to
        self._latch_pieces: list[tuple[str, bytearray, bytearray, int, int]] = []
        self._latched: set[str] | None = None  # the data blocks the PLC changed this cycle; None: none
        self.alarms = AlarmList()
        # every catalogue signal the NC reads or writes, by its catalogue symbol: the signals it models
        self.signals_used: set[str] = set()
        parts = power_on(machine, catalog, self.image, self.memory, self.alarms, self.dt, physical, self.signals_used)
        self._parts = parts
        self._state_view: StateView | None = None
        self._decode_nck = parts.nck_inputs.decode
        self._encode_nck = parts.nck_status.encode
        self._nck_inputs = NckRequests()
        self._nck_area = self.image.area("DB10")
        self._display_wcs = parts.display_wcs
        self._alarm_area = parts.alarm_area
        self._plc_alarms = parts.plc_alarms
        self._alarm_area_version = -1
        self.mode_group = parts.mode_group
        self.axes = parts.axes
        self.axes_by_name = parts.axes_by_name
        self._axis_coding = parts.axis_coding
        self.referencing = parts.referencing
        self.channels = parts.channels
        self.channels_by_name = parts.channels_by_name
        self._plc_axes_of = {name: channel.plc_axes for channel in self.channels for name in channel.plc_axes.by_name}
        self.inclined_axes = parts.inclined_axes
        self.retractions = parts.retractions
        self.spindles = parts.spindles
        self._spindle_of = parts.spindle_of
        self.couplings = parts.couplings
        self.esr = parts.esr
        self.dc_link = parts.dc_link
        self.polygons = parts.polygons
        self.manual = parts.manual
        self.fixed_stops = parts.fixed_stops
        self.software_cams = parts.software_cams
        self.gantries = parts.gantries
        self._changing_drives: list[MachineAxis] = []  # drives changing a data set: ticked until done
        # setpoint switchover: the drives several axes share, by axis; ticked while a request waits
        self.shared_drives = parts.shared_drives  # setpoint switchover: the drives two or more axes share
        self._shared_drive_of = {axis.name: drive for drive in self.shared_drives for axis in drive.axes}
        self._switching_drives: list[SharedDrive] = []
        self._drive_messages = [axis.messages for axis in self.axes if axis.messages is not None]
        if self.dc_link is not None:
            for messages in self._drive_messages:
                messages.set_link_voltage(self.dc_link.voltage)  # power-on: the link as it is (empty)
        self.alarm_reactions = AlarmReactions(self.alarms, self.axes, self.axes_by_name, self.channels_by_name,
                                              self.esr, self.polygons)
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
        self._status_seen = _StatusSeen(self.alarms.version, self.emergency_stop, self.mode_group.mode,
                                        self.mode_group.reference_function,
                                        [(c.state, c.program_state, c.reference_active) for c in self.channels])
        self._write_status()
        for channel in self.channels:
            channel.write_axis_summary()
        for retraction in self.retractions.values():
            retraction.write_outputs()

    # ------------------------------------------------------------------ the IPO cycle
    def step(self, plc_side: ProcessImage) -> None:
        """Advance one IPO cycle with the PLC's outputs as they are in ``plc_side``."""
        self.cycle += 1
        self._latch_inputs(plc_side)
        self._nck_functions()
        self._mode_group_and_channel_commands()
        self._programs()
        self.manual.cycle(self.cycle, self.emergency_stop, self._latched)
        self._spindles_and_couplings()
        self._referencing()
        moved = self._position_control()
        self._extended_stop_and_retract()
        self.alarm_reactions.react(self.emergency_stop)
        self._outputs(moved)

    def _latch_inputs(self, plc_side: ProcessImage) -> None:
        self._latched = None
        if plc_side.version != self._seen_version:
            self._seen_version = plc_side.version
            changed = self._latch(plc_side)
            if changed:
                self._latched = changed
                self._decode_inputs(changed)

    def _nck_functions(self) -> None:
        self._emergency_stop_function()
        if self.cycle > self._plc_deadline:
            self.alarms.raise_alarm(PLC_SIGN_OF_LIFE_ALARM if self._plc_started else PLC_NOT_STARTED_ALARM,
                                    self.cycle)

    def _programs(self) -> None:
        for channel in self.channels:
            channel.program_cycle(self.cycle)

    def _spindles_and_couplings(self) -> None:
        alarm_version = self.alarms.version
        for spindle in self.spindles:
            if not spindle.quiet or spindle.alarm_version != alarm_version or spindle.axis.velocity:
                channel = self.channels_by_name[spindle.channel]
                spindle.cycle(self.cycle, self.alarms, channel.state is ChannelState.RESET,
                              channel.esr_run_on_spindle == spindle.axis.name)
        if self.couplings.active:
            self.couplings.cycle(self.cycle)

    def _referencing(self) -> None:
        for watcher in self.referencing.passive_watchers:
            watcher.cycle()
        if self.referencing.any_active:
            self.referencing.run(self.cycle, {c.name: c.inputs.feed_disable for c in self.channels},
                                 {c.name: (c.edges.nc_stop, c.inputs.nc_stop or c.inputs.nc_stop_all, c.edges.nc_start)
                                  for c in self.channels})

    def _position_control(self) -> bool:
        """True when an axis moved this cycle."""
        for inclined in self.inclined_axes:
            inclined.follow()  # a manual motion of the inclined axis carries the orthogonal one along
        if self._changing_drives:
            self._drive_data_sets()
        if self._switching_drives:
            self._setpoint_switchovers()
        gantries = self.gantries
        if gantries.groupings:  # the followers take their leading axes' setpoints
            gantries.couple(self.cycle, self.mode_group.reference_function, self.referencing.any_active)
        moved = False
        for axis in self.axes:
            if axis.resting and axis.owner is Owner.NONE:
                continue  # nothing moves and no input changed: its outputs stand
            if axis.control_cycle(self.cycle, self.alarms):
                moved = True
        for fixed_stop in self.fixed_stops:
            if fixed_stop.busy:
                fixed_stop.cycle(self.cycle)  # detection and monitoring on the new actual values
        self.couplings.monitor(self.cycle)
        if gantries.groupings:
            gantries.monitor(self.cycle)  # the gantry differences on the new actual values
        if self.software_cams.busy:
            self.software_cams.cycle()  # the cam signals of the active axes on the new actual values
        return moved

    def _drive_data_sets(self) -> None:
        """The drives changing a data set over (DB31.DBX21.x -> 93.x); a motor changeover cancels
        and returns the pulses, which the axis's servo state must see this cycle."""
        for axis in self._changing_drives:
            cancelled = axis.data_sets.pulses_cancelled
            axis.data_sets.cycle()
            if axis.data_sets.pulses_cancelled != cancelled:
                axis.resting = False
        self._changing_drives = [axis for axis in self._changing_drives if axis.data_sets.busy]

    def _setpoint_switchovers(self) -> None:
        """The shared drives whose control another axis requests (DB31.DBX24.5 -> 96.5)."""
        for drive in self._switching_drives:
            drive.cycle()
        self._switching_drives = [drive for drive in self._switching_drives if drive.busy]

    def _outputs(self, moved: bool) -> None:
        if self._status_changed():
            self._write_status()
        if moved:
            for channel in self.channels:
                channel.write_axis_summary()
        for channel in self.channels:
            channel.clear_edges()
            if channel.aux.dirty:
                channel.aux.write_outputs()
        for retraction in self.retractions.values():
            retraction.write_outputs()
        self.mode_group.reset_edge = False

    # ------------------------------------------------------------------ inputs
    def _latch(self, plc_side: ProcessImage) -> set[str]:
        """Copy the PLC->NC bytes that changed; return the data blocks they belong to."""
        if plc_side is not self._latch_side:  # bound once per PLC side: an image keeps its buffers
            self._latch_side = plc_side
            areas, sources = self.image.areas, plc_side.areas
            self._latch_pieces = [(key, areas[key], sources[key], start, stop)
                                  for key, start, stop in self.plc_to_nc_ranges]
        changed: set[str] = set()
        for key, own, source, start, stop in self._latch_pieces:
            incoming = source[start:stop]
            if incoming != own[start:stop]:
                own[start:stop] = incoming
                changed.add(key)
        return changed

    def _decode_inputs(self, changed: set[str]) -> None:
        if "DB10" in changed:
            inputs = self._nck_inputs
            self._decode_nck(self._nck_area, inputs)
            self._emergency_stop_level = inputs.emergency_stop
            self._emergency_stop_ack = inputs.emergency_stop_ack
            self.esr.inputs = inputs.digital_inputs
        if "DB2" in changed:
            self._plc_alarms.decode(self.alarms, self.cycle)  # the PLC's user alarms (700000 ..)
        if "DB11" in changed:
            self.mode_group.decode_inputs()
        if "DB19" in changed:
            wcs = self._display_wcs.get(self.image.area("DB19"))
            for retraction in self.retractions.values():
                retraction.wcs_shown = wcs
        for channel in self.channels:
            if channel.area_key in changed:
                channel.decode_inputs()
        for axis in self.axes:
            if axis.area_key in changed:
                axis.decode_inputs()
                plc_axes = self._plc_axes_of.get(axis.name)
                if plc_axes is not None:
                    plc_axes.decode_inputs(axis.name)  # DBX28.7, DBX30.0, FC18 (vc/core/axis/plc_axis.py)
                if axis.data_sets.busy and axis not in self._changing_drives:
                    self._changing_drives.append(axis)  # a data set changeover or the integrator's answer
                shared = self._shared_drive_of.get(axis.name)
                if shared is not None:
                    shared.decode()  # DBX24.5: which axis requests the drive's control
                    if shared.busy and shared not in self._switching_drives:
                        self._switching_drives.append(shared)
                axis.override = self._axis_coding.factor(axis.inputs.override_raw, axis.inputs.override_active)
                self._hardware_limit_switches(axis)
                gantry = self.gantries.of.get(axis.name)
                if gantry is not None:
                    gantry.decode_inputs(axis)  # DBX29.4 / 29.5; a follower's traverse keys (chapter 12)
                cams = self.software_cams.of.get(axis.name)
                if cams is not None:
                    self.software_cams.decode_inputs(cams)  # DBX2.0, the measuring system (chapter 21)
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
                self.gantries.reset(channel.name, self.cycle)
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

    def turn_handwheel(self, number: int, detents: int, cycles: int) -> None:
        """The operator turns handwheel ``number`` (1..3) by ``detents`` over ``cycles`` IPO cycles."""
        self.manual.handwheels.turn(number, detents, cycles)

    def _extended_stop_and_retract(self) -> None:
        """Synchronized actions (after this cycle's alarms, before their reactions), the channels'
        reaction to $AC_ESR_TRIGGER, then the drives' own reaction to $AN_ESR_TRIGGER; the DC link
        when it is off its supply or precharging."""
        for channel in self.channels:
            esr = channel.esr
            assert esr is not None
            if esr.actions:
                esr.run_actions(self.cycle)
            channel.esr_trigger(self.cycle)  # returns at once unless a trigger rose
        self.esr.cycle()
        dc_link = self.dc_link
        if dc_link is not None and (not dc_link.supply_on or not dc_link.charged):
            self._dc_link_cycle(dc_link)

    def _dc_link_cycle(self, dc_link: DcLink) -> None:
        """The link without supply (the generators buffer it), or precharging on it: the power units
        cancel their pulses when it falls below 0.9 x r0208 and take them back once it is charged."""
        cancelled = dc_link.pulses_cancelled
        dc_link.cycle(self.esr.generators)
        for messages in self._drive_messages:
            messages.set_link_voltage(dc_link.voltage)  # DB31.DBX95.0 against each drive's p2172
        if dc_link.pulses_cancelled != cancelled:
            for axis in self.axes:
                axis.pulses_cancelled = dc_link.pulses_cancelled
                axis.resting = False

    def supply(self, on: bool) -> None:
        """The line supply of the drive line-up fails (or returns): the DC link is on its own."""
        if self.dc_link is not None:
            self.dc_link.supply_on = on

    # ------------------------------------------------------------------ outputs
    def _status_changed(self) -> bool:
        """Whether what the NCK, mode-group and channel outputs depend on besides the axes changed
        since they were written; compared field by field, so that the cycles in which nothing
        changed (nearly all) build nothing."""
        mode_group = self.mode_group
        seen = self._status_seen
        changed = (self.alarms.version != seen.alarms_version or self.emergency_stop != seen.emergency_stop
                   or mode_group.mode is not seen.mode or mode_group.reference_function != seen.reference_function)
        channels = seen.channels
        for index, channel in enumerate(self.channels):
            state, program_state, reference = channel.state, channel.program_state, channel.reference_active
            if state is not channels[index][0] or program_state is not channels[index][1] \
                    or reference != channels[index][2]:
                channels[index] = (state, program_state, reference)
                changed = True
        if changed:
            seen.alarms_version = self.alarms.version
            seen.emergency_stop = self.emergency_stop
            seen.mode = mode_group.mode
            seen.reference_function = mode_group.reference_function
        return changed

    def _write_status(self) -> None:
        present = self.alarms.present
        if self.alarms.version != self._alarm_area_version:
            self._alarm_area_version = self.alarms.version
            self._alarm_area.write(self.alarms)
        self._encode_nck(self._nck_area, NckStatus(emergency_stop_active=self.emergency_stop, nc_ready=True,
                                                   alarm_active=bool(present)))
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

    def plc_cycle_done(self) -> None:
        """The PLC has run a cycle on the interface as this NC wrote it (the composed machine calls
        it after every PLC cycle; in real time after every new sign of life): the auxiliary
        functions on their way are read, the ones read before are acknowledged."""
        for channel in self.channels:
            if channel.aux.busy:
                channel.aux.plc_cycle()

    def power_off(self) -> NcMemory:
        """Switch off: buffer what the control keeps, and hand its memory to the next power-on."""
        for retraction in self.retractions.values():
            retraction.keep_data()  # power failure during a thread (seed 003 L35306-35309)
        for axis in self.axes:
            buffer_at_power_off(axis, self.memory)
        return self.memory

    def program_position(self, axis: str) -> float:
        """The absolute (program) position the NC shows for ``axis``: Cartesian for the pair of an
        inclined-axis control (seed 000 L38-41), else the machine position; a transverse axis in
        diameter under DIAMON / DIAM90 (seed 003 §8)."""
        cartesian = next((position for inclined in self.inclined_axes
                          if (position := inclined.program_position(axis)) is not None), None)
        item = self.axes_by_name[axis]
        # the DRF offset is not shown (L36423)
        position = cartesian if cartesian is not None else item.shown(item.actual - item.drf_offset)
        for channel in self.channels:
            position = channel.shown_position(axis, position)  # DIAMON / DIAM90: in diameter
        return position

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

    def motor_temperature(self, axis: str, celsius: float | None) -> bool:
        """The plant's motor temperature of ``axis`` (a fault: the motor overheats; None: back at
        the ambient temperature); False when its drive reports no messages (DB31.DBX94.0 needs
        ``drive: messages: 1``)."""
        messages = self.axes_by_name[axis].messages
        if messages is None:
            return False
        messages.set_temperature(AMBIENT_TEMPERATURE if celsius is None else celsius)
        return True

    def drive_blocked(self, axis: str) -> None:
        """A fault of the machine: the drive of ``axis`` reports its motor blocked (a part twisted
        between two chucks holds it); the alarm's rapid stop takes the axis out of position control."""
        item = self.axes_by_name[axis]
        self.alarms.raise_alarm(207900, self.cycle, axis, channel=item.channel, axis=axis)
        item.resting = False

    # ------------------------------------------------------------------ observers
    def state_view(self) -> StateView:
        """The state of every instance of every state machine, for observers (built on the first
        call; reading it costs the NC's cycle nothing)."""
        if self._state_view is None:
            self._state_view = state_view(self._parts)
        return self._state_view

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
