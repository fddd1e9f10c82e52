"""How the Modbus clients of PLC tools are set up against the tables (pure, no I/O): the CODESYS
*Modbus Slave Channels* and the OpenPLC *slave devices* that docs/modbus.md describes
(``vc map --format guide``) and that the ``codesys`` and ``openplc`` exports address.

* **CODESYS**: one channel reads the link block (input registers 0..15), then channels of at most
  125 registers read the data from register 16 on; channels of at most 123 registers write the
  data from holding register 16, and one channel writes the link block last (the scan-done word
  after the outputs).  CODESYS gives the channels' words consecutive addresses in this order, so
  input register r is input word r from the first channel's word, holding register r (r >= 16)
  output word r - 16, and holding register r < 16 output word (data registers) + r.
* **OpenPLC** (v3, ``modbus_master.cpp``): the devices' input registers become %IW100.. and their
  holding registers written %QW100.., numbered on in device order; with devices that read and
  write the tables from register 0, register r is %IW(100 + r) / %QW(100 + r).
"""

from __future__ import annotations

from dataclasses import dataclass

from interfaces.links.modbus.codec import (
    LINK_REGISTERS,
    READ_INPUT,
    READ_LIMIT,
    WRITE_LIMIT,
    WRITE_REGISTERS,
    RegisterMap,
    Table,
)

OPENPLC_FIRST = 100  # slave devices start at %IX100.0, %QX100.0, %IW100, %QW100
OPENPLC_SLAVE_ENTRIES = 400  # OpenPLC v3 copies 400 bits and 400 words each way (MAX_MB_IO)


@dataclass(frozen=True, slots=True)
class RegisterBlock:
    """Registers ``offset`` .. ``offset + length - 1`` of one table, moved in one request."""

    name: str
    table: Table
    offset: int
    length: int

    @property
    def stop(self) -> int:
        return self.offset + self.length

    @property
    def function_code(self) -> int:
        return READ_INPUT if self.table is Table.NC_TO_PLC else WRITE_REGISTERS

    def holds(self, register: int) -> bool:
        return self.offset <= register < self.stop


@dataclass(frozen=True, slots=True)
class OpenPlcDevice:
    """One "Generic Modbus TCP Device": its input registers and its holding registers written."""

    name: str
    inputs: RegisterBlock | None
    outputs: RegisterBlock | None


def _chunks(name: str, table: Table, start: int, stop: int, limit: int) -> list[RegisterBlock]:
    count = -(-(stop - start) // limit)
    return [RegisterBlock(f"{name} {k + 1}" if count > 1 else name, table, first, min(limit, stop - first))
            for k, first in enumerate(range(start, stop, limit))]


def codesys_channels(register_map: RegisterMap) -> list[RegisterBlock]:
    """The Modbus Slave Channels, in the order to create them.

    The link block gets a channel of its own in each direction: a lockstep client reads it
    first and writes it last, and it stays at index = register in any machine.  The write of
    the link block comes last in the list because the scan-done word must reach the server
    after the outputs of the scan.
    """
    inputs, outputs = register_map.registers(Table.NC_TO_PLC), register_map.registers(Table.PLC_TO_NC)
    return [
        RegisterBlock("Link in", Table.NC_TO_PLC, 0, LINK_REGISTERS),
        *_chunks("NC in", Table.NC_TO_PLC, LINK_REGISTERS, inputs, READ_LIMIT),
        *_chunks("NC out", Table.PLC_TO_NC, LINK_REGISTERS, outputs, WRITE_LIMIT),
        RegisterBlock("Link out", Table.PLC_TO_NC, 0, LINK_REGISTERS),
    ]


def codesys_word(register_map: RegisterMap, table: Table, register: int) -> int:
    """The I/O-mapping word of ``register`` counted from the first channel's word of its direction
    (the channels' words are consecutive, in the order of :func:`codesys_channels`)."""
    word = 0
    for channel in codesys_channels(register_map):
        if channel.table is not table:
            continue
        if channel.holds(register):
            return word + register - channel.offset
        word += channel.length
    raise ValueError(f"register {register} lies in no CODESYS channel of the {table.value} table")


def openplc_devices(register_map: RegisterMap) -> list[OpenPlcDevice]:
    """Slave devices that read the NC-to-PLC table and write the PLC-to-NC table from register 0,
    a request each within the protocol's limits.  OpenPLC numbers the devices' words on from
    %IW100 / %QW100, so with the devices in this order register r is %IW(100 + r) / %QW(100 + r)."""
    reads = _chunks("inputs", Table.NC_TO_PLC, 0, register_map.registers(Table.NC_TO_PLC), READ_LIMIT)
    writes = _chunks("outputs", Table.PLC_TO_NC, 0, register_map.registers(Table.PLC_TO_NC), WRITE_LIMIT)
    return [OpenPlcDevice(f"nc{k + 1}", reads[k] if k < len(reads) else None,
                          writes[k] if k < len(writes) else None)
            for k in range(max(len(reads), len(writes)))]
