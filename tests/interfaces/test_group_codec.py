"""A declared signal group compiled into a generated decoder and encoder (interfaces/group_codec.py):
the generated code reads and writes exactly what the shared bit access reads and writes, by
attribute, whatever the order of the declaration."""

from __future__ import annotations

import dataclasses
import random
import struct
from dataclasses import dataclass

import pytest

from interfaces.address import Address
from interfaces.bit_access import read_field
from interfaces.group_codec import GroupCodec, SignalGroupError, declared_signals, signal
from interfaces.signals import Direction, Origin, SignalDef, SignalType, Trigger

_WIDTH = {SignalType.BOOL: "X", SignalType.BITS: "X", SignalType.BYTE: "B", SignalType.WORD: "W",
          SignalType.DWORD: "D", SignalType.REAL: "D"}
_BITS = {SignalType.BOOL: 1, SignalType.BYTE: 8, SignalType.WORD: 16, SignalType.DWORD: 32, SignalType.REAL: 32}

# a small catalogue section: (symbol, byte, bit, type, bits of a BITS field, direction)
_SECTION = {
    "out.a": (0, 0, SignalType.BOOL, 0, Direction.PLC_TO_NC),
    "out.b": (0, 7, SignalType.BOOL, 0, Direction.PLC_TO_NC),
    "out.gear": (0, 2, SignalType.BITS, 3, Direction.PLC_TO_NC),
    "out.override": (1, -1, SignalType.BYTE, 0, Direction.PLC_TO_NC),
    "out.word": (2, -1, SignalType.WORD, 0, Direction.PLC_TO_NC),
    "out.dword": (4, -1, SignalType.DWORD, 0, Direction.PLC_TO_NC),
    "out.real": (8, -1, SignalType.REAL, 0, Direction.PLC_TO_NC),
    "in.ready": (12, 3, SignalType.BOOL, 0, Direction.NC_TO_PLC),
    "in.overlap": (0, 3, SignalType.BOOL, 0, Direction.PLC_TO_NC),  # inside out.gear's bits
    "x1.in.ready": (13, 0, SignalType.BOOL, 0, Direction.NC_TO_PLC),
    "x2.in.ready": (13, 1, SignalType.BOOL, 0, Direction.NC_TO_PLC),
}


def resolve(symbol: str) -> SignalDef:
    byte, bit, kind, bits, direction = _SECTION[symbol]
    return SignalDef(Address("DB", 31, byte, bit, _WIDTH[kind]), f"<Axis>.{symbol}", symbol, direction, kind,
                     bits or _BITS[kind], Trigger.LEVEL, "", "test", Origin.PROJECT)


@dataclass(slots=True, kw_only=True)
class Requests:
    a: bool = signal("out.a")
    b: bool = signal("out.b")
    gear: int = signal("out.gear", 0)
    override: int = signal("out.override", 0)
    word: int = signal("out.word", 0)
    dword: int = signal("out.dword", 0)
    real: float = signal("out.real", 0.0)
    derived: str = "left alone"  # no symbol: not a signal


@dataclass(frozen=True, slots=True, kw_only=True)
class Ready:
    ready: bool = signal("in.ready")


def test_the_declaration_is_the_fields_with_a_symbol_in_order() -> None:
    assert declared_signals(Requests) == (("a", "out.a"), ("b", "out.b"), ("gear", "out.gear"),
                                          ("override", "out.override"), ("word", "out.word"),
                                          ("dword", "out.dword"), ("real", "out.real"))


@pytest.mark.parametrize("seed", range(20))
def test_the_decoder_reads_what_the_bit_access_reads(seed: int) -> None:
    area = bytearray(random.Random(seed).randbytes(16))
    codec = GroupCodec(Requests, resolve)
    values = codec.read(area)
    for accessor in codec.accessors:
        if accessor.type is SignalType.REAL:
            expected: object = struct.unpack_from(">f", area, accessor.byte)[0]
        elif accessor.type is SignalType.BOOL:
            expected = bool(read_field(area, accessor.byte, accessor.shift, 1))
        else:
            expected = read_field(area, accessor.byte, accessor.shift, accessor.width_bits)
        assert getattr(values, accessor.attribute) == expected, accessor
    assert values.derived == "left alone"


@pytest.mark.parametrize("seed", range(20))
def test_encode_then_decode_gives_the_values_and_keeps_every_other_bit(seed: int) -> None:
    rng = random.Random(seed)
    before = bytearray(rng.randbytes(16))
    values = Requests(a=rng.random() < 0.5, b=rng.random() < 0.5, gear=rng.randrange(8), override=rng.randrange(256),
                      word=rng.randrange(1 << 16), dword=rng.randrange(1 << 32), real=1.5)
    codec = GroupCodec(Requests, resolve)
    area = bytearray(before)
    codec.encode(area, values)
    assert codec.read(area) == values
    untouched = bytearray(before)
    untouched[0] &= 0b0110_0010  # bits 0, 2..4 and 7 of byte 0, bytes 1..11 belong to the group
    area[0] &= 0b0110_0010
    assert area[0] == untouched[0] and area[12:] == before[12:]


