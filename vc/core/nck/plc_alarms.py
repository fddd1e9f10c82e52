"""The PLC's user alarms: DB2, the basic program's alarm block, in the NC's alarm list.

On the real control the PLC user program sets a bit of DB2 and the basic program reports alarm
700000 + 100 x user area + bit to the HMI, with the text the machine builder gave it and the
reaction MD14516 asks for [control]; the seed names no PLC alarm.  The harness keeps them in the
NC's alarm list, so that a scenario's ``expect_alarm``, the traces, DB100 and every link show them
like the NC's own: user area 0 (DB2.DBX180.0 .. 187.7 = 700000 .. 700063) is read whenever the PLC
changed DB2 (the cycle's latch phase); a rising bit raises its alarm, a falling one clears it (the
PLC decides when its fault is gone).  MD14516[n] gives alarm 700000 + n its reaction: bit 0 NC start
disabled, bit 1 read-in disabled (the block change waits), bit 2 feed disabled (the axes of every
channel stop) [INF].  The texts come from the machine file's ``plc_alarms:`` (``PLC alarm 7000nn``
where it names none).
"""

from __future__ import annotations

from collections.abc import Mapping

from vc.config import md_dictionary as MD
from vc.config.machine_data import MachineData
from vc.config.model import PLC_USER_ALARMS
from vc.core.alarms import AlarmDefinition, AlarmList, Clear, Reaction
from vc.core.interface_map import SignalTable

SYMBOL = "userArea0.out.alarm{number}"  # without the instance; bit n of DB2.DBB180 .. 187
_REACTION_BITS = ((1 << 0, Reaction.NC_START_DISABLED), (1 << 1, Reaction.READ_IN_DISABLED),
                  (1 << 2, Reaction.STOP_AXES))


def definitions(nck: MachineData, texts: Mapping[int, str]) -> tuple[AlarmDefinition, ...]:
    """Alarm 700000 + n as the machine defines it: its text, its reaction from MD14516[n]."""
    result = []
    for index, number in enumerate(PLC_USER_ALARMS):
        bits = nck.int(MD.USER_DATA_PLC_ALARM, index)
        reaction = Reaction.NONE
        for bit, meaning in _REACTION_BITS:
            if bits & bit:
                reaction |= meaning
        result.append(AlarmDefinition(number, texts.get(number, f"PLC alarm {number}"), reaction, Clear.SELF,
                                      "the machine file's plc_alarms: and MD14516 (DB2 user area 0)"))
    return tuple(result)


class PlcAlarms:
    """DB2 user area 0 -> the alarm list (see the module docstring)."""

    def __init__(self, table: SignalTable, area: bytearray, definitions: tuple[AlarmDefinition, ...]):
        bits = [table.bit(SYMBOL.format(number=number)) for number in PLC_USER_ALARMS]
        self._area = area
        self._bytes = slice(bits[0].byte, bits[-1].byte + 1)
        self._definitions = definitions
        self._seen = bytes(self._bytes.stop - self._bytes.start)

    def decode(self, alarms: AlarmList, cycle: int) -> None:
        """The PLC changed DB2: raise the alarms whose bit rose, clear those whose bit fell."""
        now = bytes(self._area[self._bytes])
        if now == self._seen:
            return
        for offset, (before, after) in enumerate(zip(self._seen, now, strict=True)):
            for bit in range(8):
                mask = 1 << bit
                if (before ^ after) & mask:
                    definition = self._definitions[8 * offset + bit]
                    if after & mask:
                        alarms.raise_defined(definition, cycle)
                    else:
                        alarms.clear(definition.number)
        self._seen = now
