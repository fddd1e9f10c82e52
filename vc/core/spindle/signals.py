"""The PLC interface of a spindle, declared once: its DB31 signals (seed 003 chapter 13, spec B.3).

:class:`SpindleInputs` holds one spindle's PLC inputs as the spindle last took them: the levels,
decoded as they stand, and the last value of the edge-evaluated ones, which the spindle, its gear
change and its positioning compare with :class:`SpindleRequests` (the edge-evaluated signals as
they stand this cycle); :class:`SpindleStatus` is what the spindle shows the PLC and
:class:`SpindleSpeed` the S value.  Each signal field names its catalogue symbol; the NCK compiles
the groups once for every spindle (:mod:`interfaces.signal_group`).
"""

from __future__ import annotations

from dataclasses import dataclass

from interfaces.signal_group import signal


@dataclass(slots=True)
class SpindleInputs:
    gear_done: bool = signal("spindle.out.gearChangeoverDone")
    delete_s: bool = signal("spindle.out.deleteSValue")
    use_feed_override: bool = signal("spindle.out.useFeedrateOvr")
    invert_m3_m4: bool = signal("spindle.out.invertM3M4")
    oscillation_by_plc: bool = signal("spindle.out.oscillRequest")
    oscillation_enable: bool = signal("spindle.out.oscillEnable")
    oscillation_cw: bool = signal("spindle.out.oscillSetDirCw")
    oscillation_ccw: bool = signal("spindle.out.oscillSetDirCcw")
    override_raw: int = signal("spindle.out.ovrFactor", 0)
    rapid_stop: bool = signal("drive.out.rapidStop")
    resync_for_positioning_1: bool = signal("spindle.out.resyncEnc1ForPos")  # DBX17.4
    resync_for_positioning_2: bool = signal("spindle.out.resyncEnc2ForPos")  # DBX17.5
    # the edge-evaluated inputs as last seen (SpindleRequests, and DB31.DBX2.2 of the axis)
    gear_reported: int = 0
    reset_movement: bool = False
    resync: tuple[bool, bool] = (False, False)
    plc_stop: bool = False
    plc_start_cw: bool = False
    plc_start_ccw: bool = False


@dataclass(slots=True)
class SpindleRequests:
    """The edge-evaluated PLC -> NC spindle signals as they stand this cycle."""

    gear_reported: int = signal("spindle.out.gearStageSelection", 0)  # DBX16.0-16.2, taken when it stands still
    resync_1: bool = signal("spindle.out.resyncEnc1")  # DBX16.4
    resync_2: bool = signal("spindle.out.resyncEnc2")  # DBX16.5
    plc_stop: bool = signal("spindle.out.stop")  # DBB30: the simple spindle interface
    plc_start_cw: bool = signal("spindle.out.startCw")
    plc_start_ccw: bool = signal("spindle.out.startCcw")


@dataclass(frozen=True, slots=True)
class SpindleStatus:
    """What a spindle shows the PLC, and the position control its axis follows."""

    requested_gear: int = signal("spindle.in.requestedGearStageNumber", 0)  # the set gear in a change, else the active
    change_gear: bool = signal("spindle.in.gearChangeoverRequested")
    speed_limit_exceeded: bool = signal("spindle.in.speedLimitationExceeded")
    setpoint_limited: bool = signal("spindle.in.speedSetpointAboveMax")
    setpoint_raised: bool = signal("spindle.in.speedSetpointBelowMin")
    speed_reached: bool = signal("spindle.in.speedSetpointReached")
    clockwise: bool = signal("spindle.in.cwRotActive")
    control_mode: bool = signal("spindle.in.ctrlModeActive")
    oscillation_mode: bool = signal("spindle.in.oscillModeActive")
    positioning_mode: bool = signal("spindle.in.posModeActive")
    spindle_mode: bool = signal("basic.in.spindleModeActive")  # not in axis mode
    in_position: bool = signal("spindle.in.inPos")
    m_function: int = signal("spindle.in.mFuncNumber", 0)
    parameter_set: int = signal("drive.in.posCtrlParameterSetNumber", 0)
    position_control: bool = False  # not a signal: the axis follows it


@dataclass(frozen=True, slots=True)
class SpindleSpeed:
    s_value: float = signal("spindle.in.sFuncValue", 0.0)  # DBD88 (L17367)
