"""The S7 server with a python-snap7 client: the data blocks as they are, write protection,
bit writes, the exchange with the simulation's images, the allow-list; block downloads refused,
the session's PLC as the only writer, idle sessions that never lock a client out."""

from __future__ import annotations

import time
from collections.abc import Iterator

import pytest
import snap7
from snap7.type import Areas, WordLen
from snap7.util import set_bool

from interfaces.catalog import load_catalog
from interfaces.links.modbus.access import ConnectionLimits
from interfaces.links.modbus.s7 import S7ServerLink
from interfaces.signals import Direction, InterfaceLayout, expand

CATALOG = expand(load_catalog(), InterfaceLayout(("CHAN1",), ("X1", "Z1")))
PLANT_SIZES = {"I": 4, "Q": 2}


def _serve(allowed: tuple[str, ...] = (), limits: ConnectionLimits | None = None) -> Iterator[S7ServerLink]:
    link = S7ServerLink("127.0.0.1", 0, allowed, limits=limits)
    link.start()
    link.open_session(CATALOG, PLANT_SIZES)
    try:
        yield link
    finally:
        link.close()


@pytest.fixture
def link() -> Iterator[S7ServerLink]:
    yield from _serve()


def _client(link: S7ServerLink) -> snap7.client.Client:
    client = snap7.client.Client()
    client.connect("127.0.0.1", 0, 1, link.port)
    return client


@pytest.fixture
def client(link: S7ServerLink) -> Iterator[snap7.client.Client]:
    client = _client(link)
    yield client
    client.disconnect()


def simulation_areas() -> dict[str, bytearray]:
    areas = {key: bytearray(size) for key, size in CATALOG.area_sizes.items()}
    areas.update({key: bytearray(size) for key, size in PLANT_SIZES.items()})
    return areas


def test_an_s7_client_reads_db31_dbx60_4_directly(link: S7ServerLink, client: snap7.client.Client) -> None:
    areas = simulation_areas()
    areas["DB31"][60] = 1 << 4  # the NC: X1 referenced
    areas["I"][0] = 0x05
    link.publish(areas)
    assert client.db_read(31, 60, 1)[0] >> 4 & 1 == 1
    assert client.read_area(Areas.PE, 0, 0, 1)[0] == 0x05


def test_plc_writes_reach_the_simulation_at_the_exchange(link: S7ServerLink, client: snap7.client.Client) -> None:
    areas = simulation_areas()
    assert not link.take_outputs(areas)  # nothing written yet
    client.db_write(21, 4, bytearray([120]))  # DB21.DBB4 feed override
    client.write_area(Areas.PA, 0, 0, bytearray([0x01]))
    assert link.take_outputs(areas)
    assert areas["DB21"][4] == 120 and areas["Q"][0] == 0x01


def test_a_bit_write_changes_only_its_bit(link: S7ServerLink, client: snap7.client.Client) -> None:
    client.db_write(31, 4, bytearray([0x40]))
    client.write_area(Areas.DB, 31, 4 * 8 + 7, bytearray([1]), word_len=WordLen.Bit)
    assert link.areas["DB31"][4] == 0xC0
    client.write_area(Areas.DB, 31, 4 * 8 + 6, bytearray([0]), word_len=WordLen.Bit)
    assert link.areas["DB31"][4] == 0x80


@pytest.mark.parametrize(("area", "number", "start", "word_len"), [
    (Areas.DB, 31, 60, None),  # DB31.DBB60: NC-to-PLC
    (Areas.DB, 31, 58 * 8 + 1, WordLen.Bit),  # a byte the interface does not use
    (Areas.DB, 31, 60 * 8 + 4, WordLen.Bit),  # DB31.DBX60.4
    (Areas.DB, 40, 0, None),  # no such data block
    (Areas.PE, 0, 0, None),  # the plant inputs
])
def test_writes_outside_the_plc_to_nc_bytes_are_refused(link: S7ServerLink, client: snap7.client.Client,
                                                         area: Areas, number: int, start: int,
                                                         word_len: WordLen | None) -> None:
    before = {key: bytes(value) for key, value in link.areas.items()}
    with pytest.raises(Exception, match=r"0x84|cannot be performed"):
        client.write_area(area, number, start, bytearray([0xFF]), word_len=word_len)
    assert {key: bytes(value) for key, value in link.areas.items()} == before
    assert not link.outputs_written
    assert client.db_read(31, 0, 2) is not None  # the server keeps serving


