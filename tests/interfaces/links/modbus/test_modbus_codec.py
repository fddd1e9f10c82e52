"""The Modbus convention of interfaces/links/modbus/codec.py, checked both ways: from a signal to its
register and coil, and from register and coil values back to the signal in the process image."""

from __future__ import annotations

from functools import lru_cache

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from interfaces.catalog import load_catalog
from interfaces.image import ProcessImage
from interfaces.links.modbus.codec import (
    DATA_START_BYTE,
    RegisterMap,
    Table,
    bits_writable,
    display_number,
    read_bits,
    read_registers,
    registers_text,
    text_registers,
    words_as_bits,
    write_bits,
    write_registers,
)
from interfaces.plant_io import PlantIoMap
from interfaces.signals import Direction, ExpandedCatalog, InterfaceLayout, SignalType, expand

AXES = ("X1", "Z1", "Y1", "SP1", "SP2", "SP3")
PLANT = PlantIoMap.from_mapping({"I0.0": "EStop.chainOk", "I1.0": "X1.refCam", "I8.3": "MCP.jog",
                                 "Q0.0": "Drives.on", "Q1.7": "Lamp.alarm"}, AXES)


@lru_cache(maxsize=1)
def catalog() -> ExpandedCatalog:
    return expand(load_catalog(), InterfaceLayout(("CHAN1",), AXES))


@lru_cache(maxsize=1)
def register_map() -> RegisterMap:
    return RegisterMap.build(catalog(), PLANT.area_sizes())


def images() -> tuple[ProcessImage, dict[str, bytearray]]:
    image = ProcessImage({**catalog().area_sizes, **PLANT.area_sizes()})
    return image, image.areas


# ------------------------------------------------------------------------------ layout


def test_plant_area_then_db_ranges_from_register_16() -> None:
    nc_to_plc = register_map().segments[Table.NC_TO_PLC]
    assert (nc_to_plc[0].area, nc_to_plc[0].start, nc_to_plc[0].table_byte) == ("I", 0, DATA_START_BYTE)
    assert [segment.area for segment in nc_to_plc[1:5]] == ["DB10", "DB11", "DB19", "DB21"]
    plc_to_nc = register_map().segments[Table.PLC_TO_NC]
    assert (plc_to_nc[0].area, plc_to_nc[0].table_byte) == ("Q", DATA_START_BYTE)
    # the PLC's user alarms DB2 behind the axes: added after the layout, it moves no address
    assert [segment.area for segment in plc_to_nc][-7:] == ["DB31", "DB32", "DB33", "DB34", "DB35", "DB36", "DB2"]


def test_every_segment_starts_on_a_register_and_keeps_the_parity_of_its_db_byte() -> None:
    for table in Table:
        previous_end = DATA_START_BYTE
        for segment in register_map().segments[table]:
            assert segment.table_byte % 2 == segment.start % 2
            assert segment.table_byte - (segment.table_byte % 2) >= previous_end  # never shares a register
            previous_end = segment.table_byte + segment.stop - segment.start
        assert register_map().table_bytes[table] % 2 == 0


def test_segments_hold_exactly_the_bytes_of_their_direction() -> None:
    for table, direction in ((Table.NC_TO_PLC, Direction.NC_TO_PLC), (Table.PLC_TO_NC, Direction.PLC_TO_NC)):
        expected = set(catalog().byte_ranges(direction))
        placed = {(s.area, s.start, s.stop) for s in register_map().segments[table] if s.area.startswith("DB")}
        assert placed == expected


# ------------------------------------------------------------------------------ both ways


