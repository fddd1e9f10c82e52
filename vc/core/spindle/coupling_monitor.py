"""Monitoring of the synchronous spindle coupling (seed 003 §14), and the system variables it shows.

Every IPO cycle after the axes moved (L22434, L29557-29560): for DV/AV the deviation is the
actual relation ``phi_FS - k x phi_LS`` minus the relation the coupling heads for (programmed
offset, overlays, correction), wrapped to +-180 degrees; within MD37200 = coarse (DBX98.1),
within MD37210 = fine (DBX98.0).  VV compares speeds with MD37220 / MD37230.  DBX99.4 while the
coupling synchronises or the deviation is beyond coarse.  Stage 2 (MD37202 / MD37212, 0 =
off) gives DBX103.4 / 103.5 and the display alarms 22025 / 22026, which stay until the operator
clears them.  CPSYNCOP[FS]= and the other threshold keywords replace these machine data from the
FS's next COUPON on.  A spindle of the pair in position control without zero-mark synchronism
keeps raising 22040.

The system variables of a coupled FS ($AA_COUP_ACT, $AA_COUP_OFFS, $VA_COUP_OFFS, $P_COUP_OFFS,
$AA_COUP_CORR, $AA_SYNCDIFF, $VA_SYNCDIFF, $AA_SYNC, $AA_COUP_CORR_DIST) read what the monitoring
and the coupling's motion hold.
"""

from __future__ import annotations

from collections.abc import Callable

from vc.config import md_dictionary as MD
from vc.core.axis.axis import MachineAxis
from vc.core.program.commands import Kind
from vc.core.spindle.coupling_state import (
    ALARM_COARSE_2_EXCEEDED,
    ALARM_FINE_2_EXCEEDED,
    Coupling,
    CouplingPart,
    SyncPhase,
    actual_relation,
    leading_position,
    threshold,
    wrap180,
)
from vc.core.spindle.spindle import RPM

ALARM_NOT_SYNCHRONISED = 22040  # [control] coupled while a spindle is not synchronised with its zero mark (L22214)
COUP_ACT_SYNCHRONOUS_SPINDLE = 4  # $AA_COUP_ACT bit 2 (L22765-22770)
# the coupling's system variables a program or a synchronized action reads, and what they show
COUPLING_VARIABLES = {"$AA_COUP_ACT": "", "$AA_COUP_OFFS": "couplingOffset", "$VA_COUP_OFFS": "couplingOffsetActual",
                      "$P_COUP_OFFS": "couplingOffsetProgrammed", "$AA_COUP_CORR": "couplingCorrection",
                      "$AA_SYNCDIFF": "", "$VA_SYNCDIFF": "", "$AA_SYNC": "", "$AA_COUP_CORR_DIST": ""}


def _degrees(angle: float) -> float:
    """``angle`` in 0..360, without 360 for a rounding rest below 0."""
    value = angle % 360.0
    return 0.0 if value > 360.0 - 1e-9 else value


class SynchronismMonitor(CouplingPart):
    """Fine / coarse synchronism and the stage-2 monitoring of every coupled pair (see the module docstring)."""

    def cycle(self, cycle: int) -> None:
        """Judge every coupled pair (after the axes moved)."""
        for following, coupling in self._active.items():
            self._monitor_pair(following, coupling, cycle)
            self._check_zero_mark_synchronism(following, coupling, cycle)

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
            signed = wrap180(actual_relation(coupling, self._spindles) - heading - coupling.correction + lag)
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
            if not (coupling.stage_2_monitors(number, tolerance) and deviation > tolerance):
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

    def _stage_2_paused(self, following: str, coupling: Coupling) -> bool:
        """The stage-2 monitoring is not done (L29916-29932) with a velocity coupling, while the FS's
        DBX31.5 suppresses synchronisation or its DBX31.6 tracks the deviation, and while FS or LS
        stops on the rapid-stop ramp or reports DB31.DBX63.3 "disabled"."""
        inputs = self.inputs[following]
        axes = (self._spindles[following].axis, self._spindles[coupling.definition.leading].axis)
        return (coupling.definition.kind is Kind.VV or inputs.sync_disable or inputs.correction
                or any(axis.rapid_stopping or axis.disabled for axis in axes))

    # ------------------------------------------------------------------ system variables
    def quantity(self, following: str, name: str) -> float:
        """The system variables of a coupled FS (``COUPLING_QUANTITY_MEANINGS`` in vc/simulation/observables.py)."""
        coupling = self._active.get(following)
        if coupling is None:
            return 0.0
        if name == "couplingOffset":
            return _degrees(coupling.relation)
        if name == "couplingOffsetActual":
            return _degrees(actual_relation(coupling, self._spindles))
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
        if coupling.phase is not SyncPhase.SYNCHRONOUS:
            return 0.0
        return wrap180(actual_relation(coupling, self._spindles) - coupling.relation - coupling.correction_applied)

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
        coupling = self._active.get(spindle)
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
        position, _ = leading_position(coupling, self._spindles)
        if coupling.phase is SyncPhase.SYNCHRONOUS:
            goal = coupling.target + coupling.correction
        elif coupling.offset_pending and coupling.programmed is not None:
            goal = coupling.programmed
        else:
            return 0.0
        return wrap180(fs.setpoint - coupling.ratio * position - goal)
