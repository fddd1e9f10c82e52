"""Synchronous spindle coupling (seed 003 chapter 14), the engine polygon turning also runs on.

A pair is one following spindle (FS) and one leading spindle (LS).  While the pair is coupled
the FS turns with ``n_FS = k * n_LS`` (k = numerator / denominator, any sign, not only whole
numbers, L21720-21725, L21820-21834) and, with a position relation, ``phi_FS = k * phi_LS +
offset`` (L21727).  :class:`Couplings` keeps the pairs of every channel and drives each
coupled FS's position setpoint once per IPO cycle after the LS has moved::

    defined ──COUPON / COUPONC──▶ SYNCHRONISING ──FS speed = k x LS speed──▶ SYNCHRONOUS
    SYNCHRONISING, SYNCHRONOUS ──COUPOF / COUPOFS / COUPDEL, reset, NC start (per MD)──▶ defined

* SYNCHRONISING: the FS ramps (its position-control acceleration) from its own speed to the
  coupled speed; the relation is not defined yet.  It ends in the cycle the speeds agree; the
  relation then is the setpoint relation at that moment ("setpoint synchronism", IPOSTOP).
* SYNCHRONOUS: ``FS setpoint = k x LS position + relation + correction``.  The relation moves
  only by overlaid motion: a programmed offset (COUPON with POSFS, SPOS on the FS, resync
  with DB31.DBX31.4) at the FS's highest speed or FA[Sn], a differential speed (M3/M4 S on
  the FS, which needs DBX26.4), the JOG keys of the FS in JOG (L21993-22021, L23349-23356: not
  inhibited, the PLC blocks them if unwanted; not on a polygon slave, which holds its relation
  in manual operation too, seed 002 L63-65) and follow-up while the FS has no controller enable.

The LS position is its setpoint for DV and VV and its actual value for AV (and for DV while
the LS has no controller enable, which the control does internally, L23232-23246).  A VV FS
without position control runs on its speed controller: a load shifts its position for good.

Monitoring (every IPO cycle, L22434, L29557-29560): for DV/AV the deviation is the actual
relation ``phi_FS - k x phi_LS`` minus the relation the coupling heads for (programmed offset,
overlays, correction), wrapped to +-180 degrees; within MD37200 = coarse (DBX98.1), within
MD37210 = fine (DBX98.0).  VV compares speeds with MD37220 / MD37230.  DBX99.4 while the
coupling synchronises or the deviation is beyond coarse.  Stage 2 (MD37202 / MD37212, 0 =
off) gives DBX103.4 / 103.5 and the display alarms 22025 / 22026, which stay until the operator
clears them.  CPSYNCOP[FS]= and the other threshold keywords replace these machine data from the
FS's next COUPON on.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field
from enum import Enum

from vc.config import md_dictionary as MD
from vc.config.machine_data import MachineData, MdDef
from vc.config.model import ChannelConfig
from vc.core.alarms import AlarmList
from vc.core.axis.axis import CoupledLoop, MachineAxis, Owner
from vc.core.axis.motion import ramp, stopping_distance, stopping_velocity
from vc.core.interface_map import SignalTable
from vc.core.program.commands import BlockChange, Kind
from vc.core.spindle.spindle import RPM, Spindle, SpindleMode

ALARM_OVERLAY_NOT_ENABLED = 16771  # differential speed without DB31.DBX26.4 (L23450-23456)
ALARM_NO_SPEED_PROGRAMMED = 16111  # M3/M4 on the FS without S (L23485-23488)
ALARM_COUPLING_NOT_DEFINED = 16796  # [control] COUPON / COUPOF of a pair nobody defined
ALARM_COUPLING_ACTIVE = 16797  # [control] the pair is coupled: COUPDEF, gear change, oscillation refused
ALARM_WRITE_PROTECTED = 16787  # [control] COUPDEF of the configured pair with MD21340 = 1 (L21986-21991)
ALARM_TOO_MANY_COUPLINGS = 16792  # [control] a third pair, or a spindle already in another coupling (L21749, L23018)
ALARM_NOT_SYNCHRONISED = 22040  # [control] coupled while a spindle is not synchronised with its zero mark (L22214)
ALARM_FINE_2_EXCEEDED = 22025  # stage-2 monitoring, display only (L29878-29888)
ALARM_COARSE_2_EXCEEDED = 22026

MAX_PAIRS_PER_CHANNEL = 2  # L21749
CORRECTION_DYNAMICS = 0.1  # the correction moves with at most 10 % velocity and acceleration (L31560-31570)
FEED_STOP_ON_FS_ONLY = 1 << 4  # MD30455 bit 4 (L22391-22401)
FS_OWN_CONTROL_PARAMETERS = 1 << 5  # MD30455 bit 5 (L23756-23775): 0 = the FS takes the LS's loop
EDGE_TRIGGERED_CORRECTION = 1 << 7  # MD30455 bit 7 (L31463-31476)
# MD21330 COUPLE_RESET_MODE_1 (L22946-22975) and the channel masks (L22954-22981)
CANCEL_AT_START, CANCEL_AT_RESET, ACTIVATE_AT_START = 1 << 0, 1 << 1, 1 << 9
RESET_BEHAVIOUR, KEEP_PROGRAMMED_AT_RESET = 1 << 0, 1 << 10  # MD20110
CANCEL_PROGRAMMED_AT_START = 1 << 10  # MD20112
_SPEEDS_AGREE = 1e-6  # deg/s
COUP_ACT_SYNCHRONOUS_SPINDLE = 4  # $AA_COUP_ACT bit 2 (L22765-22770)
# the coupling's system variables a program or a synchronized action reads, and what they show
COUPLING_VARIABLES = {"$AA_COUP_ACT": "", "$AA_COUP_OFFS": "couplingOffset", "$VA_COUP_OFFS": "couplingOffsetActual",
                      "$P_COUP_OFFS": "couplingOffsetProgrammed", "$AA_COUP_CORR": "couplingCorrection",
                      "$AA_SYNCDIFF": "", "$VA_SYNCDIFF": "", "$AA_SYNC": "", "$AA_COUP_CORR_DIST": ""}


def wrap180(angle: float) -> float:
    return (angle + 180.0) % 360.0 - 180.0


def _degrees(angle: float) -> float:
    """``angle`` in 0..360, without 360 for a rounding rest below 0."""
    value = angle % 360.0
    return 0.0 if value > 360.0 - 1e-9 else value


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


class Phase(Enum):
    SYNCHRONISING = "synchronising"
    SYNCHRONOUS = "synchronous"


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
    phase: Phase = Phase.SYNCHRONISING
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
        return (self.phase is Phase.SYNCHRONOUS and self.overlay is None and not self.offset_pending
                and not self.queued)


def _loop_of(spindle: Spindle, feedforward: bool) -> CoupledLoop:
    """A spindle's own loop values, with the feedforward (its weight MD32610) on or off."""
    dyn = spindle.axis.dyn
    weight = spindle.md.float(MD.VELO_FFW_WEIGHT, 0) if feedforward else 0.0
    return CoupledLoop(dyn.kv, weight, dyn.drive_time_constant)


def threshold(coupling: Coupling, md: MachineData, datum: MdDef) -> float:
    """A synchronism threshold of the FS: its programmed CPSYNCOP.. value, else the machine datum."""
    programmed = coupling.definition.thresholds.get(datum.number)
    return md.float(datum) if programmed is None else programmed


