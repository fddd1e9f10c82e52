"""The Modbus TCP server on loopback with independent clients: pyModbusTCP, mbpoll, raw frames
(pipelined requests, split requests, exception responses), the session's PLC as the only writer,
connection limits and the idle time-out.

The server serves the turn-mill's tables (interfaces/links/modbus/codec.py); its event loop runs in a
thread here, as a test stands in for the harness that would run it while it waits.
"""

from __future__ import annotations

import asyncio
import contextlib
import logging
import os
import select
import shutil
import socket
import struct
import subprocess
import threading
import time
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from pyModbusTCP.client import ModbusClient

from interfaces.catalog import load_catalog
from interfaces.image import encode
from interfaces.links.errors import LinkError
from interfaces.links.modbus.access import ConnectionLimits, LinkOwner, OwnerState, key_file
from interfaces.links.modbus.codec import Location, RegisterMap, Table, read_registers, session_key_registers
from interfaces.links.modbus.server import ANSWER_LIMIT, RECEIVE_LIMIT, ModbusServerLink
from interfaces.links.modbus.tables import ModbusTables
from interfaces.plant_io import PlantIoMap
from interfaces.signals import InterfaceLayout, expand

AXES = ("X1", "Z1", "Y1", "SP1", "SP2", "SP3")
CATALOG = expand(load_catalog(), InterfaceLayout(("CHAN1",), AXES))
PLANT = PlantIoMap.from_mapping({"I0.0": "EStop.chainOk", "I0.2": "MCP.jog", "Q0.0": "Drives.on"}, AXES)
MAP = RegisterMap.build(CATALOG, PLANT.area_sizes())
TIMEOUT = 5.0


@dataclass
class Served:
    tables: ModbusTables
    link: ModbusServerLink
    writes: list[tuple[int, int]]

    @property
    def port(self) -> int:
        return self.link.port

    def client(self) -> ModbusClient:
        client = ModbusClient(host="127.0.0.1", port=self.port, timeout=TIMEOUT, auto_open=True)
        return client


def _serve(allowed: tuple[str, ...] = (), limits: ConnectionLimits | None = None,
           owner: LinkOwner | None = None) -> Iterator[Served]:
    writes: list[tuple[int, int]] = []
    tables = ModbusTables(bytearray(MAP.table_bytes[Table.NC_TO_PLC]), bytearray(MAP.table_bytes[Table.PLC_TO_NC]),
                          MAP.writable, on_write=lambda first, count: writes.append((first, count)))
    tables.set_description(b'{"machine": "turn_mill"}')
    loop = asyncio.new_event_loop()
    link = ModbusServerLink(tables, "127.0.0.1", 0, loop, allowed, limits=limits, owner=owner)
    link.start()
    thread = threading.Thread(target=loop.run_forever, daemon=True)
    thread.start()
    try:
        yield Served(tables, link, writes)
    finally:
        loop.call_soon_threadsafe(loop.stop)
        thread.join(TIMEOUT)
        link.close()
        loop.close()


@pytest.fixture
def served() -> Iterator[Served]:
    yield from _serve()


def location(symbol: str):  # type: ignore[no-untyped-def]
    found = MAP.location(CATALOG.resolve(symbol))
    assert found is not None
    return found


# ------------------------------------------------------------------------------ reads and writes


def test_an_independent_client_reads_a_signal_as_register_bit_and_discrete_input(served: Served) -> None:
    referenced = location("X1.basic.in.enc1Synchronized")
    byte = MAP.table_byte(Table.NC_TO_PLC, "DB31", 60)
    assert byte is not None
    served.tables.nc_to_plc[byte] |= 1 << 4  # the NC sets DB31.DBX60.4
    client = served.client()
    assert client.read_discrete_inputs(referenced.coil, 1) == [True]
    (register,) = client.read_input_registers(referenced.register, 1)
    assert register >> referenced.register_bit & 1 == 1
    assert client.read_discrete_inputs(referenced.coil + 1, 1) == [False]
    client.close()


