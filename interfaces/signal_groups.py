"""The groups of the NC/PLC interface: which signals the NC reads and writes together, declared once.

Each group is a dataclass of :mod:`interfaces.group_codec`: one attribute per signal, named after
what it means, carrying its catalogue symbol without the instance (the catalogue holds address,
type and meaning).  The NC compiles every group once at power-on for all instances of its data
block (``vc/core/interface_map.py``); the soft PLC reads a group of one instance whole
(``plc_stub/io.py``).  A group is one direction: ``...Requests`` are the PLC's outputs to the NC,
``...Status`` (and the others named by content) the NC's outputs to the PLC.

The NC keeps what it derives from a group in a subclass beside the function that owns it (the
axis's measuring system from two bits, the channel's override factors from the switch positions,
the edges of edge-evaluated signals).
"""

from __future__ import annotations

from dataclasses import dataclass

from interfaces.group_codec import signal

# ---------------------------------------------------------------------------------------- DB10 NCK


@dataclass(slots=True, kw_only=True)
class NckRequests:
    emergency_stop: bool = signal("basic.out.emergencyStop")  # DB10.DBX56.1
    emergency_stop_ack: bool = signal("basic.out.emergencyStopAck")  # DB10.DBX56.2
    digital_inputs: int = signal("basic.out.setDigitalInputs", 0)  # $A_IN[1..8]


@dataclass(frozen=True, slots=True, kw_only=True)
class NckStatus:
    emergency_stop_active: bool = signal("basic.in.emergencyStopActive")
    nc_ready: bool = signal("basic.in.ncReady")
    alarm_active: bool = signal("basic.in.alarmActive")


DISPLAY_WCS = "basic.out.displayWcsValues"  # DB19.DBX0.7: 1 WCS, 0 MCS; the one operator panel bit the NC reads

# --------------------------------------------------------------------------------- DB11 mode group


@dataclass(slots=True, kw_only=True)
class ModeGroupRequests:
    auto: bool = signal("basic.out.autoMode")
    mda: bool = signal("basic.out.mdaMode")
    jog: bool = signal("basic.out.jogMode")
    reset: bool = signal("basic.out.reset")
    ref: bool = signal("basic.out.refPoint")


@dataclass(frozen=True, slots=True, kw_only=True)
class ModeGroupStatus:
    auto_active: bool = signal("basic.in.autoModeActive")
    mda_active: bool = signal("basic.in.mdaModeActive")
    jog_active: bool = signal("basic.in.jogModeActive")
    ready: bool = signal("basic.in.ready")
    ref_active: bool = signal("basic.in.refPointActive")


# ------------------------------------------------------------------------------------ DB21 channel


@dataclass(slots=True, kw_only=True)
class ChannelRequests:
    nc_start_disable: bool = signal("basic.out.disableNcStart")
    nc_start: bool = signal("basic.out.ncStart")
    nc_stop: bool = signal("basic.out.ncStop")
    nc_stop_all: bool = signal("basic.out.ncStopAxesAndSpindles")
    reset: bool = signal("basic.out.reset")
    reference_start: bool = signal("basic.out.refPointApproach")
    feed_disable: bool = signal("basic.out.disableFeed")
    read_in_disable: bool = signal("basic.out.disableReadIn")
    delete_distance_to_go: bool = signal("basic.out.deleteDistanceToGo")
    feed_override_raw: int = signal("basic.out.pathFeedrateOvrFactor", 0)
    feed_override_active: bool = signal("basic.out.pathFeedrateOvr")
    rapid_override_raw: int = signal("basic.out.pathRapidTraversOvrFactor", 0)
    rapid_override_active: bool = signal("basic.out.pathRapidTraversOvr")
    dry_run: bool = signal("basic.out.dryRunFeedrate")
    program_test: bool = signal("basic.out.progTest")
    activate_m01: bool = signal("basic.out.activateM01")  # DB21.DBX0.5
    path_fixed_feed: int = signal("basic.out.pathFixedFeedrateSelection", 0)  # DB21.DBX29.0-29.3: MD12202


