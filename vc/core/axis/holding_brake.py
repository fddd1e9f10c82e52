"""The holding brake of an axis's motor as the NC/PLC interface carries it: the PLC's "release
holding brake" DB31.DBX20.5 to the drive, the brake's feedback "holding brake released" DB31.DBX92.5
(seed 003 §18.2, L38336, L38353).

The seed prints the two signals and, for a vertical axis, that the PLC must control its brake
(L38169-38172); the rest is the real drive's [control]: the drive switches the brake's coil as the
PLC orders and reports what the brake's released contact reads.  The brake itself, with its
switching time and its faults, is the plant's (vc/plant/holding_brake.py); it reads the order here
and reports its contact with :meth:`HoldingBrakeSignals.report`.  Only an axis with a holding brake
(the machine file's ``plant: holding_brake:``) has these signals; no cost for the others.
"""

from __future__ import annotations

from interfaces.signal_groups import HoldingBrakeRequest, HoldingBrakeStatus
from vc.core.interface_map import SignalTable


class HoldingBrakeSignals:
    """One axis's DB31.DBX20.5 and DBX92.5."""

    @staticmethod
    def declare(table: SignalTable) -> None:
        """The NC has the signals on every axis (an axis without a brake shows DBX92.5 = 0)."""
        table.codec(HoldingBrakeRequest)
        table.codec(HoldingBrakeStatus)

    def __init__(self, table: SignalTable, area: bytearray):
        self._decode = table.codec(HoldingBrakeRequest).decode
        self._encode = table.codec(HoldingBrakeStatus).encode
        self._area = area
        self._request = HoldingBrakeRequest()
        self.released = False  # what DBX92.5 shows

    @property
    def release_ordered(self) -> bool:
        """DB31.DBX20.5: the PLC orders the brake released."""
        return self._request.release

    def decode(self) -> None:
        """The PLC changed its outputs."""
        self._decode(self._area, self._request)

    def report(self, released: bool) -> None:
        """The brake's released contact as the drive reads it: DB31.DBX92.5, written when it changes."""
        if released != self.released:
            self.released = released
            self._encode(self._area, HoldingBrakeStatus(released=released))
