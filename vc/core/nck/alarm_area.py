"""The NC's alarm list for the PLC: it writes the project data block DB100 whenever its alarm list
changes; the layout and the codes are those of :mod:`interfaces.alarm_block`."""

from __future__ import annotations

from collections.abc import Mapping

from interfaces.alarm_block import ENTRY_BYTES, FIRST_ENTRY_BYTE, cleared_by_code
from interfaces.signal_groups import ALARM_ENTRY, AlarmEntry, AlarmListHeader
from vc.core.alarms import AlarmList
from vc.core.interface_map import SignalTable

NO_ENTRY = AlarmEntry()


class AlarmArea:
    """Writes the alarm list into DB100 (see the module docstring)."""

    def __init__(self, table: SignalTable, area: bytearray, channels: Mapping[str, int], axes: Mapping[str, int]):
        """``channels`` and ``axes``: the number n of each channel's DB(20+n) and axis's DB(30+n)."""
        self._area = area
        self._encode_header = table.codec(AlarmListHeader).encode
        entries = (table.size - FIRST_ENTRY_BYTE) // ENTRY_BYTES
        self._entries = [table.codec(AlarmEntry, ALARM_ENTRY.format(number=number)).encode
                         for number in range(1, entries + 1)]
        self._channels = dict(channels)
        self._axes = dict(axes)

    def write(self, alarms: AlarmList) -> None:
        area, present = self._area, alarms.present
        self._encode_header(area, AlarmListHeader(count=min(len(present), 0xFFFF), changes=alarms.version & 0xFFFF))
        for index, encode in enumerate(self._entries):
            if index >= len(present):
                encode(area, NO_ENTRY)
                continue
            alarm = present[index]
            encode(area, AlarmEntry(number=alarm.number, channel=self._channels.get(alarm.channel, 0),
                                    axis=self._axes.get(alarm.axis, 0), reaction=alarm.reaction.value,
                                    cleared_by=cleared_by_code(alarm.clear.value)))
