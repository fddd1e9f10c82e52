"""The CAN convention of interfaces/links/can/codec.py, checked both ways: the layout of the frames, the
process image through the frames and back, the place of every signal, the checksum, the link
frames and the description stream."""

from __future__ import annotations

import random
from functools import lru_cache

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from interfaces.catalog import load_catalog
from interfaces.exchange import exchange_ranges
from interfaces.image import ProcessImage, decode
from interfaces.links.can.codec import (
    FD_LENGTHS,
    LINK_VERSION,
    CanLayout,
    CanMapError,
    CanSettings,
    DescriptionAssembler,
    NcLink,
    PlcLink,
    checksum,
    description_frames,
)
from interfaces.plant_io import PlantIoMap
from interfaces.signals import Direction, ExpandedCatalog, InterfaceLayout, SignalType, expand

AXES = ("X1", "Z1", "Y1", "SP1", "SP2", "SP3")
PLANT = PlantIoMap.from_mapping({"I0.0": "EStop.chainOk", "I1.0": "X1.refCam", "I8.3": "MCP.jog",
                                 "IB9": "MCP.feedOverride", "Q0.0": "Drives.on", "Q1.7": "Lamp.alarm"}, AXES)
SETTINGS = [CanSettings(), CanSettings(fd=False), CanSettings(checksum=False), CanSettings(fd=False, checksum=False)]
SETTING_IDS = ["fd", "classic", "fd-no-checksum", "classic-no-checksum"]
DIRECTIONS = (Direction.NC_TO_PLC, Direction.PLC_TO_NC)


@lru_cache(maxsize=1)
def catalog() -> ExpandedCatalog:
    return expand(load_catalog(), InterfaceLayout(("CHAN1",), AXES))


DEFAULT = CanSettings()


@lru_cache(maxsize=8)
def layout(settings: CanSettings = DEFAULT) -> CanLayout:
    return CanLayout.build(catalog(), PLANT.area_sizes(), settings)


def image() -> ProcessImage:
    return ProcessImage({**catalog().area_sizes, **PLANT.area_sizes()})


# ------------------------------------------------------------------------------ layout


@pytest.mark.parametrize("settings", SETTINGS, ids=SETTING_IDS)
def test_the_frames_cover_every_byte_a_link_moves_once_and_keep_words_whole(settings: CanSettings) -> None:
    for direction in DIRECTIONS:
        covered = [(slot.area, byte) for slot in layout(settings).slots[direction]
                   for byte in range(slot.start, slot.stop)]
        expected = [(area, byte) for area, start, stop in exchange_ranges(catalog(), PLANT.area_sizes(), direction)
                    for byte in range(start, stop)]
        assert covered == expected
    for item in catalog().signals:
        address = item.address
        slots = {layout(settings).slot_of(direction, address.area_key, byte)
                 for direction in DIRECTIONS for byte in range(address.byte, address.byte + address.size)}
        assert len(slots - {None}) == 1, item.symbol


@pytest.mark.parametrize("settings", SETTINGS, ids=SETTING_IDS)
def test_frame_lengths_identifiers_and_sizes(settings: CanSettings) -> None:
    nc_first, plc_first = settings.nc_to_plc_id, settings.plc_to_nc_id
    for direction, first in ((Direction.NC_TO_PLC, nc_first), (Direction.PLC_TO_NC, plc_first)):
        slots = layout(settings).slots[direction]
        assert [slot.can_id for slot in slots] == list(range(first, first + len(slots)))
        for slot in slots:
            used = slot.stop - slot.start + (1 if settings.checksum else 0)
            assert used <= slot.length <= settings.frame_bytes
            assert slot.length in FD_LENGTHS if settings.fd else slot.length == used


