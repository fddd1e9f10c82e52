"""What the axis derives from its DB31 requests: the measuring system the PLC selects.

The DB31 groups of the axis (:class:`~interfaces.signal_groups.AxisRequests`,
:class:`~interfaces.signal_groups.AxisStatus`) are declared in :mod:`interfaces.signal_groups`;
:class:`AxisInputs` is the requests as the axis took them, with what follows from them.
"""

from __future__ import annotations

from dataclasses import dataclass

from interfaces.signal_groups import AxisRequests


@dataclass(slots=True)
class AxisInputs(AxisRequests):
    """The PLC-to-NC signals of one axis, decoded when the PLC changed its outputs."""

    encoder_selected: int | None = None  # 0 or 1 from DBX1.5 / 1.6; None = parked (see select_encoder)

    def select_encoder(self, encoder_count: int) -> None:
        """Measuring system 1 or 2 from DB31.DBX1.5 / 1.6 (1 wins; 2 only where the axis has it;
        neither: parked)."""
        if self.encoder_1_activation:
            self.encoder_selected = 0
        else:
            self.encoder_selected = 1 if self.encoder_2_activation and encoder_count > 1 else None
