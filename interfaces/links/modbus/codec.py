"""The interface as Modbus tables: layout, addresses and byte codecs (pure, no I/O).

Convention, stated once (``vc map`` prints the addresses it gives, the tests check it both ways):

* **Two tables.** The *NC-to-PLC table* holds what the PLC reads: the plant inputs ``I`` and every
  NC->PLC byte range of the data blocks. A client reads it as input registers (FC 4) or as
  discrete inputs (FC 2) and cannot write it. The *PLC-to-NC table* holds what the PLC writes:
  the plant outputs ``Q`` and every PLC->NC byte range; holding registers (FC 3, 6, 16, 22, 23) and
  coils (FC 1, 5, 15).
* **Registers are S7 words.** Table byte ``2r`` is the high byte of register ``r`` and byte
  ``2r + 1`` its low byte (big-endian). A data-block byte keeps its parity in the table: an
  even DB byte is always a high byte, so ``DBW n`` and ``DBD n`` (n even) are whole registers in
  S7 order, and a bit ``DBX n.b`` is bit ``8 + b`` (n even) or ``b`` (n odd) of its register.
* **Bits.** Table byte ``t``, bit ``b`` is coil / discrete input number ``t * 8 + b`` (the
  ``%QXt.b`` arithmetic OpenPLC uses as a Modbus server).  The two views of a register differ
  inside the word: coil ``16r + k`` is bit ``(k + 8) mod 16`` of register ``r``, because the
  even byte is the high byte.
* **Layout.** Registers 0..15 of each table are the link block (below). The data follow from
  register 16: first the plant area (``I`` or ``Q``), then the byte ranges of DB10, DB11, DB19, DB21..,
  DB31.. in catalogue order. Each range starts on a new register; a range that begins at an odd
  DB byte begins in that register's low byte, and its high byte is padding. Padding carries no
  signal: it reads 0, a register write leaves it 0, a coil write to it is refused::

      register  high byte        low byte
      16        I0               I1             plant inputs I0 .. I8
      ...
      21        DB10.DBB106      DB10.DBB107    DB10 NC->PLC bytes 106..109
      ...
      24        DB19.DBB20       (padding)      DB19 NC->PLC byte 20
      25        (padding)        DB21.DBB33     DB21 NC->PLC bytes 33..318 (odd start)

* **Link block**, NC-to-PLC table (input registers 0..15)::

      0  link version (2, see below)        8  first register of the description (4096)
      1  session: counts power-ons          9  description length in bytes
      2  mode: 1 lockstep, 2 free-running  10  NC-to-PLC table size in registers
      3  scan grant (lockstep)             11  PLC-to-NC table size in registers
      4  NC cycle counter, high word       12  boot id: random 1..65535, new with every harness process
      5  NC cycle counter, low word        13..15  0
      6  IPO cycle in microseconds
      7  PLC period in IPO cycles

  PLC-to-NC table (holding registers 0..15)::

      0  scan done: the number of the granted scan the PLC finished (lockstep); in
         free-running mode a counter the PLC changes every scan (its sign of life)
      1  session ready: the session the PLC has (re)started its program for
      2..5  the PLC's session key, 64 bits high word first: written with register 1 in the claim
            of a session (:mod:`interfaces.links.modbus.access`), never stored, read 0
      6..15  reserved, read 0 (register writes there are dropped, coil writes refused)

  The link version (input register 0) changes with every change of this block and of where any
  signal of a shipped machine lies (tests/interfaces/test_link_versions.py pins the layout to it):
  a PLC built for another version must not run.

  Sessions count from 1 in every harness process; the boot id tells two processes apart.  A PLC
  restarts its program whenever the session or the boot id differs from those it started for
  (also after a reconnect: a server restarted in between starts at session 1 again).

  Lockstep, as a PLC implements it: when input register 1 (session) or 12 (boot id) changes, read
  the description, restart the program, forget the last grant and write the session into holding
  register 1.  When input register 3 (grant; 1..65535, never 0, from 1 again in every session)
  differs from the last one handled: read the NC-to-PLC table, run one scan, write the
  PLC-to-NC table, and write the grant into holding register 0 last.  The harness takes the
  outputs when holding register 1 equals the session and holding register 0 the grant.

* **Description.** Input registers from 4096 (up to 16383) hold the interface description as
  UTF-8 JSON (see :mod:`interfaces.links.description`), two bytes a register, so a client that can
  be stepped configures itself from the server.

The tables never exceed 4096 registers (65536 bits, the largest coil number).
"""

