"""The PLC interface of the synchronous spindle coupling: the DB31 coupling signals (seed 003 §14).

PLC -> NC (per spindle): DBX26.4 overlay enable, DBX31.4 resynchronise, DBX31.5 no
synchronisation, DBX31.6 / 31.7 take / delete the correction, read each cycle with their rising
edges (the coupling's motion acts on them).  NC -> PLC: DBX84.4 synchronous mode, DBX98.0 /
98.1 fine / coarse synchronism, 98.4 overlaid motion, 98.5 / 98.6 speed and acceleration
warnings, 99.0 / 99.1 leading / following spindle active, 99.2 correction done, 99.3
acceleration threshold, 99.4 synchronisation running or the deviation beyond coarse, 103.0
correction active, 103.4 / 103.5 within the stage-2 tolerances; written when they change.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from vc.config import md_dictionary as MD
from vc.core.alarms import AlarmList
from vc.core.interface_map import SignalTable
from vc.core.spindle.coupling_state import ALARM_COARSE_2_EXCEEDED, ALARM_FINE_2_EXCEEDED, Coupling, threshold
from vc.core.spindle.spindle import Spindle

ALARM_OVERLAY_NOT_ENABLED = 16771  # differential speed without DB31.DBX26.4 (L23450-23456)


class CouplingSignals:
    """The DB31 coupling signals (catalogue symbols without the instance)."""

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


class CouplingInterface:
    """Reads and writes the coupling signals of every spindle (see the module docstring)."""

    def __init__(self, spindles: dict[str, Spindle], signals: CouplingSignals, areas: dict[str, bytearray],
                 active: dict[str, Coupling], inputs: dict[str, CouplingInputs], alarms: AlarmList):
        self._spindles = spindles
        self._signals = signals
        self._areas = areas  # machine axis -> its DB31.. area
        self._active = active  # the coupled pairs by FS (shared with Couplings)
        self.inputs = inputs
        self._alarms = alarms
        self._written: dict[str, tuple[object, ...]] = {}

    def decode_inputs(self, name: str) -> None:
        """The PLC -> NC coupling signals of spindle ``name`` and their rising edges."""
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

    def write_outputs(self) -> None:
        """The NC -> PLC coupling signals of every spindle, where they changed."""
        leaders = {c.definition.leading for c in self._active.values()}
        for name in self._spindles:
            coupling = self._active.get(name)
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
                    coupling.stage_2_within(ALARM_FINE_2_EXCEEDED, threshold(coupling, md, MD.COUPLE_POS_TOL_FINE_2)),
                    coupling.stage_2_within(ALARM_COARSE_2_EXCEEDED,
                                          threshold(coupling, md, MD.COUPLE_POS_TOL_COARSE_2)),
                )
            if self._written.get(name) == status:
                continue
            self._written[name] = status
            self._put(name, status, coupling is not None)

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
