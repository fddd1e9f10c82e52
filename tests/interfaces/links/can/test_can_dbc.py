"""The DBC file of interfaces/links/can/dbc.py: cantools reads it back, every signal is in it under its
symbol at its bit, and decoding the codec's frames with it gives the values of the image."""

from __future__ import annotations

import random
from functools import lru_cache

import cantools
import pytest
from cantools.database.can import Database
from hypothesis import given, settings
from hypothesis import strategies as st

from interfaces.catalog import load_catalog
from interfaces.image import ProcessImage, decode
from interfaces.links.can.codec import LINK_VERSION, CanLayout, CanSettings
from interfaces.links.can.dbc import dbc_name, dbc_text
from interfaces.plant_io import PlantIoMap
from interfaces.signals import Direction, ExpandedCatalog, InterfaceLayout, SignalRef, SignalType, expand

AXES = ("X1", "Z1", "SP1")
PLANT = PlantIoMap.from_mapping({"I0.0": "EStop.chainOk", "I0.2": "MCP.jog", "IB3": "MCP.feedOverride",
                                 "Q0.0": "Drives.on", "Q1.7": "Lamp.alarm"}, AXES)


@lru_cache(maxsize=1)
def catalog() -> ExpandedCatalog:
    return expand(load_catalog(), InterfaceLayout(("CHAN1",), AXES))


DEFAULT = CanSettings()


@lru_cache(maxsize=4)
def database(settings_: CanSettings = DEFAULT) -> Database:
    layout = CanLayout.build(catalog(), PLANT.area_sizes(), settings_)
    text = dbc_text(layout, catalog(), PLANT, nc_cycle_ms=10, plc_cycle_ms=10)
    loaded = cantools.database.load_string(text, "dbc", strict=False)
    assert isinstance(loaded, Database)
    return loaded


def references() -> list[SignalRef]:
    return [item.ref() for item in catalog().signals] + [point.ref() for point in PLANT.points]


def test_every_signal_is_in_its_frame_under_its_symbol() -> None:
    layout = CanLayout.build(catalog(), PLANT.area_sizes(), CanSettings())
    db = database()
    for ref in references():
        location = layout.location(ref)
        assert location is not None
        message = db.get_message_by_frame_id(location.can_id)
        signal = message.get_signal_by_name(dbc_name(ref.name))
        assert (signal.start, signal.length) == (location.start_bit, location.length), ref.name
        assert signal.byte_order == ("big_endian" if location.big_endian else "little_endian")
        assert ref.name in str(signal.comment) and str(ref.address) in str(signal.comment)
    names = [dbc_name(ref.name) for ref in references()]
    assert len(names) == len(set(names))  # no two symbols meet in one identifier


def test_frames_nodes_cycle_times_and_the_link_frames() -> None:
    db = database()
    x1 = db.get_message_by_name("NC_DB31_60_105")
    assert (x1.frame_id, x1.length, x1.is_fd, x1.senders, x1.cycle_time) == (0x20B, 48, True, ["NC"], 10)
    assert "checksum" in [signal.name for signal in x1.signals]
    assert {node.name for node in db.nodes} == {"NC", "PLC"}
    assert [db.get_message_by_frame_id(can_id).name for can_id in (0x100, 0x101, 0x102)] == [
        "NC_LINK", "PLC_LINK", "NC_DESCRIPTION"]
    classic = database(CanSettings(fd=False, checksum=False))
    assert not any(message.is_fd for message in classic.messages)
    assert max(message.length for message in classic.messages) == 8


@settings(max_examples=10, deadline=None)
@given(seed=st.integers(0, 2**32 - 1))
def test_cantools_decodes_the_frames_to_the_values_of_the_image(seed: int) -> None:
    layout = CanLayout.build(catalog(), PLANT.area_sizes(), CanSettings())
    generator = random.Random(seed)
    image = ProcessImage({**catalog().area_sizes, **PLANT.area_sizes()})
    for buffer in image.areas.values():
        buffer[:] = generator.randbytes(len(buffer))
    for ref in references():  # reals stay finite numbers (random bytes may be NaN)
        if ref.type is SignalType.REAL:
            image.write(ref, generator.uniform(-1e6, 1e6))
    decoded: dict[str, float] = {}
    for direction in (Direction.NC_TO_PLC, Direction.PLC_TO_NC):
        for frame in layout.frames(direction, image.areas):
            values = database().decode_message(frame.can_id, frame.data, decode_choices=False)
            decoded.update({name: float(value) for name, value in values.items()})  # type: ignore[arg-type]
    for ref in references():
        expected = decode(image.areas[ref.area_key], ref)
        assert decoded[dbc_name(ref.name)] == pytest.approx(expected, rel=1e-6), ref.name


def test_link_frames_decode_with_the_dbc() -> None:
    from interfaces.links.can.codec import NcLink, PlcLink

    nc = NcLink(1, 7, 3, 42).encode(CanSettings())
    assert database().decode_message(nc.can_id, nc.data) == {
        "mode": 1, "version": LINK_VERSION, "ncLife": 7, "session": 3, "scanGrant": 42, "checksum": nc.data[7]}
    plc = PlcLink(9, 3, 42, True).encode(CanSettings(), fd=True)
    decoded = database().decode_message(plc.can_id, plc.data)
    assert (decoded["needsDescription"], decoded["plcLife"], decoded["sessionReady"], decoded["scanDone"]) == (
        1, 9, 3, 42)
    missing = PlcLink(10, 3, 43, misses_nc_frames=True).encode(CanSettings(), fd=True)
    decoded = database().decode_message(missing.can_id, missing.data)
    assert (decoded["needsDescription"], decoded["missesNcFrames"]) == (0, 1)