def test_values_beyond_a_field_are_cut_to_its_width() -> None:
    codec = GroupCodec(Requests, resolve)
    area = bytearray(16)
    codec.encode(area, Requests(gear=0b1111_1111, word=0x12345))
    assert area[0] == 0b0001_1100 and area[2:4] == b"\x23\x45"


def test_a_prefix_selects_a_repeated_block() -> None:
    first, second = GroupCodec(Ready, resolve, "x1."), GroupCodec(Ready, resolve, "x2.")
    area = bytearray(16)
    second.encode(area, Ready(ready=True))
    assert (first.read(area), second.read(area)) == (Ready(ready=False), Ready(ready=True))
    assert area[13] == 0b10


def test_resolving_records_every_symbol() -> None:
    seen: list[str] = []

    def recording(symbol: str) -> SignalDef:
        seen.append(symbol)
        return resolve(symbol)

    GroupCodec(Ready, recording, "x1.")
    assert seen == ["x1.in.ready"]


@dataclass(slots=True, kw_only=True)
class Reordered:
    """``Requests`` declared in another order."""

    real: float = signal("out.real", 0.0)
    dword: int = signal("out.dword", 0)
    gear: int = signal("out.gear", 0)
    b: bool = signal("out.b")
    word: int = signal("out.word", 0)
    a: bool = signal("out.a")
    override: int = signal("out.override", 0)


@pytest.mark.parametrize("seed", range(10))
def test_the_order_of_a_declaration_changes_no_byte(seed: int) -> None:
    rng = random.Random(seed)
    values = {"a": rng.random() < 0.5, "b": rng.random() < 0.5, "gear": rng.randrange(8),
              "override": rng.randrange(256), "word": rng.randrange(1 << 16), "dword": rng.randrange(1 << 32),
              "real": 2.5}
    before = bytearray(rng.randbytes(16))
    declared, reordered = bytearray(before), bytearray(before)
    GroupCodec(Requests, resolve).encode(declared, Requests(**values))
    GroupCodec(Reordered, resolve).encode(reordered, Reordered(**values))
    assert declared == reordered
    read = GroupCodec(Reordered, resolve).read(declared)
    assert {name: getattr(read, name) for name in values} == values


def test_a_group_that_can_be_built_by_position_is_refused() -> None:
    @dataclass
    class Positional:
        a: bool = signal("out.a")
        b: bool = signal("out.b")

    with pytest.raises(SignalGroupError, match=r"Positional lets a, b be given by position: declare the group "
                                               r"@dataclass\(kw_only=True\)"):
        GroupCodec(Positional, resolve)


def test_every_group_of_the_interface_is_built_by_keyword() -> None:
    from interfaces import signal_groups

    groups = [item for item in vars(signal_groups).values()
              if isinstance(item, type) and dataclasses.is_dataclass(item) and declared_signals(item)]
    assert len(groups) >= 20
    for group in groups:
        assert all(field.kw_only for field in dataclasses.fields(group)), group
        with pytest.raises(TypeError):
            group(*[field.default for field in dataclasses.fields(group)])


def test_a_group_is_one_direction() -> None:
    @dataclass(kw_only=True)
    class Mixed:
        a: bool = signal("out.a")
        ready: bool = signal("in.ready")

    with pytest.raises(SignalGroupError, match="mixes directions"):
        GroupCodec(Mixed, resolve)


def test_two_signals_on_one_bit_are_refused() -> None:
    @dataclass(kw_only=True)
    class Overlapping:
        gear: int = signal("out.gear", 0)
        overlap: bool = signal("in.overlap")

    with pytest.raises(SignalGroupError, match="share byte 0"):
        GroupCodec(Overlapping, resolve)


def test_a_field_of_another_type_than_its_signal_is_refused() -> None:
    @dataclass(kw_only=True)
    class Mistyped:
        override: bool = signal("out.override")

    with pytest.raises(SignalGroupError, match=r"Mistyped.override is declared bool, but out.override is a byte: int"):
        GroupCodec(Mistyped, resolve)


def test_a_group_without_signals_is_refused() -> None:
    @dataclass(kw_only=True)
    class Empty:
        value: int = 0

    with pytest.raises(SignalGroupError, match="declares no signal"):
        GroupCodec(Empty, resolve)


def test_an_unknown_symbol_fails_at_power_on() -> None:
    @dataclass(kw_only=True)
    class Unknown:
        a: bool = signal("out.nothing")

    with pytest.raises(KeyError):
        GroupCodec(Unknown, resolve)
