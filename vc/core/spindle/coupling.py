"""Synchronous spindle coupling (seed 003 chapter 14), the engine polygon turning also runs on.

:class:`Couplings` keeps the pairs of every channel: the coupling table (the configured pair of
MD21300.., COUPDEF / COUPDEL / COUPRES, the CPSYNCOP.. thresholds), the commands that couple and
decouple (COUPON / COUPONC / COUPOF / COUPOFS, with the automatic position control of FS and LS),
the block change criteria (COUPON's, WAITC) and what NC start, reset and the spindle reset do to
the couplings.  It owns by composition the parts that run every cycle:

``coupling_state``    a pair, a coupled pair and its phases (the diagram)
``coupling_motion``   :class:`CouplingMotion`: drives each coupled FS, overlaid motions, correction
``coupling_monitor``  :class:`SynchronismMonitor`: fine / coarse synchronism, stage 2, 22040, the
                      system variables
``coupling_signals``  :class:`CouplingInterface`: the DB31 coupling signals
"""

from __future__ import annotations

from collections.abc import Callable

from vc.config import md_dictionary as MD
from vc.config.model import ChannelConfig
from vc.core.alarms import AlarmList
from vc.core.axis.owner import Owner
from vc.core.interface_map import SignalTable
from vc.core.program.commands import BlockChange, Kind
from vc.core.spindle.coupling_monitor import ALARM_NOT_SYNCHRONISED, SynchronismMonitor
from vc.core.spindle.coupling_motion import CouplingMotion
from vc.core.spindle.coupling_signals import ALARM_OVERLAY_NOT_ENABLED, CouplingInterface
from vc.core.spindle.coupling_state import Coupling, CouplingInputs, PairDefinition, SyncPhase, wrap180
from vc.core.spindle.spindle import RPM, Spindle, SpindleMode

ALARM_COUPLING_NOT_DEFINED = 16796  # [control] COUPON / COUPOF of a pair nobody defined
ALARM_COUPLING_ACTIVE = 16797  # [control] the pair is coupled: COUPDEF, gear change, oscillation refused
ALARM_WRITE_PROTECTED = 16787  # [control] COUPDEF of the configured pair with MD21340 = 1 (L21986-21991)
ALARM_TOO_MANY_COUPLINGS = 16792  # [control] a third pair, or a spindle already in another coupling (L21749, L23018)

MAX_PAIRS_PER_CHANNEL = 2  # L21749
# MD21330 COUPLE_RESET_MODE_1 (L22946-22975) and the channel masks (L22954-22981)
CANCEL_AT_START, CANCEL_AT_RESET, ACTIVATE_AT_START = 1 << 0, 1 << 1, 1 << 9
RESET_BEHAVIOUR, KEEP_PROGRAMMED_AT_RESET = 1 << 0, 1 << 10  # MD20110
CANCEL_PROGRAMMED_AT_START = 1 << 10  # MD20112


class Couplings:
    """The synchronous spindle pairs of all channels (see the module docstring)."""

    def __init__(self, channels: list[ChannelConfig], spindles: dict[str, Spindle], table: SignalTable,
                 areas: dict[str, bytearray], dt: float, alarms: AlarmList):
        self._spindles = spindles
        self._alarms = alarms
        self._channels = {channel.name: channel for channel in channels}
        self.inputs = {name: CouplingInputs() for name in spindles}
        self.definitions: dict[str, PairDefinition] = {}
        self.active: dict[str, Coupling] = {}
        self._motion = CouplingMotion(spindles, self.active, self.inputs, dt, alarms)
        self._monitor = SynchronismMonitor(spindles, self.active, self.inputs, dt, alarms)
        self._interface = CouplingInterface(spindles, table, areas, self.active, self.inputs, alarms)
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
        if coupling.phase is SyncPhase.SYNCHRONISING:
            # $P_COUP_OFFS counts the SPOS increments queued behind COUPON's offset (see _synchronous)
            coupling.programmed = (offset + sum(distance for distance, _, _ in coupling.queued)) % 360.0
            coupling.offset_pending = True
        elif self.inputs[following].sync_disable:
            coupling.programmed = offset % 360.0
        else:
            self._motion.set_offset(coupling, offset, waits=False)

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

    # ------------------------------------------------------------------ block change
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
                    self._motion.delete_positioning(kept)  # reset ends SPOS on the FS, not the coupling
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
                self._motion.delete_positioning(coupling)

    def reset_movement(self, name: str) -> None:
        """DB31.DBX2.2 delete distance to go / spindle reset on its rising edge (the spindle itself
        brakes, vc/core/spindle/spindle.py).  On an FS: the differential speed and its direction are
        deleted (L23529-23532) and a SPOS offset motion ends; on an LS: the overlaid motions of
        its FSs end as fast as possible, those of COUPON / COUPONC excepted, and the coupling stays
        (L23299-23303)."""
        coupling = self.active.get(name)
        if coupling is not None:
            coupling.differential = 0.0
            self._motion.delete_positioning(coupling)
        for each in self.active.values():
            if each.definition.leading == name:
                self._motion.delete_positioning(each)

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

    # ------------------------------------------------------------------ the parts (coupling_*.py)
    def decode_inputs(self, name: str) -> None:
        """The PLC's coupling signals of spindle ``name``."""
        self._interface.decode_inputs(name)

    def cycle(self, cycle: int) -> None:
        """Drive every coupled FS after the spindles ran (the LS has its setpoint of this cycle)."""
        self._motion.cycle(cycle)

    def monitor(self, cycle: int) -> None:
        """Synchronism, warning thresholds and the DB31 coupling signals (after the axes moved)."""
        if not self.active and self._idle_written:
            return  # no pair coupled and the outputs already say so
        self._monitor.cycle(cycle)
        self._interface.write_outputs()
        self._idle_written = not self.active

    def feedforward_withdrawn(self, name: str) -> bool:
        return self._motion.feedforward_withdrawn(name)

    def position_following(self, following: str, mode: str, value: float, feed: float, wait: bool) -> None:
        self._motion.position_following(following, mode, value, feed, wait)

    def program_differential(self, following: str, direction: int | None, speed: float | None, cycle: int,
                             block: str) -> int:
        return self._motion.program_differential(following, direction, speed, cycle, block)

    def jog(self, following: str, direction: int, stopped: bool) -> None:
        self._motion.jog(following, direction, stopped)

    def drf(self, following: str, distance: float) -> None:
        self._motion.drf(following, distance)

    def quantity(self, following: str, name: str) -> float:
        return self._monitor.quantity(following, name)

    def relation_error(self, coupling: Coupling) -> float:
        return self._monitor.relation_error(coupling)

    def variable_reader(self, spindles: dict[str, str]) -> Callable[[str, str], float]:
        return self._monitor.variable_reader(spindles)

    def read_variable(self, name: str, spindle: str) -> float:
        return self._monitor.read_variable(name, spindle)
