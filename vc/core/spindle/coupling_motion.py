"""The motion of the synchronous spindle coupling (seed 003 §14): each coupled FS, once per IPO cycle.

:class:`CouplingMotion` drives each coupled FS's position setpoint after the LS has moved:
while SYNCHRONISING it ramps the FS to the coupled speed and fixes the relation at setpoint
synchronism; while SYNCHRONOUS ``FS setpoint = k x LS position + relation + correction``
(vc/core/spindle/coupling_state.py).  The relation moves only by overlaid motion: a programmed
offset (COUPON with POSFS, SPOS on the FS, resync with DB31.DBX31.4) at the FS's highest speed or
FA[Sn], a differential speed (M3/M4 S on the FS, which needs DBX26.4), the JOG keys of the FS in
JOG (L21993-22021, L23349-23356: not inhibited, the PLC blocks them if unwanted; not on a polygon
slave, which holds its relation in manual operation too, seed 002 L63-65), DRF pulses, and
follow-up while the FS has no controller enable.  The correction (DBX31.6 / 31.7,
$AA_COUP_CORR) moves with 10 % of the dynamics.

A VV FS without position control runs on its speed controller: a load shifts its position for
good.  The position loop of a coupled spindle follows the pair (feedforward MD32620, dynamic
matching MD30455 bit 5).
"""

from __future__ import annotations

import math

from vc.config import md_dictionary as MD
from vc.core.axis.axis import MachineAxis
from vc.core.axis.dynamics import CoupledLoop
from vc.core.axis.motion import ramp, stopping_distance, stopping_velocity
from vc.core.axis.owner import Owner
from vc.core.program.commands import Kind
from vc.core.spindle.coupling_signals import ALARM_OVERLAY_NOT_ENABLED
from vc.core.spindle.coupling_state import (
    Coupling,
    CouplingPart,
    Overlay,
    SyncPhase,
    actual_relation,
    leading_position,
    wrap180,
)
from vc.core.spindle.spindle import RPM, Spindle

ALARM_NO_SPEED_PROGRAMMED = 16111  # M3/M4 on the FS without S (L23485-23488)
CORRECTION_DYNAMICS = 0.1  # the correction moves with at most 10 % velocity and acceleration (L31560-31570)
FEED_STOP_ON_FS_ONLY = 1 << 4  # MD30455 bit 4 (L22391-22401)
FS_OWN_CONTROL_PARAMETERS = 1 << 5  # MD30455 bit 5 (L23756-23775): 0 = the FS takes the LS's loop
EDGE_TRIGGERED_CORRECTION = 1 << 7  # MD30455 bit 7 (L31463-31476)
_SPEEDS_AGREE = 1e-6  # deg/s


def _loop_of(spindle: Spindle, feedforward: bool) -> CoupledLoop:
    """A spindle's own loop values, with the feedforward (its weight MD32610) on or off."""
    dyn = spindle.axis.dyn
    weight = spindle.md.float(MD.VELO_FFW_WEIGHT, 0) if feedforward else 0.0
    return CoupledLoop(dyn.kv, weight, dyn.drive_time_constant)