@dataclass(frozen=True, slots=True, kw_only=True)
class ChannelStatus:
    """The channel and program state and the alarm bits (DB21.DBX35.x, 36.x, 33.x)."""

    running: bool = signal("basic.in.progStateRunning")
    waiting: bool = signal("basic.in.progStateWaiting")
    stopped: bool = signal("basic.in.progStateStopped")
    interrupted: bool = signal("basic.in.progStateInterrupted")
    aborted: bool = signal("basic.in.progStateAborted")
    state_active: bool = signal("basic.in.stateActive")
    state_interrupted: bool = signal("basic.in.stateInterrupted")
    state_reset: bool = signal("basic.in.stateReset")
    alarm_active: bool = signal("basic.in.alarmActive")
    alarm_with_stop: bool = signal("basic.in.alarmWithStopActive")
    reference_active: bool = signal("basic.in.refActive")


@dataclass(frozen=True, slots=True, kw_only=True)
class DryRunStatus:
    """DB21.DBX318.6: the NC took the dry-run feed (seed 003 L9433-9438)."""

    active: bool = signal("basic.in.dryRunFeedrateActive")


@dataclass(frozen=True, slots=True, kw_only=True)
class FeedTypeStatus:
    """The channel's feed type (DB21.DBX33.2): G95 / G96 / G97, F per revolution."""

    revolution_feed: bool = signal("basic.in.revolutionalFeedrateActive")


@dataclass(frozen=True, slots=True, kw_only=True)
class AxisSummary:
    all_referenced: bool = signal("basic.in.allAxesReferenced")
    all_stationary: bool = signal("basic.in.allAxesStationary")


# --------------------------------------------------------------- DB21 auxiliary functions (H2)

AUX_FUNCTION = "aux{kind}Funcs[{number}].in."  # the prefix of one output slot: auxMFuncs[1].in.


@dataclass(frozen=True, slots=True, kw_only=True)
class AuxWholeFunction:
    """One slot of the M, T or D functions (DB21.DBX58.x / 61.0 / 62.0 change, the quick bit, the
    extended address and the value: a DINT, the D number an INT)."""

    change: bool = signal("change")
    quick: bool = signal("quick")
    extended_address: int = signal("extendedAddress", 0)
    value: int = signal("value", 0)


@dataclass(frozen=True, slots=True, kw_only=True)
class AuxRealFunction:
    """One slot of the S, H or DL functions: as :class:`AuxWholeFunction` with a REAL value."""

    change: bool = signal("change")
    quick: bool = signal("quick")
    extended_address: int = signal("extendedAddress", 0)
    value: float = signal("value", 0.0)


@dataclass(frozen=True, slots=True, kw_only=True)
class AuxFeedFunction:
    """F function 1, the path feed (DB21.DBX65.0, DBW158, DBD160): no quick output."""

    change: bool = signal("change")
    extended_address: int = signal("extendedAddress", 0)
    value: float = signal("value", 0.0)


AUX_M_DECODED = "auxMDynFuncs.in.m{number:02d}Decoded"  # DB21.DBX194.0 + M: M00 .. M99 decoded


@dataclass(frozen=True, slots=True, kw_only=True)
class ProgramStopStatus:
    """A programmed stop or end holds the program (DB21.DBX32.5, DBX33.5)."""

    m00_m01_active: bool = signal("basic.in.m00M01Active")
    m02_m30_active: bool = signal("basic.in.m02M30Active")


RETRACTION_REQUEST = "piService.out.retracRequest"  # DB21.DBX396.0: PI service RETRAC, read every IPO cycle