def test_a_client_write_lands_in_the_table_and_is_reported(served: Served) -> None:
    key = location("X1.basic.out.traversKeyPlus")
    override = location("CHAN1.basic.out.pathFeedrateOvrFactor")
    client = served.client()
    assert client.write_single_coil(key.coil, True)
    assert client.write_single_register(override.register, 120 << override.byte_bit)
    table = served.tables.plc_to_nc
    key_byte = MAP.table_byte(Table.PLC_TO_NC, "DB31", 4)
    override_byte = MAP.table_byte(Table.PLC_TO_NC, "DB21", 4)
    assert key_byte is not None and override_byte is not None
    assert table[key_byte] == 1 << 7 and table[override_byte] == 120
    assert client.read_coils(key.coil, 1) == [True]
    assert client.read_holding_registers(override.register, 1) == [120 << 8]
    assert len(served.writes) == 2
    client.close()


@pytest.mark.parametrize("request_kind", ["coil beyond the table", "register beyond the table", "coil in padding",
                                          "coil in the reserved link registers", "input register beyond"])
def test_addresses_outside_the_map_get_exception_02(served: Served, request_kind: str) -> None:
    client = served.client()
    holding = MAP.registers(Table.PLC_TO_NC)
    padding = next(i for i in range(32, len(MAP.writable)) if not MAP.writable[i])
    result = {
        "coil beyond the table": lambda: client.write_single_coil(16 * holding, True),
        "register beyond the table": lambda: client.write_multiple_registers(holding - 1, [1, 2]),
        "coil in padding": lambda: client.write_single_coil(8 * padding, True),
        "coil in the reserved link registers": lambda: client.write_single_coil(2 * 16, True),
        "input register beyond": lambda: client.read_input_registers(MAP.registers(Table.NC_TO_PLC), 1),
    }[request_kind]()
    assert result in (None, False)  # pyModbusTCP: None for a failed read, False for a failed write
    assert client.last_except == 2  # illegal data address
    assert served.writes == []
    # the server keeps serving
    assert client.read_input_registers(0, 4) is not None
    client.close()


def test_register_writes_leave_padding_and_reserve_at_zero(served: Served) -> None:
    client = served.client()
    assert client.write_multiple_registers(0, [0xFFFF] * 100)
    values = client.read_holding_registers(0, 100)
    assert values == read_registers(bytes(b & 0xFF for b in MAP.writable[:200]), 0, 100)
    assert values[2:16] == [0] * 14
    client.close()


def test_the_description_is_readable_from_register_4096(served: Served) -> None:
    client = served.client()
    words = client.read_input_registers(4096, 12)
    assert words is not None
    assert struct.pack(">12H", *words)[:24] == b'{"machine": "turn_mill"}'
    client.close()


# ------------------------------------------------------------------------------ bad requests


def _raw(port: int, frame: bytes, wait_s: float = 1.0) -> bytes:
    """Send ``frame`` on a new connection; the answer, or b"" when none comes within ``wait_s``."""
    with socket.create_connection(("127.0.0.1", port), timeout=TIMEOUT) as raw:
        raw.sendall(frame)
        raw.settimeout(wait_s)
        try:
            return raw.recv(300)
        except (TimeoutError, ConnectionResetError):
            return b""


def _frame(function: int, payload: bytes, transaction: int = 7, protocol: int = 0, length: int | None = None) -> bytes:
    pdu = bytes([function]) + payload
    return struct.pack(">HHHB", transaction, protocol, length if length is not None else len(pdu) + 1, 1) + pdu


