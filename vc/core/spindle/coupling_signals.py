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

from interfaces.signal_groups import CouplingStatus
from vc.config import md_dictionary as MD
from vc.core.alarms import AlarmList
from vc.core.interface_map import SignalTable
from vc.core.spindle.coupling_state import (
    ALARM_COARSE_2_EXCEEDED,
    ALARM_FINE_2_EXCEEDED,
    Coupling,
    CouplingInputs,
    threshold,
)
from vc.core.spindle.spindle import Spindle

ALARM_OVERLAY_NOT_ENABLED = 16771  # differential speed without DB31.DBX26.4 (L23450-23456)


_EDGE_EVALUATED = ("overlay_enable", "resync", "sync_disable", "correction", "delete_correction")


class CouplingInterface:
    """Reads and writes the coupling signals of every spindle (see the module docstring)."""

    def __init__(self, spindles: dict[str, Spindle], table: SignalTable, areas: dict[str, bytearray],
                 active: dict[str, Coupling], inputs: dict[str, CouplingInputs], alarms: AlarmList):
        self._spindles = spindles
        self._decode = table.codec(CouplingInputs).decode
        self._encode = table.codec(CouplingStatus).encode
        self._areas = areas  # machine axis -> its DB31.. area
        self._active = active  # the coupled pairs by FS (shared with Couplings)
        self.inputs = inputs
        self._alarms = alarms
        self._written: dict[str, tuple[object, ...]] = {}

    def decode_inputs(self, name: str) -> None:
        """The PLC -> NC coupling signals of spindle ``name`` and their rising edges."""
        inputs = self.inputs[name]
        before = (inputs.overlay_enable, inputs.resync, inputs.sync_disable, inputs.correction,
                  inputs.delete_correction)
        self._decode(self._areas[name], inputs)
        now = (inputs.overlay_enable, inputs.resync, inputs.sync_disable, inputs.correction, inputs.delete_correction)
        for key, was, value in zip(_EDGE_EVALUATED, before, now, strict=True):
            if value and not was:
                inputs.edges.add(key)
        if inputs.overlay_enable:
            self._alarms.clear(ALARM_OVERLAY_NOT_ENABLED, axis=name)

    def write_outputs(self) -> None:
        """The NC -> PLC coupling signals of every spindle, where they changed."""
        leaders = {c.definition.leading for c in self._active.values()}
        for name in self._spindles:
            coupling = self._active.get(name)
            leading = name in leaders
            if coupling is not None:
                self._write_following(name, coupling, leading)
                continue
            status = (leading,)
            if self._written.get(name) != status:
                self._written[name] = status
                self._encode(self._areas[name], CouplingStatus(leading_active=leading))

    def _write_following(self, name: str, coupling: Coupling, leading: bool) -> None:
        md, axis = self._spindles[name].md, self._spindles[name].axis
        warning = md.float(MD.EG_VEL_WARNING) / 100.0
        accel_threshold = md.float(MD.EG_ACC_TOL) / 100.0 * axis.dyn.max_accel
        overlay = coupling.overlay
        overlaid = (overlay is not None and overlay.left != 0.0) or coupling.differential_velocity != 0.0 \
            or coupling.jog_velocity != 0.0
        speed_warning = abs(axis.command_velocity) > warning * axis.dyn.max_velocity
        accel_warning = abs(coupling.acceleration) > warning * axis.dyn.max_accel
        accelerating = abs(coupling.acceleration) > accel_threshold
        process_active = not coupling.coarse or (overlay is not None and overlay.resync)
        correction_active = coupling.correction_applied != 0.0
        fine_2 = coupling.stage_2_within(ALARM_FINE_2_EXCEEDED, threshold(coupling, md, MD.COUPLE_POS_TOL_FINE_2))
        coarse_2 = coupling.stage_2_within(ALARM_COARSE_2_EXCEEDED,
                                           threshold(coupling, md, MD.COUPLE_POS_TOL_COARSE_2))
        # a plain tuple first: compared every cycle, the status is built (by keyword) only when it changed
        status = (leading, coupling.fine, coupling.coarse, overlaid, speed_warning, accel_warning,
                  coupling.correction_done, accelerating, process_active, correction_active, fine_2, coarse_2)
        if self._written.get(name) == status:
            return
        self._written[name] = status
        self._encode(self._areas[name], CouplingStatus(
            leading_active=leading, fine=coupling.fine, coarse=coupling.coarse, overlaid=overlaid,
            speed_warning=speed_warning, accel_warning=accel_warning, correction_done=coupling.correction_done,
            accelerating=accelerating, process_active=process_active, correction_active=correction_active,
            fine_2=fine_2, coarse_2=coarse_2, following_active=True, sync_mode=True))
