"""Power on: build every part of the NCK from the machine data, wired to one another.

The order is the control's: the axes first (they restore what the NC memory buffered for them,
which may raise alarms), the channel-side referencing control over them, the channels, the
inclined-axis controls of the channels, manual retraction, the mode group's power-on mode, the
spindles, the couplings over the spindles, extended stop and retract of every drive and channel,
polygon turning over the couplings.  A channel is built first and given its spindles, its
inclined-axis control, its ESR, its couplings and its polygon turning afterwards, here and
nowhere else: those parts need the channel's axes, and the channel needs them.

Every part reads and writes its signals in the NCK's own process image (``image``), looked up by
declared signal groups compiled once per kind of data block (one :class:`SignalTable` each, shared
by every part; ``signals_used`` collects what the NC models).
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable
from dataclasses import dataclass

from interfaces.bit_access import Bit
from interfaces.group_codec import GroupCodec
from interfaces.image import ProcessImage
from interfaces.signal_groups import DISPLAY_WCS, FixedStopStatus, NckRequests, NckStatus
from interfaces.signals import Catalog, InstanceKind
from vc.config import md_dictionary as MD
from vc.config.model import MachineConfig
from vc.core.alarms import AlarmList
from vc.core.axis.axis import MachineAxis
from vc.core.axis.drive_messages import DriveMessages
from vc.core.axis.dynamics import fixed_feeds_of
from vc.core.axis.index_variables import index_variable_reader
from vc.core.axis.parameter_sets import ServoParameterSets, selected_by_the_plc
from vc.core.axis.plc_axis import PlcAxis
from vc.core.axis.setpoint_switchover import SharedDrive
from vc.core.axis.software_cams import SoftwareCams
from vc.core.channel.channel import Channel
from vc.core.channel.program_run import Mode
from vc.core.channel.referencing_control import ReferencingControl
from vc.core.fixed_stop.fixed_stop import FixedStop
from vc.core.gantry.gantry import Gantries
from vc.core.interface_map import SignalTable
from vc.core.nc_memory import NcMemory
from vc.core.nck.alarm_area import AlarmArea
from vc.core.nck.jog_functions import JogFunctions
from vc.core.nck.jog_targets import JogTargets
from vc.core.nck.manual_functions import ManualFunctions
from vc.core.nck.manual_retraction import ManualRetraction
from vc.core.nck.mode_group import ModeGroup
from vc.core.nck.plc_alarms import PlcAlarms, definitions
from vc.core.overrides import OverrideCoding
from vc.core.referencing.buffered_positions import restore_at_power_on
from vc.core.retraction.dc_link import DcLink
from vc.core.retraction.drive_esr import DriveEsr
from vc.core.retraction.esr import ChannelEsr, NckEsr
from vc.core.spindle.coupling import Couplings
from vc.core.spindle.polygon import PolygonTurning
from vc.core.spindle.spindle import Spindle
from vc.core.transforms.inclined_axis_control import InclinedAxisControl, inclined_axis_control


@dataclass(slots=True)
class NckParts:
    """Everything the NCK is made of, complete and wired."""

    nck_inputs: GroupCodec[NckRequests]
    nck_status: GroupCodec[NckStatus]
    display_wcs: Bit  # of the operator panel's DB19
    alarm_area: AlarmArea
    plc_alarms: PlcAlarms  # DB2: the PLC's user alarms into the alarm list
    mode_group: ModeGroup
    axes: list[MachineAxis]
    axes_by_name: dict[str, MachineAxis]
    axis_coding: OverrideCoding
    referencing: ReferencingControl
    channels: list[Channel]
    channels_by_name: dict[str, Channel]
    inclined_axes: list[InclinedAxisControl]  # GSK inclined-axis control (seed 000) per channel
    retractions: dict[str, ManualRetraction]
    spindles: list[Spindle]
    spindle_of: dict[str, Spindle]
    couplings: Couplings
    esr: NckEsr
    dc_link: DcLink | None
    polygons: list[PolygonTurning]
    manual: ManualFunctions
    fixed_stops: list[FixedStop]  # travel to fixed stop of the axes whose MD37000 allows it
    shared_drives: list[SharedDrive]  # setpoint switchover: the axes of one drive (equal MD30110)
    software_cams: SoftwareCams  # the cam pairs of MD10450 by axis (seed 003 chapter 21)
    gantries: Gantries  # the gantry groupings of MD37100 (seed 003 chapter 12); none on most machines


def power_on(machine: MachineConfig, catalog: Catalog, image: ProcessImage, memory: NcMemory, alarms: AlarmList,
             dt: float, physical: dict[str, float] | None, used: set[str]) -> NckParts:
    """Build the NCK's parts for ``machine``; ``physical``: where the slides stand now (default:
    the start positions of the machine file); ``used`` collects every catalogue signal looked up."""
    nck = machine.nck
    nck_table = SignalTable(catalog, InstanceKind.NCK, used)
    axis_table = SignalTable(catalog, InstanceKind.AXIS, used)
    channel_table = SignalTable(catalog, InstanceKind.CHANNEL, used)
    alarm_area = AlarmArea(SignalTable(catalog, InstanceKind.ALARMS, used), image.area("DB100"),
                           {channel.name: channel.number for channel in machine.channels},
                           {axis.name: axis.number for axis in machine.axes})
    plc_alarms = PlcAlarms(SignalTable(catalog, InstanceKind.PLC_ALARMS, used), image.area("DB2"),
                           definitions(nck, machine.plc_alarms))
    display_wcs = SignalTable(catalog, InstanceKind.HMI, used).bit(DISPLAY_WCS)
    mode_group = ModeGroup(SignalTable(catalog, InstanceKind.MODE_GROUP, used), image.area("DB11"))

    axes = _axes(machine, axis_table, image, memory, alarms, dt, physical)
    for axis in axes:  # MD12202 / MD12204: the fixed feedrates of JOG and of the path (seed 003 L9692-9722)
        axis.dyn = dataclasses.replace(axis.dyn, fixed_feeds=fixed_feeds_of(nck, axis.config))
    axes_by_name = {axis.name: axis for axis in axes}
    referencing = ReferencingControl(machine, axes, memory, dt, alarms)
    feed_coding = OverrideCoding(nck.bool(MD.OVR_FEED_IS_GRAY_CODE), nck.floats(MD.OVR_FACTOR_FEEDRATE),
                                 nck.float(MD.OVR_FACTOR_LIMIT_BIN))
    rapid_coding = OverrideCoding(nck.bool(MD.OVR_RAPID_IS_GRAY_CODE), nck.floats(MD.OVR_FACTOR_RAPID_TRA),
                                  nck.float(MD.OVR_FACTOR_LIMIT_BIN))
    axis_coding = OverrideCoding(nck.bool(MD.OVR_AX_IS_GRAY_CODE), nck.floats(MD.OVR_FACTOR_AX_SPEED),
                                 nck.float(MD.OVR_FACTOR_LIMIT_BIN))

    channels = [
        Channel(channel, channel_table, image.area(f"DB{channel.db}"),
                [axes_by_name[name] for name in channel.axes], alarms, feed_coding, rapid_coding, dt, referencing,
                nck.floats(MD.PERMANENT_FEED))
        for channel in machine.channels
    ]
    inclined_axes: list[InclinedAxisControl] = []
    for channel in channels:
        inclined = inclined_axis_control(channel.config, channel.axes_by_name, channel_table,
                                         image.area(f"DB{channel.config.db}"), dt, alarms)
        if inclined is not None:
            channel.inclined = inclined
            inclined_axes.append(inclined)
    referencing.order_inclined_pairs(inclined_axes)
    for channel in channels:
        for command in channel.command_axes.by_name.values():  # DB31.DBX76.5, DBD78 of a positioning axis
            area = image.area(f"DB{command.axis.config.db}")
            command.publish_to(axis_table, area)
            channel.plc_axes.add(PlcAxis(command, channel.config.number, axis_table, area))  # FC18, DBX28.7
    retractions = {channel.name: ManualRetraction(channel, memory, channel_table,
                                                  image.area(f"DB{channel.config.db}"), nck.int(MD.JOG_MODE_MASK))
                   for channel in channels}
    mode_group.power_on(power_on_mode(machine, retractions))

    spindles = _spindles(machine, axis_table, image, memory, alarms, dt, channels, axis_coding)
    spindle_of = {spindle.name: spindle for spindle in spindles}
    couplings = Couplings(list(machine.channels), spindle_of, axis_table,
                          {spindle.name: image.area(f"DB{spindle.axis.config.db}") for spindle in spindles}, dt, alarms)
    for axis in axes:
        _servo_parameter_sets(axis, axis_table, image)
    esr = NckEsr({axis.name: DriveEsr(axis, axis_table, image.area(f"DB{axis.config.db}"), dt,
                                      _parameter_set_of(axis, spindle_of))
                  for axis in axes})
    for axis in axes:
        _drive_messages(axis, axis_table, image, dt, _parameter_set_of(axis, spindle_of))
    dc_link = DcLink(machine.dc_link, dt) if machine.dc_link is not None else None
    fixed_stops = _fixed_stops(channels, axis_table, image, dt, alarms)
    for channel in channels:
        geometry = {name: axis for name, axis in zip(channel.config.geometry_names, channel.config.geometry_axes,
                                                       strict=True) if axis}
        channel.esr = ChannelEsr(channel.name, channel.axes_by_name, alarms, dt, esr, geometry,
                                 {**channel.spindles, **channel.command_axes.by_name}, channel.command_axes)
        others = channel.fixed_stops.reader(channel.config, couplings.variable_reader(channel.spindle_indices()))
        channel.esr.other_variables = (index_variable_reader(channel.config, channel.axes_by_name,
                                                             nck.int(MD.INDEX_AX_MODE), others),
                                       channel.write_other_variable)
    polygons: list[PolygonTurning] = []
    for channel in channels:
        channel.couplings = couplings
        polygon = PolygonTurning(channel.config, couplings, channel.spindles, channel.axes_by_name)
        if polygon.configured:
            channel.polygon = polygon
            polygons.append(polygon)
    for spindle in spindles:
        spindle.write_outputs()  # the power-on state
    manual = ManualFunctions(axis_table, channel_table, image, mode_group, channels, alarms, referencing, retractions,
                             couplings, JogFunctions(nck, axis_table, channel_table, image, axes),
                             JogTargets(nck, axis_table, image, axes))
    return NckParts(nck_table.codec(NckRequests), nck_table.codec(NckStatus), display_wcs, alarm_area, plc_alarms,
                    mode_group, axes, axes_by_name, axis_coding, referencing,
                    channels, {channel.name: channel for channel in channels}, inclined_axes, retractions, spindles,
                    spindle_of, couplings, esr, dc_link, polygons, manual, fixed_stops,
                    _shared_drives(axes, axis_table, image),
                    SoftwareCams(nck, axes, nck_table, axis_table, image.area("DB10"),
                                 {axis.name: image.area(f"DB{axis.config.db}") for axis in axes}),
                    Gantries(axes, referencing.of, referencing.start, axis_table,
                             {axis.name: image.area(f"DB{axis.config.db}") for axis in axes}, memory, dt, alarms))


def _shared_drives(axes: list[MachineAxis], table: SignalTable, image: ProcessImage) -> list[SharedDrive]:
    """The drives two or more axes share (the same MD30110 above 0): setpoint switchover."""
    SharedDrive.declare(table)
    by_number: dict[int, list[MachineAxis]] = {}
    for axis in axes:
        number = axis.config.md.int(MD.CTRLOUT_MODULE_NR)
        if number > 0:
            by_number.setdefault(number, []).append(axis)
    return [SharedDrive(number, members, table, [image.area(f"DB{axis.config.db}") for axis in members])
            for number, members in by_number.items() if len(members) > 1]


def _fixed_stops(channels: list[Channel], table: SignalTable, image: ProcessImage, dt: float,
                 alarms: AlarmList) -> list[FixedStop]:
    """Travel to fixed stop for every channel axis whose MD37000 bit 0 allows it from the program;
    DB31.DBX62.4 / 62.5 of the other axes stay 0 (the function is not there)."""
    table.codec(FixedStopStatus)
    fixed_stops = []
    for channel in channels:
        for axis in channel.axes:
            if axis.config.md.int(MD.FIXED_STOP_MODE) & 1:
                fixed_stop = FixedStop(axis, table, image.area(f"DB{axis.config.db}"), dt, alarms)
                channel.fixed_stops.add(fixed_stop)
                fixed_stops.append(fixed_stop)
    return fixed_stops


def _axes(machine: MachineConfig, table: SignalTable, image: ProcessImage, memory: NcMemory, alarms: AlarmList,
          dt: float, physical: dict[str, float] | None) -> list[MachineAxis]:
    """Every machine axis, with what the NC memory kept of its position and calibration."""
    channel_of_axis = {axis: channel.name for channel in machine.channels for axis in channel.axes}
    positions = physical or {}
    axes = [
        MachineAxis(axis, table, image.area(f"DB{axis.db}"), dt,
                    channel_of_axis.get(axis.name, ""), positions.get(axis.name))
        for axis in machine.axes
    ]
    for axis in axes:
        restore_at_power_on(axis, memory, alarms)
    return axes


def _spindles(machine: MachineConfig, table: SignalTable, image: ProcessImage, memory: NcMemory, alarms: AlarmList,
              dt: float, channels: list[Channel], axis_coding: OverrideCoding) -> list[Spindle]:
    """The spindles of every channel, each given to its channel."""
    nck = machine.nck
    spindle_coding = OverrideCoding(nck.bool(MD.OVR_SPIND_IS_GRAY_CODE), nck.floats(MD.OVR_FACTOR_SPIND_SPEED),
                                    nck.float(MD.OVR_FACTOR_LIMIT_BIN))
    spindles: list[Spindle] = []
    for channel in channels:
        for axis in channel.axes:
            if axis.is_spindle:
                spindle = Spindle(axis, table, image.area(f"DB{axis.config.db}"), channel.name,
                                  spindle_coding, axis_coding, dt, nck.int(MD.SUPPRESS_ALARM_MASK),
                                  nck.float(MD.GEAR_CHANGE_WAIT_TIME), memory, alarms)
                channel.spindles[axis.name] = spindle
                spindles.append(spindle)
    return spindles


def _drive_messages(axis: MachineAxis, table: SignalTable, image: ProcessImage, dt: float,
                    parameter_set: Callable[[], int]) -> None:
    """The drive's messages DB31.DBX94.x / 95.0 for an axis whose drive reports them (``drive:
    messages: 1``); the NC knows the signals of every axis, the others' stay 0."""
    messages = DriveMessages(axis.config, table, image.area(f"DB{axis.config.db}"), dt, parameter_set)
    if axis.config.drive.messages:
        messages.set_max_accel(axis.dyn.max_accel)
        axis.messages = messages
        messages.publish()