@dataclass(frozen=True, slots=True, kw_only=True)
class RetractionStatus:
    """Manual retraction (DB21.DBX377.4 / 377.5) and the answer to the PI service RETRAC (397.0 / 397.1)."""

    data_available: bool = signal("basic.in.jogRetractDataAvailable")
    active: bool = signal("basic.in.jogRetractActive")
    done: bool = signal("piService.in.retracDone")
    error: bool = signal("piService.in.retracError")


# ------------------------------------------------------------------------- DB31 / DB21 handwheels

HANDWHEEL_OF_MACHINE_AXIS = "basic.out."  # the prefix of HandwheelSelection in DB31
HANDWHEEL_OF_GEOMETRY_AXIS = "geoAxis{number}.out."  # the prefix in DB21, geometry axis 1..3


@dataclass(slots=True, kw_only=True)
class HandwheelSelection:
    """A machine axis's (DB31.DBX4.0..4.2, 5.0..5.4) or a geometry axis's handwheel assignment and
    its increment INC1 .. INC10000 (symbols after the prefix)."""

    assigned: int = signal("handwheelSelection", 0)  # bit mask: bit 0 = handwheel 1
    inc1: bool = signal("inc1")
    inc10: bool = signal("inc10")
    inc100: bool = signal("inc100")
    inc1000: bool = signal("inc1000")
    inc10000: bool = signal("inc10000")


HANDWHEEL_INVERSION_OF_MACHINE_AXIS = "basic."  # DB31.DBX7.0 / 67.0
HANDWHEEL_INVERSION_OF_GEOMETRY_AXIS_1 = "geoAxis1."  # DB21.DBX15.0 / 43.0


@dataclass(frozen=True, slots=True, kw_only=True)
class HandwheelInversionRequest:
    """The PLC inverts the handwheel's direction of rotation for a machine axis or geometry axis 1
    (seed 003 §16.6.1 L33280-33306; symbol after the prefix)."""

    invert: bool = signal("out.handwheelInvertDir")


@dataclass(frozen=True, slots=True, kw_only=True)
class HandwheelInversionStatus:
    """The NC's acknowledgement: the handwheel's direction inverted (DB31.DBX67.0, DB21.DBX43.0)."""

    inverted: bool = signal("in.handwheelDirInverted")


# ------------------------------------------------------------------- manual travel: JOG machine functions


@dataclass(frozen=True, slots=True, kw_only=True)
class JogMachineFunctions:
    """A machine axis's machine function of JOG (DB31.DBX5.0..5.6, seed 003 §16.4 / §16.5): the
    increment of incremental JOG, or continuous JOG."""

    inc1: bool = signal("basic.out.inc1")
    inc10: bool = signal("basic.out.inc10")
    inc100: bool = signal("basic.out.inc100")
    inc1000: bool = signal("basic.out.inc1000")
    inc10000: bool = signal("basic.out.inc10000")
    inc_var: bool = signal("basic.out.incVar")
    continuous: bool = signal("basic.out.contTravers")


@dataclass(frozen=True, slots=True, kw_only=True)
class JogTargetRequests:
    """JOG to a fixed point (DB31.DBX13.0..13.2, its number binary, 0 = off) or to the position
    SD43320 (DB31.DBX13.3) of a machine axis (seed 003 §16.9, §16.10)."""

    fixed_point: int = signal("basic.out.jogFixedPointSelection", 0)
    to_position: bool = signal("basic.out.jogToPos")


@dataclass(frozen=True, slots=True, kw_only=True)
class JogTargetStatus:
    """What the NC reports of JOG to a fixed point / to a position (DB31.DBX75.0..75.7)."""

    fixed_point_selected: int = signal("basic.in.jogFixedPointSelectedNumber", 0)
    fixed_point_reached: int = signal("basic.in.jogFixedPointReachedNumber", 0)
    to_position_active: bool = signal("basic.in.jogToPosActive")
    position_reached: bool = signal("basic.in.jogPosReached")