from __future__ import annotations

import struct
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass
from enum import IntEnum, StrEnum

from interfaces.errors import VcError
from interfaces.exchange import MODE_FREE_RUNNING as MODE_FREE_RUNNING  # the link block's mode values
from interfaces.exchange import MODE_LOCKSTEP as MODE_LOCKSTEP
from interfaces.exchange import exchange_ranges, link_direction
from interfaces.signals import Direction, ExpandedCatalog, SignalRef, SignalType

LINK_REGISTERS = 16  # registers 0..15 of each table: the link block
DATA_START_BYTE = 2 * LINK_REGISTERS
MAX_TABLE_REGISTERS = 4096  # 65536 bits: the highest coil / discrete input number is 65535
DESCRIPTION_REGISTER = 4096  # first input register of the description
MAX_DESCRIPTION_BYTES = 2 * 12288  # input registers 4096..16383 (the commissioning facts of many axes fit)
READ_LIMIT = 125  # registers in one read request or response (FC 3, 4): the protocol's limit
WRITE_LIMIT = 123  # registers in one write request (FC 16)
LINK_VERSION = 6  # raised with every change of the layout (tests/interfaces/test_link_versions.py)
SESSION_KEY_REGISTERS = 4  # holding registers 2..5: a 64-bit key

# Modbus function codes by the table they address
READ_COILS, READ_DISCRETE_INPUTS, READ_HOLDING, READ_INPUT = 1, 2, 3, 4
WRITE_COIL, WRITE_REGISTER, WRITE_COILS, WRITE_REGISTERS = 5, 6, 15, 16
MASK_WRITE_REGISTER, READ_WRITE_REGISTERS = 22, 23


class LinkInput(IntEnum):
    """The link block of the NC-to-PLC table (input registers 0..15): what the harness tells the PLC."""

    VERSION = 0
    SESSION = 1
    MODE = 2
    SCAN_GRANT = 3
    NC_CYCLE_HIGH = 4
    NC_CYCLE_LOW = 5
    IPO_CYCLE_US = 6
    PLC_CYCLE_IPO = 7
    DESCRIPTION_START = 8
    DESCRIPTION_BYTES = 9
    NC_TO_PLC_REGISTERS = 10
    PLC_TO_NC_REGISTERS = 11
    BOOT_ID = 12


class LinkHolding(IntEnum):
    """The link block of the PLC-to-NC table (holding registers 0..15): what the PLC answers.

    A table of its own, not members of :class:`LinkInput`: the numbers restart at 0, and
    one IntEnum would make ``SCAN_DONE`` an alias of ``VERSION``."""

    SCAN_DONE = 0
    SESSION_READY = 1
    SESSION_KEY = 2  # 2..5: the PLC's session key, high word first; written, never read back


class ModbusMapError(VcError, ValueError):
    """The interface does not fit the Modbus tables (too many bytes)."""


class Table(StrEnum):
    NC_TO_PLC = "nc_to_plc"  # input registers and discrete inputs: the PLC reads
    PLC_TO_NC = "plc_to_nc"  # holding registers and coils: the PLC writes


_DIRECTION = {Table.NC_TO_PLC: Direction.NC_TO_PLC, Table.PLC_TO_NC: Direction.PLC_TO_NC}


@dataclass(frozen=True, slots=True)
class Segment:
    """Bytes ``start`` .. ``stop - 1`` of one area, placed from table byte ``table_byte``."""

    area: str  # "DB31", "I", "Q"
    start: int
    stop: int
    table_byte: int

    def holds(self, area: str, byte: int) -> bool:
        return area == self.area and self.start <= byte < self.stop

    def table_byte_of(self, byte: int) -> int:
        return self.table_byte + byte - self.start


