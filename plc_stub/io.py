"""The PLC's own process image and typed access to it, resolved once per signal.

A program asks for its inputs and outputs by name at construction, interface signals by
symbol (``X1.basic.out.traversKeyPlus``) and plant I/O by function (``MCP.plus.X1``),
and then reads and writes ``.value`` in every scan (through the accessors of
:mod:`interfaces.bit_access`, which the NC uses too).  A group of the NC's outputs
(:mod:`interfaces.signal_groups`, the groups the NC writes) is read whole, like a structure
copied from a data block: ``io.input_group(RetractionStatus, "CHAN1").read()``, decoded by the
same generated code as on the NC's side (:mod:`interfaces.group_codec`).  Asking for an input
as an output (or the other way round) is a programming error and fails when the program is built.
"""

from __future__ import annotations

import struct
from typing import Generic, TypeVar

from interfaces.bit_access import Bit, Field
from interfaces.group_codec import GroupCodec
from interfaces.image import ProcessImage
from interfaces.plc import PlcEnvironment
from interfaces.signals import Direction, SignalRef, SignalType, UnknownSignalError

T = TypeVar("T")
_INPUTS = (Direction.NC_TO_PLC, Direction.PLANT_TO_PLC)
_OUTPUTS = (Direction.PLC_TO_NC, Direction.PLC_TO_PLANT)


class Bool:
    """One bit of the PLC's image."""

    __slots__ = ("_area", "_bit", "name")

    def __init__(self, area: bytearray, ref: SignalRef):
        self._area = area
        self._bit = Bit(ref.address.byte, 1 << ref.address.bit)
        self.name = ref.name

    @property
    def value(self) -> bool:
        return self._bit.get(self._area)

    @value.setter
    def value(self, on: bool) -> None:
        self._bit.put(self._area, on)


class Byte:
    """One byte of the PLC's image (an override switch, an override factor)."""

    __slots__ = ("_area", "_field", "name")

    def __init__(self, area: bytearray, ref: SignalRef):
        self._area = area
        self._field = Field(ref.address.byte, 0, 8, SignalType.BYTE)
        self.name = ref.name

    @property
    def value(self) -> int:
        return self._field.get(self._area)

    @value.setter
    def value(self, number: int) -> None:
        self._field.put(self._area, number)


class BitField:
    """An unsigned field of a few bits inside one byte (a gear stage in DB31.DBX16.0..16.2)."""

    __slots__ = ("_area", "_field", "name")

    def __init__(self, area: bytearray, ref: SignalRef):
        self._area = area
        self._field = Field(ref.address.byte, ref.address.bit, ref.bits, SignalType.BITS)
        self.name = ref.name

    @property
    def value(self) -> int:
        return self._field.get(self._area)

    @value.setter
    def value(self, number: int) -> None:
        self._field.put(self._area, number)


class Real:
    """A REAL (32-bit IEEE 754, big-endian as S7 stores it) of the PLC's image: FC18's Pos and FRate."""

    __slots__ = ("_area", "_byte", "name")

    def __init__(self, area: bytearray, ref: SignalRef):
        self._area = area
        self._byte = ref.address.byte
        self.name = ref.name

    @property
    def value(self) -> float:
        return float(_REAL.unpack_from(self._area, self._byte)[0])

    @value.setter
    def value(self, number: float) -> None:
        _REAL.pack_into(self._area, self._byte, number)


_REAL = struct.Struct(">f")


class GroupInput(Generic[T]):
    """A group of one instance's NC -> PLC signals, read whole."""

    __slots__ = ("_area", "_read", "name")

    def __init__(self, area: bytearray, codec: GroupCodec[T], name: str):
        self._area = area
        self._read = codec.read
        self.name = name

    def read(self) -> T:
        return self._read(self._area)


class PlcIo:
    def __init__(self, environment: PlcEnvironment):
        self.environment = environment
        sizes = dict(environment.catalog.area_sizes)
        sizes.update(environment.plant_io.area_sizes())
        self.image = ProcessImage(sizes)

    def _resolve(self, name: str) -> SignalRef:
        try:
            return self.environment.catalog.resolve(name)
        except UnknownSignalError:
            return self.environment.plant_io.resolve(name)

    def is_wired(self, name: str) -> bool:
        """True if the machine has this plant I/O point."""
        return self.environment.plant_io.by_name(name) is not None

    def input(self, name: str) -> Bool:
        ref = self._checked(name, _INPUTS, SignalType.BOOL)
        return Bool(self.image.area(ref.area_key), ref)

    def output(self, name: str) -> Bool:
        ref = self._checked(name, _OUTPUTS, SignalType.BOOL)
        return Bool(self.image.area(ref.area_key), ref)

    def input_byte(self, name: str) -> Byte:
        ref = self._checked(name, _INPUTS, SignalType.BYTE)
        return Byte(self.image.area(ref.area_key), ref)

    def output_byte(self, name: str) -> Byte:
        ref = self._checked(name, _OUTPUTS, SignalType.BYTE)
        return Byte(self.image.area(ref.area_key), ref)

    def input_field(self, name: str) -> BitField:
        ref = self._checked(name, _INPUTS, SignalType.BITS)
        return BitField(self.image.area(ref.area_key), ref)

    def output_field(self, name: str) -> BitField:
        ref = self._checked(name, _OUTPUTS, SignalType.BITS)
        return BitField(self.image.area(ref.area_key), ref)

    def output_real(self, name: str) -> Real:
        ref = self._checked(name, _OUTPUTS, SignalType.REAL)
        return Real(self.image.area(ref.area_key), ref)

    def input_group(self, group: type[T], instance: str, prefix: str = "") -> GroupInput[T]:
        """The NC's outputs of ``group`` for ``instance`` (a channel, an axis, ``NC``...); ``prefix``
        goes before the group's symbols (one of a repeated block: ``auxMFuncs[2].in.``)."""
        refs: list[SignalRef] = []

        def resolve(symbol: str) -> SignalRef:
            refs.append(self.environment.catalog.resolve(f"{instance}.{symbol}"))
            return refs[-1]

        codec = GroupCodec(group, resolve, prefix)
        if codec.direction is not Direction.NC_TO_PLC:
            raise TypeError(f"{group.__name__} is an output of the PLC")
        areas = {ref.area_key for ref in refs}
        if len(areas) != 1:
            raise TypeError(f"{group.__name__} of {instance} spans {', '.join(sorted(areas))}")
        return GroupInput(self.image.area(areas.pop()), codec, f"{instance} {group.__name__}")

    def _checked(self, name: str, directions: tuple[Direction, ...], signal_type: SignalType) -> SignalRef:
        ref = self._resolve(name)
        if ref.direction not in directions:
            kind = "an input" if ref.direction in _INPUTS else "an output"
            raise TypeError(f"{name} is {kind} of the PLC")
        if ref.type is not signal_type:
            raise TypeError(f"{name} is a {ref.type.value}, not a {signal_type.value}")
        return ref