@dataclass(frozen=True, slots=True, kw_only=True)
class ActiveJogMachineFunction:
    """The machine function of JOG the NC has active for a machine axis (DB31.DBX65.0..65.6)."""

    inc1: bool = signal("basic.in.inc1Active")
    inc10: bool = signal("basic.in.inc10Active")
    inc100: bool = signal("basic.in.inc100Active")
    inc1000: bool = signal("basic.in.inc1000Active")
    inc10000: bool = signal("basic.in.inc10000Active")
    inc_var: bool = signal("basic.in.incVarActive")
    continuous: bool = signal("basic.in.contTraversActive")


@dataclass(frozen=True, slots=True, kw_only=True)
class GeometryJogMachineFunctions:
    """Geometry axis 1's machine function of JOG in DB21 (DBX13.0..13.6): its handwheel's increment."""

    inc1: bool = signal("geoAxis1.out.inc1")
    inc10: bool = signal("geoAxis1.out.inc10")
    inc100: bool = signal("geoAxis1.out.inc100")
    inc1000: bool = signal("geoAxis1.out.inc1000")
    inc10000: bool = signal("geoAxis1.out.inc10000")
    inc_var: bool = signal("geoAxis1.out.incVar")
    continuous: bool = signal("geoAxis1.out.contManualTravers")


@dataclass(frozen=True, slots=True, kw_only=True)
class ActiveGeometryJogMachineFunction:
    """The machine function of JOG the NC has active for geometry axis 1 (DB21.DBX41.0..41.6)."""

    inc1: bool = signal("geoAxis1.in.inc1Active")
    inc10: bool = signal("geoAxis1.in.inc10Active")
    inc100: bool = signal("geoAxis1.in.inc100Active")
    inc1000: bool = signal("geoAxis1.in.inc1000Active")
    inc10000: bool = signal("geoAxis1.in.inc10000Active")
    inc_var: bool = signal("geoAxis1.in.incVarActive")
    continuous: bool = signal("geoAxis1.in.contManualTraversActive")


# --------------------------------------------------------------------------------------- DB31 axis


@dataclass(slots=True, kw_only=True)
class AxisRequests:
    controller_enable: bool = signal("basic.out.enableCtrl")
    pulse_enable: bool = signal("drive.out.enablePulses")
    disable: bool = signal("basic.out.disable")
    follow_up_mode: bool = signal("basic.out.followUpMode")
    override_active: bool = signal("basic.out.enableOvr")
    override_raw: int = signal("basic.out.feedrateOvrFactor", 0)
    feed_stop: bool = signal("basic.out.feedStopSpindleStop")
    rapid_key: bool = signal("basic.out.enableRapidTravers")
    key_minus: bool = signal("basic.out.traversKeyMinus")
    key_plus: bool = signal("basic.out.traversKeyPlus")
    hw_limit_minus: bool = signal("basic.out.hwLimitSwitchMinus")
    hw_limit_plus: bool = signal("basic.out.hwLimitSwitchPlus")
    reset_movement: bool = signal("basic.out.resetMovement")
    ref_cam: bool = signal("basic.out.refPointApproachCam")  # DB31.DBX12.7: the cam as the PLC copied it
    ref_point_selection: int = signal("basic.out.refPointSelection", 0)  # DBX2.4..2.7: reference point 1..4
    encoder_1_activation: bool = signal("basic.out.enc1Activation")  # DBX1.5
    encoder_2_activation: bool = signal("basic.out.enc2Activation")  # DBX1.6
    fixed_stop_enable: bool = signal("basic.out.fixedStopEnable")  # DBX3.1: travel to fixed stop enabled
    fixed_stop_ack: bool = signal("basic.out.fixedStopAckReached")  # DBX1.1
    limit_switch_2_minus: bool = signal("basic.out.swLimitSwitch2Minus")  # DBX12.2: MD36120 instead of MD36100
    limit_switch_2_plus: bool = signal("basic.out.swLimitSwitch2Plus")  # DBX12.3: MD36130 instead of MD36110
    fixed_feed: int = signal("basic.out.fixedFeedrateSelection", 0)  # DBX3.2-3.5: JOG at MD12202 / MD12204
    fixed_stop_sensor: bool = signal("basic.out.fixedStopSensor")  # DBX1.2
    modulo_limit_enable: bool = signal("basic.out.enableModuloLimitSwitch")  # DBX12.4
    clamping: bool = signal("basic.out.clampingInProgress")  # DBX2.3: the clamping monitor replaces standstill's