def test_turn_mill_frames_as_the_docstring_draws_them() -> None:
    nc = layout().slots[Direction.NC_TO_PLC]
    plc = layout().slots[Direction.PLC_TO_NC]
    assert (len(nc), len(plc)) == (20, 15)
    assert [(hex(s.can_id), s.name, s.length) for s in nc[:5]] == [
        ("0x200", "NC_I_0_9", 12), ("0x201", "NC_DB10_106_109", 5), ("0x202", "NC_DB11_6_7", 3),
        ("0x203", "NC_DB19_20_20", 2), ("0x204", "NC_DB21_32_93", 64)]
    assert (hex(plc[3].can_id), plc[3].name, plc[3].length) == ("0x403", "PLC_DB19_0_0", 2)
    assert (hex(nc[-9].can_id), nc[-9].name, nc[-9].length) == ("0x20b", "NC_DB31_60_105", 48)
    assert [(hex(s.can_id), s.name, s.length) for s in nc[-3:]] == [
        ("0x211", "NC_DB100_0_59", 64), ("0x212", "NC_DB100_60_67", 12),  # the alarm block, a dword not cut
        ("0x213", "NC_DB10_110_117", 12)]  # the software cams, behind every block (link version 5)
    assert (hex(plc[8].can_id), plc[8].name) == ("0x408", "PLC_DB31_0_43")
    assert (hex(plc[-1].can_id), plc[-1].name, plc[-1].length) == ("0x40e", "PLC_DB2_180_187", 12)  # behind the axes
    classic = layout(CanSettings(fd=False))
    assert (len(classic.slots[Direction.NC_TO_PLC]), len(classic.slots[Direction.PLC_TO_NC])) == (111, 63)


def test_identifiers_that_clash_or_overflow_are_refused_with_their_ranges() -> None:
    with pytest.raises(CanMapError) as caught:
        CanLayout.build(catalog(), PLANT.area_sizes(), CanSettings(nc_to_plc_id=0x102))
    assert str(caught.value) == ("the link frames (0x100..0x102) overlap the NC-to-PLC data frames (0x102..0x115)")
    with pytest.raises(CanMapError) as caught:
        CanLayout.build(catalog(), PLANT.area_sizes(), CanSettings(plc_to_nc_id=0x7FA))
    assert str(caught.value) == ("the PLC-to-NC data frames need identifiers 0x7FA..0x808; standard identifiers"
                                 " end at 0x7FF")


# ------------------------------------------------------------------------------ both ways


@settings(max_examples=40, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), which=st.sampled_from(range(len(SETTINGS))))
def test_an_image_survives_the_frames(seed: int, which: int) -> None:
    settings_ = SETTINGS[which]
    source = image()
    generator = random.Random(seed)
    for buffer in source.areas.values():
        buffer[:] = generator.randbytes(len(buffer))
    target = image()
    for direction in DIRECTIONS:
        frames = layout(settings_).frames(direction, source.areas)
        for slot, frame in zip(layout(settings_).slots[direction], frames, strict=True):
            assert frame.can_id == slot.can_id and len(frame.data) == slot.length and frame.fd is settings_.fd
            assert slot.decode(frame.data, target.areas)
    for direction in DIRECTIONS:
        for area, start, stop in exchange_ranges(catalog(), PLANT.area_sizes(), direction):
            assert target.areas[area][start:stop] == source.areas[area][start:stop]


@settings(max_examples=30, deadline=None)
@given(seed=st.integers(0, 2**32 - 1))
def test_a_damaged_frame_is_dropped_and_changes_nothing(seed: int) -> None:
    generator = random.Random(seed)
    source = image()
    for buffer in source.areas.values():
        buffer[:] = generator.randbytes(len(buffer))
    slot = generator.choice(layout().slots[Direction.PLC_TO_NC])
    frame = slot.encode(source.areas)
    damaged = bytearray(frame.data)
    position = generator.randrange(len(damaged))
    damaged[position] ^= 1 << generator.randrange(8)
    target = image()
    before = target.snapshot()
    assert not slot.decode(bytes(damaged), target.areas)
    assert not slot.decode(frame.data[:-1], target.areas)
    assert target.snapshot() == before


