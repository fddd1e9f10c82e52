"""A synchronous spindle pair and its state (seed 003 chapter 14): what every part of the coupling shares.

A pair is one following spindle (FS) and one leading spindle (LS).  While the pair is coupled
the FS turns with ``n_FS = k * n_LS`` (k = numerator / denominator, any sign, not only whole
numbers, L21720-21725, L21820-21834) and, with a position relation, ``phi_FS = k * phi_LS +
offset`` (L21727).  :class:`PairDefinition` is the pair of the table (MD21300.. or COUPDEF),
:class:`Coupling` one coupled pair and the phase it is in::

    defined ──COUPON / COUPONC──▶ SYNCHRONISING ──FS speed = k x LS speed──▶ SYNCHRONOUS
    SYNCHRONISING, SYNCHRONOUS ──COUPOF / COUPOFS / COUPDEL, reset, NC start (per MD)──▶ defined

* SYNCHRONISING: the FS ramps (its position-control acceleration) from its own speed to the
  coupled speed; the relation is not defined yet.  It ends in the cycle the speeds agree; the
  relation then is the setpoint relation at that moment ("setpoint synchronism", IPOSTOP).
* SYNCHRONOUS: ``FS setpoint = k x LS position + relation + correction``.  The relation moves
  only by overlaid motion (:class:`Overlay`, vc/core/spindle/coupling_motion.py).

The LS position is its setpoint for DV and VV and its actual value for AV (and for DV while
the LS has no controller enable, which the control does internally, L23232-23246).

Observers see each spindle as a following spindle (``COUPLING_STATES``): UNCOUPLED while it
follows no leading spindle (its pair defined or not), else the phase of its coupling.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from enum import Enum

from interfaces.signal_groups import CouplingRequests
from vc.config.machine_data import MachineData, MdDef
from vc.core.alarms import AlarmList
from vc.core.axis.axis import MachineAxis
from vc.core.program.commands import BlockChange, Kind
from vc.core.spindle.spindle import Spindle
from vc.core.state_machine import Instance, StateMachine, StateValue, states, transitions

ALARM_FINE_2_EXCEEDED = 22025  # stage-2 monitoring, display only (L29878-29888)
ALARM_COARSE_2_EXCEEDED = 22026


def wrap180(angle: float) -> float:
    return (angle + 180.0) % 360.0 - 180.0


def dynamic_matching(leading_time: float, following_time: float) -> tuple[int, float]:
    """MD32900 / MD32910 for the faster spindle of a pair: it gets the difference of the
    equivalent speed-control times MD32810 as extra delay (L23700-23721, TV-SS-6)."""
    difference = leading_time - following_time
    return (1, round(difference, 9)) if difference > 0.0 else (0, 0.0)


@dataclass(slots=True)
class PairDefinition:
    """A synchronous spindle pair (MD21300.. or COUPDEF), keyed by its FS."""

    following: str  # machine axis names
    leading: str
    numerator: float = 1.0
    denominator: float = 1.0
    block_change: BlockChange = BlockChange.IPOSTOP
    kind: Kind = Kind.DV
    configured: bool = False  # the channel's pair of MD21300
    write_protected: bool = False  # MD21340
    # CPSYNCOP.. in force, MD number -> value: they replace MD37200.. until COUPRES or COUPDEL [INF]
    thresholds: dict[int, float] = field(default_factory=dict)

    @property
    def ratio(self) -> float:
        return self.numerator / self.denominator


class SyncPhase(Enum):
    SYNCHRONISING = "synchronising"
    SYNCHRONOUS = "synchronous"


COUPLING_STATES: StateMachine[FollowingSpindle] = StateMachine(
    __name__, "coupling", "Synchronous spindle coupling of a following spindle", Instance.SPINDLE,
    states(("UNCOUPLED", "follows no leading spindle"), *SyncPhase),
    transitions(("UNCOUPLED", "SYNCHRONISING", "COUPON, the configured pair at NC start"),
                ("UNCOUPLED", "SYNCHRONOUS", "COUPON with both spindles at standstill: synchronous at once"),
                ("SYNCHRONISING", "SYNCHRONOUS", "synchronism reached"),
                ("SYNCHRONOUS", "UNCOUPLED", "COUPOF, reset"), ("SYNCHRONISING", "UNCOUPLED", "COUPOF, reset")),
    read=lambda spindle: spindle.state())


@dataclass(slots=True)
class Overlay:
    """Overlaid motion of the relation (COUPON offset, SPOS on the FS, resynchronisation)."""

    left: float  # degrees still to go
    limit: float  # deg/s
    velocity: float = 0.0
    waits: bool = True  # SPOS holds its block until done; SPOSA does not
    resync: bool = False  # started by DBX31.4: DBX99.4 while it runs
    positioning: bool = False  # SPOS / SPOSA on the FS: DBX2.2 deletes its distance to go


@dataclass(slots=True)
class Coupling:
    """One coupled pair."""

    definition: PairDefinition
    channel: str
    block: str = ""  # the COUPON block, shown by the stage-2 alarms
    phase: SyncPhase = SyncPhase.SYNCHRONISING
    relation: float = 0.0  # $AA_COUP_OFFS: FS setpoint - k x LS position (without the correction)
    target: float = 0.0  # the relation the coupling heads for
    programmed: float | None = None  # $P_COUP_OFFS
    offset_pending: bool = False  # COUPON with POSFS: applied at setpoint synchronism
    overlay: Overlay | None = None
    # SPOS [IC] on the FS before setpoint synchronism: (distance, FA[Sn] limit, waits), run one after
    # the other once the relation is defined and COUPON's offset is reached
    queued: list[tuple[float, float, bool]] = field(default_factory=list)
    differential: float = 0.0  # programmed differential speed, rev/min, signed
    differential_velocity: float = 0.0  # its ramped value, deg/s
    correction: float = 0.0  # $AA_COUP_CORR
    correction_applied: float = 0.0
    correction_velocity: float = 0.0
    correction_done: bool = False  # DBX99.2: the requested correction (or its deletion) is through
    deviation: float = 0.0  # degrees (DV/AV) or rev/min (VV)
    signed_deviation: float = 0.0  # $VA_SYNCDIFF: negative while the FS lags
    coarse: bool = False
    fine: bool = False
    last_velocity: float = 0.0
    acceleration: float = 0.0
    helix: tuple[MachineAxis, float] | None = None  # polygon turning: an axis and its lead per LS turn
    pending_shift: float = 0.0  # polygon turning's R: moves the relation once synchronous
    jog_allowed: bool = True  # the FS's JOG keys move the relation (not on a polygon slave)
    jog_velocity: float = 0.0  # deg/s of the relation moved by the JOG keys
    drf_rest: float = 0.0  # degrees of the relation the DRF handwheel pulses still have to move
    spcon_following: bool = False  # SPCON was programmed on the FS: position control stays after COUPOF
    shifts_seen: tuple[float, float] = (0.0, 0.0)  # the coordinate shifts of FS and LS the relation knows
    stage_2_exceeded: set[int] = field(default_factory=set)  # 22025 / 22026 whose tolerance is exceeded now
    # the stage-2 monitorings (by their alarm) started with stage-1 fine / coarse synchronism
    # (L29855-29866) and not ended since by a new synchronisation or a lost FS enable (L29895-29909)
    stage_2_running: set[int] = field(default_factory=set)
    stage_2_paused: bool = False  # an exclusion of the stage-2 monitoring holds (L29916-29932)

    @property
    def ratio(self) -> float:
        return self.definition.ratio

    @property
    def setpoint_synchronous(self) -> bool:
        return (self.phase is SyncPhase.SYNCHRONOUS and self.overlay is None and not self.offset_pending
                and not self.queued)

    def stage_2_monitors(self, number: int, tolerance: float) -> bool:
        """The stage-2 monitoring of ``number`` (22025 fine, 22026 coarse) runs: configured, started
        and not paused by an exclusion."""
        return tolerance > 0.0 and number in self.stage_2_running and not self.stage_2_paused

    def stage_2_within(self, number: int, tolerance: float) -> bool:
        """DBX103.4 / 103.5: the running stage-2 monitoring finds the deviation within its tolerance."""
        return self.stage_2_monitors(number, tolerance) and self.deviation <= tolerance


@dataclass(frozen=True, slots=True)
class FollowingSpindle:
    """A spindle as the following spindle of a coupling, as observers see it (``COUPLING_STATES``)."""

    active: dict[str, Coupling]  # the couplings in force, by their following spindle
    name: str

    def state(self) -> StateValue:
        coupling = self.active.get(self.name)
        return "UNCOUPLED" if coupling is None else coupling.phase


def threshold(coupling: Coupling, md: MachineData, datum: MdDef) -> float:
    """A synchronism threshold of the FS: its programmed CPSYNCOP.. value, else the machine datum."""
    programmed = coupling.definition.thresholds.get(datum.number)
    return md.float(datum) if programmed is None else programmed


def leading_position(coupling: Coupling, spindles: dict[str, Spindle]) -> tuple[float, float]:
    """Position and velocity of the LS the FS follows (setpoint, or actual value for AV)."""
    ls = spindles[coupling.definition.leading].axis
    if not ls.drive_ready and abs(ls.velocity) <= ls.dyn.standstill_velocity:
        # an LS without enable that stands: the settling residue of its drive is no motion
        # the FS should command (else removing both enables together reads as 21612 on the FS)
        return ls.actual, 0.0
    if coupling.definition.kind is Kind.AV or not ls.drive_ready:
        return ls.actual, ls.velocity
    return ls.setpoint, ls.command_velocity


def actual_relation(coupling: Coupling, spindles: dict[str, Spindle]) -> float:
    """``phi_FS - k x phi_LS`` of the actual positions."""
    fs = spindles[coupling.definition.following].axis
    ls = spindles[coupling.definition.leading].axis
    return fs.actual - coupling.ratio * ls.actual


@dataclass(slots=True)
class CouplingInputs(CouplingRequests):
    """The PLC -> NC coupling signals of one spindle and their rising edges not yet acted on."""

    edges: set[str] = field(default_factory=set)


class CouplingPart:
    """What the coupling's motion and its synchronism monitor share with :class:`Couplings`: the
    spindles, the coupled pairs by FS, the PLC's coupling inputs, the IPO cycle and the alarms."""

    def __init__(self, spindles: dict[str, Spindle], active: dict[str, Coupling], inputs: dict[str, CouplingInputs],
                 dt: float, alarms: AlarmList):
        self._spindles = spindles
        self._active = active  # the coupled pairs by FS (shared with Couplings)
        self.inputs = inputs
        self._dt = dt
        self._alarms = alarms