class CouplingMotion(CouplingPart):
    """Drives the coupled FSs and moves their relations (see the module docstring)."""

    # ------------------------------------------------------------------ the cycle
    def cycle(self, cycle: int) -> None:
        """Drive every coupled FS after the spindles ran (the LS has its setpoint of this cycle)."""
        for following, coupling in self._active.items():
            self._plc_requests(following, coupling)
            self._drive(following, coupling)
        loops = self._coupled_loops()
        for name, spindle in self._spindles.items():
            spindle.axis.coupled_loop = loops.get(name)

    def feedforward_withdrawn(self, name: str) -> bool:
        """MD32620 FFW_MODE = 0 on FS or LS of the pair ``name`` is coupled in: the pair runs without
        feedforward, and SPCON in motion, SPOS, M19 and SPOSA have no effect on it (L22999-23006)."""
        return any(name in (following, coupling.definition.leading) and not self._feedforward(coupling)
                   for following, coupling in self._active.items())

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
        for following, coupling in self._active.items():
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
        if "resync" in edges and coupling.programmed is not None and coupling.phase is SyncPhase.SYNCHRONOUS:
            # DBX31.4: restore the programmed offset (L23098-23145); the relation restarts from where
            # the FS stands now
            coupling.target = coupling.relation
            self.move_relation(coupling, wrap180(coupling.programmed - (coupling.relation % 360.0)),
                                waits=False, resync=True)
        allowed = not fs.axis.inputs.disable and coupling.definition.kind is not Kind.VV \
            and abs(abs(coupling.ratio) - 1.0) < 1e-12 and coupling.setpoint_synchronous
        measure = inputs.correction and ("correction" in edges or not fs.md.int(MD.MISC_FUNCTION_MASK)
                                         & EDGE_TRIGGERED_CORRECTION)
        if measure and allowed:
            # DBX31.6: take the measured deviation as correction (L31317-31700)
            coupling.correction = wrap180(actual_relation(coupling, self._spindles) - coupling.relation)
            coupling.correction_done = False
        if "delete_correction" in edges:
            coupling.correction = 0.0
            coupling.correction_done = False
        settled = coupling.correction_applied == coupling.correction
        if not inputs.correction and not inputs.delete_correction and settled:
            coupling.correction_done = False  # the PLC took note: 99.2 goes with 31.6 / 31.7

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
        position, velocity = leading_position(coupling, self._spindles)
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
            if coupling.phase is SyncPhase.SYNCHRONISING:
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
        if coupling.phase is SyncPhase.SYNCHRONISING:
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
        coupling.phase = SyncPhase.SYNCHRONOUS
        coupling.relation = coupling.target = fs.setpoint - leading_part
        if coupling.pending_shift:
            self.move_relation(coupling, coupling.pending_shift, waits=False)
            coupling.pending_shift = 0.0
        if coupling.offset_pending:
            coupling.offset_pending = False
            assert coupling.programmed is not None
            # $P_COUP_OFFS already counts the increments queued meanwhile: COUPON's own offset first
            coupon_offset = coupling.programmed - sum(distance for distance, _, _ in coupling.queued)
            if not self.inputs[following].sync_disable:
                self.set_offset(coupling, coupon_offset, waits=False)  # the block change criterion waits
        if coupling.overlay is None:
            self._start_queued(coupling)

    def _start_queued(self, coupling: Coupling) -> None:
        """The next SPOS increment programmed before setpoint synchronism."""
        if coupling.queued:
            distance, limit, waits = coupling.queued.pop(0)
            coupling.programmed = (coupling.target + distance) % 360.0
            self.move_relation(coupling, distance, waits, limit, positioning=True)

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

    # ------------------------------------------------------------------ overlaid motion
    def set_offset(self, coupling: Coupling, offset: float, waits: bool, limit: float | None = None,
                    positioning: bool = False) -> None:
        """Move the relation to ``offset`` (degrees, relative to the LS's 0) the short way."""
        coupling.programmed = offset % 360.0
        self.move_relation(coupling, wrap180(offset - coupling.target), waits, limit, positioning=positioning)

    def move_relation(self, coupling: Coupling, distance: float, waits: bool, limit: float | None = None,
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

    def delete_positioning(self, coupling: Coupling) -> None:
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
        coupling = self._active[following]
        fs = self._spindles[following]
        # FA[Sn] (DBX17.0 scales it: _overlay_step), else MD35300
        limit = feed * RPM / 360.0 if feed > 0.0 else fs.speed_control.positioning_speed() * RPM
        if coupling.phase is SyncPhase.SYNCHRONISING:
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
            self.move_relation(coupling, value, wait, limit, positioning=True)
        else:
            self.set_offset(coupling, value, wait, limit, positioning=True)

    def program_differential(self, following: str, direction: int | None, speed: float | None, cycle: int,
                             block: str) -> int:
        """M3/M4/M5 S on a coupled FS: a differential speed on top of the coupling (L23402-23597)."""
        coupling = self._active[following]
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
        coupling = self._active.get(following)
        if coupling is None or coupling.phase is not SyncPhase.SYNCHRONOUS:
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
        coupling = self._active.get(following)
        if coupling is not None and coupling.phase is SyncPhase.SYNCHRONOUS and coupling.jog_allowed:
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