def test_protocol_errors_get_their_exception_responses(served: Served) -> None:
    unknown = _raw(served.port, _frame(0x41, b"\x00\x00"))
    assert unknown[7:9] == bytes([0xC1, 0x01])  # illegal function, under the request's own code
    # counts the protocol forbids: illegal data value
    for function, count in ((0x04, 126), (0x03, 0), (0x01, 2001)):
        answer = _raw(served.port, _frame(function, struct.pack(">HH", 0, count)))
        assert answer[:2] == b"\x00\x07" and answer[7:9] == bytes([function | 0x80, 0x03]), (function, count)
    beyond = _raw(served.port, _frame(0x03, struct.pack(">HH", 4000, 10)))
    assert beyond[7:9] == bytes([0x83, 0x02])
    client = served.client()
    assert client.read_input_registers(0, 2) is not None
    client.close()


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(st.binary(min_size=1, max_size=300))
def test_fuzzed_frames_never_stop_the_server(served: Served, garbage: bytes) -> None:
    _raw(served.port, garbage, wait_s=0.05)  # most garbage gets no answer: the server waits for the rest
    client = served.client()
    assert client.read_input_registers(0, 1) is not None  # answered after whatever came before
    client.close()


def test_an_oversized_length_field_closes_only_that_connection(served: Served) -> None:
    _raw(served.port, _frame(0x03, struct.pack(">HH", 0, 1), length=0xFFFF))
    client = served.client()
    assert client.read_holding_registers(0, 1) is not None
    client.close()


# ------------------------------------------------------------------------------ pipelining and framing


class _Wire:
    """A raw connection: bytes out, whole answers (by their MBAP length) in."""

    def __init__(self, port: int):
        self.socket = socket.create_connection(("127.0.0.1", port), timeout=TIMEOUT)
        self.socket.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
        self.received = b""

    def send(self, data: bytes) -> None:
        self.socket.sendall(data)

    def answers(self, count: int) -> list[bytes]:
        """``count`` answers, or fewer when the server sends nothing more for a second."""
        found: list[bytes] = []
        self.socket.settimeout(1.0)
        while len(found) < count:
            while len(self.received) >= 6 and len(self.received) >= 6 + struct.unpack_from(">H", self.received, 4)[0]:
                end = 6 + struct.unpack_from(">H", self.received, 4)[0]
                found.append(self.received[:end])
                self.received = self.received[end:]
            if len(found) >= count:
                break
            try:
                chunk = self.socket.recv(65536)
            except (TimeoutError, ConnectionResetError):
                break
            if not chunk:
                break
            self.received += chunk
        return found

    def closed_by_server(self) -> bool:
        self.socket.settimeout(TIMEOUT)
        try:
            return self.socket.recv(1) == b""
        except ConnectionResetError:
            return True

    def close(self) -> None:
        self.socket.close()


def _read(transaction: int, register: int = 0, count: int = 1) -> bytes:
    return _frame(0x04, struct.pack(">HH", register, count), transaction=transaction)


def _transactions(answers: list[bytes]) -> list[int]:
    return [struct.unpack_from(">H", answer)[0] for answer in answers]


def test_ten_requests_in_one_segment_get_ten_answers_in_order(served: Served) -> None:
    wire = _Wire(served.port)
    wire.send(b"".join(_read(transaction, register=transaction) for transaction in range(1, 11)))
    answers = wire.answers(11)
    assert _transactions(answers) == list(range(1, 11))
    assert all(answer[7] == 0x04 for answer in answers)
    wire.close()


def test_back_to_back_segments_are_each_answered_once(served: Served) -> None:
    wire = _Wire(served.port)
    for round_ in range(200):
        wire.send(_read(2 * round_ + 1))
        wire.send(_read(2 * round_ + 2, register=3))
    assert _transactions(wire.answers(401)) == list(range(1, 401))
    wire.close()


def test_a_request_split_over_segments_and_one_behind_it(served: Served) -> None:
    wire = _Wire(served.port)
    first, second = _read(1), _read(2)
    wire.send(first[:3])
    wire.send(first[3:9])
    wire.send(first[9:] + second[:5])
    wire.send(second[5:])
    assert _transactions(wire.answers(3)) == [1, 2]
    wire.close()


