"""Where the NC core finds its interface signals, resolved from the catalogue once.

The core never writes an address: it declares each group of signals it reads or writes once, by
their catalogue symbols without the instance (``basic.out.traversKeyPlus``), and gets the group's
decoder and encoder (:mod:`interfaces.group_codec`); a lone signal comes as a :class:`Bit` or
:class:`Field` with the byte offset and mask inside the instance's data block
(:mod:`interfaces.bit_access`, shared with the PLC runtime).  The cycle then works on the bytes
directly, which keeps an IPO cycle cheap.
"""

from __future__ import annotations

from typing import Any, TypeVar

from interfaces.bit_access import Bit, Field
from interfaces.group_codec import GroupCodec
from interfaces.signals import PLACEHOLDER, Catalog, InstanceKind, SignalDef, SignalType

T = TypeVar("T")


class SignalTable:
    """The signals of one DB kind, looked up by their symbol without the instance.

    ``used`` collects the catalogue symbol of every signal looked up: what the NC reads and writes
    (shared by the tables of one NCK, it tells which catalogue signals the NC models)."""

    def __init__(self, catalog: Catalog, kind: InstanceKind, used: set[str] | None = None):
        section = catalog.section(kind)
        prefix = PLACEHOLDER[kind] + "."
        self._signals: dict[str, SignalDef] = {s.symbol[len(prefix):]: s for s in section.signals}
        self.size = section.size
        self.used: set[str] = used if used is not None else set()
        self._codecs: dict[tuple[type, str], Any] = {}  # compiled once per table

    def definition(self, name: str) -> SignalDef:
        try:
            definition = self._signals[name]
        except KeyError:
            raise KeyError(f"the signal catalogue has no '{name}'") from None
        self.used.add(definition.symbol)
        return definition

    def codec(self, group: type[T], prefix: str = "") -> GroupCodec[T]:
        """The declared signal group ``group`` (:mod:`interfaces.group_codec`) compiled for this
        kind of data block; ``prefix`` goes before its symbols (``geoAxis2.out.``)."""
        key = (group, prefix)
        codec: GroupCodec[T] | None = self._codecs.get(key)  # keyed by its group: a GroupCodec[T]
        if codec is None:
            codec = self._codecs[key] = GroupCodec(group, self.definition, prefix)
        return codec

    def bit(self, name: str) -> Bit:
        definition = self.definition(name)
        if definition.type is not SignalType.BOOL:
            raise TypeError(f"{name} is a {definition.type.value}, not a bool")
        return Bit(definition.address.byte, 1 << definition.address.bit)

    def field(self, name: str) -> Field:
        definition = self.definition(name)
        address = definition.address
        shift = address.bit if address.is_bit else 0
        return Field(address.byte, shift, definition.bits, definition.type)

    def real_offset(self, name: str) -> int:
        definition = self.definition(name)
        if definition.type is not SignalType.REAL:
            raise TypeError(f"{name} is a {definition.type.value}, not a real")
        return definition.address.byte
