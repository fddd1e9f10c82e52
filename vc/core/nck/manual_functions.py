"""The manual functions of the NCK: JOG with the traverse keys, handwheels, DRF, referencing
with the traverse keys (JOG-REF / MDA-REF), and manual retraction following the operator.

They run after the channels' programs in the IPO cycle (a channel that runs a program takes no
manual motion) and before the spindles and position control, which move what they command.
Handwheels are a function of the NCK, not of an axis: one handwheel's pulses go to the axes the
PLC assigns it to (DB31.DBX4.0..4.2, or a geometry axis's DB21.DBX12.0..2 / 16.0..2 / 20.0..2), so
the routing lives here, over every channel.
"""

from __future__ import annotations

from interfaces.image import ProcessImage
from interfaces.signal_groups import HANDWHEEL_OF_GEOMETRY_AXIS, HANDWHEEL_OF_MACHINE_AXIS, HandwheelSelection
from vc.core.alarms import STOP_AXES, AlarmList
from vc.core.axis.axis import MachineAxis
from vc.core.axis.handwheel import GEOMETRY_AXES, Handwheels
from vc.core.axis.owner import Owner
from vc.core.channel.channel import Channel
from vc.core.channel.program_run import Mode
from vc.core.channel.referencing_control import ReferencingControl
from vc.core.interface_map import SignalTable
from vc.core.nck.handwheel_inversion import HandwheelInversion
from vc.core.nck.jog_functions import JogFunctions
from vc.core.nck.jog_targets import JogTargets
from vc.core.nck.manual_retraction import ManualRetraction
from vc.core.nck.mode_group import ModeGroup
from vc.core.spindle.coupling import Couplings