@dataclass(frozen=True, slots=True)
class Location:
    """Where a signal lies in the Modbus tables."""

    table: Table
    register: int  # first register (0-based protocol address)
    register_bit: int | None  # bit in the register of a bit signal (0..15), else None
    registers: int  # how many registers the value spans
    coil: int | None  # coil / discrete input number of a bit signal, else None
    byte_bit: int  # lowest bit of the value inside its register (8 for a byte in the high half)

    @property
    def bit_kind(self) -> str:
        return "coil" if self.table is Table.PLC_TO_NC else "discrete_input"

    @property
    def register_kind(self) -> str:
        return "holding_register" if self.table is Table.PLC_TO_NC else "input_register"


def display_number(kind: str, address: int) -> str:
    """The 1-based reference number of the Modicon convention: 0xxxx coils, 1xxxx discrete
    inputs, 3xxxx input registers, 4xxxx holding registers (six digits above address 9998)."""
    prefix = {"coil": 0, "discrete_input": 1, "input_register": 3, "holding_register": 4}[kind]
    number = address + 1
    return f"{prefix}{number:04d}" if number <= 9999 else f"{prefix}{number:05d}"


class RegisterMap:
    """The two Modbus tables of one machine: which area byte lies in which register."""

    def __init__(self, segments: Mapping[Table, Sequence[Segment]], table_bytes: Mapping[Table, int]):
        self.segments = {table: tuple(segments[table]) for table in Table}
        self.table_bytes = dict(table_bytes)
        self._writable = self._data_mask(Table.PLC_TO_NC)
        # registers 0 and 1 of the PLC-to-NC link block are the PLC's own words
        self._writable[2 * LinkHolding.SCAN_DONE: 2 * LinkHolding.SESSION_READY + 2] = b"\xff" * 4

    @classmethod
    def build(cls, catalog: ExpandedCatalog, plant_sizes: Mapping[str, int]) -> RegisterMap:
        """The layout of the module docstring for a machine's expanded catalogue and plant I/O."""
        segments: dict[Table, list[Segment]] = {}
        sizes: dict[Table, int] = {}
        for table in Table:
            cursor = DATA_START_BYTE
            placed: list[Segment] = []
            for area, start, stop in exchange_ranges(catalog, plant_sizes, _DIRECTION[table]):
                cursor += cursor % 2  # a new register
                cursor += start % 2  # keep the DB byte's parity: an odd byte is a low byte
                placed.append(Segment(area, start, stop, cursor))
                cursor += stop - start
            cursor += cursor % 2
            if cursor > 2 * MAX_TABLE_REGISTERS:
                raise ModbusMapError(f"the {table.value} table needs {cursor // 2} registers; Modbus bit"
                                     f" numbers allow {MAX_TABLE_REGISTERS}")
            segments[table], sizes[table] = placed, cursor
        return cls(segments, sizes)

    def registers(self, table: Table) -> int:
        return self.table_bytes[table] // 2

    def _data_mask(self, table: Table) -> bytearray:
        mask = bytearray(self.table_bytes[table])
        for segment in self.segments[table]:
            mask[segment.table_byte: segment.table_byte + segment.stop - segment.start] = \
                b"\xff" * (segment.stop - segment.start)
        return mask

    @property
    def writable(self) -> bytes:
        """Per PLC-to-NC table byte: 0xFF where a client write lands, 0 for padding and reserve."""
        return bytes(self._writable)

    def table_byte(self, table: Table, area: str, byte: int) -> int | None:
        for segment in self.segments[table]:
            if segment.holds(area, byte):
                return segment.table_byte_of(byte)
        return None

    def location(self, ref: SignalRef) -> Location | None:
        """Where ``ref`` lies, or None when its direction has no table (it cannot happen for
        catalogue signals and plant I/O) or its bytes are outside the tables."""
        table = Table.NC_TO_PLC if link_direction(ref.direction) is Direction.NC_TO_PLC else Table.PLC_TO_NC
        address = ref.address
        first = self.table_byte(table, ref.area_key, address.byte)
        if first is None:
            return None
        register = first // 2
        if ref.type in (SignalType.BOOL, SignalType.BITS):
            bit = address.bit + (8 if first % 2 == 0 else 0)
            return Location(table, register, bit, 1, first * 8 + address.bit, bit)
        size = address.size
        last = first + size - 1
        return Location(table, register, None, last // 2 - register + 1, None,
                        8 if size == 1 and first % 2 == 0 else 0)

    # ------------------------------------------------------------------ moving bytes
    def fill_table(self, table: Table, areas: Mapping[str, bytearray], out: bytearray) -> None:
        """Copy the areas' bytes into the table bytes ``out`` (segments only; the rest stays)."""
        for segment in self.segments[table]:
            out[segment.table_byte: segment.table_byte + segment.stop - segment.start] = \
                areas[segment.area][segment.start: segment.stop]

    def fill_areas(self, table: Table, source: bytes | bytearray, areas: Mapping[str, bytearray]) -> None:
        """Copy the table bytes ``source`` back into the areas (segments only)."""
        for segment in self.segments[table]:
            areas[segment.area][segment.start: segment.stop] = \
                source[segment.table_byte: segment.table_byte + segment.stop - segment.start]