def _servo_parameter_sets(axis: MachineAxis, table: SignalTable, image: ProcessImage) -> None:
    """The PLC's servo parameter set selection DB31.DBX9.0-9.2 for an axis whose MD35590 allows it;
    the NC knows the signals of every axis."""
    sets = ServoParameterSets(axis.config, table, image.area(f"DB{axis.config.db}"))
    if selected_by_the_plc(axis.config):
        axis.parameter_sets = sets


def _parameter_set_of(axis: MachineAxis, spindle_of: dict[str, Spindle]) -> Callable[[], int]:
    """The active parameter set of ``axis``: a spindle's gear stage, the PLC's selection, else the first."""
    spindle = spindle_of.get(axis.name)
    if spindle is not None:
        return lambda: spindle.parameter_set
    sets = axis.parameter_sets
    if sets is not None:
        return lambda: sets.active
    return lambda: 0


def power_on_mode(machine: MachineConfig, retractions: dict[str, ManualRetraction]) -> Mode:
    """MD10720 of the mode group (0 AUTOMATIC, 3 MDA, 7 JOG; the sub-modes count as JOG [control]);
    MD10721 = 1 selects JOG when a channel has retract data (seed 003 L35366-35378)."""
    nck = machine.nck
    if nck.int(MD.OPERATING_MODE_EXTENDED, 0) == 1 and any(r.data for r in retractions.values()):
        return Mode.JOG
    return {0: Mode.AUTO, 3: Mode.MDA}.get(nck.int(MD.OPERATING_MODE_DEFAULT, 0), Mode.JOG)
