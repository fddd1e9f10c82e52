"""The PLC interface of a spindle: its DB31 signals (seed 003 chapter 13, spec B.3) and the inputs
as the spindle last took them.

:class:`SpindleSignals` names the signals once for every spindle (catalogue symbols without the
instance) and reads and writes them; :class:`SpindleInputs` holds one spindle's PLC inputs of this
cycle, which the spindle, its gear change and its positioning read (edge-evaluated inputs keep
their last value); :class:`SpindleStatus` is what the spindle shows the PLC.
"""

from __future__ import annotations

import struct
from dataclasses import dataclass
from typing import NamedTuple

from vc.core.interface_map import SignalTable


class SpindleSignals:
    """The DB31 spindle signals (catalogue symbols without the instance)."""

    def __init__(self, table: SignalTable):
        self.gear_reported = table.field("spindle.out.gearStageSelection")
        self.gear_done = table.bit("spindle.out.gearChangeoverDone")
        self.delete_s = table.bit("spindle.out.deleteSValue")
        self.use_feed_override = table.bit("spindle.out.useFeedrateOvr")
        self.invert_m3_m4 = table.bit("spindle.out.invertM3M4")
        self.oscillation_by_plc = table.bit("spindle.out.oscillRequest")
        self.oscillation_enable = table.bit("spindle.out.oscillEnable")
        self.oscillation_cw = table.bit("spindle.out.oscillSetDirCw")
        self.oscillation_ccw = table.bit("spindle.out.oscillSetDirCcw")
        self.override = table.field("spindle.out.ovrFactor")
        self.rapid_stop = table.bit("drive.out.rapidStop")
        self.resync = (table.bit("spindle.out.resyncEnc1"), table.bit("spindle.out.resyncEnc2"))
        self.resync_for_positioning = (table.bit("spindle.out.resyncEnc1ForPos"),
                                       table.bit("spindle.out.resyncEnc2ForPos"))
        self.plc_stop = table.bit("spindle.out.stop")
        self.plc_start_cw = table.bit("spindle.out.startCw")
        self.plc_start_ccw = table.bit("spindle.out.startCcw")
        self.requested_gear = table.field("spindle.in.requestedGearStageNumber")
        self.change_gear = table.bit("spindle.in.gearChangeoverRequested")
        self.speed_limit_exceeded = table.bit("spindle.in.speedLimitationExceeded")
        self.setpoint_limited = table.bit("spindle.in.speedSetpointAboveMax")
        self.setpoint_raised = table.bit("spindle.in.speedSetpointBelowMin")
        self.speed_reached = table.bit("spindle.in.speedSetpointReached")
        self.clockwise = table.bit("spindle.in.cwRotActive")
        self.positioning_mode = table.bit("spindle.in.posModeActive")
        self.oscillation_mode = table.bit("spindle.in.oscillModeActive")
        self.control_mode = table.bit("spindle.in.ctrlModeActive")
        self.in_position = table.bit("spindle.in.inPos")
        self.m_function = table.field("spindle.in.mFuncNumber")
        self.s_value = table.real_offset("spindle.in.sFuncValue")
        self.spindle_mode = table.bit("basic.in.spindleModeActive")
        self.parameter_set = table.field("drive.in.posCtrlParameterSetNumber")

    def write(self, area: bytearray, status: SpindleStatus) -> None:
        self.requested_gear.put(area, status.requested_gear)
        self.change_gear.put(area, status.change_gear)
        self.speed_limit_exceeded.put(area, status.speed_limit_exceeded)
        self.setpoint_limited.put(area, status.setpoint_limited)
        self.setpoint_raised.put(area, status.setpoint_raised)
        self.speed_reached.put(area, status.speed_reached)
        self.clockwise.put(area, status.clockwise)
        self.control_mode.put(area, status.control_mode)
        self.oscillation_mode.put(area, status.oscillation_mode)
        self.positioning_mode.put(area, status.positioning_mode)
        self.spindle_mode.put(area, status.spindle_mode)
        self.in_position.put(area, status.in_position)
        self.m_function.put(area, status.m_function)
        self.parameter_set.put(area, status.parameter_set)

    def write_s_value(self, area: bytearray, speed: float) -> None:
        struct.pack_into(">f", area, self.s_value, speed)  # DBD88 (L17367)

    def read_levels(self, area: bytearray, inputs: SpindleInputs) -> None:
        """The inputs taken as they stand; the gear report, the resynchronisation, the spindle keys
        and the spindle reset are edge-evaluated by the spindle."""
        inputs.gear_done = self.gear_done.get(area)
        inputs.delete_s = self.delete_s.get(area)
        inputs.use_feed_override = self.use_feed_override.get(area)
        inputs.invert_m3_m4 = self.invert_m3_m4.get(area)
        inputs.oscillation_by_plc = self.oscillation_by_plc.get(area)
        inputs.oscillation_enable = self.oscillation_enable.get(area)
        inputs.oscillation_cw = self.oscillation_cw.get(area)
        inputs.oscillation_ccw = self.oscillation_ccw.get(area)
        inputs.override_raw = self.override.get(area)
        inputs.rapid_stop = self.rapid_stop.get(area)
        inputs.resync_for_positioning = (self.resync_for_positioning[0].get(area),
                                         self.resync_for_positioning[1].get(area))


@dataclass(slots=True)
class SpindleInputs:
    gear_reported: int = 0
    gear_done: bool = False
    delete_s: bool = False
    use_feed_override: bool = False
    invert_m3_m4: bool = False
    reset_movement: bool = False  # DB31.DBX2.2 as last seen (edge-evaluated)
    oscillation_by_plc: bool = False
    oscillation_enable: bool = False
    oscillation_cw: bool = False
    oscillation_ccw: bool = False
    override_raw: int = 0
    rapid_stop: bool = False
    resync: tuple[bool, bool] = (False, False)
    resync_for_positioning: tuple[bool, bool] = (False, False)
    plc_stop: bool = False
    plc_start_cw: bool = False
    plc_start_ccw: bool = False


class SpindleStatus(NamedTuple):
    """What a spindle shows the PLC (the NC -> PLC signals of :class:`SpindleSignals`), and the
    position control its axis follows."""

    requested_gear: int  # the set gear during a change, else the active one
    change_gear: bool
    speed_limit_exceeded: bool
    setpoint_limited: bool
    setpoint_raised: bool
    speed_reached: bool
    clockwise: bool
    control_mode: bool
    oscillation_mode: bool
    positioning_mode: bool
    spindle_mode: bool  # not in axis mode
    in_position: bool
    m_function: int
    parameter_set: int
    position_control: bool