@dataclass(frozen=True, slots=True, kw_only=True)
class AxisStatus:
    exact_coarse: bool = signal("basic.in.posCoarseReached")
    exact_fine: bool = signal("basic.in.posFineReached")
    stationary: bool = signal("basic.in.isStationary")
    position_control: bool = signal("basic.in.posCtrlActive")
    follow_up_active: bool = signal("basic.in.followUpModeActive")
    referenced_1: bool = signal("basic.in.enc1Synchronized")
    referenced_2: bool = signal("basic.in.enc2Synchronized")
    restored_1: bool = signal("basic.in.enc1Restored")
    restored_2: bool = signal("basic.in.enc2Restored")
    frequency_exceeded_1: bool = signal("basic.in.enc1FreqLimitExceeded")
    frequency_exceeded_2: bool = signal("basic.in.enc2FreqLimitExceeded")
    disabled: bool = signal("basic.in.disabled")
    command_plus: bool = signal("basic.in.traversPlusCommandActive")
    command_minus: bool = signal("basic.in.traversMinusCommandActive")
    drive_enabled: bool = signal("drive.in.enabled")
    modulo_limit_active: bool = signal("basic.in.moduloLimitSwitchActive")  # DBX74.4
    index_in_position: bool = signal("basic.in.indexAxisInPos")  # DBX76.6: an indexing axis on a position


@dataclass(frozen=True, slots=True, kw_only=True)
class PositioningAxisStatus:
    """A positioning axis of the part program (seed 003 §9.7, L12267; §7.3, L8921)."""

    positioning_axis: bool = signal("basic.in.isPosAxis")  # DBX76.5
    feed: float = signal("basic.in.posAxisFeedrateValue", 0.0)  # DBD78: FA, mm/min or deg/min


@dataclass(slots=True, kw_only=True)
class PlcAxisRequests:
    """A PLC axis (seed 003 §9.3.2, §9.7): the PLC takes and gives back the axis, stops, resumes
    and resets it; and the parameters of FC18 SINU_TraversePosAxis (the exchange area of the basic
    program, DBB32-43, DBB104-105: interfaces/catalog/db31_axis.yaml)."""

    request_plc_control: bool = signal("plcCtrl.out.requestPlcCtrl")  # DBX28.7
    axis_reset: bool = signal("spindle.out.plcCtrl")  # DBX28.1 (the seed's [DOC-ERR]: the axis reset)
    resume: bool = signal("spindle.out.resume")  # DBX28.2
    axis_stop: bool = signal("spindle.out.stop")  # DBX30.0
    start: bool = signal("plcAxis.out.start")  # FC18 Start
    stop: bool = signal("plcAxis.out.stop")  # FC18 Stop
    function: int = signal("plcAxis.out.function", 0)  # FC18 Funct (4 indexing axis, 5 or 0 positioning axis)
    mode: int = signal("plcAxis.out.mode", 0)  # FC18 Mode
    position: float = signal("plcAxis.out.position", 0.0)  # FC18 Pos
    feedrate: float = signal("plcAxis.out.feedrate", 0.0)  # FC18 FRate


