"""The signal catalogue: what each interface location means, and its names per machine.

The catalogue lists every signal once, in the first data block of its kind (DB10 NCK,
DB11 mode group, DB19 operator panel (HMI), DB21 channel, DB31 axis/spindle), with a symbol that still carries the
placeholder of its instance (``<Axis>.basic.in.enc1Synchronized``).  A machine's
:class:`InterfaceLayout` (its channels and machine axes) expands the catalogue into
:class:`SignalInstance` objects with concrete names and addresses:

* channel k is ``DB(20+k)`` and ``<Chan>`` becomes the channel name (``CHAN1``),
* machine axis n is ``DB(30+n)`` and ``<Axis>`` becomes the axis name (``X1``),
* ``<ModeGroup>`` becomes ``MODEGROUP``, ``<Nc>`` becomes ``NC`` and ``<Hmi>`` becomes ``HMI``
  (the operator panel's DB19: its ``.out.`` signals go PLC -> OP, its ``.in.`` signals OP -> PLC,
  so the OP stands on the NC's side of the interface),
* ``<Alarms>`` becomes ``ALARMS``: DB100, the NC's alarm list for the PLC (a project block behind
  the axis blocks),
* ``<PlcAlarms>`` becomes ``PLCALARMS``: DB2, the PLC's user alarms (700000 ..).  It was added after
  the links' layout existed: the links carry it behind every other block (``byte_ranges``), so
  it moves no address of the other blocks.

This module is pure: it builds the catalogue from already parsed documents
(``interfaces.catalog.load_catalog`` reads the YAML files).
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from enum import StrEnum
from typing import Any

from interfaces.address import Address, AddressError
from interfaces.errors import VcError


class CatalogError(VcError, ValueError):
    """One or more problems in catalogue documents; ``problems`` holds each with its location."""

    def __init__(self, problems: Sequence[str]):
        self.problems = list(problems)
        super().__init__("\n".join(self.problems))


class UnknownSignalError(VcError, KeyError):
    """A name that is neither a catalogue symbol, a catalogue address nor a plant I/O point.

    The message may be given as a function that writes it: a "did you mean" search costs a
    millisecond, and most misses are lookups that go on elsewhere (a PLC program's plant I/O name
    tried in the catalogue first) and never show the message."""

    def __init__(self, message: str | Callable[[], str]):
        super().__init__(message if isinstance(message, str) else "")
        self._message = message

    @property
    def message(self) -> str:
        if not isinstance(self._message, str):
            self._message = self._message()
            self.args = (self._message,)
        return self._message

    def __str__(self) -> str:
        return self.message

    def __reduce__(self) -> tuple[type[UnknownSignalError], tuple[str]]:  # crosses processes as its text
        return type(self), (self.message,)


class Direction(StrEnum):
    PLC_TO_NC = "plc_to_nc"
    NC_TO_PLC = "nc_to_plc"
    PLANT_TO_PLC = "plant_to_plc"  # plant input I: sensors, keys, switches wired to the PLC
    PLC_TO_PLANT = "plc_to_plant"  # plant output Q: actuators driven by the PLC


class SignalType(StrEnum):
    BOOL = "bool"
    BITS = "bits"  # unsigned field of 2..8 bits inside one byte (e.g. gear stage A..C)
    BYTE = "byte"
    WORD = "word"
    DWORD = "dword"
    REAL = "real"  # IEEE 754 single precision in a double word, as S7 REAL


class Trigger(StrEnum):
    LEVEL = "level"
    EDGE = "edge"


class Origin(StrEnum):
    SEED = "seed"  # address and symbols printed in the seed manual
    CONTROL = "control"  # not in the seeds: taken from the real control, marked in the entry
    PROJECT = "project"  # no counterpart on the real control: a project-specific location


class InstanceKind(StrEnum):
    NCK = "nck"
    MODE_GROUP = "mode_group"
    HMI = "hmi"  # the operator panel (OP): DB19
    CHANNEL = "channel"
    AXIS = "axis"
    ALARMS = "alarms"  # the NC's alarm list for the PLC: DB100 (project)
    PLC_ALARMS = "plc_alarms"  # the PLC's user alarms: DB2 (the basic program's alarm block)


FIRST_DB: dict[InstanceKind, int] = {
    InstanceKind.NCK: 10,
    InstanceKind.MODE_GROUP: 11,
    InstanceKind.HMI: 19,
    InstanceKind.CHANNEL: 21,
    InstanceKind.AXIS: 31,
    InstanceKind.ALARMS: 100,
    InstanceKind.PLC_ALARMS: 2,
}
PLACEHOLDER: dict[InstanceKind, str] = {
    InstanceKind.NCK: "<Nc>",
    InstanceKind.MODE_GROUP: "<ModeGroup>",
    InstanceKind.HMI: "<Hmi>",
    InstanceKind.CHANNEL: "<Chan>",
    InstanceKind.AXIS: "<Axis>",
    InstanceKind.ALARMS: "<Alarms>",
    InstanceKind.PLC_ALARMS: "<PlcAlarms>",
}
NCK_INSTANCE = "NC"
MODE_GROUP_INSTANCE = "MODEGROUP"
HMI_INSTANCE = "HMI"
ALARMS_INSTANCE = "ALARMS"
PLC_ALARMS_INSTANCE = "PLCALARMS"

_TYPE_BYTES: dict[SignalType, int] = {
    SignalType.BOOL: 1,
    SignalType.BITS: 1,
    SignalType.BYTE: 1,
    SignalType.WORD: 2,
    SignalType.DWORD: 4,
    SignalType.REAL: 4,
}
_TYPE_WIDTH: dict[SignalType, str] = {
    SignalType.BOOL: "X",
    SignalType.BITS: "X",
    SignalType.BYTE: "B",
    SignalType.WORD: "W",
    SignalType.DWORD: "D",
    SignalType.REAL: "D",
}


@dataclass(frozen=True, slots=True)
class SignalDef:
    """One catalogue entry, in the first data block of its kind."""

    address: Address
    symbol: str
    bp_symbol: str
    direction: Direction
    type: SignalType
    bits: int  # field width: 1 for bool, 2..8 for bits, 8/16/32 for byte/word/dword/real
    trigger: Trigger
    meaning: str
    source: str
    origin: Origin
    note: str = ""
    not_modelled: str = ""  # why the simulated NC neither reads nor writes it ("" = it does)

    @property
    def modelled(self) -> bool:
        return not self.not_modelled

    @property
    def byte_span(self) -> range:
        """Byte offsets this signal occupies inside its data block."""
        return range(self.address.byte, self.address.byte + _TYPE_BYTES[self.type])


@dataclass(frozen=True, slots=True)
class CatalogSection:
    """All signals of one data block kind."""

    kind: InstanceKind
    db: int
    size: int  # bytes per instance
    signals: tuple[SignalDef, ...]


@dataclass(frozen=True, slots=True)
class Catalog:
    sections: tuple[CatalogSection, ...]

    def section(self, kind: InstanceKind) -> CatalogSection:
        for section in self.sections:
            if section.kind is kind:
                return section
        raise KeyError(f"the catalogue has no section for {kind.value}")

    @property
    def signals(self) -> tuple[SignalDef, ...]:
        return tuple(signal for section in self.sections for signal in section.signals)

    @classmethod
    def from_documents(cls, documents: Iterable[tuple[str, Mapping[str, Any]]]) -> Catalog:
        """Build the catalogue from parsed YAML documents ``(file name, content)``.

        Every problem in every document is collected with its location; one
        :class:`CatalogError` lists them all.
        """
        problems: list[str] = []
        sections: list[CatalogSection] = []
        for name, document in documents:
            section = _parse_section(name, document, problems)
            if section is not None:
                sections.append(section)
        _check_sections(sections, problems)
        if problems:
            raise CatalogError(problems)
        # in the links' order (``_db_order``): a block added later comes after the others everywhere
        return cls(tuple(sorted(sections, key=lambda s: _db_order(f"DB{s.db}"))))


def _parse_section(name: str, document: Mapping[str, Any], problems: list[str]) -> CatalogSection | None:
    if not isinstance(document, Mapping):
        problems.append(f"{name}: the document must be a mapping with db, kind, size and signals")
        return None
    try:
        kind = InstanceKind(str(document.get("kind")))
    except ValueError:
        problems.append(f"{name}: kind must be one of {', '.join(k.value for k in InstanceKind)}")
        return None
    db = document.get("db")
    if db != FIRST_DB[kind]:
        problems.append(f"{name}: a {kind.value} catalogue describes DB{FIRST_DB[kind]}, not DB{db}")
        return None
    size = document.get("size")
    if not isinstance(size, int) or size <= 0:
        problems.append(f"{name}: size must be the positive number of bytes of one DB{db} instance")
        return None
    entries = document.get("signals")
    if not isinstance(entries, list):
        problems.append(f"{name}: signals must be a list")
        return None
    signals: list[SignalDef] = []
    for index, entry in enumerate(entries):
        where = f"{name}: signals[{index}]"
        signal = _parse_signal(where, entry, kind, db, size, problems)
        if signal is not None:
            signals.append(signal)
    return CatalogSection(kind, db, size, tuple(signals))


_REQUIRED_FIELDS = ("address", "symbol", "bp_symbol", "direction", "type", "trigger", "meaning", "source", "origin")


def _parse_signal(
    where: str, entry: Any, kind: InstanceKind, db: int, size: int, problems: list[str]
) -> SignalDef | None:
    if not isinstance(entry, Mapping):
        problems.append(f"{where}: each signal must be a mapping")
        return None
    missing = [key for key in _REQUIRED_FIELDS if key not in entry]
    if missing:
        problems.append(f"{where} ({entry.get('address', '?')}): missing {', '.join(missing)}")
        return None
    unknown = sorted(set(entry) - set(_REQUIRED_FIELDS) - {"bits", "note", "not_modelled"})
    if unknown:
        problems.append(f"{where} ({entry['address']}): unknown keys {', '.join(unknown)}")
    try:
        address = Address.parse(str(entry["address"]))
        direction = Direction(entry["direction"])
        signal_type = SignalType(entry["type"])
        trigger = Trigger(entry["trigger"])
        origin = Origin(entry["origin"])
    except (AddressError, ValueError) as error:
        problems.append(f"{where} ({entry['address']}): {error}")
        return None
    label = f"{where} ({address})"
    if address.area != "DB" or address.db != db:
        problems.append(f"{label}: the address must lie in DB{db}")
        return None
    if direction not in (Direction.PLC_TO_NC, Direction.NC_TO_PLC):
        problems.append(f"{label}: interface signals go plc_to_nc or nc_to_plc")
        return None
    if address.width != _TYPE_WIDTH[signal_type]:
        problems.append(f"{label}: a {signal_type.value} signal needs a DB{_TYPE_WIDTH[signal_type]} address")
        return None
    bits = _field_width(signal_type, entry.get("bits"))
    if bits is None:
        problems.append(f"{label}: a bits signal needs bits: 2..8, other types take no bits")
        return None
    if signal_type is SignalType.BITS and address.bit + bits > 8:
        problems.append(f"{label}: a {bits}-bit field starting at bit {address.bit} leaves its byte")
        return None
    if address.byte + _TYPE_BYTES[signal_type] > size:
        problems.append(f"{label}: lies outside the {size} bytes of DB{db}")
        return None
    symbol = str(entry["symbol"])
    placeholder = PLACEHOLDER[kind]
    if not symbol.startswith(placeholder + "."):
        problems.append(f"{label}: symbol '{symbol}' must start with '{placeholder}.'")
        return None
    return SignalDef(
        address=address,
        symbol=symbol,
        bp_symbol=str(entry["bp_symbol"]),
        direction=direction,
        type=signal_type,
        bits=bits,
        trigger=trigger,
        meaning=str(entry["meaning"]).strip(),
        source=str(entry["source"]).strip(),
        origin=origin,
        note=str(entry.get("note", "")).strip(),
        not_modelled=str(entry.get("not_modelled", "")).strip(),
    )


def _field_width(signal_type: SignalType, declared: Any) -> int | None:
    if signal_type is SignalType.BITS:
        return declared if isinstance(declared, int) and 2 <= declared <= 8 else None
    if declared is not None:
        return None
    return 1 if signal_type is SignalType.BOOL else 8 * _TYPE_BYTES[signal_type]


def _check_sections(sections: list[CatalogSection], problems: list[str]) -> None:
    seen_kinds: set[InstanceKind] = set()
    for section in sections:
        if section.kind in seen_kinds:
            problems.append(f"DB{section.db}: described by more than one document")
        seen_kinds.add(section.kind)
        symbols: dict[str, SignalDef] = {}
        owner_of_bit: dict[tuple[int, int], SignalDef] = {}
        direction_of_byte: dict[int, tuple[Direction, SignalDef]] = {}
        for signal in section.signals:
            if signal.symbol in symbols:
                problems.append(
                    f"DB{section.db}: symbol {signal.symbol} is used by {symbols[signal.symbol].address}"
                    f" and {signal.address}"
                )
            symbols[signal.symbol] = signal
            for byte, bit in _occupied_bits(signal):
                other = owner_of_bit.get((byte, bit))
                if other is not None:
                    problems.append(f"DB{section.db}: {signal.address} overlaps {other.address}")
                    break
                owner_of_bit[(byte, bit)] = signal
            for byte in signal.byte_span:
                known = direction_of_byte.get(byte)
                if known is not None and known[0] is not signal.direction:
                    problems.append(
                        f"DB{section.db}: byte {byte} mixes {known[0].value} ({known[1].address})"
                        f" and {signal.direction.value} ({signal.address})"
                    )
                direction_of_byte.setdefault(byte, (signal.direction, signal))


def _occupied_bits(signal: SignalDef) -> Iterable[tuple[int, int]]:
    if signal.type in (SignalType.BOOL, SignalType.BITS):
        return ((signal.address.byte, signal.address.bit + offset) for offset in range(signal.bits))
    return ((byte, bit) for byte in signal.byte_span for bit in range(8))


# --------------------------------------------------------------------------------------------
# Expansion for one machine


@dataclass(frozen=True, slots=True)
class InterfaceLayout:
    """Which DB instances a machine has: its channels (DB21..) and machine axes (DB31..)."""

    channels: tuple[str, ...]
    axes: tuple[str, ...]

    def instances(self, kind: InstanceKind) -> tuple[tuple[str, int], ...]:
        """``(instance name, DB number)`` for every instance of ``kind``."""
        if kind is InstanceKind.NCK:
            return ((NCK_INSTANCE, 10),)
        if kind is InstanceKind.MODE_GROUP:
            return ((MODE_GROUP_INSTANCE, 11),)
        if kind is InstanceKind.HMI:
            return ((HMI_INSTANCE, 19),)
        if kind is InstanceKind.ALARMS:
            return ((ALARMS_INSTANCE, FIRST_DB[InstanceKind.ALARMS]),)
        if kind is InstanceKind.PLC_ALARMS:
            return ((PLC_ALARMS_INSTANCE, FIRST_DB[InstanceKind.PLC_ALARMS]),)
        if kind is InstanceKind.CHANNEL:
            return tuple((name, 20 + k) for k, name in enumerate(self.channels, start=1))
        return tuple((name, 30 + n) for n, name in enumerate(self.axes, start=1))

    def axis_db(self, axis: str) -> int:
        return 31 + self.axes.index(axis)

    def channel_db(self, channel: str) -> int:
        return 21 + self.channels.index(channel)


@dataclass(frozen=True, slots=True)
class SignalRef:
    """A resolved, typed location: what scenarios, traces and links read and write."""

    name: str  # the name it is shown under (symbol, or address for raw access)
    address: Address
    type: SignalType
    bits: int
    direction: Direction
    signal: SignalInstance | None = None  # the catalogue signal it belongs to, if any

    @property
    def area_key(self) -> str:
        return self.address.area_key


@dataclass(frozen=True, slots=True)
class SignalInstance:
    """A catalogue signal in one DB instance, with its concrete symbol and address."""

    definition: SignalDef
    instance: str
    symbol: str
    address: Address

    @property
    def direction(self) -> Direction:
        return self.definition.direction

    @property
    def type(self) -> SignalType:
        return self.definition.type

    def ref(self) -> SignalRef:
        d = self.definition
        return SignalRef(self.symbol, self.address, d.type, d.bits, d.direction, self)


@dataclass(slots=True)
class ExpandedCatalog:
    """The catalogue expanded for one machine: every DB instance, both name forms."""

    catalog: Catalog
    layout: InterfaceLayout
    signals: list[SignalInstance] = field(default_factory=list)
    _by_symbol: dict[str, SignalInstance] = field(default_factory=dict)
    _by_symbol_folded: dict[str, SignalInstance] = field(default_factory=dict)
    _by_address: dict[Address, SignalInstance] = field(default_factory=dict)
    _bit_owner: dict[tuple[str, int, int], SignalInstance] = field(default_factory=dict)
    _byte_direction: dict[tuple[str, int], Direction] = field(default_factory=dict)
    _sizes: dict[str, int] = field(default_factory=dict)

    def __post_init__(self) -> None:
        for section in self.catalog.sections:
            for instance, db in self.layout.instances(section.kind):
                self._sizes[f"DB{db}"] = section.size
                placeholder = PLACEHOLDER[section.kind]
                for definition in section.signals:
                    symbol = instance + definition.symbol[len(placeholder) :]
                    item = SignalInstance(definition, instance, symbol, definition.address.in_db(db))
                    self.signals.append(item)
                    self._by_symbol[symbol] = item
                    self._by_symbol_folded[symbol.casefold()] = item
                    self._by_address[item.address] = item
                    key = item.address.area_key
                    for byte, bit in _occupied_bits(definition):
                        self._bit_owner[(key, byte, bit)] = item
                    for byte in definition.byte_span:
                        self._byte_direction[(key, byte)] = definition.direction

    @property
    def area_sizes(self) -> dict[str, int]:
        """Bytes per data block instance, keyed ``DB10``, ``DB21``, ``DB31`` ..."""
        return dict(self._sizes)

    def by_symbol(self, symbol: str) -> SignalInstance:
        return self._by_symbol[symbol]

    def signal_at(self, address: Address) -> SignalInstance | None:
        """The catalogue signal declared exactly at ``address``, if any."""
        return self._by_address.get(address)

    def owner_of_bit(self, area_key: str, byte: int, bit: int) -> SignalInstance | None:
        return self._bit_owner.get((area_key, byte, bit))

    def byte_direction(self, area_key: str, byte: int) -> Direction | None:
        return self._byte_direction.get((area_key, byte))

    def byte_ranges(self, direction: Direction) -> list[tuple[str, int, int]]:
        """``(area key, start, stop)`` byte ranges to copy for ``direction``.

        Each range starts and ends on a byte that carries ``direction`` and never contains
        a byte of the other direction; bytes that hold no signal may lie inside a range,
        which keeps the ranges few (a link copies them every PLC cycle).
        """
        ranges: list[tuple[str, int, int]] = []
        for key, size in sorted(self._sizes.items(), key=lambda item: _db_order(item[0])):
            start: int | None = None
            last_owned = -1
            for byte in range(size):
                owner = self._byte_direction.get((key, byte))
                # a byte of a range placed behind every block (below) ends the range it interrupts
                late = any(area == key and first <= byte < stop for area, first, stop in _RANGES_LINKED_LAST)
                if owner is direction and not late:
                    if start is None:
                        start = byte
                    last_owned = byte
                elif (owner is not None or late) and start is not None:
                    ranges.append((key, start, last_owned + 1))
                    start = None
            if start is not None:
                ranges.append((key, start, last_owned + 1))
        for key, first, stop in _RANGES_LINKED_LAST:
            owned = [byte for byte in range(first, stop) if self._byte_direction.get((key, byte)) is direction]
            if key in self._sizes and owned:
                ranges.append((key, owned[0], owned[-1] + 1))
        return ranges

    def resolve(self, name: str) -> SignalRef:
        """Resolve a symbolic name or an absolute address to a typed reference.

        An absolute address resolves if it is a catalogue signal's address, a bit inside a
        catalogue signal (one bit of a bits field or of an override byte), or a byte, word
        or double word whose bytes all belong to catalogue signals of one direction.
        """
        text = name.strip()
        item = self._by_symbol.get(text) or self._by_symbol_folded.get(text.casefold())
        if item is not None:
            return item.ref()
        try:
            address = Address.parse(text)
        except AddressError:
            raise UnknownSignalError(lambda: self._unknown_symbol_message(text)) from None
        return self.resolve_address(address)

    def resolve_address(self, address: Address) -> SignalRef:
        exact = self._by_address.get(address)
        # A bit address at the start of a bits field means that one bit, not the whole field.
        whole_signal = exact is not None and exact.type is not SignalType.BITS
        if exact is not None and whole_signal and address.is_bit == (exact.type is SignalType.BOOL):
            return exact.ref()
        key = address.area_key
        if address.area != "DB" or key not in self._sizes:
            raise UnknownSignalError(f"{address}: this machine has no {key}" if address.area == "DB"
                                     else f"{address}: plant I/O is not part of the NC/PLC interface")
        if address.is_bit:
            owner = self._bit_owner.get((key, address.byte, address.bit))
            if owner is None:
                raise UnknownSignalError(f"{address} is not a signal of the catalogue")
            return SignalRef(str(address), address, SignalType.BOOL, 1, owner.direction, owner)
        directions = {self._byte_direction.get((key, b)) for b in range(address.byte, address.byte + address.size)}
        if None in directions:
            raise UnknownSignalError(f"{address} covers bytes that hold no catalogue signal")
        if len(directions) != 1:
            raise UnknownSignalError(f"{address} mixes PLC-to-NC and NC-to-PLC bytes")
        direction = directions.pop()
        assert direction is not None
        raw_type = {"B": SignalType.BYTE, "W": SignalType.WORD, "D": SignalType.DWORD}[address.width]
        return SignalRef(str(address), address, raw_type, 8 * address.size, direction, None)

    def _unknown_symbol_message(self, text: str) -> str:
        head = text.split(".", 1)[0]
        known_instances = {item.instance for item in self.signals}
        if head not in known_instances:
            return (f"unknown signal '{text}': '{head}' is not an instance of this machine"
                    f" (known: {', '.join(sorted(known_instances))})")
        # only the named instance's symbols: X1.x must not suggest the same signal of axis Z1
        suggestions = _close_symbols(text, {s: i for s, i in self._by_symbol.items() if i.instance == head})
        hint = f"; did you mean {' or '.join(suggestions)}?" if suggestions else ""
        return f"unknown signal '{text}'{hint}"


# Blocks added after the links' layout existed go behind all others in the links' order, so that
# no address of the other blocks moves.
_LINKED_LAST = (f"DB{FIRST_DB[InstanceKind.PLC_ALARMS]}",)


# Byte ranges added to a block after the links' layout existed: behind every block (those of
# _LINKED_LAST too), in this order, so that no address before them moves.  DB10.DBB110-117: the
# software cams' minus and plus signals (seed 003 L41268-41273, link version 5).
_RANGES_LINKED_LAST = (("DB10", 110, 118),)


def _db_order(key: str) -> tuple[int, str]:
    if key in _LINKED_LAST:
        return (5_000 + _LINKED_LAST.index(key), key)
    return (int(key[2:]), key) if key.startswith("DB") else (10_000, key)


def _close_symbols(text: str, symbols: Mapping[str, Any]) -> list[str]:
    import difflib

    return difflib.get_close_matches(text, list(symbols), n=2, cutoff=0.75)


def expand(catalog: Catalog, layout: InterfaceLayout) -> ExpandedCatalog:
    """Expand ``catalog`` for a machine with the given channels and axes."""
    return ExpandedCatalog(catalog, layout)