def test_a_hundred_pipelined_requests_are_all_answered(served: Served) -> None:
    """More than a connection may have waiting: the server stops reading until it has answered."""
    wire = _Wire(served.port)
    wire.send(b"".join(_read(transaction % 65536) for transaction in range(1, 101)))
    assert _transactions(wire.answers(101)) == list(range(1, 101))
    wire.close()


def test_every_function_code_gets_an_answer_under_its_own_code(served: Served) -> None:
    wire = _Wire(served.port)
    served_functions = {1, 2, 3, 4, 5, 6, 15, 16, 22, 23}
    for function in range(256):
        wire.send(_frame(function, b"\x00\x00\x00\x01", transaction=function))
        (answer,) = wire.answers(1)
        assert struct.unpack_from(">H", answer)[0] == function
        if function not in served_functions:
            assert answer[7:9] == bytes([function | 0x80, 0x01]), function
        else:
            assert answer[7] in (function, function | 0x80), function
    wire.close()


@pytest.mark.parametrize("body", [b"", b"\x07", b"\x00", b"\x07\x06\x00\x01\x00\x02\x00\x01\x12\x34",
                                  b"\xff" + b"\x06" * 10])
def test_file_record_writes_are_answered_with_exception_01(served: Served, body: bytes) -> None:
    wire = _Wire(served.port)
    wire.send(_frame(21, body))
    (answer,) = wire.answers(1)
    assert answer[7:9] == bytes([0x95, 0x01])
    wire.close()


def test_a_malformed_header_closes_the_connection_after_the_requests_before_it(served: Served) -> None:
    wire = _Wire(served.port)
    wire.send(_read(1) + _read(2) + _frame(0x04, struct.pack(">HH", 0, 1), protocol=7) + _read(3))
    assert _transactions(wire.answers(3)) == [1, 2]
    assert wire.closed_by_server()
    assert served.link.counters.framing_errors == 1
    wire.close()


def test_a_failure_in_the_server_is_answered_with_04_counted_and_logged(served: Served,
                                                                        caplog: pytest.LogCaptureFixture) -> None:
    def broken(first: int, count: int) -> None:
        raise RuntimeError("the simulation refused the write")

    served.tables.on_write = broken
    wire = _Wire(served.port)
    with caplog.at_level("INFO", logger="interfaces.links.modbus.server"):
        wire.send(_frame(0x06, struct.pack(">HH", 16, 0x0100)))
        (answer,) = wire.answers(1)
    assert answer[7:9] == bytes([0x86, 0x04])
    assert served.link.counters.failures == 1
    assert "the simulation refused the write" in caplog.text and "Traceback" in caplog.text
    wire.close()


# ------------------------------------------------------------------------------ the session's PLC


SESSION = 5


def _open_session(tables: ModbusTables) -> None:
    tables.nc_to_plc[0:4] = struct.pack(">HH", 1, SESSION)  # link version 1, session 5


KEY = 0x0123_4567_89AB_CDEF  # the PLC's session key


def _claim(client: ModbusClient, key: int = KEY) -> bool:
    """The claim of a PLC: holding register 1 = the session, 2..5 = its key."""
    return bool(client.write_multiple_registers(1, [SESSION, *session_key_registers(key)]))


def _until_no_owner(served: Served) -> None:
    deadline = time.monotonic() + TIMEOUT
    while served.link.owner.owner is not None and time.monotonic() < deadline:
        time.sleep(0.01)