@dataclass(frozen=True, slots=True, kw_only=True)
class PlcAxisStatus:
    """The axis's type towards the PLC (DBX63.0-63.2, DBB68) and FC18's feedback."""

    reset_done: bool = signal("plcCtrl.in.resetDone")  # DBX63.0
    plc_controlled: bool = signal("plcCtrl.in.active")  # DBX63.1
    stopped: bool = signal("plcCtrl.in.stopped")  # DBX63.2
    channel_number: int = signal("plcCtrl.in.assignedChanNumber", 0)  # DBX68.0-68.3
    new_type_requested: bool = signal("plcCtrl.in.newTypeRequested")  # DBX68.4
    changeover_possible: bool = signal("plcCtrl.in.changeoverPossible")  # DBX68.5
    neutral: bool = signal("plcCtrl.in.neutralModeActive")  # DBX68.6
    plc_axis: bool = signal("plcCtrl.in.assignedToPlc")  # DBX68.7
    active: bool = signal("plcAxis.in.active")  # FC18: the motion runs
    in_position: bool = signal("plcAxis.in.inPosition")  # FC18 InPos
    error: bool = signal("plcAxis.in.error")  # FC18 Error
    error_number: int = signal("plcAxis.in.errorNumber", 0)  # FC18 State
    start_acknowledged: bool = signal("plcAxis.in.startAcknowledged")  # the NC has taken the Start


@dataclass(frozen=True, slots=True, kw_only=True)
class FixedStopStatus:
    """Travel to fixed stop (DB31.DBX62.4 / 62.5, seed 003 §17.2.2)."""

    active: bool = signal("basic.in.fixedStopRequest")  # selected: the torque is limited
    reached: bool = signal("basic.in.fixedStopReached")


@dataclass(frozen=True, slots=True, kw_only=True)
class DriveEsrStatus:
    """The drive's ESR feedback (DB31.DBX95.2..95.4) and its own motion while it reacts (DBX92.4)."""

    response_initiated: bool = signal("drive.in.esrResponseInitiated")  # r0887.12
    dc_link_undervoltage: bool = signal("drive.in.esrDcVoltageAlarmActive")  # r0056.15
    below_minimum_speed: bool = signal("drive.in.esrSpeedBelowMin")  # r2199.0
    autonomous_motion: bool = signal("drive.in.autonomousMotionActive")  # r0887.13: the reaction runs


@dataclass(slots=True, kw_only=True)
class ParameterSetRequest:
    """The PLC's servo parameter set selection of an axis (DB31.DBX9.0-9.2, MD35590 = 1 / 2; seed 003
    §7.4.11 L10220, §13.4.4 L18927-18958)."""

    selection: int = signal("basic.out.posCtrlParameterSetSelection", 0)  # the set's index 0..5 (6, 7: 5)


@dataclass(frozen=True, slots=True, kw_only=True)
class ParameterSetStatus:
    """The active servo parameter set (DB31.DBX69.0-69.2, L19065): a spindle's is SpindleStatus's."""

    active: int = signal("drive.in.posCtrlParameterSetNumber", 0)


@dataclass(slots=True, kw_only=True)
class DriveDataSetRequest:
    """The PLC's drive and motor data set selection and the speed controller's integrator
    (DB31.DBX21.0-21.6; seed 003 §18.2 L38337-38344)."""

    drive_data_set: int = signal("drive.out.driveDataSetSelection", 0)  # DDS A..C: 0..7
    motor_data_set: int = signal("drive.out.motorDataSetSelection", 0)  # MDS A..B: 0..3
    motor_changeover_done: bool = signal("drive.out.motorChangeoverDone")  # the PLC switched the contactors
    integrator_disable: bool = signal("drive.out.disableSpeedCtrlIntegrator")


@dataclass(frozen=True, slots=True, kw_only=True)
class DriveDataSetStatus:
    """The drive's active data sets and integrator (DB31.DBX93.0-93.6; L38355-38361)."""

    drive_data_set: int = signal("drive.in.driveDataSetNumber", 0)
    motor_data_set: int = signal("drive.in.motorDataSetNumber", 0)
    integrator_disabled: bool = signal("drive.in.speedCtrlIntegratorDisabled")


