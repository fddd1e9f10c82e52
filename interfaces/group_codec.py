"""Groups of interface signals, declared once and compiled at power-on into a decoder and an encoder.

A group is a keyword-only dataclass whose signal fields name their catalogue symbol with
:func:`signal` (the groups of the NC/PLC interface are in :mod:`interfaces.signal_groups`)::

    @dataclass(slots=True, kw_only=True)
    class AxisRequests:
        controller_enable: bool = signal("basic.out.enableCtrl")   # DB31.DBX2.1
        override_raw: int = signal("basic.out.feedrateOvrFactor", 0)

The attribute is the one name the code uses, the symbol the one the catalogue (and the manual)
uses; nothing else names the signal.  Whoever builds a group names each value
(``AxisStatus(exact_fine=..., stationary=...)``), as the codec reads and writes them by attribute:
the order of a declaration moves no value to another signal, and a group whose signal fields may
be given by position is refused.  A user may subclass a group to keep what it derives from
the signals beside them (the NC's axis adds the measuring system the two selection bits give);
fields without a symbol are left alone by the codec.

:class:`GroupCodec` resolves every symbol once, through the caller's ``resolve``: the NC resolves
symbols without the instance in its catalogue section (one codec serves every axis, channel,
...), the PLC runtime the signals of one instance.  An optional prefix serves the repeated blocks
of one data block (``geoAxis2.out.``, ``entry[3].in.``).  The result is one :class:`Accessor` row
per attribute (byte, shift, width, type), from which the codec generates plain functions:
``decode(area, into)`` sets the attributes of ``into`` from the bytes, ``read(area)`` returns a
new instance of the group decoded from them, ``encode(area, values)`` writes the attributes of
``values`` into the bytes, the bits of one byte in one store.  The functions hold the offsets as
constants, as fast as hand-written code (namedtuple and dataclasses generate their methods the
same way).  The bit convention is :mod:`interfaces.bit_access`'s: S7's, stated there once.
"""

from __future__ import annotations

import dataclasses
import functools
import struct
from collections import defaultdict
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any, Generic, Protocol, TypeVar

from interfaces.address import Address
from interfaces.errors import VcError
from interfaces.signals import Direction, SignalType

SYMBOL = "catalogue symbol"  # the field metadata key :func:`signal` sets

T = TypeVar("T")
Decoder = Callable[[Any, Any], None]  # (area, into): the attributes of ``into`` from the bytes of ``area``
Encoder = Callable[[bytearray, Any], None]  # (area, values): the attributes of ``values`` into ``area``


class SignalLocation(Protocol):
    """Where a resolved signal lies: a catalogue entry (the NC resolves symbols without the
    instance) or a signal of one instance (the PLC runtime resolves ``X1.basic.in.inPos``)."""

    @property
    def address(self) -> Address: ...
    @property
    def type(self) -> SignalType: ...
    @property
    def bits(self) -> int: ...
    @property
    def direction(self) -> Direction: ...


class SignalGroupError(VcError, TypeError):
    """A signal group that does not fit the catalogue (mixed directions, overlapping signals, a
    field type that is not the signal's) or that could be built by position."""


def signal(symbol: str, default: Any = False) -> Any:
    """A dataclass field carrying the value of the catalogue signal ``symbol`` (without the
    instance, ``basic.out.enableCtrl``); ``default`` is its value before the first decode."""
    return dataclasses.field(default=default, metadata={SYMBOL: symbol})


@functools.cache
def declared_signals(group: type) -> tuple[tuple[str, str], ...]:
    """(attribute, symbol) of every signal field of ``group``, in declaration order."""
    return tuple((f.name, f.metadata[SYMBOL]) for f in dataclasses.fields(group) if SYMBOL in f.metadata)