def test_only_the_connection_that_claimed_the_session_writes(served: Served) -> None:
    _open_session(served.tables)
    plc, other = served.client(), served.client()
    assert not plc.write_single_register(16, 0x0100)  # before its claim, nobody writes
    assert plc.last_except == 1
    assert _claim(plc)  # the claim: session ready = the session, with the key
    assert plc.write_multiple_registers(0, [7, SESSION])  # sign of life and outputs
    assert plc.write_single_coil(8 * 32, True)  # Q0.0
    for refused in (lambda: other.write_single_register(0, 8), lambda: other.write_single_register(1, SESSION),
                    lambda: other.write_single_coil(8 * 32 + 1, True),
                    lambda: other.write_multiple_registers(16, [0xFFFF])):
        assert not refused()
        assert other.last_except == 1
    assert other.read_holding_registers(0, 6) == [7, SESSION, 0, 0, 0, 0]  # reading is everybody's; the key is not
    assert served.link.owner.refused == 5 and served.link.counters.requests >= 9
    plc.close()
    other.close()


def test_a_lost_plc_closes_its_session_and_only_its_key_takes_it_back(served: Served) -> None:
    """The PLC's connection ended and the next client that wrote the session number into holding
    register 1 owned the link: it kept alarm 2000 away with the sign of life and moved the axes."""
    _open_session(served.tables)
    plc, intruder = served.client(), served.client()
    assert _claim(plc) and plc.write_multiple_registers(0, [7, SESSION])
    plc.close()  # the PLC is lost
    _until_no_owner(served)
    assert served.link.owner.state is OwnerState.CLOSED
    for claim in (lambda: intruder.write_single_register(1, SESSION),
                  lambda: intruder.write_multiple_registers(0, [8, SESSION]),
                  lambda: _claim(intruder, key=0), lambda: _claim(intruder, key=KEY ^ 1)):
        assert not claim()
        assert intruder.last_except == 1
    assert intruder.read_holding_registers(0, 2) == [7, SESSION]  # nothing of it landed
    assert served.link.owner.refused_claims == 4
    back = served.client()  # the same PLC on a new connection, with its key
    assert _claim(back) and back.write_single_register(0, 9)
    assert served.link.owner.state is OwnerState.OWNED and served.link.owner.claims == 2
    back.close()
    intruder.close()


def test_a_session_claimed_without_a_key_stays_closed_until_a_new_session(served: Served) -> None:
    _open_session(served.tables)
    plc = served.client()
    assert plc.write_single_register(1, SESSION)  # a PLC that claims with the session alone (no key)
    plc.close()
    _until_no_owner(served)
    again = served.client()
    assert not again.write_single_register(1, SESSION) and not _claim(again, key=0)
    served.link.owner.open_session()  # the next power-on, or the operator's new session
    assert again.write_single_register(1, SESSION) and again.write_single_register(0, 1)
    again.close()


def test_with_a_required_key_only_its_claim_takes_a_session() -> None:
    for served in _serve(owner=LinkOwner(required_key=KEY)):
        _open_session(served.tables)
        stranger, plc = served.client(), served.client()
        assert not stranger.write_single_register(1, SESSION) and not _claim(stranger, key=KEY + 1)
        assert _claim(plc)
        plc.close()
        _until_no_owner(served)
        served.link.owner.open_session()  # a new session: still the key alone
        assert not stranger.write_single_register(1, SESSION)
        assert _claim(stranger)  # whoever holds the key is the PLC
        stranger.close()


def test_a_key_file_is_made_for_its_owner_alone_and_read_back(tmp_path: Path) -> None:
    path = tmp_path / "plc.key"
    key = key_file(str(path))
    assert 0 < key < 1 << 64 and key_file(str(path)) == key
    assert os.stat(path).st_mode & 0o777 == 0o600
    path.write_text("not a key\n")
    with pytest.raises(LinkError, match="16 hexadecimal digits"):
        key_file(str(path))


def test_allowed_writers_write_without_owning_the_link() -> None:
    for served in _serve(owner=LinkOwner(allow_writers=("127.0.0.1",))):
        _open_session(served.tables)
        tool = served.client()
        assert tool.write_single_register(16, 0x0100)
        assert served.link.owner.owner is None
        tool.close()


# ------------------------------------------------------------------------------ a flood