@dataclass(slots=True, kw_only=True)
class HoldingBrakeRequest:
    """The PLC's order to the drive to release the motor's holding brake (DB31.DBX20.5; seed 003
    §18.2 L38336)."""

    release: bool = signal("drive.out.releaseHoldingBrake")


@dataclass(frozen=True, slots=True, kw_only=True)
class HoldingBrakeStatus:
    """The brake's feedback through the drive (DB31.DBX92.5 "holding brake released", L38353)."""

    released: bool = signal("drive.in.holdingBrakeReleased")


@dataclass(slots=True, kw_only=True)
class SetpointSwitchoverRequest:
    """The PLC's request for the shared drive's control (DB31.DBX24.5; seed 003 §18.2 L38226-38230)."""

    request: bool = signal("drive.out.requestDriveCtrl")


@dataclass(frozen=True, slots=True, kw_only=True)
class SetpointSwitchoverStatus:
    """Which axis of a shared drive has its control (DB31.DBX96.5, L38232-38236)."""

    active: bool = signal("drive.in.driveCtrlActive")


@dataclass(frozen=True, slots=True, kw_only=True)
class DriveMessageStatus:
    """The drive's messages (DB31.DBX94.0..94.6, 95.0; seed 003 §18.2 L38362-38366 and the control's
    list manual): temperature, ramp-up, torque and speed thresholds, the DC link."""

    motor_temperature_warning: bool = signal("drive.in.motorTempPrewarning")  # DBX94.0, p0604
    ramp_up_complete: bool = signal("drive.in.speedSetpointReached")  # DBX94.2
    torque_below_threshold: bool = signal("drive.in.torqueBelowThreshold")  # DBX94.3, p2174 / p2176
    speed_below_minimum: bool = signal("drive.in.speedBelowMin")  # DBX94.4, p2161
    speed_below_threshold: bool = signal("drive.in.speedBelowThreshold")  # DBX94.5, p2155
    speed_at_setpoint: bool = signal("drive.in.speedAtSetpoint")  # DBX94.6, p2163
    dc_link_below_warning: bool = signal("drive.in.dcLinkBelowWarning")  # DBX95.0, p2172


# ------------------------------------------------------------------------------ DB31 software cams


@dataclass(slots=True, kw_only=True)
class SoftwareCamRequests:
    """DB31.DBX2.0: activate the axis's software cams (seed 003 L41202-41225)."""

    activate: bool = signal("basic.out.swCams")


@dataclass(frozen=True, slots=True, kw_only=True)
class SoftwareCamStatus:
    """DB31.DBX62.0: the axis's software cams are active (L41226-41267)."""

    active: bool = signal("basic.in.swCamsActive")


# ------------------------------------------------------------------------------------ DB31 spindle


@dataclass(slots=True, kw_only=True)
class SpindleRequests:
    """The spindle signals the NC takes as they stand."""

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


@dataclass(slots=True, kw_only=True)
class SpindleEdgeRequests:
    """The spindle signals the NC evaluates against their last value."""

    gear_reported: int = signal("spindle.out.gearStageSelection", 0)  # DBX16.0-16.2, taken when it stands still
    resync_1: bool = signal("spindle.out.resyncEnc1")  # DBX16.4
    resync_2: bool = signal("spindle.out.resyncEnc2")  # DBX16.5
    plc_stop: bool = signal("spindle.out.stop")  # DBB30: the simple spindle interface
    plc_start_cw: bool = signal("spindle.out.startCw")
    plc_start_ccw: bool = signal("spindle.out.startCcw")


@dataclass(frozen=True, slots=True, kw_only=True)
class SpindleStatus:
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
    constant_cutting_speed: bool = signal("spindle.in.constantCuttingSpeedActive")  # DBX84.0: G96 / G961


