"""The Modbus TCP server on loopback with independent clients: pyModbusTCP, mbpoll, raw frames.

The server serves the turn-mill's tables (interfaces/codec_modbus.py); its event loop runs in a
thread here, as a test stands in for the harness that would run it while it waits.
"""

from __future__ import annotations

import asyncio
import os
import shutil
import socket
import struct
import subprocess
import threading
from collections.abc import Iterator
from dataclasses import dataclass

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from pyModbusTCP.client import ModbusClient

from interfaces.catalog import load_catalog
from interfaces.codec_modbus import RegisterMap, Table, read_registers
from interfaces.links.modbus_tcp import LinkError, ModbusServerLink, ModbusTables
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


def _serve(allowed: tuple[str, ...] = ()) -> Iterator[Served]:
    writes: list[tuple[int, int]] = []
    tables = ModbusTables(bytearray(MAP.table_bytes[Table.NC_TO_PLC]), bytearray(MAP.table_bytes[Table.PLC_TO_NC]),
                          MAP.writable, on_write=lambda first, count: writes.append((first, count)))
    tables.set_description(b'{"machine": "turn_mill"}')
    loop = asyncio.new_event_loop()
    link = ModbusServerLink(tables, "127.0.0.1", 0, loop, allowed)
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
    # illegal function; pymodbus answers an undecodable function code as function 0 | 0x80
    assert unknown[7] & 0x80 and unknown[8] == 0x01
    # counts the protocol forbids: pymodbus cannot decode the request and answers the same way
    for function, count in ((0x04, 126), (0x03, 0), (0x01, 2001)):
        answer = _raw(served.port, _frame(function, struct.pack(">HH", 0, count)))
        assert answer[:2] == b"\x00\x07" and answer[7] & 0x80, (function, count)
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
        assert served.link.refused >= 1
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
    # the same number as a coil lies outside the PLC-to-NC table: refused
    refused = _mbpoll(served.port, "-t", "0", "-r", str(referenced.coil + 1), "127.0.0.1", "1")
    assert refused.returncode != 0
    assert "Illegal data address" in refused.stderr + refused.stdout