@settings(max_examples=200, deadline=None)
@given(st.data())
def test_a_bit_signal_is_its_register_bit_and_its_coil(data: st.DataObject) -> None:
    bits = [s for s in catalog().signals if s.definition.type is SignalType.BOOL]
    signal = data.draw(st.sampled_from(bits))
    ref = catalog().resolve(signal.symbol)
    location = register_map().location(ref)
    assert location is not None and location.coil is not None and location.register_bit is not None
    table = Table.NC_TO_PLC if ref.direction is Direction.NC_TO_PLC else Table.PLC_TO_NC
    assert location.table is table
    # image -> table: the signal set alone shows in its register bit and its coil
    image, areas = images()
    image.write(ref, 1)
    buffer = bytearray(register_map().table_bytes[table])
    register_map().fill_table(table, areas, buffer)
    registers = read_registers(buffer, 0, len(buffer) // 2)
    assert [(r, v) for r, v in enumerate(registers) if v] == [(location.register, 1 << location.register_bit)]
    assert read_bits(buffer, 0, len(buffer) * 8).index(True) == location.coil
    assert location.coil == 16 * location.register + (location.register_bit + 8) % 16
    # table -> image: setting the coil alone gives back the signal
    buffer = bytearray(len(buffer))
    write_bits(buffer, location.coil, [True])
    fresh, fresh_areas = images()
    register_map().fill_areas(table, buffer, fresh_areas)
    assert fresh.read(ref) == 1
    assert sum(sum(area) for area in fresh_areas.values()) == 1 << ref.address.bit


def test_db31_dbx60_4_of_the_first_axis_by_hand() -> None:
    ref = catalog().resolve("DB31.DBX60.4")
    location = register_map().location(ref)
    assert location is not None
    segment = next(s for s in register_map().segments[Table.NC_TO_PLC] if s.area == "DB31")
    table_byte = segment.table_byte + 60 - 60  # the DB31 range starts at its byte 60
    assert (location.register, location.register_bit) == (table_byte // 2, 8 + 4)  # even byte: high half
    assert location.coil == table_byte * 8 + 4
    assert location.register_kind == "input_register" and location.bit_kind == "discrete_input"


@settings(max_examples=100, deadline=None)
@given(st.data())
def test_words_and_bytes_are_big_endian_registers(data: st.DataObject) -> None:
    wide = [s for s in catalog().signals if s.definition.type in (SignalType.WORD, SignalType.DWORD, SignalType.BYTE)]
    signal = data.draw(st.sampled_from(wide))
    ref = catalog().resolve(signal.symbol)
    size = ref.address.size
    value = data.draw(st.integers(min_value=0, max_value=(1 << (8 * size)) - 1))
    location = register_map().location(ref)
    assert location is not None
    image, areas = images()
    image.write(ref, value)
    buffer = bytearray(register_map().table_bytes[location.table])
    register_map().fill_table(location.table, areas, buffer)
    registers = read_registers(buffer, location.register, location.registers)
    if size == 1:
        assert registers == [value << location.byte_bit]
    else:
        assert ref.address.byte % 2 == 0 and location.byte_bit == 0
        combined = 0
        for register in registers:
            combined = combined << 16 | register
        assert combined == value
    back, back_areas = images()
    register_map().fill_areas(location.table, buffer, back_areas)
    assert back.read(ref) == value


def test_plant_io_lies_in_the_plant_segments() -> None:
    jog = register_map().location(PLANT.resolve("MCP.jog"))
    lamp = register_map().location(PLANT.resolve("Lamp.alarm"))
    assert jog is not None and lamp is not None
    assert (jog.table, jog.coil) == (Table.NC_TO_PLC, (DATA_START_BYTE + 8) * 8 + 3)
    assert (lamp.table, lamp.register, lamp.register_bit) == (Table.PLC_TO_NC, 16, 7)  # Q1 low byte


# ------------------------------------------------------------------------------ writes


def test_register_writes_keep_padding_and_reserve_at_zero() -> None:
    writable = register_map().writable
    table = bytearray(register_map().table_bytes[Table.PLC_TO_NC])
    write_registers(table, writable, 0, [0xFFFF] * (len(table) // 2))
    for index, byte in enumerate(table):
        assert byte == (0xFF if writable[index] else 0)
    assert table[0:4] == b"\xff" * 4 and table[4:DATA_START_BYTE] == bytes(DATA_START_BYTE - 4)
    padding = [i for i in range(DATA_START_BYTE, len(table)) if not writable[i]]
    assert padding  # DB21 byte 321 starts in a low byte
    assert not bits_writable(writable, padding[0] * 8, 1)
    assert bits_writable(writable, DATA_START_BYTE * 8, 8)


def test_display_numbers_follow_the_modicon_convention() -> None:
    assert display_number("coil", 0) == "00001"
    assert display_number("discrete_input", 484) == "10485"
    assert display_number("input_register", 30) == "30031"
    assert display_number("holding_register", 9998) == "49999"
    assert display_number("holding_register", 9999) == "410000"


def test_words_as_bits_pack_two_bytes_bit_zero_first() -> None:
    assert words_as_bits(bytes([0x01, 0x80, 0xFF, 0x00]), 0, 2) == [0x8001, 0x00FF]


@given(st.binary(max_size=300))
def test_text_round_trips_through_registers(text: bytes) -> None:
    assert registers_text(text_registers(text), len(text)) == text


@pytest.mark.parametrize("table", list(Table))
def test_the_shipped_machines_fit_the_coil_numbers(table: Table) -> None:
    assert register_map().registers(table) * 16 <= 65536
