"""The PLC interface of a spindle: its DB31 signals (seed 003 chapter 13, spec B.3) and the inputs
as the spindle last took them.

:class:`SpindleSignals` names the signals once for every spindle (catalogue symbols without the
instance); :class:`SpindleInputs` holds one spindle's PLC inputs of this cycle, which the spindle,
its gear change and its positioning read (edge-evaluated inputs keep their last value).
"""

from __future__ import annotations

from dataclasses import dataclass

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
