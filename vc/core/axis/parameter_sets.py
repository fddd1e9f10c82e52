"""The servo parameter set of an axis selected by the PLC: DB31.DBX9.0-9.2 -> DBX69.0-69.2
(seed 003 §6.5.4 L6828-6870, §7.4.11 L10014-10023, §13.4.4 L18927-18958).

Each machine axis has six parameter sets (index 0..5) of the position controller, so that it can
be adapted to what changes while the machine runs.  Which one acts is MD35590
PARAMSET_CHANGE_ENABLE:

* 0 - the NC's own choice: an axis runs with set 1 (index 0), a spindle with its gear stage + 1
  (vc/core/spindle/gear_change.py);
* 1 - the NC's choice and the PLC's (DBX9.0-9.2) or SCPARA; the NC's has priority where it
  chooses (thread cutting: the set of the master spindle's gear); "only for axes" (L18941);
* 2 - the PLC's or SCPARA alone (axes and spindles).  After power-on set 1 (L18958).

The 3-bit selection is the set's index: 000 = set 1 .. 101 = set 6, 110 and 111 also set 6 (the
table at L18975-18993).  The NC switches in the cycle it reads the selection and shows the active
set at once in DBX69.0-69.2 [control].  A set switches the position controller's gain MD32200[n]
and the gear ratio MD31050 / MD31060[n] the drive's speeds are counted with (drive_messages.py);
the other members of the set (L6836-6860: MD32452, MD32610, MD32800, MD32810, MD32910, MD36012,
MD36200) keep the first set's values [INF: as the spindle's gear stage change does].

Built for axes: a spindle (MD35590 = 2 on a spindle) keeps its gear stage's set; SCPARA,
DBX9.3 (disable the switchover by SCPARA) and the NC's priority in thread cutting with
MD35590 = 1 are not modelled (no axis of the harness cuts a thread but the spindle's partners).
"""

from __future__ import annotations

from interfaces.signal_groups import ParameterSetRequest, ParameterSetStatus
from vc.config import md_dictionary as MD
from vc.config.model import AxisConfig
from vc.core.interface_map import SignalTable

PARAMETER_SETS = 6
INTERNAL_AND_EXTERNAL = 1  # MD35590
EXTERNAL_ONLY = 2


def selected_by_the_plc(config: AxisConfig) -> bool:
    """An axis (not a spindle) whose MD35590 lets the PLC select its servo parameter set."""
    return not config.is_spindle and config.md.int(MD.PARAMSET_CHANGE_ENABLE) in (INTERNAL_AND_EXTERNAL, EXTERNAL_ONLY)


class ServoParameterSets:
    """The PLC's selection of one axis's servo parameter set and the NC's feedback."""

    def __init__(self, config: AxisConfig, table: SignalTable, area: bytearray):
        self._md = config.md
        self._decode = table.codec(ParameterSetRequest).decode
        self._encode = table.codec(ParameterSetStatus).encode
        self._area = area
        self._request = ParameterSetRequest()
        self.active = 0  # power-on: set 1 (L18958)

    def decode(self) -> float | None:
        """The PLC changed its outputs: the new set's Kv MD32200[n] when it selects another set, else None."""
        self._decode(self._area, self._request)
        selected = min(self._request.selection, PARAMETER_SETS - 1)
        if selected == self.active:
            return None
        self.active = selected
        self.publish()
        return self._md.float(MD.POSCTRL_GAIN, selected)

    def publish(self) -> None:
        self._encode(self._area, ParameterSetStatus(active=self.active))