def _value_from_frame(data: bytes, start_bit: int, length: int, big_endian: bool) -> int:
    """A signal's raw value read from frame bytes as a DBC tool reads it."""
    if not big_endian:
        return int.from_bytes(data, "little") >> start_bit & ((1 << length) - 1)
    first = start_bit // 8  # Motorola: the start bit is the most significant bit, bit 7 of the first byte
    assert start_bit % 8 == 7
    return int.from_bytes(data[first: first + length // 8], "big")


@settings(max_examples=25, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), which=st.sampled_from(range(len(SETTINGS))))
def test_every_signal_sits_at_the_bit_its_location_names(seed: int, which: int) -> None:
    settings_ = SETTINGS[which]
    generator = random.Random(seed)
    source = image()
    for buffer in source.areas.values():
        buffer[:] = generator.randbytes(len(buffer))
    refs = [item.ref() for item in catalog().signals] + [point.ref() for point in PLANT.points]
    for ref in generator.sample(refs, 60):
        location = layout(settings_).location(ref)
        assert location is not None, ref.name
        frame = location.slot.encode(source.areas)
        raw = _value_from_frame(frame.data, location.start_bit, location.length, location.big_endian)
        value = decode(source.areas[ref.area_key], ref)
        if ref.type is SignalType.REAL:
            assert raw == int.from_bytes(source.areas[ref.area_key][ref.address.byte: ref.address.byte + 4], "big")
        else:
            assert raw == value, ref.name


def test_locations_of_known_signals() -> None:
    synchronized = layout().location(catalog().resolve("X1.basic.in.enc1Synchronized"))  # DB31.DBX60.4
    assert synchronized is not None
    assert (synchronized.can_id, synchronized.start_bit, synchronized.length) == (0x20B, 4, 1)
    cam = layout().location(catalog().resolve("X1.basic.out.refPointApproachCam"))  # DB31.DBX12.7
    assert cam is not None and (cam.can_id, cam.start_bit) == (0x408, 12 * 8 + 7)
    override = layout().location(catalog().resolve("CHAN1.basic.out.pathFeedrateOvrFactor"))  # DB21.DBB4
    assert override is not None and (override.can_id, override.start_bit, override.big_endian) == (0x404, 32, False)
    jog = layout().location(PLANT.resolve("MCP.jog"))  # I8.3
    assert jog is not None and (jog.can_id, jog.start_bit) == (0x200, 8 * 8 + 3)


def test_the_checksum_is_crc8_sae_j1850() -> None:
    # the check value of CRC-8/SAE-J1850 is 0x4B for "123456789": here the identifier carries "12"
    assert checksum(0x3132, b"3456789", 7) == 0x4B
    assert checksum(0x200, bytes(8), 7) != checksum(0x201, bytes(8), 7)  # the identifier counts


# ------------------------------------------------------------------------------ link frames, description


@given(mode=st.sampled_from((1, 2)), life=st.integers(0, 255), session=st.integers(1, 0xFFFF),
       grant=st.integers(0, 0xFFFF))
def test_nc_link_frames_both_ways(mode: int, life: int, session: int, grant: int) -> None:
    frame = NcLink(mode, life, session, grant).encode(CanSettings())
    assert frame.can_id == 0x100 and len(frame.data) == 8
    assert frame.data[0] == LINK_VERSION << 4 | mode and frame.data[1] == life
    assert int.from_bytes(frame.data[2:4], "big") == session and int.from_bytes(frame.data[4:6], "big") == grant
    assert NcLink.decode(0x100, frame.data) == NcLink(mode, life, session, grant)
    assert NcLink.decode(0x101, frame.data) is None  # the identifier is part of the checksum


@given(life=st.integers(0, 255), ready=st.integers(0, 0xFFFF), done=st.integers(0, 0xFFFF), wants=st.booleans())
def test_plc_link_frames_both_ways(life: int, ready: int, done: int, wants: bool) -> None:
    settings_ = CanSettings(link_id=0x300)
    frame = PlcLink(life, ready, done, wants).encode(settings_, fd=False)
    assert frame.can_id == 0x301 and not frame.fd and frame.data[0] == LINK_VERSION << 4 | int(wants)
    assert PlcLink.decode(0x301, frame.data) == PlcLink(life, ready, done, wants)
    assert PlcLink.decode(0x301, frame.data[:7] + bytes([frame.data[7] ^ 0xFF])) is None


@settings(max_examples=40, deadline=None)
@given(text=st.binary(max_size=3000), fd=st.booleans(), seed=st.integers(0, 1000))
def test_the_description_arrives_in_any_order(text: bytes, fd: bool, seed: int) -> None:
    settings_ = CanSettings(fd=fd)
    frames = description_frames(settings_, text)
    assert all(frame.can_id == 0x102 and len(frame.data) in FD_LENGTHS for frame in frames)
    assert all(len(frame.data) == settings_.frame_bytes for frame in frames[:-1])
    random.Random(seed).shuffle(frames)
    assembler = DescriptionAssembler(0x102)
    results = [assembler.add(frame.data) for frame in frames]
    assert results[-1] == text and all(result is None for result in results[:-1])


def test_a_damaged_description_is_not_taken() -> None:
    frames = description_frames(CanSettings(), b'{"format": 1}' * 20)
    assembler = DescriptionAssembler(0x102)
    damaged = bytearray(frames[1].data)
    damaged[5] ^= 0x01
    assert assembler.add(bytes(damaged)) is None  # its checksum fails: the segment is missing
    assert [assembler.add(frame.data) for frame in (frames[0], *frames[2:])][-1] is None
