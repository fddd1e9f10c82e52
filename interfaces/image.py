"""Process images: the bytes of the interface data blocks and of the plant I/O.

One ``bytearray`` per area (``DB10``, ``DB11``, ``DB21``.., ``DB31``.., ``I``, ``Q``).
Words and double words are big-endian as in S7; a ``real`` is an IEEE 754 single in a
double word.  Every link (in-process, Modbus, CAN, S7, FMU) only moves these bytes.

Typed access goes through :class:`~interfaces.signals.SignalRef`; the NC core and the
PLC programs resolve their signals once and then work on the byte areas directly.
"""

from __future__ import annotations

import struct
from collections.abc import Iterable, Mapping
from dataclasses import dataclass

from interfaces.bit_access import read_field, write_field
from interfaces.errors import VcError
from interfaces.signals import SignalRef, SignalType

Value = int | float

_REAL = struct.Struct(">f")


class ValueRangeError(VcError, ValueError):
    """A value that does not fit the signal's type (e.g. 300 for a byte)."""


def value_range(signal_type: SignalType, bits: int) -> tuple[float, float]:
    """Smallest and largest value a signal of this type holds."""
    if signal_type is SignalType.REAL:
        return (-3.4028234663852886e38, 3.4028234663852886e38)
    return (0, (1 << bits) - 1)


def decode(buffer: bytes | bytearray, ref: SignalRef) -> Value:
    """Read the value of ``ref`` from the bytes of its area."""
    address = ref.address
    if ref.type is SignalType.REAL:
        return float(_REAL.unpack_from(buffer, address.byte)[0])
    return read_field(buffer, address.byte, address.bit if address.is_bit else 0, ref.bits)


def encode(buffer: bytearray, ref: SignalRef, value: Value) -> None:
    """Write ``value`` into the bytes of ``ref``'s area; raises :class:`ValueRangeError`."""
    address = ref.address
    signal_type = ref.type
    if signal_type is SignalType.REAL:
        _REAL.pack_into(buffer, address.byte, float(value))
        return
    if isinstance(value, float):
        if not value.is_integer():
            raise ValueRangeError(f"{ref.name} is a {signal_type.value}; {value} is not a whole number")
        value = int(value)
    low, high = value_range(signal_type, ref.bits)
    if not low <= value <= high:
        raise ValueRangeError(f"{ref.name} is a {signal_type.value}; {value} is outside {int(low)}..{int(high)}")
    write_field(buffer, address.byte, address.bit if address.is_bit else 0, ref.bits, value)


@dataclass(frozen=True, slots=True)
class ByteChange:
    area: str
    byte: int
    old: int
    new: int


class ProcessImage:
    """Named byte areas with typed access, snapshots, diffs and direction-wise copies.

    ``version`` counts writes through this class (and ``touch`` for writers that change
    an area's bytes directly), so a reader can skip decoding an image that did not change.
    """

    __slots__ = ("areas", "version")

    def __init__(self, sizes: Mapping[str, int]):
        self.areas: dict[str, bytearray] = {key: bytearray(size) for key, size in sizes.items()}
        self.version = 0

    def touch(self) -> None:
        """Record that bytes were changed directly in an area."""
        self.version += 1

    def area(self, key: str) -> bytearray:
        return self.areas[key]

    def read(self, ref: SignalRef) -> Value:
        return decode(self.areas[ref.area_key], ref)

    def write(self, ref: SignalRef, value: Value) -> None:
        encode(self.areas[ref.area_key], ref, value)
        self.version += 1

    def snapshot(self) -> dict[str, bytes]:
        return {key: bytes(buffer) for key, buffer in self.areas.items()}

    def restore(self, snapshot: Mapping[str, bytes]) -> None:
        for key, content in snapshot.items():
            self.areas[key][:] = content
        self.version += 1

    def copy_from(self, source: ProcessImage, ranges: Iterable[tuple[str, int, int]]) -> None:
        """Copy the given ``(area, start, stop)`` byte ranges from ``source`` into this image."""
        for key, start, stop in ranges:
            self.areas[key][start:stop] = source.areas[key][start:stop]
        self.version += 1

    def changes_since(self, snapshot: Mapping[str, bytes]) -> list[ByteChange]:
        """Bytes that differ from ``snapshot`` (cheap when nothing changed)."""
        changes: list[ByteChange] = []
        for key, buffer in self.areas.items():
            before = snapshot.get(key)
            if before is None or before == buffer:
                continue
            for index, (old, new) in enumerate(zip(before, buffer, strict=True)):
                if old != new:
                    changes.append(ByteChange(key, index, old, new))
        return changes


class RangeCopy:
    """The same ``(area, start, stop)`` byte ranges copied from one image into another again and
    again (every PLC scan): each range is bound once as a view on both buffers, as the accessors
    bind theirs (an image keeps its areas' buffers, at their size, for its whole life), so that a
    copy neither looks an area up nor builds a temporary copy of the bytes."""

    __slots__ = ("_pieces", "source", "target")

    def __init__(self, target: ProcessImage, source: ProcessImage, ranges: Iterable[tuple[str, int, int]]):
        self.target = target
        self.source = source
        self._pieces = [(memoryview(target.areas[key])[start:stop], memoryview(source.areas[key])[start:stop])
                        for key, start, stop in ranges]

    def run(self) -> None:
        for into, origin in self._pieces:
            into[:] = origin
        self.target.version += 1
