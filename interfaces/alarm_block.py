"""DB100, the NC's alarm list for the PLC: its layout and codes (pure, no I/O).

The catalogue (``interfaces/catalog/db100_alarms.yaml``, origin project) declares the signals;
this module states the codes once, for the NC that writes them (``vc/core/nck/alarm_area.py``), the
link description that tells a PLC where they are, and the documentation::

    DBW0   count: alarms present (may exceed ENTRIES)
    DBW2   changes: counts every change of the list (65535 wraps to 0)
    from DBB4, ENTRIES entries of ENTRY_BYTES bytes, the alarms present in the order raised:
      +0 DBD  number (0: no alarm)
      +4 DBB  channel: n = the channel of DB(20 + n), 0 = none (an NCK alarm)
      +5 DBB  axis: n = the machine axis of DB(30 + n), 0 = none
      +6 DBB  reaction bits, REACTION_BITS
      +7 DBB  cleared by, CLEARED_BY (code = index + 1)

Over Modbus the block is the last range of the NC-to-PLC table (input registers); over S7 it is
data block 100; over CAN its frames follow the axes' frames.
"""

from __future__ import annotations

from interfaces.links.modbus.codec import RegisterMap, Table
from interfaces.signals import FIRST_DB, ExpandedCatalog, InstanceKind

ALARM_DB = FIRST_DB[InstanceKind.ALARMS]
FIRST_ENTRY_BYTE = 4
ENTRY_BYTES = 8
# bit n of an entry's reaction byte
REACTION_BITS = ("axes stop (interpolation stop)", "NC start disabled", "read-in disabled",
                 "channel interrupted (NC stop)", "rapid stop, then no controller enable",
                 "acts on the whole mode group")
# code n (1..) of an entry's cleared-by byte: CLEARED_BY[n - 1]
CLEARED_BY = ("reset", "cancel", "self", "power_on", "emergency_stop_ack")
CLEARED_BY_TEXT = ("reset (channel or mode group)", "the cancel key (or a reset)", "by itself, when its cause is gone",
                   "power on", "emergency stop released, acknowledged with DB10.DBX56.2 and reset")


def entries(catalog: ExpandedCatalog) -> int:
    """How many alarms the block shows, from its size in the catalogue."""
    return (catalog.catalog.section(InstanceKind.ALARMS).size - FIRST_ENTRY_BYTE) // ENTRY_BYTES


def cleared_by_code(clear: str) -> int:
    """The code of a clearing condition (``reset`` .. ``emergency_stop_ack``)."""
    return CLEARED_BY.index(clear) + 1


def describe(catalog: ExpandedCatalog, register_map: RegisterMap) -> dict[str, object]:
    """Where the block is and what its codes mean, for the link description."""
    first = register_map.table_byte(Table.NC_TO_PLC, f"DB{ALARM_DB}", 0)
    return {
        "data_block": ALARM_DB, "input_register": None if first is None else first // 2,
        "entries": entries(catalog), "first_entry_byte": FIRST_ENTRY_BYTE, "entry_bytes": ENTRY_BYTES,
        "entry": {"number": "DBD +0", "channel": "DBB +4", "axis": "DBB +5", "reaction": "DBB +6",
                  "cleared_by": "DBB +7"},
        "reaction_bits": list(REACTION_BITS), "cleared_by": list(CLEARED_BY_TEXT),
    }
