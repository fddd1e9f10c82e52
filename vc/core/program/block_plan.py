"""The block plan: what one decoded block asks of the channel, and the modal state decoding keeps.

``decode`` (``interpreter.py``) fills a :class:`BlockPlan` from a block's words; the channel runs
it.  :class:`ModalState` holds the modal G-code state of a channel between blocks.  The software
limit checks of a block's end points live here as well: the transforms run them on the points they
compute.
"""

from __future__ import annotations

from collections.abc import Collection, Mapping
from dataclasses import dataclass, field

from vc.core.axis.axis import MachineAxis
from vc.core.axis.command_axis import MOTION_END_COARSE, MOTION_END_FINE, MOTION_END_IPO
from vc.core.axis.stroke_limits import StrokeCommand
from vc.core.interpolation.circle import Arc
from vc.core.interpolation.thread_cutting import ThreadCommand
from vc.core.program.commands import (
    AuxiliaryFunction,
    CouplingCommand,
    DriveEsrCommand,
    FixedStopWords,
    PolygonCommand,
    RetractProgramming,
    SpindleCommand,
)
from vc.core.program.five_axis_program import FiveAxisModal, FiveAxisWords
from vc.core.program.sync_actions import SyncAction, VariableWrite

# Block-end condition of a motion block (G60 exact stop with its window, or G64 continuous path).
EXACT_STOP_FINE = "G601"
EXACT_STOP_COARSE = "G602"
INTERPOLATION_END = "G603"

# The motion-end conditions of a positioning axis (seed 003 L10112-10122), evaluated by its axis interpolator
MOTION_ENDS = (MOTION_END_FINE, MOTION_END_COARSE, MOTION_END_IPO)


@dataclass(frozen=True, slots=True)
class PositioningMotion:
    """POS[ax]= (type 1: the block ends when the axis has reached its end) or POSA[ax]= (type 2: the
    program goes on, WAITP waits), seed 003 L11832-11858."""

    target: float  # machine position
    wait: bool  # POS: the block waits for the axis; POSA: it does not


@dataclass(slots=True)
class ModalState:
    """Modal G-code state of a channel; ``reset()`` restores the values after reset / program start."""

    rapid: bool = True  # group 1: G0 (reset value) / G1
    absolute: bool = True  # G90 / G91
    block_end: str = EXACT_STOP_FINE  # G60 + G601 / G602 / G603; G64 ends at interpolation end
    feed: float | None = None  # F: path feed in mm/min (G94) or mm per master spindle revolution (G95)
    per_revolution: bool = False  # group 15: G94 (reset value) / G95, the ISO G98 / G99 of seed 002 alike
    # group 15 constant cutting speed: "G96" (F in mm/rev) / "G961" (F in mm/min) while it is selected,
    # "" under G94 / G95 / G97 / G971; the cutting speed in m/min, kept for a re-selection (L7666-7668)
    constant_cutting: str = ""
    cutting_speed: float | None = None
    # group 29: DIAMOF (reset value) / DIAMON (the transverse axis's end points in diameter) / DIAM90
    # (in diameter with G90, in radius with G91), seed 003 §8.1, L10360-10415
    diameter: str = "DIAMOF"
    polygon: bool = False  # G51.2 (polygon turning) until G50.2 (seed 002)
    five_axis: FiveAxisModal = field(default_factory=FiveAxisModal)  # G43.4 / G43 / G68.2 (seed 001)
    # group 1 thread modes: "G33" (thread cutting), "G331"/"G332" (tapping); "" after G0/G1
    thread: str = ""
    plane: str = "G17"  # G17 / G18 / G19 working plane; reset value G17 (MD20150 as delivered) [control]
    circle: str = ""  # group 1 circular interpolation: "G2" (clockwise) / "G3"; "" after G0/G1/G33/G331
    thread_lead: ThreadCommand | None = None  # the last G33 lead: it holds for G33 blocks without one
    retract: RetractProgramming = field(default_factory=RetractProgramming)  # LFON, DILF, ALF, POLF ...

    def reset(self) -> None:
        self.rapid = True
        self.absolute = True
        self.block_end = EXACT_STOP_FINE
        self.feed = None
        self.per_revolution = False
        self.constant_cutting = ""
        self.cutting_speed = None
        self.diameter = "DIAMOF"
        self.polygon = False
        self.five_axis.reset()
        self.thread = ""
        self.plane = "G17"
        self.circle = ""
        self.thread_lead = None
        self.retract.reset()