class ManualFunctions:
    def __init__(self, axis_table: SignalTable, channel_table: SignalTable, image: ProcessImage, mode_group: ModeGroup,
                 channels: list[Channel], alarms: AlarmList, referencing: ReferencingControl,
                 retractions: dict[str, ManualRetraction], couplings: Couplings, jog_functions: JogFunctions,
                 jog_targets: JogTargets):
        self.image = image
        self.mode_group = mode_group
        self.channels = channels
        self.alarms = alarms
        self.referencing = referencing
        self.retractions = retractions
        self.couplings = couplings
        self.handwheels = Handwheels()
        self.handwheel_inversion = HandwheelInversion(axis_table, channel_table, image)  # DB31.DBX7.0 / 67.0
        self.jog_functions = jog_functions  # DB31.DBX5.x / 65.x: continuous or incremental JOG
        self.jog_targets = jog_targets  # DB31.DBX13.0..13.3 / 75.x: JOG to a fixed point / to a position
        self._handwheel = axis_table.codec(HandwheelSelection, HANDWHEEL_OF_MACHINE_AXIS)
        self._geometry_handwheels = tuple(
            channel_table.codec(HandwheelSelection, HANDWHEEL_OF_GEOMETRY_AXIS.format(number=number))
            for number in range(1, GEOMETRY_AXES + 1))
        self._geometry_handwheel_shown = channel_table.field("geoAxis1.in.handwheelAssignedNumber")
        self._drf_requested = channel_table.bit("basic.out.handwheelOffsetDrf")  # DB21.DBX0.3
        self._drf_shown = channel_table.bit("basic.in.handwheelOvrActive")  # DB21.DBX33.3
        # the mode the handwheel outputs were written for: written again in a new mode or when DB21 changed
        self._handwheel_outputs_for: object = None
        self._drf_active: dict[str, bool] = {}
        self._drf_travelling: set[str] = set()  # axes with DRF travel to go (most cycles: none)

    def cycle(self, cycle: int, emergency_stop: bool, latched: set[str] | None) -> None:
        """JOG with the traverse keys, or in JOG-REF / MDA-REF referencing with them; handwheels
        and DRF; then manual retraction follows what moved.  ``latched``: the data blocks whose PLC
        signals changed this cycle, None for none (a channel's handwheel outputs depend on its DB21)."""
        mode_group = self.mode_group
        reference_keys = mode_group.reference_function and mode_group.mode in (Mode.JOG, Mode.MDA)
        jog_mode = mode_group.mode is Mode.JOG and not mode_group.reference_function
        keys_followed = reference_keys or jog_mode
        pulses = self.handwheels.pulses() if self.handwheels.any_turning else {}
        drf_mode = mode_group.mode in (Mode.AUTO, Mode.MDA) and not mode_group.reference_function
        outputs_for = (mode_group.mode, mode_group.reference_function)
        refresh_all = outputs_for != self._handwheel_outputs_for
        self._handwheel_outputs_for = outputs_for
        for channel in self.channels:
            axes_stopped = emergency_stop or bool(self.alarms.reactions(channel.name) & STOP_AXES)
            allowed = keys_followed and not channel.is_active and not axes_stopped
            self.handwheel_inversion.follow(channel, channel.axes, latched, refresh_all)
            if pulses and allowed and jog_mode:
                self._handwheel_pulses(channel, pulses)
            if refresh_all or (latched is not None and channel.area_key in latched):
                self._show_geometry_handwheel(channel)
                self.jog_functions.report_geometry_axis(channel, jog_mode)
                self._show_drf(channel, drf_mode)
            self._drf(channel, pulses, axes_stopped)
            self.jog_targets.cycle(channel.axes, jog_mode, emergency_stop, latched, cycle, self.alarms)
            self.referencing.traverse_keys(channel.name, channel.axes, allowed and reference_keys, cycle)
            feed_disable = channel.inputs.feed_disable
            jog_allowed = allowed and jog_mode
            retraction = self.retractions[channel.name]
            inclined = channel.inclined
            for axis in channel.axes:
                if refresh_all or (latched is not None and axis.area_key in latched):
                    self.jog_functions.report(axis, jog_mode)
                if axis.is_spindle and axis.name in self.couplings.active:
                    inputs = axis.inputs
                    direction = (1 if inputs.key_plus else -1) if jog_allowed and inputs.key_plus != inputs.key_minus \
                        else 0
                    self.couplings.jog(axis.name, direction, inputs.feed_stop or feed_disable)
                # outside JOG only a jog that is still running out needs its cycle; in JOG an axis at
                # rest needs it only when a key or its handwheel asks it to move (limits cost time)
                inputs = axis.inputs
                # (or its keys' state machine has a motion to end or a key to see released)
                asked = jog_allowed and (inputs.key_plus != inputs.key_minus or axis.handwheel_rest != 0.0
                                         or axis.jog.keys.busy)
                index_jog = axis.index_jog  # an indexing axis runs out to, or waits on, an index position
                if (asked or axis.owner is Owner.JOG or (index_jog is not None and index_jog.busy)) \
                        and not axis.is_spindle:
                    limits = retraction.jog_limits(axis)
                    if inclined is not None:
                        limits = limits.and_(inclined.jog_limits(axis))
                    limits = limits.and_(channel.stroke_jog_limits(axis, cycle))  # G22, stroke limit 3
                    limits = limits.and_(self.jog_targets.jog_limits(axis))  # towards a fixed point / position
                    axis.jog_cycle(jog_allowed, feed_disable, limits, self.jog_functions.selection(axis))
        for retraction in self.retractions.values():
            retraction.follow()

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
            for axis in channel.axes:
                selection = self._handwheel.read(self.image.area(axis.area_key))
                assigned, per_detent = selection.assigned, self.jog_functions.handwheel_increment(selection, axis)
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
        assigned = self._geometry_handwheels[0].read(area).assigned if channel.config.geometry_axes[0] else 0
        if self._geometry_handwheel_shown.get(area) != assigned:
            self._geometry_handwheel_shown.put(area, assigned)

    def _handwheel_receivers(self, channel: Channel, pulses: dict[int, int]) -> list[tuple[int, MachineAxis, float]]:
        """(handwheel, machine axis, its travel per detent) of every assignment of a turning handwheel."""
        receivers: list[tuple[int, MachineAxis, float]] = []
        inverted = self.handwheel_inversion.axes  # DB31.DBX7.0: the handwheel turns the other way
        for axis in channel.axes:
            axis_selection = self._handwheel.read(self.image.area(axis.area_key))
            if axis_selection.assigned:
                per_detent = self.jog_functions.handwheel_increment(axis_selection, axis)
                if axis.name in inverted:
                    per_detent = -per_detent
                receivers += [(number, axis, per_detent) for number in pulses
                              if axis_selection.assigned & (1 << (number - 1))]
        area = self.image.area(channel.area_key)
        inclined = channel.inclined
        inverted_1 = channel.name in self.handwheel_inversion.geometry_axis_1  # DB21.DBX15.0
        for geometry, name in zip(self._geometry_handwheels, channel.config.geometry_axes, strict=False):
            selection = geometry.read(area) if name else None
            if selection is not None and selection.assigned:
                assigned = selection.assigned
                axis = channel.axes_by_name[name]
                per_detent = self.jog_functions.handwheel_increment(selection, axis) * \
                    (inclined.geometry_travel(axis) if inclined else 1.0)
                if inverted_1 and geometry is self._geometry_handwheels[0]:
                    per_detent = -per_detent
                receivers += [(number, axis, per_detent) for number in pulses if assigned & (1 << (number - 1))]
        return receivers
