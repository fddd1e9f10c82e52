"""The rows of ``vc map`` as PLC tags: what every export for a PLC tool starts from (pure, no I/O).

A :class:`PlcTag` is one variable a PLC program declares: a bit, byte, word, double word or
REAL, read from the NC-to-PLC table (an input) or written into the PLC-to-NC table (an
output), with the names a tool can take.  The tags follow from the map's Modbus columns alone,
so every row ``vc map`` lists (catalogue signals, plant I/O, the link block, rows added later)
becomes a tag without this module knowing it:

* a ``bool`` row is one bit: table byte ``n // 8``, bit ``n % 8`` of its discrete input / coil ``n``;
* a ``bits`` row (a field of 2..8 bits inside one byte, e.g. a gear stage) is one BOOL per bit,
  ``<symbol>.bit0``, ``.bit1`` ..: a tool has no type for the field, a program tests its bits;
* a ``byte`` row lies in the high (``bit`` 8) or low (``bit`` 0) byte of its register; a ``word``,
  ``dword`` or ``real`` row starts at table byte ``2r`` (an odd data-block byte keeps its parity:
  table byte ``2r + 1``);
* rows without a table place (the description text) are no tags.

**The process image view** (STEP 7, TIA Portal, awlsim): table byte ``t`` of the NC-to-PLC table is
input byte ``IB(base + t)``, table byte ``t`` of the PLC-to-NC table output byte ``QB(base + t)``,
so a register is the S7 word ``IW``/``QW(base + 2r)`` (both big-endian) and a double word of two
registers, high word first, the S7 double word ``ID``/``QD``.  The awlsim bridge (``plc_awlsim``)
copies the tables so; a Modbus client block of a real S7 copies its receive buffer so.

**Names.** :func:`identifier` makes an IEC 61131-3 identifier of a symbol (``X1.basic.in.
enc1Synchronized`` -> ``X1_basic_in_enc1Synchronized``).  :func:`short_names` gives the
symbols of tools that allow :data:`S7_SYMBOL_LENGTH` characters (STEP 7 classic, awlsim):
the group ``basic`` and the direction words ``in`` / ``out`` are dropped (the address says
input or output) -- ``X1_enc1Synchronized`` -- and, while still too long, the longest word of
the camel-case parts after the instance (numbers stay whole) loses its last letter (not below three letters, then
not below two); a bit of a bits field ends in ``_<bit>``;
names that then clash (case-insensitive, as STEP 7 compares them) end in ``_`` and four
hexadecimal digits of the symbol's SHA-1.  Deterministic: the same map gives the same names.
"""

from __future__ import annotations

import hashlib
import re
from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from enum import StrEnum

from interfaces.signal_map import MapRow

S7_SYMBOL_LENGTH = 24  # STEP 7 classic symbol table, awlsim
MIN_WORD_LETTERS = 3  # a shortened word keeps at least this many letters
DROPPED_WORDS = frozenset({"basic", "in", "out"})  # the catalogue's default group and the direction words
_INPUT_KINDS = ("discrete_input", "input_register")
_BYTE_PARITY = re.compile(r"(\d+)(?:\.\d+)?$")  # the byte number of an address (DB31.DBW68, IB3, DB21.DBX12.0)
_CAMEL_WORD = re.compile(r"[A-Z]+(?![a-z])|[A-Z]?[a-z]+|\d+")
_FIELD_BIT = re.compile(r"\.bit(\d)$")


class DataType(StrEnum):
    BOOL = "BOOL"
    BYTE = "BYTE"
    WORD = "WORD"
    DWORD = "DWORD"
    REAL = "REAL"

    @property
    def bytes(self) -> int:
        return {DataType.BOOL: 1, DataType.BYTE: 1, DataType.WORD: 2}.get(self, 4)


_ROW_TYPES = {"bool": DataType.BOOL, "bits": DataType.BOOL, "byte": DataType.BYTE, "word": DataType.WORD,
              "dword": DataType.DWORD, "real": DataType.REAL}


