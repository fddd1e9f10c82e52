"""Synchronisation of a turning spindle with its encoder's zero mark (seed 003 §13.3).

A spindle whose encoder is not referenced takes the zero mark it passes: there its actual value
is MD34100[n] - direction x (MD34080 + MD34090), the relation axis referencing uses between the
mark and the reference point (L18011-18025).  An absolute encoder is referenced by its
calibration instead (§4.9), and one that lost it stays unreferenced until it is calibrated again
(seed 003 L2025-2040).
"""

from __future__ import annotations

from vc.config import md_dictionary as MD
from vc.core.axis.axis import MachineAxis


class ZeroMarkSynchronisation:
    """Watches one spindle's encoder for the zero mark it passes while unsynchronised."""

    def __init__(self, axis: MachineAxis):
        self._axis = axis
        self._md = axis.config.md
        self._last_physical = axis.physical

    def cycle(self) -> None:
        """An unsynchronised turning spindle takes the zero mark it passed since the last cycle."""
        axis = self._axis
        physical, before = axis.physical, self._last_physical
        self._last_physical = physical
        encoder = axis.encoder
        if encoder.referenced or encoder.frequency_exceeded or physical == before or axis.active_encoder is None \
                or encoder.absolute:
            return
        mark = encoder.zero_mark_between(before, physical)
        if mark is None:
            return
        md, index = self._md, encoder.index
        direction = 1 if physical > before else -1
        offset = md.float(MD.REFP_MOVE_DIST, index) + md.float(MD.REFP_MOVE_DIST_CORR, index)
        value = md.float(MD.REFP_SET_POS, self._reference_value_index()) - direction * offset
        axis.synchronise(encoder, mark, value)

    def _reference_value_index(self) -> int:
        """DB31.DBX2.4..2.7 select one of the four reference values MD34100[0..3]."""
        selection = self._axis.inputs.ref_point_selection
        for index in range(4):
            if selection & (1 << index):
                return index
        return 0