def test_a_flood_is_answered_a_little_each_pass_of_the_loop_and_the_plc_first() -> None:
    """50 connections reading back to back stalled the real-time NC: pymodbus answered whatever
    had arrived in one pass of the event loop, the pacer's cycles waited behind it."""
    tables = ModbusTables(bytearray(MAP.table_bytes[Table.NC_TO_PLC]), bytearray(MAP.table_bytes[Table.PLC_TO_NC]),
                          MAP.writable)
    _open_session(tables)
    loop = asyncio.new_event_loop()
    link = ModbusServerLink(tables, "127.0.0.1", 0, loop)
    link.start()

    def passes(count: int) -> None:
        for _ in range(count):
            loop.run_until_complete(asyncio.sleep(0))

    try:
        plc = _Wire(link.port)
        plc.send(_frame(0x06, struct.pack(">HH", 1, SESSION)))  # the claim: this connection is the PLC
        for _ in range(1000):
            if _pending(plc):
                break
            passes(1)
        assert plc.answers(1) and link.owner.owner is not None
        flood = [_Wire(link.port) for _ in range(50)]
        passes(20)  # every connection accepted
        assert link.clients == 51
        for wire in flood:
            wire.send(_read(1, count=125))
        plc.send(_read(2))  # the PLC's request comes last
        waited = 0
        while not _pending(plc) and waited < 1000:
            passes(1)
            waited += 1
        answered = sum(_pending(wire) for wire in flood)
        assert answered < 25  # a pass answers what 0.2 ms allow, not everything that arrived
        assert len(plc.answers(1)) == 1  # and the PLC's request was among the first
        passes(400)
        assert all(len(wire.answers(1)) == 1 for wire in flood)
        for wire in [plc, *flood]:
            wire.close()
    finally:
        link.close()
        loop.close()


def _pending(wire: _Wire) -> bool:
    """Whether an answer waits in the socket (without waiting for one)."""
    readable, _, _ = select.select([wire.socket], [], [], 0)
    return bool(readable)


# ------------------------------------------------------------------------------ connection limits


def test_idle_connections_are_closed_after_the_idle_time_out() -> None:
    for served in _serve(limits=ConnectionLimits(max_clients=200, idle_timeout_s=0.5)):
        idle = [_Wire(served.port) for _ in range(100)]
        half_open = _Wire(served.port)
        half_open.send(_read(1)[:5])  # the start of a request, never finished
        deadline = time.monotonic() + TIMEOUT
        while served.link.clients < 101 and time.monotonic() < deadline:
            time.sleep(0.01)
        assert all(wire.closed_by_server() for wire in [*idle, half_open])
        assert served.link.clients == 0 and served.link.counters.idle_closed == 101
        for wire in [*idle, half_open]:
            wire.close()


