"""What a spindle keeps of its PLC inputs (seed 003 chapter 13, spec B.3).

The DB31 spindle groups are declared in :mod:`interfaces.signal_groups`: the levels
(:class:`~interfaces.signal_groups.SpindleRequests`), the edge-evaluated requests
(:class:`~interfaces.signal_groups.SpindleEdgeRequests`), the status and the S value.
:class:`SpindleInputs` is the levels as the spindle last took them, with the last value of the
edge-evaluated inputs, which the spindle, its gear change and its positioning compare with.
"""

from __future__ import annotations

from dataclasses import dataclass

from interfaces.signal_groups import SpindleRequests


@dataclass(slots=True)
class SpindleInputs(SpindleRequests):
    gear_reported: int = 0  # DBX16.0-16.2 as last seen
    reset_movement: bool = False  # DB31.DBX2.2 as last seen
    resync: tuple[bool, bool] = (False, False)  # DBX16.4 / 16.5 as last seen
    plc_stop: bool = False  # DBB30 as last seen
    plc_start_cw: bool = False
    plc_start_ccw: bool = False