@dataclass(frozen=True, slots=True)
class Tapping:
    """G331 / G332: the drilling axis and the spindle interpolated with it (seed 003 L17640-17664).

    The spindle turns ``pitch`` mm per revolution of the drilling axis: G331 in the direction of
    the pitch's sign (+ = M3, right-hand thread), G332 against it; the path feed is S x |pitch|
    (L8573, L8581)."""

    function: str  # "G331" or "G332"
    axis: str  # machine axis of the drilling (geometry) axis
    spindle: str  # machine axis of the master spindle
    pitch: float  # mm/rev, signed
    travel: float = 0.0  # mm of the drilling axis, signed; known when the block starts to move

    def spindle_degrees(self, travel: float) -> float:
        """How far the spindle turns while the drilling axis travels ``travel`` mm."""
        direction = (1.0 if self.pitch > 0 else -1.0) * (1.0 if self.function == "G331" else -1.0)
        return direction * abs(travel) / abs(self.pitch) * 360.0

    @property
    def spindle_per_mm(self) -> float:
        """Spindle degrees per mm of the drilling axis's travel, signed (0 before the block moves)."""
        return self.spindle_degrees(self.travel) / self.travel if self.travel else 0.0


@dataclass(slots=True)
class BlockPlan:
    targets: dict[str, float] = field(default_factory=dict)  # machine axis -> end position
    rapid: bool = True
    feed: float = 0.0  # mm/min, or mm/rev with feed_per_revolution
    feed_per_revolution: bool = False  # G95 / G99: the channel multiplies F by the spindle speed each cycle
    constant_cutting: str = ""  # "G96" / "G961": the master spindle's speed follows the transverse axis
    cutting_speed: float = 0.0  # m/min, with constant_cutting
    spindle_limits: dict[str, float] = field(default_factory=dict)  # LIMS: machine axis of the spindle -> rev/min
    dwell: float = 0.0  # seconds
    program_stop: bool = False  # M0
    optional_stop: bool = False  # M1: stops only with DB21.DBX0.5 "activate M01"
    program_end: bool = False  # M2 / M30 / M17
    block_end: str = EXACT_STOP_FINE
    reference_axes: tuple[str, ...] = ()  # G74: machine axes to reference
    preset: dict[str, float] = field(default_factory=dict)  # PRESETON: machine axis -> new actual value
    delete_drf: bool = False  # DRFOF: the DRF offsets of the channel's axes are deleted (seed 003 L36470)
    fixed_stop: dict[str, FixedStopWords] = field(default_factory=dict)  # FXS / FXST / FXSW by machine axis
    spindles: dict[str, SpindleCommand] = field(default_factory=dict)  # machine axis -> its part of the block
    couplings: list[CouplingCommand] = field(default_factory=list)
    # CPSYNCOP[Sn]=.. and the other synchronism thresholds: machine axis of the FS -> MD number -> value
    coupling_thresholds: dict[str, dict[int, float]] = field(default_factory=dict)
    feeds: dict[str, float] = field(default_factory=dict)  # FA[Sn]: machine axis -> deg/min (0 = MD)
    position_control: dict[str, bool] = field(default_factory=dict)  # SPCON / SPCOF: machine axis -> on
    dwell_revolutions: float = 0.0  # G4 S: revolutions of the spindle ``dwell_spindle``
    dwell_spindle: str = ""  # the machine axis of the spindle whose revolutions G4 S / G4 S<n>= counts
    spindle_waits: list[str] = field(default_factory=list)  # WAITS: machine axes of the spindles waited for
    polygon: PolygonCommand | None = None
    five_axis: FiveAxisWords | None = None  # G43.4 / G43 / G49 / G68.2 / G69 / G53.1 and their words
    tapping: Tapping | None = None  # G331 / G332 with a drilling axis
    thread: ThreadCommand | None = None  # G33 with axes: thread cutting slaved to the master spindle
    variables: list[VariableWrite] = field(default_factory=list)  # $AC_.. / $AA_.. / $AN_.. assignments
    sync_actions: list[SyncAction] = field(default_factory=list)  # ID= / IDS= synchronized actions
    drive_esr: list[DriveEsrCommand] = field(default_factory=list)  # ESRS / ESRR
    single_axis_retract: list[tuple[str, int, float | None]] = field(default_factory=list)  # POLFA
    machine_coordinates: bool = False  # G53: the axis words are machine positions, in rapid (seed 000 L154-158)
    reference_return: int = 0  # G28 = 1, G30 = 2: via the axis words (intermediate point) to reference point n
    return_targets: dict[str, float] = field(default_factory=dict)  # G28 / G30: machine axis -> reference point
    path_length: float | None = None  # the length F is measured along where a transform makes it differ
    arc: Arc | None = None  # G2 / G3: the path in program coordinates (``targets`` hold its end point)
    stroke_limit: StrokeCommand | None = None  # G22 (with the box corners it sets) / G23
    aux_functions: list[AuxiliaryFunction] = field(default_factory=list)  # to the PLC, in the block's order
    positioning: dict[str, PositioningMotion] = field(default_factory=dict)  # POS / POSA: machine axis -> motion
    axis_feeds: dict[str, float] = field(default_factory=dict)  # FA[ax] of an axis: machine axis -> per minute
    motion_ends: dict[str, str] = field(default_factory=dict)  # FINEA / COARSEA / IPOENDA: machine axis -> it
    positioning_waits: tuple[str, ...] = ()  # WAITP: the machine axes the block waits for