def test_a_write_across_the_boundary_changes_nothing(link: S7ServerLink, client: snap7.client.Client) -> None:
    last_output = max(stop for area, _, stop in CATALOG.byte_ranges(Direction.PLC_TO_NC) if area == "DB31")
    with pytest.raises(Exception, match=r"0x84|cannot be performed"):
        client.db_write(31, last_output - 1, bytearray([1, 2]))
    assert link.areas["DB31"][last_output - 1] == 0


def test_other_links_outputs_are_mirrored_for_s7_readers(link: S7ServerLink, client: snap7.client.Client) -> None:
    areas = simulation_areas()
    areas["DB31"][4] = 0x80  # a Modbus PLC pressed X1's plus key
    link.mirror_outputs(areas)
    assert client.db_read(31, 4, 1)[0] == 0x80


def test_clients_outside_the_allow_list_cannot_connect() -> None:
    for link in _serve(allowed=("10.9.9.9",)):
        client = snap7.client.Client()
        with pytest.raises(Exception):  # noqa: B017 - snap7 raises its own connection errors
            client.connect("127.0.0.1", 0, 1, link.port)
        assert link.refused >= 1


# ------------------------------------------------------------------------------ downloads, ownership, sessions


def test_a_block_download_is_refused_and_leaves_the_nc_to_plc_bytes(link: S7ServerLink,
                                                                     client: snap7.client.Client) -> None:
    areas = simulation_areas()
    areas["DB31"][60] = 0x10  # the NC: X1 referenced
    link.publish(areas)
    block = bytearray(len(link.areas["DB31"]))
    set_bool(block, 60, 4, False)
    block[4] = 0x80  # and a traverse key pressed
    with pytest.raises(Exception, match=r"0x84|cannot be performed|download"):
        client.download(block, 31)
    assert link.areas["DB31"][60] == 0x10 and link.areas["DB31"][4] == 0
    assert link.refused_downloads == 1
    assert not link.outputs_written
    assert client.db_read(31, 60, 1)[0] == 0x10  # the server keeps serving


def test_only_the_first_writer_of_the_session_writes_and_its_loss_closes_the_session(link: S7ServerLink) -> None:
    plc, other = _client(link), _client(link)
    try:
        plc.db_write(21, 4, bytearray([100]))  # the PLC's first write: it owns the link now
        with pytest.raises(Exception, match=r"0x84|cannot be performed"):
            other.db_write(21, 4, bytearray([0]))
        assert link.areas["DB21"][4] == 100 and link.owner.refused == 1
        assert other.db_read(21, 4, 1)[0] == 100  # reading is everybody's
        plc.disconnect()
        deadline = time.monotonic() + 5
        while link.owner.owner is not None and time.monotonic() < deadline:
            time.sleep(0.01)
        # the owner left: its session is closed, a later writer does not take it (it did)
        with pytest.raises(Exception, match=r"0x84|cannot be performed"):
            other.db_write(21, 4, bytearray([50]))
        assert link.areas["DB21"][4] == 100 and link.owner.refused == 2
        link.owner.open_session()  # the next power-on, or the operator's new session
        other.db_write(21, 4, bytearray([50]))  # the first writer of the new session owns the link
        assert link.areas["DB21"][4] == 50
    finally:
        other.disconnect()
        plc.disconnect()


def test_idle_sessions_never_lock_a_client_out() -> None:
    for link in _serve(limits=ConnectionLimits(max_clients=8, idle_timeout_s=60)):
        idle = [_client(link) for _ in range(12)]  # beyond the limit: the longest idle make room
        try:
            assert link.clients == 8 and link.evicted == 4
            plc = _client(link)
            assert plc.db_read(31, 60, 1) is not None
            plc.db_write(21, 4, bytearray([100]))
            assert link.areas["DB21"][4] == 100
            plc.disconnect()
        finally:
            for client in idle:
                client.disconnect()


def test_a_silent_session_is_closed_after_the_idle_time_out() -> None:
    for link in _serve(limits=ConnectionLimits(max_clients=8, idle_timeout_s=0.2)):
        client = _client(link)
        assert link.clients == 1
        time.sleep(0.3)
        link.close_idle()
        deadline = time.monotonic() + 5
        while link.clients and time.monotonic() < deadline:
            time.sleep(0.01)
        assert link.clients == 0 and link.idle_closed == 1
        client.disconnect()