class CouplingSignals:
    def __init__(self, table: SignalTable):
        self.overlay_enable = table.bit("coupling.out.enableFollowOverlay")
        self.resync = table.bit("coupling.out.syncSpindleResync")
        self.sync_disable = table.bit("coupling.out.syncSpindleSyncDisable")
        self.correction = table.bit("coupling.out.syncCorrection")
        self.delete_correction = table.bit("coupling.out.syncResetCorrection")
        self.sync_mode = table.bit("spindle.in.syncModeActive")
        self.fine = table.bit("coupling.in.syncFineReached")
        self.coarse = table.bit("coupling.in.syncCoarseReached")
        self.overlaid = table.bit("coupling.in.MotionOverlaid")
        self.speed_warning = table.bit("coupling.in.egSpeedThresholdReached")
        self.accel_warning = table.bit("coupling.in.egAccelThresholdReached")
        self.leading_active = table.bit("coupling.in.leadingSpindleActive")
        self.following_active = table.bit("coupling.in.followingSpindleActive")
        self.correction_done = table.bit("coupling.in.CorrectionDone")
        self.accelerating = table.bit("coupling.in.egAccelReached")
        self.process_active = table.bit("coupling.in.ProcessActive")
        self.correction_active = table.bit("coupling.in.CorrectionActive")
        self.fine_2 = table.bit("coupling.in.syncFine2Reached")
        self.coarse_2 = table.bit("coupling.in.syncCoarse2Reached")


@dataclass(slots=True)
class CouplingInputs:
    overlay_enable: bool = False
    resync: bool = False
    sync_disable: bool = False
    correction: bool = False
    delete_correction: bool = False
    edges: set[str] = field(default_factory=set)