@dataclass(frozen=True, slots=True)
class DecodeAlarm:
    number: int
    parameters: tuple[object, ...]
    axis: str = ""


SOFTWARE_LIMIT = 10720
LIMIT_TOLERANCE = 1e-9  # mm: an end point a transform computes onto the limit is on it, not beyond


def software_limit_alarm(channel: str, label: str, axis: MachineAxis, position: float) -> DecodeAlarm | None:
    """Alarm 10720 when ``position`` of ``axis`` lies beyond its software limit switches MD36100 /
    MD36110 (active once referenced): the check before a block moves, for ordinary end points, for
    the Cartesian position of the inclined pair and for the points of a transformed path."""
    if not axis.software_limits_active:
        return None
    minus, plus = axis.software_limits
    if position > plus + LIMIT_TOLERANCE:
        return DecodeAlarm(SOFTWARE_LIMIT, (channel, axis.name, label, "+"), axis.name)
    if position < minus - LIMIT_TOLERANCE:
        return DecodeAlarm(SOFTWARE_LIMIT, (channel, axis.name, label, "-"), axis.name)
    return None


def end_point_limit_alarm(plan: BlockPlan, channel: str, label: str, axes: Mapping[str, MachineAxis],
                          limits_checked_elsewhere: Collection[str] = ()) -> DecodeAlarm | None:
    """10720 for the first machine end point of an ordinary block beyond its software limits;
    ``limits_checked_elsewhere`` are axes a transform checks in its own coordinates."""
    ends = plan.targets if not plan.positioning else \
        {**plan.targets, **{name: motion.target for name, motion in plan.positioning.items()}}
    for name, target in ends.items():
        if name not in limits_checked_elsewhere:
            alarm = software_limit_alarm(channel, label, axes[name], target)
            if alarm is not None:
                return alarm
    return None