def test_a_client_that_never_takes_its_answers_is_not_read_and_cannot_grow_the_server(
        caplog: pytest.LogCaptureFixture) -> None:
    """It grew the server from 58 to 405 MB in 120 s: every answer waited in the server's buffer."""
    caplog.set_level(logging.INFO, logger="interfaces.links.modbus.server")
    for served in _serve(limits=ConnectionLimits(idle_timeout_s=3.0)):
        hog = socket.create_connection(("127.0.0.1", served.port), timeout=TIMEOUT)
        hog.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, 4096)
        hog.setblocking(False)
        # The kernel takes megabytes of answers into its own buffers first (how many depends on the host,
        # and it may hold the client back before the server's buffer fills): a small send buffer on the
        # server's side of the connection makes the server's own buffer the one that fills, as it does
        # on every host once the kernel's are full.
        deadline = time.monotonic() + TIMEOUT
        while not served.link.clients and time.monotonic() < deadline:
            time.sleep(0.01)
        (connection,) = served.link._connections
        connection.transport.get_extra_info("socket").setsockopt(socket.SOL_SOCKET, socket.SO_SNDBUF, 4096)
        batch = b"".join(struct.pack(">HHHBBHH", number, 0, 6, 1, 4, 0, 125) for number in range(1000))
        sent, most, waiting = 0, 0, b""
        deadline = time.monotonic() + 20.0
        after_stall = 200  # sends on while it is no longer read
        while after_stall and time.monotonic() < deadline:
            waiting = waiting or batch  # 259-byte answers to 12-byte requests, never read
            with contextlib.suppress(BlockingIOError):
                done = hog.send(waiting)
                sent, waiting = sent + done, waiting[done:]
            most = max(most, served.link.held_bytes())
            after_stall -= served.link.counters.stalls > 0
            time.sleep(0.001)
        assert sent > 100 * 1024  # the answers to what it sent would be more than 2 MB
        assert most <= RECEIVE_LIMIT + 256 * 1024 + ANSWER_LIMIT + 4096  # what the server held for it
        assert served.link.counters.stalls >= 1
        assert "does not take its answers" in caplog.text
        other = served.client()  # everybody else is served meanwhile
        assert other.read_input_registers(0, 2) is not None
        deadline = time.monotonic() + 10.0
        while served.link.counters.stalled_closed == 0 and time.monotonic() < deadline:
            time.sleep(0.05)
        assert served.link.counters.stalled_closed == 1  # closed after the idle time-out, its answers dropped
        other.close()
        hog.close()


def test_a_full_server_closes_the_longest_idle_connection_for_a_new_one() -> None:
    for served in _serve(limits=ConnectionLimits(max_clients=4, idle_timeout_s=60)):
        idle = [_Wire(served.port) for _ in range(4)]
        for wire in idle:
            wire.send(_read(1))
            assert len(wire.answers(1)) == 1
        plc = served.client()
        assert plc.read_input_registers(0, 1) is not None
        assert idle[0].closed_by_server()  # the one heard first
        assert served.link.clients == 4 and served.link.counters.evicted == 1
        plc.close()
        for wire in idle:
            wire.close()


# ------------------------------------------------------------------------------ connections


def test_two_clients_at_once_and_a_reconnect(served: Served) -> None:
    first, second = served.client(), served.client()
    assert first.write_single_register(16, 0x0100)
    assert second.read_holding_registers(16, 1) == [0x0100]
    first.close()
    assert second.read_holding_registers(16, 1) == [0x0100]
    again = served.client()
    assert again.read_input_registers(0, 1) is not None
    assert served.link.clients >= 1
    again.close()
    second.close()


def test_clients_outside_the_allow_list_are_disconnected() -> None:
    for served in _serve(allowed=("10.1.2.0/24",)):
        client = served.client()
        assert client.read_input_registers(0, 1) is None
        client.close()
        assert served.link.counters.refused >= 1
    for served in _serve(allowed=("127.0.0.1",)):
        client = served.client()
        assert client.read_input_registers(0, 1) is not None
        client.close()


def test_a_bad_allow_list_entry_is_named() -> None:
    with pytest.raises(LinkError, match=r"'127\.0\.0\.x' is not an IP address"):
        ModbusServerLink(ModbusTables(), "127.0.0.1", 0, asyncio.new_event_loop(), ("127.0.0.x",))


def test_a_busy_port_is_reported() -> None:
    for served in _serve():
        loop = asyncio.new_event_loop()
        second = ModbusServerLink(ModbusTables(), "127.0.0.1", served.port, loop)
        with pytest.raises(LinkError, match=f"cannot serve Modbus TCP on 127.0.0.1:{served.port}"):
            second.start()
        loop.close()


# ------------------------------------------------------------------------------ mbpoll

MBPOLL = shutil.which("mbpoll")
needs_mbpoll = pytest.mark.skipif(MBPOLL is None and not os.environ.get("VC_REQUIRE_MBPOLL"),
                                  reason="mbpoll is not installed (.ci/run installs it)")