@dataclass(frozen=True, slots=True, kw_only=True)
class SpindleSpeed:
    s_value: float = signal("spindle.in.sFuncValue", 0.0)  # DBD88 (L17367)


# ----------------------------------------------------------------------- DB31 synchronous spindle


@dataclass(slots=True, kw_only=True)
class CouplingRequests:
    overlay_enable: bool = signal("coupling.out.enableFollowOverlay")  # DBX26.4
    resync: bool = signal("coupling.out.syncSpindleResync")  # DBX31.4
    sync_disable: bool = signal("coupling.out.syncSpindleSyncDisable")  # DBX31.5
    correction: bool = signal("coupling.out.syncCorrection")  # DBX31.6
    delete_correction: bool = signal("coupling.out.syncResetCorrection")  # DBX31.7


@dataclass(frozen=True, slots=True, kw_only=True)
class CouplingStatus:
    """Every bit but the first is the following spindle's (all off for a spindle that does not follow)."""

    leading_active: bool = signal("coupling.in.leadingSpindleActive")
    fine: bool = signal("coupling.in.syncFineReached")
    coarse: bool = signal("coupling.in.syncCoarseReached")
    overlaid: bool = signal("coupling.in.MotionOverlaid")
    speed_warning: bool = signal("coupling.in.egSpeedThresholdReached")
    accel_warning: bool = signal("coupling.in.egAccelThresholdReached")
    correction_done: bool = signal("coupling.in.CorrectionDone")
    accelerating: bool = signal("coupling.in.egAccelReached")
    process_active: bool = signal("coupling.in.ProcessActive")
    correction_active: bool = signal("coupling.in.CorrectionActive")
    fine_2: bool = signal("coupling.in.syncFine2Reached")
    coarse_2: bool = signal("coupling.in.syncCoarse2Reached")
    following_active: bool = signal("coupling.in.followingSpindleActive")
    sync_mode: bool = signal("spindle.in.syncModeActive")


# ----------------------------------------------------------------------------- DB31 gantry axes


@dataclass(slots=True, kw_only=True)
class GantryRequests:
    """Read at the leading axis of a gantry grouping (seed 003 §12.6, L15362-15410)."""

    start_sync_run: bool = signal("coupling.out.gantryStartSyncRun")  # DBX29.4
    disable_sync: bool = signal("coupling.out.gantryDisableSync")  # DBX29.5


@dataclass(frozen=True, slots=True, kw_only=True)
class GantryStatus:
    """101.4 / 101.5 are the leading axis's, 101.2 / 101.3 each following axis's (L15362-15410)."""

    cut_off_limit: bool = signal("coupling.in.gantryCutOffLimitExceeded")  # DBX101.2
    warning_limit: bool = signal("coupling.in.gantryWarningLimitExceeded")  # DBX101.3
    sync_run_ready: bool = signal("coupling.in.gantrySyncRunReady")  # DBX101.4
    sync_ok: bool = signal("coupling.in.gantrySyncOk")  # DBX101.5
    leading: bool = signal("coupling.in.gantryLeadingActive")  # DBX101.6
    gantry: bool = signal("coupling.in.gantryActive")  # DBX101.7


# ----------------------------------------------------------------------------- DB100 alarm list


@dataclass(frozen=True, slots=True, kw_only=True)
class AlarmListHeader:
    count: int = signal("list.in.count", 0)
    changes: int = signal("list.in.changes", 0)  # the alarm list's version, modulo 2^16


ALARM_ENTRY = "entry[{number}].in."  # the prefix of AlarmEntry, entry 1..n


@dataclass(frozen=True, slots=True, kw_only=True)
class AlarmEntry:
    """One entry of the list; all 0: no alarm."""

    number: int = signal("number", 0)
    channel: int = signal("channel", 0)
    axis: int = signal("axis", 0)
    reaction: int = signal("reaction", 0)
    cleared_by: int = signal("clearedBy", 0)
