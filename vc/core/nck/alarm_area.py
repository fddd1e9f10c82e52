"""The NC's alarm list for the PLC: it writes the project data block DB100 whenever its alarm list
changes; the layout and the codes are those of :mod:`interfaces.alarm_block`."""

from __future__ import annotations

from collections.abc import Mapping

from interfaces.alarm_block import ENTRY_BYTES, FIRST_ENTRY_BYTE, cleared_by_code
from interfaces.bit_access import Field
from vc.core.alarms import AlarmList
from vc.core.interface_map import SignalTable


class _EntrySignals:
    def __init__(self, table: SignalTable, number: int):
        prefix = f"entry[{number}].in."
        self.number = table.field(f"{prefix}number")
        self.channel = table.field(f"{prefix}channel")
        self.axis = table.field(f"{prefix}axis")
        self.reaction = table.field(f"{prefix}reaction")
        self.cleared_by = table.field(f"{prefix}clearedBy")

    def fields(self) -> tuple[Field, ...]:
        return (self.number, self.channel, self.axis, self.reaction, self.cleared_by)


class AlarmArea:
    """Writes the alarm list into DB100 (see the module docstring)."""

    def __init__(self, table: SignalTable, area: bytearray, channels: Mapping[str, int], axes: Mapping[str, int]):
        """``channels`` and ``axes``: the number n of each channel's DB(20+n) and axis's DB(30+n)."""
        self._area = area
        self._count = table.field("list.in.count")
        self._changes = table.field("list.in.changes")
        entries = (table.size - FIRST_ENTRY_BYTE) // ENTRY_BYTES
        self._entries = [_EntrySignals(table, number) for number in range(1, entries + 1)]
        self._channels = dict(channels)
        self._axes = dict(axes)

    def write(self, alarms: AlarmList) -> None:
        area, present = self._area, alarms.present
        self._count.put(area, min(len(present), 0xFFFF))
        self._changes.put(area, alarms.version & 0xFFFF)
        for index, entry in enumerate(self._entries):
            if index >= len(present):
                for field in entry.fields():
                    field.put(area, 0)
                continue
            alarm = present[index]
            entry.number.put(area, alarm.number)
            entry.channel.put(area, self._channels.get(alarm.channel, 0))
            entry.axis.put(area, self._axes.get(alarm.axis, 0))
            entry.reaction.put(area, alarm.reaction.value)
            entry.cleared_by.put(area, cleared_by_code(alarm.clear.value))