@dataclass(frozen=True, slots=True)
class Accessor:
    """Where one attribute of a group lies in its data block."""

    attribute: str
    symbol: str  # as resolved: with the prefix, without the instance
    byte: int
    shift: int  # the lowest bit of a bool or a bits field; 0 for byte, word, double word and real
    width_bits: int
    type: SignalType

    @classmethod
    def of(cls, attribute: str, symbol: str, location: SignalLocation) -> Accessor:
        address = location.address
        shift = address.bit if address.is_bit else 0
        return cls(attribute, symbol, address.byte, shift, location.bits, location.type)

    @property
    def mask(self) -> int:
        """The bits a bool or a field of at most 8 bits occupies in its byte."""
        return ((1 << self.width_bits) - 1) << self.shift

    @property
    def in_one_byte(self) -> bool:
        return self.type in (SignalType.BOOL, SignalType.BITS, SignalType.BYTE)


class GroupCodec(Generic[T]):
    """One signal group resolved against a catalogue section (see the module docstring)."""

    def __init__(self, group: type[T], resolve: Callable[[str], SignalLocation], prefix: str = ""):
        """``resolve`` maps a symbol to where it lies (it may record the signal as used);
        ``prefix`` is put before every declared symbol."""
        self.group = group
        group_class: type = group  # a class: hashable, the key of what is kept per group
        rows = [(attribute, prefix + symbol, resolve(prefix + symbol))
                for attribute, symbol in declared_signals(group_class)]
        if not rows:
            raise SignalGroupError(f"{group.__name__} declares no signal")
        directions = {location.direction for _, _, location in rows}
        if len(directions) != 1:
            raise SignalGroupError(f"{group.__name__} mixes directions: "
                                   + ", ".join(f"{symbol} {location.direction.value}" for _, symbol, location in rows))
        self.direction: Direction = directions.pop()
        self.accessors = tuple(Accessor.of(attribute, symbol, location) for attribute, symbol, location in rows)
        self.decode: Decoder
        self.encode: Encoder
        # read: a fresh instance of the group decoded from the area (fields without a symbol at their defaults)
        self.read: Callable[[bytes | bytearray], T]
        self.decode, self.encode, self.read = _functions(group_class, self.accessors)


_PYTHON_TYPE = {SignalType.BOOL: "bool", SignalType.BITS: "int", SignalType.BYTE: "int", SignalType.WORD: "int",
                SignalType.DWORD: "int", SignalType.REAL: "float"}


@functools.cache
def _functions(group: type, accessors: tuple[Accessor, ...]) -> tuple[Decoder, Encoder, Any]:
    """The generated functions of ``group`` laid out as ``accessors``, after checking the layout
    (SignalGroupError).  Kept per layout: every
    power-on of an NCK (a scenario, a campaign's run) compiles the same groups against the same
    catalogue, and the functions depend on nothing else."""
    name = group.__name__
    _check_overlaps(name, accessors)
    _check_types(group, accessors)
    _check_keyword_only(group)
    values = _values(accessors)
    decode = _generate(f"decode_{name}", "area, into", [f"into.{attribute} = {value}" for attribute, value in values])
    encode = _generate(f"encode_{name}", "area, values", _encoder_lines(accessors))
    # built by keyword, so a frozen group reads too
    keywords = ", ".join(f"{attribute}={value}" for attribute, value in values)
    read = _generate(f"read_{name}", "area", [f"return _group({keywords})"], group)
    return decode, encode, read


def _check_types(group: type, accessors: tuple[Accessor, ...]) -> None:
    """Each field is declared with the Python type its signal decodes to (bool, int or float)."""
    declared = {f.name: f.type if isinstance(f.type, str) else getattr(f.type, "__name__", str(f.type))
                for f in dataclasses.fields(group)}
    for accessor in accessors:
        expected = _PYTHON_TYPE[accessor.type]
        if declared[accessor.attribute] != expected:
            raise SignalGroupError(f"{group.__name__}.{accessor.attribute} is declared "
                                   f"{declared[accessor.attribute]}, but {accessor.symbol} is a "
                                   f"{accessor.type.value}: {expected}")