@dataclass(frozen=True, slots=True)
class PlcTag:
    """One variable of a PLC program, placed in the Modbus tables."""

    symbol: str  # the map's symbol; ``.bitN`` appended for a bit of a bits field
    address: str  # the S7 address of the row (DB31.DBX60.4, I7.0; "-" for the link block)
    data_type: DataType
    is_input: bool  # in the NC-to-PLC table (the PLC reads it)
    table_byte: int  # first byte of the value in its table
    bit: int | None  # bit in that byte (BOOL only)
    meaning: str

    @property
    def register(self) -> int:
        """The (first) register the value lies in."""
        return self.table_byte // 2

    @property
    def register_bit(self) -> int:
        """The lowest bit of the value in its register, S7 byte order (an even table byte is the high byte)."""
        low = 8 if self.table_byte % 2 == 0 and self.data_type.bytes == 1 else 0
        return low + (self.bit or 0)

    @property
    def registers(self) -> int:
        return (self.table_byte + self.data_type.bytes - 1) // 2 - self.register + 1

    @property
    def word_aligned(self) -> bool:
        """A word or double word that starts at an even table byte: whole registers."""
        return self.table_byte % 2 == 0

    @property
    def identifier(self) -> str:
        return identifier(self.symbol)

    def image_address(self, base: int = 0) -> str:
        """The address in the process image view (module docstring): ``I 386.4``, ``QB 33``, ``IW 0``, ``ID 8``."""
        area = "I" if self.is_input else "Q"
        byte = base + self.table_byte
        if self.data_type is DataType.BOOL:
            return f"{area} {byte}.{self.bit}"
        width = {1: "B", 2: "W", 4: "D"}[self.data_type.bytes]
        return f"{area}{width} {byte}"


def plc_tags(rows: Iterable[MapRow]) -> list[PlcTag]:
    """The tags of the map's rows, in the map's order (module docstring)."""
    tags: list[PlcTag] = []
    for row in rows:
        data_type = _ROW_TYPES.get(row.type)
        if data_type is None or not row.modbus_table or not isinstance(row.modbus_address, int):
            continue
        is_input = row.modbus_table in _INPUT_KINDS
        number = row.modbus_address
        if row.type == "bool":
            tags.append(PlcTag(row.symbol, row.address, data_type, is_input, number // 8, number % 8, row.meaning))
        elif row.type == "bits":
            tags += [PlcTag(f"{row.symbol}.bit{k}", row.address, data_type, is_input, (number + k) // 8,
                            (number + k) % 8, f"bit {k} of {row.meaning}") for k in range(row.bits)]
        else:
            in_low_byte = row.bit == 0 if data_type is DataType.BYTE else _odd_byte(row.address)
            tags.append(PlcTag(row.symbol, row.address, data_type, is_input, 2 * number + in_low_byte, None,
                               row.meaning))
    return tags


def _odd_byte(address: str) -> bool:
    match = _BYTE_PARITY.search(address)
    return match is not None and int(match.group(1)) % 2 == 1


def identifier(symbol: str) -> str:
    """An IEC 61131-3 identifier: every run of other characters becomes one underscore."""
    return re.sub(r"[^A-Za-z0-9]+", "_", symbol).strip("_")


def short_name(symbol: str, limit: int = S7_SYMBOL_LENGTH) -> str:
    """The symbol in at most ``limit`` characters (module docstring), before clashes are resolved."""
    field_bit = _FIELD_BIT.search(symbol)
    if field_bit is not None:  # a bit of a bits field keeps its number: <field>_<bit>
        suffix = f"_{field_bit.group(1)}"
        return short_name(symbol[:field_bit.start()], limit - len(suffix)) + suffix
    instance, *rest = re.sub(r"[^A-Za-z0-9.]+", ".", symbol).strip(".").split(".")
    parts = [part for part in rest if part not in DROPPED_WORDS]
    words = [[instance]] + [_CAMEL_WORD.findall(part) or [part] for part in parts]
    for shortest in (MIN_WORD_LETTERS, MIN_WORD_LETTERS - 1):
        while _joined_length(words) > limit:
            candidates = [(len(word), index, position) for index, part in enumerate(words) if index > 0
                          for position, word in enumerate(part) if len(word) > shortest and not word.isdigit()]
            if not candidates:
                break
            _, index, position = max(candidates)
            words[index][position] = words[index][position][:-1]
    return "_".join("".join(part) for part in words)[:limit]


def _joined_length(words: Sequence[Sequence[str]]) -> int:
    return sum(len(word) for part in words for word in part) + len(words) - 1


def short_names(symbols: Sequence[str], limit: int = S7_SYMBOL_LENGTH) -> dict[str, str]:
    """Every symbol's short name, unique regardless of case (module docstring)."""
    names = {symbol: short_name(symbol, limit) for symbol in symbols}
    seen: dict[str, list[str]] = {}
    for symbol, name in names.items():
        seen.setdefault(name.lower(), []).append(symbol)
    for clashing in seen.values():
        if len(clashing) > 1:
            for symbol in clashing:
                digest = hashlib.sha1(symbol.encode()).hexdigest()[:4].upper()
                names[symbol] = f"{names[symbol][:limit - 5]}_{digest}"
    if len({name.lower() for name in names.values()}) != len(names):
        raise ValueError("the short symbol names are not unique even with their digests")
    return names


def ascii_text(text: str, limit: int) -> str:
    """``text`` in printable ASCII (the classic tools read their code page), at most ``limit`` characters."""
    cleaned = "".join(character if " " <= character <= "~" else "?" for character in text)
    return cleaned[:limit]