class Couplings:
    """The synchronous spindle pairs of all channels (see the module docstring)."""

    def __init__(self, channels: list[ChannelConfig], spindles: dict[str, Spindle], signals: CouplingSignals,
                 areas: dict[str, bytearray], dt: float, alarms: AlarmList):
        self._spindles = spindles
        self._signals = signals
        self._areas = areas  # machine axis -> its DB31.. area
        self._dt = dt
        self._alarms = alarms
        self._channels = {channel.name: channel for channel in channels}
        self.inputs = {name: CouplingInputs() for name in spindles}
        self.definitions: dict[str, PairDefinition] = {}
        self.active: dict[str, Coupling] = {}
        self._written: dict[str, tuple[object, ...]] = {}
        self._idle_written = False  # the outputs were written with no pair coupled
        # CPSYNCOP[FS].. programmed, waiting for the FS's next COUPON / COUPONC (L29849)
        self._programmed_thresholds: dict[str, dict[int, float]] = {}
        for channel in channels:
            configured = self._configured_pair(channel)
            if configured is not None:
                self.definitions[configured.following] = configured

    # ------------------------------------------------------------------ definitions
    def _configured_pair(self, channel: ChannelConfig) -> PairDefinition | None:
        """MD21300 COUPLE_AXIS_1 = [FS, LS] as channel axis numbers (MD20070), 0 = none."""
        numbers = [channel.md.int(MD.COUPLE_AXIS_1, index) for index in (0, 1)]
        if not all(numbers) or max(numbers) > len(channel.axes):
            return None
        following, leading = (channel.axes[number - 1] for number in numbers)
        if following not in self._spindles or leading not in self._spindles:
            return None
        return self._configured_data(channel, following, leading)

    def _configured_data(self, channel: ChannelConfig, following: str, leading: str) -> PairDefinition:
        md = channel.md
        numerator, denominator = md.floats(MD.COUPLE_RATIO_1)
        return PairDefinition(following, leading, numerator, denominator,
                              BlockChange(md.int(MD.COUPLE_BLOCK_CHANGE_CTRL_1)), Kind(md.int(MD.COUPLING_MODE_1)),
                              configured=True, write_protected=md.bool(MD.COUPLE_IS_WRITE_PROT_1))

    def coupled(self, name: str) -> Coupling | None:
        """The coupling ``name`` follows in, if any."""
        return self.active.get(name)

    def involved(self, name: str) -> bool:
        return name in self.active or any(c.definition.leading == name for c in self.active.values())

    def define(self, channel: str, following: str, leading: str, numerator: float | None, denominator: float | None,
               block_change: BlockChange | None, kind: Kind | None) -> int:
        """COUPDEF: only the parameters written change (L22560-22632).  Returns an alarm number or 0."""
        definition = self.definitions.get(following)
        if definition is not None and definition.leading != leading:
            if definition.configured:
                return ALARM_WRITE_PROTECTED  # the configured pair's axes cannot be changed (L21887-21893)
            if following in self.active:
                return ALARM_COUPLING_ACTIVE
            definition = None  # a user pair with another LS: replaced
        if definition is None:
            definition = PairDefinition(following, leading)
        if definition.write_protected:
            return ALARM_WRITE_PROTECTED
        if kind is not None and kind is not definition.kind and following in self.active:
            return ALARM_COUPLING_ACTIVE  # the type changes only while decoupled (L22616)
        if numerator is not None:
            definition.numerator = numerator
            definition.denominator = 1.0 if denominator is None else denominator
        if block_change is not None:
            definition.block_change = block_change
        if kind is not None:
            definition.kind = kind
        self.definitions[following] = definition
        return 0

    def delete(self, following: str, stop: bool = False) -> int:
        """COUPDEL: end an active coupling like COUPOF (``stop``: like COUPOFS) and forget the user
        pair (L22638-22647)."""
        definition = self.definitions.get(following)
        if definition is None:
            return ALARM_COUPLING_NOT_DEFINED
        if following in self.active:
            self.decouple(following, stop=stop)
        if not definition.configured:
            del self.definitions[following]
        self._programmed_thresholds.pop(following, None)
        return 0

    def restore(self, following: str) -> int:
        """COUPRES: the machine data (or the defaults of a user pair) apply again (L22649-22657)."""
        definition = self.definitions.get(following)
        if definition is None:
            return ALARM_COUPLING_NOT_DEFINED
        channel = self._channels[self._spindles[following].channel]
        fresh = (self._configured_data(channel, following, definition.leading) if definition.configured
                 else PairDefinition(following, definition.leading))
        definition.numerator, definition.denominator = fresh.numerator, fresh.denominator
        definition.block_change = fresh.block_change
        definition.thresholds.clear()  # MD37200.. apply again [INF]
        self._programmed_thresholds.pop(following, None)
        if following not in self.active:
            definition.kind = fresh.kind
        return 0

    def program_thresholds(self, following: str, thresholds: dict[int, float]) -> None:
        """CPSYNCOP[FS]=.. and the other threshold keywords: like every CP property programmed in a
        part program they act with the next switching command (L29849, L28387), here the FS's
        next COUPON / COUPONC, also one in the same block or on a pair already coupled."""
        self._programmed_thresholds.setdefault(following, {}).update(thresholds)

    # ------------------------------------------------------------------ activation
    def couple(self, channel: str, following: str, leading: str, offset: float | None, keep_speed: bool,
               cycle: int, block: str) -> int:
        """COUPON / COUPONC (L22707-22727).  Returns an alarm number or 0."""
        definition = self.definitions.get(following)
        if definition is None or definition.leading != leading:
            return ALARM_COUPLING_NOT_DEFINED
        definition.thresholds.update(self._programmed_thresholds.pop(following, {}))  # L29849
        present = self.active.get(following)
        if present is not None:
            if offset is not None:
                self._repeated_offset(following, present, offset)
            return 0
        busy = self.involved(leading) and leading not in [c.definition.leading for c in self.active.values()]
        in_channel = sum(1 for coupling in self.active.values() if coupling.channel == channel)
        if busy or self.involved(following) or in_channel >= MAX_PAIRS_PER_CHANNEL:
            return ALARM_TOO_MANY_COUPLINGS
        fs, ls = self._spindles[following], self._spindles[leading]
        # unlike control parameters MD33000, MD32400-32430 (L23736-23748) are not checked here, as on the
        # control [control]; the loader checks the configured pair (vc/config/loader.py)
        if fs.change is not None or ls.change is not None or fs.mode is SpindleMode.OSCILLATION:
            return ALARM_COUPLING_ACTIVE
        if definition.kind is not Kind.VV and not (fs.axis.referenced and ls.axis.referenced):
            # allowed (a part clamped in both spindles after power-on), but the control warns (L22214-22231)
            self._alarms.raise_alarm(ALARM_NOT_SYNCHRONISED, cycle, channel, block,
                                     following if not fs.axis.referenced else leading, channel=channel,
                                     axis=following)
        coupling = Coupling(definition, channel, block,
                            shifts_seen=(fs.axis.coordinate_shift, ls.axis.coordinate_shift))
        coupling.spcon_following = fs.position_control and fs.mode is not SpindleMode.AXIS
        if offset is not None:
            coupling.programmed = offset % 360.0
            coupling.offset_pending = True
        if keep_speed:
            # COUPONC: the FS's own M3/M4 S stays as differential speed (L22719-22721, L23466-23470)
            coupling.differential = fs.direction * fs.speed
            coupling.differential_velocity = fs.axis.command_velocity  # taken over without a jump
            if coupling.differential and not self.inputs[following].overlay_enable:
                # a differential speed needs the overlay enable as a programmed one does (L23450-23456)
                self._alarms.raise_alarm(ALARM_OVERLAY_NOT_ENABLED, cycle, channel, following,
                                         channel=channel, axis=following)
        self.active[following] = coupling
        fs.enter_synchronous_mode()
        axis = fs.axis
        if axis.owner not in (Owner.NONE, Owner.SPINDLE, Owner.COUPLING):
            axis.brake()
        axis.take(Owner.COUPLING)
        self._switch_position_control(coupling, on=True)
        return 0

    def _repeated_offset(self, following: str, coupling: Coupling, offset: float) -> None:
        """COUPON(FS,LS,POSFS) on a pair already coupled.  While it still synchronises, the new offset
        replaces the pending one; once synchronous, DBX31.5 is evaluated as for the first COUPON
        (L22285-22297): 0 moves to the offset as overlaid motion (COUPON's block change criterion
        decides the wait), 1 keeps the relation and only records the offset, which DBX31.4 or a
        COUPON with 31.5 = 0 restores later (L22361-22380)."""
        if coupling.phase is Phase.SYNCHRONISING:
            # $P_COUP_OFFS counts the SPOS increments queued behind COUPON's offset (see _synchronous)
            coupling.programmed = (offset + sum(distance for distance, _, _ in coupling.queued)) % 360.0
            coupling.offset_pending = True
        elif self.inputs[following].sync_disable:
            coupling.programmed = offset % 360.0
        else:
            self._set_offset(coupling, offset, waits=False)

    def _switch_position_control(self, coupling: Coupling, on: bool) -> None:
        """Automatic position control (L22816-22857): DV switches on FS and LS, AV the FS."""
        definition = coupling.definition
        fs, ls = self._spindles[definition.following], self._spindles[definition.leading]
        if definition.kind is Kind.VV:
            return
        if on:
            fs.set_position_control(True)
            if definition.kind is Kind.DV:
                ls.set_position_control(True)
            return
        if not coupling.spcon_following:
            fs.set_position_control(False)
        other_dv = any(c.definition.leading == ls.name and c.definition.kind is Kind.DV
                       for c in self.active.values())
        if definition.kind is Kind.DV and not other_dv and not ls.spcon and ls.mode is SpindleMode.CONTROL:
            ls.set_position_control(False)

    def decouple(self, following: str, stop: bool) -> int:
        """COUPOF / COUPOFS: the FS keeps its present speed as M3/M4 S (L22234-22260, L23555-23561)
        or, with COUPOFS, brakes to a stop."""
        coupling = self.active.pop(following, None)
        if coupling is None:
            return 0 if following in self.definitions else ALARM_COUPLING_NOT_DEFINED
        fs = self._spindles[following]
        velocity = fs.axis.command_velocity
        fs.axis.set_speed_control(False)
        # both take their own loop again; the next cycle sets it anew for an LS still leading another FS
        fs.axis.coupled_loop = self._spindles[coupling.definition.leading].axis.coupled_loop = None
        self._switch_position_control(coupling, on=False)
        fs.leave_synchronous_mode(0.0 if stop else velocity / RPM)
        self._alarms.clear(ALARM_OVERLAY_NOT_ENABLED, axis=following)
        leading = self._spindles[coupling.definition.leading]
        leading.speed_control.speed_cap = None
        leading.speed_control.acceleration_cap = None
        leading.coupling_hold = False
        if coupling.helix is not None:
            coupling.helix[0].fold_overlay()
        return 0

    def _set_offset(self, coupling: Coupling, offset: float, waits: bool, limit: float | None = None,
                    positioning: bool = False) -> None:
        """Move the relation to ``offset`` (degrees, relative to the LS's 0) the short way."""
        coupling.programmed = offset % 360.0
        self._move_relation(coupling, wrap180(offset - coupling.target), waits, limit, positioning=positioning)

    def _move_relation(self, coupling: Coupling, distance: float, waits: bool, limit: float | None = None,
                       resync: bool = False, positioning: bool = False) -> None:
        # COUPON's offset, the resynchronisation and polygon turning's R move "at the highest possible
        # velocity" (L22015-22021): the FS's largest set speed of its gear stage, which under
        # position control keeps the 10 % control reserve (L22089-22094) and MD35135
        fs = self._spindles[coupling.definition.following]
        speed = limit if limit else fs.speed_control.max_speed(fs.position_control) * RPM
        if coupling.overlay is not None:
            distance += coupling.overlay.left
        coupling.target += distance
        coupling.overlay = Overlay(distance, speed, coupling.overlay.velocity if coupling.overlay else 0.0,
                                   waits, resync, positioning)

    def _delete_positioning(self, coupling: Coupling) -> None:
        """Delete distance to go of the FS's SPOS / SPOSA: the queued ones are dropped (with their
        share of $P_COUP_OFFS), the running overlay brakes as fast as it can and the relation stays
        where it stops; COUPON's offset motion goes on (L23299-23303) [control]."""
        if coupling.queued and coupling.programmed is not None:
            coupling.programmed = (coupling.programmed - sum(distance for distance, _, _ in coupling.queued)) % 360.0
        coupling.queued.clear()
        overlay = coupling.overlay
        if overlay is None or not overlay.positioning:
            return
        accel = self._spindles[coupling.definition.following].speed_control.position_control_acceleration()
        braking = math.copysign(stopping_distance(abs(overlay.velocity), accel, self._dt), overlay.velocity)
        if abs(braking) < abs(overlay.left):
            coupling.target -= overlay.left - braking
            overlay.left = braking

    def position_following(self, following: str, mode: str, value: float, feed: float, wait: bool) -> None:
        """SPOS / SPOSA on a coupled FS: the offset changes as overlaid motion at FA[Sn]
        (L21993-22021); an absolute value names the new offset, IC an increment of it [INF].  Behind
        COUPON's offset motion (or a resynchronisation) the SPOS waits in ``queued`` and runs as a
        motion of its own, so DBX2.2 deletes only the SPOS [control]."""
        coupling = self.active[following]
        fs = self._spindles[following]
        # FA[Sn] (DBX17.0 scales it: _overlay_step), else MD35300
        limit = feed * RPM / 360.0 if feed > 0.0 else fs.speed_control.positioning_speed() * RPM
        if coupling.phase is Phase.SYNCHRONISING:
            # no relation yet: the motion follows COUPON's pending offset once setpoint synchronism
            # is reached; an absolute position replaces that offset [control]
            if mode == "IC":
                coupling.queued.append((value, limit, wait))
                if coupling.programmed is not None:
                    coupling.programmed = (coupling.programmed + value) % 360.0
            else:
                coupling.queued.clear()
                coupling.programmed = value % 360.0
                coupling.offset_pending = True
            return
        if coupling.queued or (coupling.overlay is not None and not coupling.overlay.positioning):
            start = coupling.target + sum(distance for distance, _, _ in coupling.queued)
            distance = value if mode == "IC" else wrap180(value - start)
            coupling.queued.append((distance, limit, wait))
            coupling.programmed = (start + distance) % 360.0
            return
        if mode == "IC":
            coupling.programmed = (coupling.target + value) % 360.0
            self._move_relation(coupling, value, wait, limit, positioning=True)
        else:
            self._set_offset(coupling, value, wait, limit, positioning=True)

    def program_differential(self, following: str, direction: int | None, speed: float | None, cycle: int,
                             block: str) -> int:
        """M3/M4/M5 S on a coupled FS: a differential speed on top of the coupling (L23402-23597)."""
        coupling = self.active[following]
        fs = self._spindles[following]
        if direction in (3, 4) and speed is None:
            return ALARM_NO_SPEED_PROGRAMMED
        if speed is not None:
            fs.show_speed(speed)
        if direction == 5:
            coupling.differential = 0.0
        elif direction is not None and speed is not None:
            coupling.differential = (1.0 if direction == 3 else -1.0) * abs(speed)
        elif speed is not None:
            coupling.differential = math.copysign(abs(speed), coupling.differential or 1.0)
        if coupling.differential and not self.inputs[following].overlay_enable:
            self._alarms.raise_alarm(ALARM_OVERLAY_NOT_ENABLED, cycle, coupling.channel, following,
                                     channel=coupling.channel, axis=following)
        return 0

    def jog(self, following: str, direction: int, stopped: bool) -> None:
        """The JOG keys of a coupled FS in JOG, one IPO cycle: the relation moves at the FS's JOG
        velocity (MD32020 with its override) as overlaid motion, DBX98.4 while it moves
        (L21993-22021, L23349-23356) [control: the velocity of a spindle's JOG]; ``stopped`` (feed
        stop, feed disable) brakes it as an axis's JOG.  Ignored until setpoint synchronism and on a
        polygon slave (seed 002 L63-65: the relation holds in manual operation too)."""
        coupling = self.active.get(following)
        if coupling is None or coupling.phase is not Phase.SYNCHRONOUS:
            return
        fs = self._spindles[following]
        axis = fs.axis
        accel = fs.speed_control.position_control_acceleration()
        if coupling.drf_rest and not direction:
            self._drf_step(coupling, axis, accel, stopped)
            return
        wanted = 0.0 if stopped or not coupling.jog_allowed else \
            direction * axis.dyn.jog_velocity * fs.speed_control.override()
        if wanted or coupling.jog_velocity:
            coupling.jog_velocity = ramp(coupling.jog_velocity, wanted, accel, self._dt)
            axis.resting = False

    def drf(self, following: str, distance: float) -> None:
        """DRF pulses for a coupled FS in AUTO / MDA: the relation moves by ``distance`` as overlaid
        motion (L22011-22015) the way the JOG keys move it - synchronism kept, DBX98.4 while it moves -
        at the FS's DRF handwheel velocity (JOG velocity x MD32090), and the FS's DRF offset counts
        it.  Refused where the JOG keys are: before setpoint synchronism, on a polygon slave (seed 002
        L63-65)."""
        coupling = self.active.get(following)
        if coupling is not None and coupling.phase is Phase.SYNCHRONOUS and coupling.jog_allowed:
            coupling.drf_rest += distance

    def _drf_step(self, coupling: Coupling, axis: MachineAxis, accel: float, stopped: bool) -> None:
        """One cycle of the DRF travel on the relation, braking to land on its end point; feed stop
        and feed disable brake it and drop the rest beyond the braking distance [control, as the
        handwheel in JOG]."""
        rest = coupling.drf_rest
        if stopped:
            rest = math.copysign(stopping_distance(abs(coupling.jog_velocity), accel, self._dt), rest)
        target = math.copysign(min(axis.dyn.drf_velocity, stopping_velocity(abs(rest), accel, self._dt)), rest) \
            if rest else 0.0
        velocity = ramp(coupling.jog_velocity, target, accel, self._dt)
        if rest and (rest - velocity * self._dt) * rest <= 1e-9 * abs(rest):
            velocity = rest / self._dt  # the last step lands exactly on the end point
        coupling.jog_velocity = velocity
        coupling.drf_rest = rest - velocity * self._dt if rest else 0.0
        if abs(coupling.drf_rest) <= 1e-12:
            coupling.drf_rest = 0.0
        axis.drf_offset += velocity * self._dt
        axis.resting = False

    def holds_block(self, following: str, criterion: BlockChange | None = None) -> bool:
        """The block change after COUPON (or WAITC) waits for the criterion (L22583-22592, L22659-22690)."""
        coupling = self.active.get(following)
        if coupling is None:
            return False
        wanted = coupling.definition.block_change if criterion is None else criterion
        if criterion is None and self.overlay_holds_block(following):
            return True
        if wanted is BlockChange.NOC:
            return False
        if not coupling.setpoint_synchronous:
            return True
        if wanted is BlockChange.FINE:
            return not coupling.fine
        if wanted is BlockChange.COARSE:
            return not coupling.coarse
        return False

    def waitc_criterion(self, following: str) -> BlockChange:
        """WAITC without a condition waits for the pair's programmed or configured criterion, at least
        for setpoint synchronism (L22679-22680)."""
        definition = self.definitions.get(following)
        wanted = definition.block_change if definition is not None else BlockChange.IPOSTOP
        return BlockChange.IPOSTOP if wanted is BlockChange.NOC else wanted

    def overlay_holds_block(self, following: str) -> bool:
        coupling = self.active.get(following)
        return coupling is not None and ((coupling.overlay is not None and coupling.overlay.waits)
                                         or any(waits for _, _, waits in coupling.queued))

    # ------------------------------------------------------------------ channel events
    def nc_start(self, channel: str, kept_by_polygon: str | None = None) -> None:
        """Program start: configured pair per MD21330, programmed pairs per MD20112 bit 10 (L22946-22956);
        the slave of polygon turning (``kept_by_polygon``) stays coupled (seed 002 L134-138)."""
        config = self._channels[channel]
        for following, definition in list(self.definitions.items()):
            if self._spindles[following].channel != channel:
                continue
            if definition.configured:
                mode = config.md.int(MD.COUPLE_RESET_MODE_1)
                if mode & CANCEL_AT_START and following in self.active:
                    self.decouple(following, stop=False)
                if mode & (1 << 5):
                    self.restore(following)
                if mode & ACTIVATE_AT_START and following not in self.active:
                    self.couple(channel, following, definition.leading, None, False, 0, "")
            elif config.md.int(MD.START_MODE_MASK) & CANCEL_PROGRAMMED_AT_START and following in self.active \
                    and following != kept_by_polygon:
                self.decouple(following, stop=False)

    def reset(self, channel: str, kept_by_polygon: str | None = None) -> None:
        """Reset / program end: configured pair per MD21330 bits 1/6 with MD20110 bit 0, programmed
        pairs kept only with MD20110 bits 0 and 10 (L22968-22981); the slave of polygon turning
        (``kept_by_polygon``) stays coupled as its HBR decides (seed 002 L198-202).  A kept coupling
        loses the SPOS motions of its FS, running and queued, as reset ends every motion of a
        spindle [control]."""
        config = self._channels[channel]
        for following in [name for name in self._programmed_thresholds if self._spindles[name].channel == channel]:
            del self._programmed_thresholds[following]  # programmed, but no COUPON switched them in [control]
        reset_mode = config.md.int(MD.RESET_MODE_MASK)
        if not reset_mode & RESET_BEHAVIOUR:
            for following, kept in self.active.items():
                if self._spindles[following].channel == channel:
                    self._delete_positioning(kept)  # reset ends SPOS on the FS, not the coupling
            return
        for following, definition in list(self.definitions.items()):
            if self._spindles[following].channel != channel:
                continue
            if definition.configured:
                mode = config.md.int(MD.COUPLE_RESET_MODE_1)
                cancel = bool(mode & CANCEL_AT_RESET)
                if mode & (1 << 6):
                    self.restore(following)
            else:
                cancel = not reset_mode & KEEP_PROGRAMMED_AT_RESET and following != kept_by_polygon
            coupling = self.active.get(following)
            if cancel and coupling is not None:
                self.decouple(following, stop=False)
            elif coupling is not None:
                coupling.differential = 0.0  # reset ends the FS's own motion, not the coupling
                self._delete_positioning(coupling)

    # ------------------------------------------------------------------ PLC inputs
    def reset_movement(self, name: str) -> None:
        """DB31.DBX2.2 delete distance to go / spindle reset on its rising edge (the spindle itself
        brakes, vc/core/spindle/spindle.py).  On an FS: the differential speed and its direction are
        deleted (L23529-23532) and a SPOS offset motion ends; on an LS: the overlaid motions of
        its FSs end as fast as possible, those of COUPON / COUPONC excepted, and the coupling stays
        (L23299-23303)."""
        coupling = self.active.get(name)
        if coupling is not None:
            coupling.differential = 0.0
            self._delete_positioning(coupling)
        for each in self.active.values():
            if each.definition.leading == name:
                self._delete_positioning(each)

    def decode_inputs(self, name: str) -> None:
        area, sig = self._areas[name], self._signals
        inputs = self.inputs[name]
        now = {
            "overlay_enable": sig.overlay_enable.get(area), "resync": sig.resync.get(area),
            "sync_disable": sig.sync_disable.get(area), "correction": sig.correction.get(area),
            "delete_correction": sig.delete_correction.get(area),
        }
        for key, value in now.items():
            if value and not getattr(inputs, key):
                inputs.edges.add(key)
            setattr(inputs, key, value)
        if inputs.overlay_enable:
            self._alarms.clear(ALARM_OVERLAY_NOT_ENABLED, axis=name)

    # ------------------------------------------------------------------ the cycle
    def cycle(self, cycle: int) -> None:
        """Drive every coupled FS after the spindles ran (the LS has its setpoint of this cycle)."""
        for following, coupling in self.active.items():
            self._plc_requests(following, coupling)
            self._drive(following, coupling)
        loops = self._coupled_loops()
        for name, spindle in self._spindles.items():
            spindle.axis.coupled_loop = loops.get(name)

    def feedforward_withdrawn(self, name: str) -> bool:
        """MD32620 FFW_MODE = 0 on FS or LS of the pair ``name`` is coupled in: the pair runs without
        feedforward, and SPCON in motion, SPOS, M19 and SPOSA have no effect on it (L22999-23006)."""
        return any(name in (following, coupling.definition.leading) and not self._feedforward(coupling)
                   for following, coupling in self.active.items())

    def _feedforward(self, coupling: Coupling) -> bool:
        """The coupling always runs LS and FS with feedforward, unless MD32620 = 0 on either takes it
        away (L22997-23003) [INF: the feedforward of the pair, so both lose it]."""
        return all(self._spindles[name].md.int(MD.FFW_MODE)
                   for name in (coupling.definition.following, coupling.definition.leading))

    def _coupled_loops(self) -> dict[str, CoupledLoop]:
        """The position loop of every coupled spindle (L22997-23006, L23756-23775): the LS keeps its
        Kv (active parameter set) and MD32810 with the pair's feedforward; the FS takes the LS's
        values with MD30455 bit 5 = 0 (automatic dynamic matching), its own with bit 5 = 1."""
        loops: dict[str, CoupledLoop] = {}
        for following, coupling in self.active.items():
            fs, ls = self._spindles[following], self._spindles[coupling.definition.leading]
            feedforward = self._feedforward(coupling)
            leading_loop = _loop_of(ls, feedforward)
            loops[ls.name] = leading_loop
            own = fs.md.int(MD.MISC_FUNCTION_MASK) & FS_OWN_CONTROL_PARAMETERS
            loops[following] = _loop_of(fs, feedforward) if own else leading_loop
        return loops

    def _plc_requests(self, following: str, coupling: Coupling) -> None:
        inputs = self.inputs[following]
        edges, inputs.edges = inputs.edges, set()
        fs = self._spindles[following]
        if "resync" in edges and coupling.programmed is not None and coupling.phase is Phase.SYNCHRONOUS:
            # DBX31.4: restore the programmed offset (L23098-23145); the relation restarts from where
            # the FS stands now
            coupling.target = coupling.relation
            self._move_relation(coupling, wrap180(coupling.programmed - (coupling.relation % 360.0)),
                                waits=False, resync=True)
        allowed = not fs.axis.inputs.disable and coupling.definition.kind is not Kind.VV \
            and abs(abs(coupling.ratio) - 1.0) < 1e-12 and coupling.setpoint_synchronous
        measure = inputs.correction and ("correction" in edges or not fs.md.int(MD.MISC_FUNCTION_MASK)
                                         & EDGE_TRIGGERED_CORRECTION)
        if measure and allowed:
            # DBX31.6: take the measured deviation as correction (L31317-31700)
            coupling.correction = wrap180(self._actual_relation(coupling) - coupling.relation)
            coupling.correction_done = False
        if "delete_correction" in edges:
            coupling.correction = 0.0
            coupling.correction_done = False
        settled = coupling.correction_applied == coupling.correction
        if not inputs.correction and not inputs.delete_correction and settled:
            coupling.correction_done = False  # the PLC took note: 99.2 goes with 31.6 / 31.7

    def _leading(self, coupling: Coupling) -> tuple[float, float]:
        """Position and velocity of the LS the FS follows (setpoint, or actual value for AV)."""
        ls = self._spindles[coupling.definition.leading].axis
        if not ls.drive_ready and abs(ls.velocity) <= ls.dyn.standstill_velocity:
            # an LS without enable that stands: the settling residue of its drive is no motion
            # the FS should command (else removing both enables together reads as 21612 on the FS)
            return ls.actual, 0.0
        if coupling.definition.kind is Kind.AV or not ls.drive_ready:
            return ls.actual, ls.velocity
        return ls.setpoint, ls.command_velocity

    def _actual_relation(self, coupling: Coupling) -> float:
        fs = self._spindles[coupling.definition.following].axis
        ls = self._spindles[coupling.definition.leading].axis
        return fs.actual - coupling.ratio * ls.actual

    def _drive(self, following: str, coupling: Coupling) -> None:
        fs = self._spindles[following]
        ls = self._spindles[coupling.definition.leading]
        axis, dt, k = fs.axis, self._dt, coupling.ratio
        # the LS slows so the FS keeps its limits
        ls.speed_control.speed_cap = fs.speed_control.max_speed(fs.position_control) / abs(k) if k else None
        # an LS with a kinked acceleration characteristic accelerates no faster than the FS can follow
        # with its own constant acceleration (L23797-23805; the seed says so in that context, so an LS
        # without MD35230 keeps its ramps [INF])
        kinked = ls.md.float(MD.ACCEL_REDUCTION_FACTOR) > 0.0
        accel = fs.speed_control.position_control_acceleration()
        ls.speed_control.acceleration_cap = accel / abs(k) if k and kinked else None
        self._follow_coordinate_shifts(coupling, axis, ls.axis)
        position, velocity = self._leading(coupling)
        # VV: only the speed is coupled; an FS without position control runs on its speed controller,
        # so what a load takes from its position stays lost (L21965-21968)
        axis.set_speed_control(coupling.definition.kind is Kind.VV and not fs.position_control)
        # the LS's disable acts on the FS as well; the FS's own is ignored while coupled (L23212-23230)
        axis.disable_by_coupling = ls.axis.inputs.disable
        # the FS's spindle stop brakes the coupled group unless MD30455 bit 4 limits it to the FS's own
        # motion (L22391-22401)
        fs_stop = axis.inputs.feed_stop
        ls.coupling_hold = fs_stop and not fs.md.int(MD.MISC_FUNCTION_MASK) & FEED_STOP_ON_FS_ONLY
        wanted_differential = self._differential_setpoint(fs, coupling)
        if fs_stop or not self.inputs[following].overlay_enable:
            wanted_differential = 0.0  # the spindle stop brakes the FS's own speed too, back after it (L23304-23314)
        coupling.differential_velocity = ramp(coupling.differential_velocity, wanted_differential, accel, dt)
        fs.sync_speed_reached = self.inputs[following].overlay_enable and wanted_differential != 0.0 and \
            coupling.differential_velocity == wanted_differential
        if axis.owner is not Owner.COUPLING:
            # braked by an alarm or the e-stop: the relation follows the FS until the brake is done
            coupling.relation = axis.setpoint - k * position
            if axis.owner is Owner.NONE:
                axis.take(Owner.COUPLING)
            return
        if not axis.servo_on and (axis.follow_up or not axis.drive_ready):
            if coupling.phase is Phase.SYNCHRONISING:
                axis.command_velocity = 0.0
                if velocity != 0.0:
                    return  # the FS stands until both spindles have their enables (L23240-23243)
                # selected without enables at standstill: the setpoint relation holds from now on,
                # 98.0 / 98.1 follow the actual positions (L23240-23243) [control]
                self._synchronous(following, coupling, k * position)
            if axis.follow_up:
                coupling.relation = axis.actual - k * position  # follow-up: the relation is lost (L23080)
            axis.setpoint = k * position + coupling.relation + coupling.correction_applied
            axis.command_velocity = 0.0
            return
        if coupling.phase is Phase.SYNCHRONISING:
            coupled_velocity = k * velocity + coupling.differential_velocity
            # the FS's own kinked characteristic counts only while it synchronises (L23806-23809)
            new_velocity = ramp(axis.command_velocity, coupled_velocity,
                                accel * fs.speed_control.acceleration_reduction(axis.command_velocity), dt)
            axis.command_velocity = new_velocity
            axis.setpoint += new_velocity * dt
            if abs(new_velocity - coupled_velocity) <= _SPEEDS_AGREE:
                self._synchronous(following, coupling, k * position)
            return
        overlay_velocity = 0.0 if fs_stop else self._overlay_step(coupling, accel)
        own_velocity = coupling.differential_velocity + coupling.jog_velocity  # the relation moves on with them
        coupling.relation += (overlay_velocity + own_velocity) * dt
        coupling.target += own_velocity * dt
        correction_velocity = self._correction_step(coupling, accel)
        axis.setpoint = k * position + coupling.relation + coupling.correction_applied
        axis.command_velocity = k * velocity + overlay_velocity + own_velocity + correction_velocity
        if coupling.helix is not None:
            helix_axis, lead = coupling.helix
            helix_axis.add_overlay(lead * velocity * dt / 360.0, lead * velocity / 360.0)

    @staticmethod
    def _differential_setpoint(fs: Spindle, coupling: Coupling) -> float:
        """The FS's own speed component (deg/s): DBX17.6 inverts it, the FS's override DBB19 scales
        it, DBX16.7 deletes it while set; the coupled component sees none of them (L23529-23552).
        NC stop axes and spindles (DB21.DBX7.4) brakes it with the rest of the pair until NC start
        (L23358-23362), and so does an alarm's interpolation stop, which brakes the LS [control]."""
        if fs.inputs.delete_s or fs.held or fs.stopped_by_alarm or not coupling.differential:
            return 0.0
        direction = -1.0 if fs.inputs.invert_m3_m4 else 1.0
        return direction * coupling.differential * fs.speed_control.override() * RPM

    @staticmethod
    def _follow_coordinate_shifts(coupling: Coupling, fs: MachineAxis, ls: MachineAxis) -> None:
        """A spindle that synchronises with its zero mark while coupled moves its coordinates, not
        itself: the relation moves with them, so the pair keeps its physical relation [control]."""
        seen_fs, seen_ls = coupling.shifts_seen
        if fs.coordinate_shift == seen_fs and ls.coordinate_shift == seen_ls:
            return
        moved = (fs.coordinate_shift - seen_fs) - coupling.ratio * (ls.coordinate_shift - seen_ls)
        coupling.relation += moved
        coupling.target += moved
        coupling.shifts_seen = (fs.coordinate_shift, ls.coordinate_shift)

    def _synchronous(self, following: str, coupling: Coupling, leading_part: float) -> None:
        """Setpoint synchronism: the relation is fixed; a programmed offset follows as overlay
        unless DBX31.5 forbids it (L22277-22319)."""
        fs = self._spindles[following].axis
        coupling.phase = Phase.SYNCHRONOUS
        coupling.relation = coupling.target = fs.setpoint - leading_part
        if coupling.pending_shift:
            self._move_relation(coupling, coupling.pending_shift, waits=False)
            coupling.pending_shift = 0.0
        if coupling.offset_pending:
            coupling.offset_pending = False
            assert coupling.programmed is not None
            # $P_COUP_OFFS already counts the increments queued meanwhile: COUPON's own offset first
            coupon_offset = coupling.programmed - sum(distance for distance, _, _ in coupling.queued)
            if not self.inputs[following].sync_disable:
                self._set_offset(coupling, coupon_offset, waits=False)  # the block change criterion waits
        if coupling.overlay is None:
            self._start_queued(coupling)

    def _start_queued(self, coupling: Coupling) -> None:
        """The next SPOS increment programmed before setpoint synchronism."""
        if coupling.queued:
            distance, limit, waits = coupling.queued.pop(0)
            coupling.programmed = (coupling.target + distance) % 360.0
            self._move_relation(coupling, distance, waits, limit, positioning=True)

    def _overlay_step(self, coupling: Coupling, accel: float) -> float:
        overlay = coupling.overlay
        if overlay is None:
            return 0.0
        if overlay.left == 0.0:
            # done: setpoint synchronism again, which also ends DBX99.4 of a resynchronisation
            # even while DBX31.4 is still set (L23134-23145)
            coupling.overlay = None
            self._start_queued(coupling)
            return 0.0
        direction = 1.0 if overlay.left > 0 else -1.0
        fs = self._spindles[coupling.definition.following]
        # DBX17.0: the feed override scales FA[Sn] of an SPOS on the FS in every cycle of the motion
        # (L22017-22021), so a change of the override or of 17.0 acts on the running motion
        override = fs.speed_control.override() if overlay.positioning and fs.inputs.use_feed_override else 1.0
        speed = min(ramp(abs(overlay.velocity), overlay.limit * override, accel, self._dt),
                    stopping_velocity(abs(overlay.left), accel, self._dt))
        step = min(speed * self._dt, abs(overlay.left))
        overlay.left -= direction * step
        if abs(overlay.left) <= 1e-9:
            overlay.left = 0.0
        overlay.velocity = direction * speed
        return direction * step / self._dt

    def _correction_step(self, coupling: Coupling, accel: float) -> float:
        """The correction moves with 10 % of the dynamics (L31560-31570)."""
        remaining = coupling.correction - coupling.correction_applied
        if remaining == 0.0:
            coupling.correction_velocity = 0.0
            inputs = self.inputs[coupling.definition.following]
            coupling.correction_done = inputs.correction or inputs.delete_correction
            return 0.0
        fs = self._spindles[coupling.definition.following].axis
        limit = fs.dyn.max_velocity * CORRECTION_DYNAMICS
        correction_accel = accel * CORRECTION_DYNAMICS
        direction = 1.0 if remaining > 0 else -1.0
        speed = min(ramp(abs(coupling.correction_velocity), limit, correction_accel, self._dt),
                    stopping_velocity(abs(remaining), correction_accel, self._dt))
        step = min(speed * self._dt, abs(remaining))
        coupling.correction_applied += direction * step
        if abs(coupling.correction - coupling.correction_applied) <= 1e-9:
            coupling.correction_applied = coupling.correction
        coupling.correction_velocity = direction * speed
        return direction * step / self._dt

    def quantity(self, following: str, name: str) -> float:
        """The system variables of a coupled FS (``COUPLING_QUANTITY_MEANINGS`` in vc/observables.py)."""
        coupling = self.active.get(following)
        if coupling is None:
            return 0.0
        if name == "couplingOffset":
            return _degrees(coupling.relation)
        if name == "couplingOffsetActual":
            return _degrees(self._actual_relation(coupling))
        if name == "couplingOffsetProgrammed":
            return coupling.programmed or 0.0
        if name == "couplingCorrection":
            return coupling.correction
        if name == "couplingRelationError":
            return self.relation_error(coupling)
        return coupling.deviation

    def relation_error(self, coupling: Coupling) -> float:
        """How far the actual angle relation of FS and LS is from the one commanded in this cycle
        (``phi_FS - k x phi_LS - relation - correction``, degrees, wrapped): the following errors
        of both spindles and whatever disturbs the FS.  Unlike the deviation the monitoring judges
        it does not count an overlaid motion still to go; before setpoint synchronism the
        relation is not defined and it reads 0."""
        if coupling.phase is not Phase.SYNCHRONOUS:
            return 0.0
        return wrap180(self._actual_relation(coupling) - coupling.relation - coupling.correction_applied)

    def variable_reader(self, spindles: dict[str, str]) -> Callable[[str, str], float]:
        """A channel's reader of the coupling's system variables; ``spindles`` maps the index as
        written (S<n> or the machine axis name) to the machine axis.  KeyError: not one of them."""
        def read(name: str, index: str) -> float:
            if name not in COUPLING_VARIABLES or index not in spindles:
                raise KeyError(name)
            return self.read_variable(name, spindles[index])
        return read

    def read_variable(self, name: str, spindle: str) -> float:
        """$AA_COUP_ACT (L22755-22770: bit 2 = 4 while ``spindle`` follows in a synchronous spindle
        coupling), $AA_COUP_OFFS / $VA_COUP_OFFS / $P_COUP_OFFS (L22383-22389, L22773-22790),
        $AA_COUP_CORR (L31506-31524) and the signed deviations $AA_SYNCDIFF (setpoint side) /
        $VA_SYNCDIFF (actual side), negative while the FS lags (L29578-29586), $AA_SYNC (0 not
        synchronous, 1 coarse, 2 fine: L29620-29632) and $AA_COUP_CORR_DIST (what the correction
        still has to travel, L31626).  0 while not coupled."""
        coupling = self.active.get(spindle)
        if coupling is None:
            return 0.0
        if name == "$AA_COUP_ACT":
            return float(COUP_ACT_SYNCHRONOUS_SPINDLE)
        if name == "$AA_SYNCDIFF":
            return self._setpoint_deviation(coupling)
        if name == "$VA_SYNCDIFF":
            return coupling.signed_deviation
        if name == "$AA_SYNC":
            return 2.0 if coupling.fine else 1.0 if coupling.coarse else 0.0
        if name == "$AA_COUP_CORR_DIST":
            return coupling.correction - coupling.correction_applied
        return self.quantity(spindle, COUPLING_VARIABLES[name])

    def _setpoint_deviation(self, coupling: Coupling) -> float:
        """The FS setpoint against the coupling law with the offset and correction it heads for.
        Before setpoint synchronism it is measured against COUPON's offset, 0 without one [control]."""
        fs = self._spindles[coupling.definition.following].axis
        position, _ = self._leading(coupling)
        if coupling.phase is Phase.SYNCHRONOUS:
            goal = coupling.target + coupling.correction
        elif coupling.offset_pending and coupling.programmed is not None:
            goal = coupling.programmed
        else:
            return 0.0
        return wrap180(fs.setpoint - coupling.ratio * position - goal)

    def write_correction(self, spindle: str, value: float) -> None:
        """``$AA_COUP_CORR[Sn]=value`` from a program or a synchronized action: the correction is
        given directly (L31543-31551); 0 deletes it on the correction's ramp (L23619-23620).  Without
        a coupling of ``spindle`` there is no correction to set [control]."""
        coupling = self.active.get(spindle)
        if coupling is not None:
            coupling.correction = wrap180(value)
            coupling.correction_done = False

    def clamp(self, following: str, twist: float) -> bool:
        """A part clamped in FS and LS: the FS is held at the LS's angle plus its present relation
        and ``twist`` degrees (a plant fault; False: the spindle follows nobody)."""
        coupling = self.active.get(following)
        if coupling is None:
            return False
        fs = self._spindles[following].axis
        ls = self._spindles[coupling.definition.leading].axis
        fs.clamp = (ls, coupling.ratio, fs.physical - coupling.ratio * ls.physical + twist)
        fs.resting = False
        return True

    # ------------------------------------------------------------------ monitoring and signals
    def monitor(self, cycle: int) -> None:
        """Synchronism, warning thresholds and the DB31 coupling signals (after the axes moved)."""
        if not self.active and self._idle_written:
            return  # no pair coupled and the outputs already say so
        for following, coupling in self.active.items():
            self._monitor_pair(following, coupling, cycle)
            self._check_zero_mark_synchronism(following, coupling, cycle)
        self._write_outputs()
        self._idle_written = not self.active

    def _monitor_pair(self, following: str, coupling: Coupling, cycle: int) -> None:
        fs = self._spindles[following]
        md, axis = fs.md, fs.axis
        if coupling.definition.kind is Kind.VV:
            ls = self._spindles[coupling.definition.leading].axis
            signed = (axis.velocity - coupling.ratio * ls.velocity - coupling.differential_velocity) / RPM
            coarse_tolerance = threshold(coupling, md, MD.COUPLE_VELO_TOL_COARSE)
            fine_tolerance = threshold(coupling, md, MD.COUPLE_VELO_TOL_FINE)
        else:
            # a resynchronisation is judged against the relation commanded now, which still has
            # ``left`` to go to the target
            heading = coupling.target - (coupling.overlay.left if coupling.overlay and coupling.overlay.resync else 0.0)
            # the FS's own motion (differential speed) lags like any setpoint behind its position
            # controller; the coupled part lags as the LS does and cancels.  The lag comes from the
            # FS's loop, not from its present following error: with k x n_LS + n_diff = 0 the FS
            # stands without any following error while the LS lags by its own
            lag = (coupling.differential_velocity + coupling.jog_velocity) * axis.lag_per_velocity
            signed = wrap180(self._actual_relation(coupling) - heading - coupling.correction + lag)
            coarse_tolerance = threshold(coupling, md, MD.COUPLE_POS_TOL_COARSE)
            fine_tolerance = threshold(coupling, md, MD.COUPLE_POS_TOL_FINE)
        coupling.signed_deviation, coupling.deviation = signed, abs(signed)
        deviation = coupling.deviation
        synchronous = coupling.setpoint_synchronous
        coupling.coarse = synchronous and deviation <= coarse_tolerance
        coupling.fine = synchronous and deviation <= fine_tolerance
        coupling.stage_2_paused = self._stage_2_paused(following, coupling)
        self._start_or_end_stage_2(following, coupling, axis)
        for number, tolerance in ((ALARM_FINE_2_EXCEEDED, threshold(coupling, md, MD.COUPLE_POS_TOL_FINE_2)),
                                  (ALARM_COARSE_2_EXCEEDED, threshold(coupling, md, MD.COUPLE_POS_TOL_COARSE_2))):
            if not (self._stage_2_monitors(coupling, number, tolerance) and deviation > tolerance):
                coupling.stage_2_exceeded.discard(number)
            elif number not in coupling.stage_2_exceeded:
                # raised as the deviation leaves the tolerance (or an exclusion ends with it outside);
                # a display alarm the operator clears (L29878-29879), it stays when the deviation returns
                coupling.stage_2_exceeded.add(number)
                self._alarms.raise_alarm(number, cycle, coupling.channel, coupling.block, following,
                                         channel=coupling.channel, axis=following)
        coupling.acceleration = (axis.command_velocity - coupling.last_velocity) / self._dt
        coupling.last_velocity = axis.command_velocity

    def _check_zero_mark_synchronism(self, following: str, coupling: Coupling, cycle: int) -> None:
        """The cyclic check of FS and LS while their position control is active (L30398-30400): a
        spindle of the pair without zero-mark synchronism (DB31.DBX60.4 / 60.5) keeps raising 22040,
        so cancelling the alarm does not hide it while the cause lasts.  CPMALARM bit 10, which
        suppresses it, is not a program word of the core."""
        for name in (following, coupling.definition.leading):
            spindle = self._spindles[name]
            if spindle.position_control and not spindle.axis.referenced:
                self._alarms.raise_alarm(ALARM_NOT_SYNCHRONISED, cycle, coupling.channel, coupling.block, name,
                                         channel=coupling.channel, axis=following)
                return

    def _start_or_end_stage_2(self, following: str, coupling: Coupling, fs: MachineAxis) -> None:
        """Stage 2 ends with a new synchronisation (DBX31.4, a resynchronisation running) and when
        the setpoint synchronism goes for a missing FS enable (e-stop, alarm reaction); it starts
        again, per tolerance, once stage 1 reports fine (98.0) or coarse (98.1) synchronism in
        setpoint synchronism (L29855-29866, L29895-29909) [INF: fine starts fine 2, coarse coarse 2]."""
        resynchronising = self.inputs[following].resync or (coupling.overlay is not None and coupling.overlay.resync)
        if not coupling.setpoint_synchronous or not fs.servo_on or resynchronising:
            coupling.stage_2_running.clear()
            return
        if coupling.fine:
            coupling.stage_2_running.add(ALARM_FINE_2_EXCEEDED)
        if coupling.coarse:
            coupling.stage_2_running.add(ALARM_COARSE_2_EXCEEDED)

    @staticmethod
    def _stage_2_monitors(coupling: Coupling, number: int, tolerance: float) -> bool:
        """The stage-2 monitoring of ``number`` (22025 fine, 22026 coarse) runs: configured, started
        and not paused by an exclusion."""
        return tolerance > 0.0 and number in coupling.stage_2_running and not coupling.stage_2_paused

    def _stage_2_paused(self, following: str, coupling: Coupling) -> bool:
        """The stage-2 monitoring is not done (L29916-29932) with a velocity coupling, while the FS's
        DBX31.5 suppresses synchronisation or its DBX31.6 tracks the deviation, and while FS or LS
        stops on the rapid-stop ramp or reports DB31.DBX63.3 "disabled"."""
        inputs = self.inputs[following]
        axes = (self._spindles[following].axis, self._spindles[coupling.definition.leading].axis)
        return (coupling.definition.kind is Kind.VV or inputs.sync_disable or inputs.correction
                or any(axis.rapid_stopping or axis.disabled for axis in axes))

    def _write_outputs(self) -> None:
        leaders = {c.definition.leading for c in self.active.values()}
        for name in self._spindles:
            coupling = self.active.get(name)
            status: tuple[object, ...]
            if coupling is None:
                status = (name in leaders,)
            else:
                md, axis = self._spindles[name].md, self._spindles[name].axis
                warning = md.float(MD.EG_VEL_WARNING) / 100.0
                accel_threshold = md.float(MD.EG_ACC_TOL) / 100.0 * axis.dyn.max_accel
                overlay = coupling.overlay
                overlaid = (overlay is not None and overlay.left != 0.0) or coupling.differential_velocity != 0.0 \
                    or coupling.jog_velocity != 0.0
                status = (
                    name in leaders, coupling.fine, coupling.coarse, overlaid,
                    abs(axis.command_velocity) > warning * axis.dyn.max_velocity,
                    abs(coupling.acceleration) > warning * axis.dyn.max_accel,
                    coupling.correction_done, abs(coupling.acceleration) > accel_threshold,
                    not coupling.coarse or (overlay is not None and overlay.resync),
                    coupling.correction_applied != 0.0,
                    self._within(coupling, ALARM_FINE_2_EXCEEDED, threshold(coupling, md, MD.COUPLE_POS_TOL_FINE_2)),
                    self._within(coupling, ALARM_COARSE_2_EXCEEDED,
                                 threshold(coupling, md, MD.COUPLE_POS_TOL_COARSE_2)),
                )
            if self._written.get(name) == status:
                continue
            self._written[name] = status
            self._put(name, status, coupling is not None)

    def _within(self, coupling: Coupling, number: int, tolerance: float) -> bool:
        """DBX103.4 / 103.5: the running stage-2 monitoring finds the deviation within its tolerance."""
        return self._stage_2_monitors(coupling, number, tolerance) and coupling.deviation <= tolerance

    def _put(self, name: str, status: tuple[object, ...], following: bool) -> None:
        area, sig = self._areas[name], self._signals
        sig.leading_active.put(area, bool(status[0]))
        values = status[1:] if following else (False,) * 11
        bits = (sig.fine, sig.coarse, sig.overlaid, sig.speed_warning, sig.accel_warning, sig.correction_done,
                sig.accelerating, sig.process_active, sig.correction_active, sig.fine_2, sig.coarse_2)
        for bit, value in zip(bits, values, strict=True):
            bit.put(area, bool(value))
        sig.following_active.put(area, following)
        sig.sync_mode.put(area, following)