# ---------------------------------------------------------------------------------- register codecs


def read_registers(table: bytes | bytearray, address: int, count: int) -> list[int]:
    """Registers ``address`` .. ``address + count - 1`` of a table, S7 (big-endian) byte order."""
    return list(struct.unpack_from(f">{count}H", table, 2 * address))


def write_registers(table: bytearray, writable: bytes, address: int, values: Sequence[int]) -> None:
    """Store register values; bytes that ``writable`` marks 0 stay 0 (padding, reserve)."""
    start = 2 * address
    stop = start + 2 * len(values)
    table[start:stop] = struct.pack(f">{len(values)}H", *values)
    for index in range(start, stop):
        if not writable[index]:
            table[index] = 0


def read_bits(table: bytes | bytearray, first: int, count: int) -> list[bool]:
    """Coils / discrete inputs ``first`` .. ``first + count - 1``: bit ``t * 8 + b`` is bit b of byte t."""
    return [bool(table[number >> 3] >> (number & 7) & 1) for number in range(first, first + count)]


def bits_writable(writable: bytes, first: int, count: int) -> bool:
    return all(writable[number >> 3] for number in range(first, first + count))


def write_bits(table: bytearray, first: int, values: Iterable[bool]) -> None:
    for number, on in enumerate(values, start=first):
        if on:
            table[number >> 3] |= 1 << (number & 7)
        else:
            table[number >> 3] &= ~(1 << (number & 7)) & 0xFF


def words_as_bits(table: bytes | bytearray, first_word: int, count: int) -> list[int]:
    """Table bytes as 16-bit words with bit 0 first: byte ``2w`` is bits 0..7 of word w, byte
    ``2w + 1`` bits 8..15 (the little-endian packing bit-addressed stores use)."""
    return list(struct.unpack_from(f"<{count}H", table, 2 * first_word))


def session_key_of(registers: Sequence[int]) -> int:
    """The 64-bit session key of holding registers 2..5, high word first."""
    key = 0
    for register in registers[:SESSION_KEY_REGISTERS]:
        key = key << 16 | register & 0xFFFF
    return key


def session_key_registers(key: int) -> list[int]:
    """Holding registers 2..5 of a 64-bit session key, high word first."""
    return [key >> shift & 0xFFFF for shift in (48, 32, 16, 0)]


def text_registers(text: bytes) -> list[int]:
    """UTF-8 bytes two a register (high byte first), zero-padded."""
    padded = text + b"\0" * (len(text) % 2)
    return list(struct.unpack(f">{len(padded) // 2}H", padded))


def registers_text(registers: Sequence[int], length: int) -> bytes:
    return struct.pack(f">{len(registers)}H", *registers)[:length]