def _mbpoll(port: int, *arguments: str) -> subprocess.CompletedProcess[str]:
    assert MBPOLL is not None, "mbpoll is required here (VC_REQUIRE_MBPOLL is set)"
    return subprocess.run([MBPOLL, "-m", "tcp", "-a", "1", "-p", str(port), "-1", *arguments],
                          capture_output=True, text=True, timeout=TIMEOUT)


@needs_mbpoll
def test_mbpoll_reads_a_documented_bit_and_gets_exception_02_for_a_read_only_address(served: Served) -> None:
    referenced = location("X1.basic.in.enc1Synchronized")
    byte = MAP.table_byte(Table.NC_TO_PLC, "DB31", 60)
    assert byte is not None
    served.tables.nc_to_plc[byte] |= 1 << 4
    # mbpoll counts references from 1: discrete input n is reference n + 1
    result = _mbpoll(served.port, "-t", "1", "-r", str(referenced.coil + 1), "-c", "1", "127.0.0.1")
    assert result.returncode == 0, result.stderr
    assert f"[{referenced.coil + 1}]: \t1" in result.stdout
    register = _mbpoll(served.port, "-t", "3", "-r", str(referenced.register + 1), "-c", "1", "127.0.0.1")
    assert int(register.stdout.split(f"[{referenced.register + 1}]:")[1].split()[0]) >> referenced.register_bit & 1
    # a coil beyond the PLC-to-NC table (the NC-to-PLC table is longer): refused
    outside = MAP.registers(Table.PLC_TO_NC) * 16
    refused = _mbpoll(served.port, "-t", "0", "-r", str(outside + 1), "127.0.0.1", "1")
    assert refused.returncode != 0
    assert "Illegal data address" in refused.stderr + refused.stdout


# ------------------------------------------------------------------------------ REAL values

S_VALUE = -1234.5678  # an S7 REAL whose words differ (0xC49A, 0x522B), so a swapped order cannot pass


def _serve_real(served: Served) -> Location:
    """SP1's S function value (DB34.DBD88, a REAL) in the NC-to-PLC table as the NC writes it."""
    ref = CATALOG.resolve("SP1.spindle.in.sFuncValue")
    areas = {key: bytearray(size) for key, size in {**CATALOG.area_sizes, **PLANT.area_sizes()}.items()}
    encode(areas["DB34"], ref, S_VALUE)
    MAP.fill_table(Table.NC_TO_PLC, areas, served.tables.nc_to_plc)
    return location("SP1.spindle.in.sFuncValue")


def test_a_real_is_two_registers_high_word_first_of_an_ieee_754_single(served: Served) -> None:
    """docs/modbus.md, "REAL values": DBD n is input registers r, r + 1; (r << 16 | r + 1) is the bit
    pattern of the IEEE 754 single, so it is a REAL by a bit cast, not by a conversion."""
    found = _serve_real(served)
    assert found.registers == 2
    high, low = served.client().read_input_registers(found.register, 2)
    assert (high, low) == (0xC49A, 0x522B)
    pattern = high << 16 | low  # what a PLC gets from the two words, as the doc writes it
    assert struct.unpack(">f", struct.pack(">I", pattern))[0] == pytest.approx(S_VALUE, rel=1e-7)
    assert struct.unpack(">f", struct.pack(">I", low << 16 | high))[0] != pytest.approx(S_VALUE, rel=1e-3)


@needs_mbpoll
def test_mbpoll_reads_a_real_with_big_endian_word_order(served: Served) -> None:
    found = _serve_real(served)
    result = _mbpoll(served.port, "-t", "3:float", "-B", "-r", str(found.register + 1), "-c", "1", "127.0.0.1")
    assert result.returncode == 0, result.stderr
    printed = result.stdout.split(f"[{found.register + 1}]:")[1].split()[0]
    assert float(printed) == pytest.approx(S_VALUE, abs=0.01)  # mbpoll prints six digits: -1234.57