def _check_keyword_only(group: type) -> None:
    """Every signal field is keyword-only (``@dataclass(kw_only=True)``), so that no caller builds
    the group by position: reordering the declaration would silently move values to other signals."""
    positional = [f.name for f in dataclasses.fields(group) if SYMBOL in f.metadata and not f.kw_only]
    if positional:
        raise SignalGroupError(f"{group.__name__} lets {', '.join(positional)} be given by position: declare "
                               f"the group @dataclass(kw_only=True), so that it is built by keyword")


def _check_overlaps(group: str, accessors: tuple[Accessor, ...]) -> None:
    taken: dict[tuple[int, int], str] = {}
    for accessor in accessors:
        if accessor.in_one_byte:
            bits = [(accessor.byte, bit) for bit in range(8) if accessor.mask >> bit & 1]
        else:
            bits = [(accessor.byte + offset, bit) for offset in range(accessor.width_bits // 8) for bit in range(8)]
        for place in bits:
            if place in taken:
                raise SignalGroupError(f"{group}: {accessor.attribute} and {taken[place]} share byte {place[0]}")
            taken[place] = accessor.attribute


def _values(accessors: tuple[Accessor, ...]) -> list[tuple[str, str]]:
    """(attribute, the expression of its value in ``area``) of every accessor."""
    values = []
    for a in accessors:
        if a.type is SignalType.BOOL:
            value = f"(area[{a.byte}] & {a.mask}) != 0"
        elif a.type is SignalType.BITS:
            value = f"(area[{a.byte}] >> {a.shift}) & {(1 << a.width_bits) - 1}"
        elif a.type is SignalType.BYTE:
            value = f"area[{a.byte}]"
        elif a.type is SignalType.REAL:
            value = f"_unpack_real(area, {a.byte})[0]"
        else:
            value = f"int.from_bytes(area[{a.byte}:{a.byte + a.width_bits // 8}], 'big')"
        values.append((a.attribute, value))
    return values


def _encoder_lines(accessors: tuple[Accessor, ...]) -> list[str]:
    """The bits and fields of one byte are put in one store, in the order of the bytes; words,
    double words and reals are stored whole."""
    by_byte: defaultdict[int, list[Accessor]] = defaultdict(list)
    lines = []
    for a in accessors:
        if a.in_one_byte:
            by_byte[a.byte].append(a)
        elif a.type is SignalType.REAL:
            lines.append(f"_pack_real(area, {a.byte}, values.{a.attribute})")
        else:
            size = a.width_bits // 8
            lines.append(f"area[{a.byte}:{a.byte + size}] = (values.{a.attribute} & {(1 << a.width_bits) - 1})"
                         f".to_bytes({size}, 'big')")
    for byte, members in sorted(by_byte.items()):
        keep = 0xFF
        terms = []
        for a in members:
            keep &= ~a.mask & 0xFF
            if a.type is SignalType.BOOL:
                terms.append(f"({a.mask} if values.{a.attribute} else 0)")
            else:
                terms.append(f"((values.{a.attribute} << {a.shift}) & {a.mask})")
        kept = [f"(area[{byte}] & {keep})"] if keep else []
        lines.append(f"area[{byte}] = " + " | ".join(kept + terms))
    return lines


_NAMESPACE = {"_unpack_real": struct.Struct(">f").unpack_from, "_pack_real": struct.Struct(">f").pack_into}


def _generate(name: str, parameters: str, lines: list[str], group: type | None = None) -> Any:
    source = f"def {name}({parameters}):\n" + "".join(f"    {line}\n" for line in lines)
    namespace: dict[str, Any] = dict(_NAMESPACE, _group=group)
    exec(compile(source, f"<signal group {name}>", "exec"), namespace)
    function = namespace[name]
    function.__doc__ = source  # what was generated, for a reader at the prompt
    return function
