"""Modbus TCP: the harness's server (the NC as remote I/O) and the PLC's client, on pymodbus.

This is the only module that imports pymodbus; its exceptions become :class:`LinkError`.
The tables, the link block and the description follow :mod:`interfaces.codec_modbus`.

Server: pymodbus answers the protocol (framing, function codes, malformed and oversized
requests, exception responses); a request action hands every data access to
:class:`ModbusTables`, the bytes the harness shares with the simulation.  pymodbus's own store
is sized to the largest tables the convention allows and only buffers the answer: what the
tables do not hold (an address outside the current map, a coil in padding or in the reserved
link registers) gets exception 02 (illegal data address).  Modbus itself has no function that
writes input registers or discrete inputs: the NC-to-PLC table is read-only by construction.

The server runs on an asyncio loop the harness owns and runs whenever it waits (for the PLC's
acknowledgement in lockstep, for the next cycle in real time): one thread, no hand-off.
"""

from __future__ import annotations

import asyncio
import contextlib
import ipaddress
import logging
from collections.abc import Callable, Collection, Iterable, Sequence
from dataclasses import dataclass, field
from typing import Any

from pymodbus.client import ModbusTcpClient
from pymodbus.constants import ExcCodes
from pymodbus.exceptions import ModbusException
from pymodbus.server import ModbusTcpServer
from pymodbus.server.requesthandler import ServerRequestHandler
from pymodbus.simulator import DataType, SimData, SimDevice

from interfaces.codec_modbus import (
    DESCRIPTION_REGISTER,
    LINK_REGISTERS,
    MAX_DESCRIPTION_BYTES,
    MAX_TABLE_REGISTERS,
    READ_COILS,
    READ_DISCRETE_INPUTS,
    READ_INPUT,
    READ_LIMIT,
    WRITE_COIL,
    WRITE_COILS,
    WRITE_LIMIT,
    bits_writable,
    read_registers,
    text_registers,
    words_as_bits,
    write_bits,
    write_registers,
)
from interfaces.links.errors import LinkError as LinkError  # the links' error, raised here for pymodbus's

_COIL_CODES = (READ_COILS, WRITE_COIL, WRITE_COILS)

# pymodbus logs every refused request and every dropped connection at warning/error level;
# the link reports what matters itself.
logging.getLogger("pymodbus").setLevel(logging.CRITICAL)


@dataclass(slots=True)
class ModbusTables:
    """The bytes the Modbus server serves: the two tables and the description.

    ``nc_to_plc`` and ``plc_to_nc`` are table bytes (register ``r`` = bytes ``2r``, ``2r + 1``);
    ``writable`` marks the PLC-to-NC bytes a write lands in.  ``on_write`` is called with the
    first register and the register count of every accepted PLC write.
    """

    # before the first session only the link block, all zeros: version 0 says "not ready"
    nc_to_plc: bytearray = field(default_factory=lambda: bytearray(2 * LINK_REGISTERS))
    plc_to_nc: bytearray = field(default_factory=lambda: bytearray(2 * LINK_REGISTERS))
    writable: bytes = bytes(2 * LINK_REGISTERS)
    description: bytes = b""
    on_write: Callable[[int, int], None] = lambda first, count: None
    writes: int = 0  # accepted PLC write requests, for statistics

    def set_description(self, text: bytes) -> None:
        if len(text) > MAX_DESCRIPTION_BYTES:
            raise LinkError(f"the interface description has {len(text)} bytes; the link carries"
                            f" {MAX_DESCRIPTION_BYTES}")
        self.description = text

    # ------------------------------------------------------------------ requests
    def answer(self, function_code: int, address: int, count: int, registers: list[int],
               values: Sequence[int] | Sequence[bool] | None) -> ExcCodes | None:
        """Serve one data access of a request (see the module docstring); None when granted."""
        if function_code == READ_INPUT:
            return self._input_registers(address, count, registers)
        if function_code == READ_DISCRETE_INPUTS:
            return self._bit_words(self.nc_to_plc, address, count, registers)
        if function_code in _COIL_CODES:
            if values is not None:
                return self._write_coils(address, [bool(value) for value in values])
            return self._bit_words(self.plc_to_nc, address, count, registers)
        # holding registers: FC 3, 6, 16, 22, 23
        if address + count > len(self.plc_to_nc) // 2:
            return ExcCodes.ILLEGAL_ADDRESS
        if values is not None:
            write_registers(self.plc_to_nc, self.writable, address, [int(value) for value in values])
            self.writes += 1
            self.on_write(address, count)
        registers[address: address + count] = read_registers(self.plc_to_nc, address, count)
        return None

    def _input_registers(self, address: int, count: int, registers: list[int]) -> ExcCodes | None:
        if address + count <= len(self.nc_to_plc) // 2:
            registers[address: address + count] = read_registers(self.nc_to_plc, address, count)
            return None
        described = text_registers(self.description)
        first = address - DESCRIPTION_REGISTER
        if first >= 0 and first + count <= len(described):
            registers[address: address + count] = described[first: first + count]
            return None
        return ExcCodes.ILLEGAL_ADDRESS

    @staticmethod
    def _bit_words(table: bytearray, address: int, words: int, registers: list[int]) -> ExcCodes | None:
        # the bit store packs 16 bits a word, bit 0 first; ``words`` is how many the request touches
        first = address // 16
        if first + words > len(table) // 2:
            return ExcCodes.ILLEGAL_ADDRESS
        registers[first: first + words] = words_as_bits(table, first, words)
        return None

    def _write_coils(self, address: int, values: list[bool]) -> ExcCodes | None:
        if address + len(values) > 8 * len(self.plc_to_nc) or not bits_writable(self.writable, address, len(values)):
            return ExcCodes.ILLEGAL_ADDRESS
        write_bits(self.plc_to_nc, address, values)
        self.writes += 1
        self.on_write(address // 16, (address % 16 + len(values) + 15) // 16)
        return None


def _device(tables: ModbusTables) -> SimDevice:
    """A pymodbus device as large as the convention allows; ``tables`` decide what is valid."""
    async def action(function_code: int, _start: int, address: int, count: int, registers: list[int],
                     values: list[int] | list[bool] | None) -> ExcCodes | None:
        return tables.answer(function_code, address, count, registers, values)

    bits = [False] * (MAX_TABLE_REGISTERS * 16)  # a bits entry takes its size from the values
    return SimDevice(
        id=0,  # every unit id
        simdata=(
            [SimData(0, values=bits, datatype=DataType.BITS)],
            [SimData(0, values=bits, datatype=DataType.BITS)],
            [SimData(0, count=MAX_TABLE_REGISTERS, values=0, datatype=DataType.REGISTERS)],
            [SimData(0, count=DESCRIPTION_REGISTER + MAX_DESCRIPTION_BYTES // 2, values=0,
                     datatype=DataType.REGISTERS)],
        ),
        action=action,
    )


def parse_allowed_clients(texts: Collection[str]) -> list[ipaddress.IPv4Network | ipaddress.IPv6Network]:
    """``127.0.0.1``, ``10.0.0.0/24`` ... as networks; raises LinkError naming a bad entry."""
    networks = []
    for text in texts:
        try:
            networks.append(ipaddress.ip_network(text.strip(), strict=False))
        except ValueError:
            raise LinkError(f"'{text}' is not an IP address or network (e.g. 127.0.0.1, 10.0.0.0/24)") from None
    return networks


class _Handler(ServerRequestHandler):
    """One client connection; refuses clients outside the allow-list right after they connect."""

    def __init__(self, owner: _Server, *args: Any):
        super().__init__(owner, *args)
        self.link = owner.link
        self.admitted = False

    def callback_connected(self) -> None:
        peer = self.transport.get_extra_info("peername") if self.transport else None
        if not self.link.admits(peer[0] if peer else ""):
            self.link.refused += 1
            self.transport.close()
            return
        self.admitted = True
        self.link.clients += 1
        super().callback_connected()

    def callback_disconnected(self, exc: Exception | None) -> None:
        if self.admitted:
            self.admitted = False
            self.link.clients -= 1
        super().callback_disconnected(exc)


class _Server(ModbusTcpServer):
    def __init__(self, link: ModbusServerLink, device: SimDevice, address: tuple[str, int]):
        self.link = link
        super().__init__(device, address=address)

    def callback_new_connection(self) -> _Handler:
        return _Handler(self, self.trace_packet, self.trace_pdu, self.trace_connect)


class ModbusServerLink:
    """The harness's Modbus TCP server on ``loop`` (started with :meth:`start`)."""

    def __init__(self, tables: ModbusTables, host: str, port: int, loop: asyncio.AbstractEventLoop,
                 allowed: Collection[str] = ()):
        self.tables = tables
        self.host = host
        self.loop = loop
        self.allowed = parse_allowed_clients(allowed)
        self.clients = 0  # connected, admitted clients
        self.refused = 0  # connections closed because of the allow-list
        self._requested_port = port
        self._server: _Server | None = None

    def admits(self, peer: str) -> bool:
        if not self.allowed:
            return True
        try:
            address = ipaddress.ip_address(peer)
        except ValueError:
            return False
        return any(address in network for network in self.allowed)

    def start(self) -> None:
        async def listen() -> _Server:
            server = _Server(self, _device(self.tables), (self.host, self._requested_port))
            await server.serve_forever(background=True)
            return server

        try:
            self._server = self.loop.run_until_complete(listen())
        except (OSError, RuntimeError, ModbusException) as error:
            raise LinkError(f"cannot serve Modbus TCP on {self.host}:{self._requested_port}: {error}") from None

    @property
    def port(self) -> int:
        """The port the server listens on (the ephemeral one when 0 was asked for)."""
        if self._server is None or self._server.transport is None:
            return self._requested_port
        sockets = getattr(self._server.transport, "sockets", None)  # an asyncio Server's listening sockets
        return int(sockets[0].getsockname()[1]) if sockets else self._requested_port

    def close(self) -> None:
        if self._server is not None:
            with contextlib.suppress(Exception):
                self.loop.run_until_complete(self._server.shutdown())
            self._server = None


def start_plain_register_server(loop: asyncio.AbstractEventLoop, input_registers: int,
                                holding_registers: int) -> tuple[int, Callable[[], None]]:
    """A plain pymodbus server on its own store (no link tables, no request action) on an ephemeral
    loopback port: the yardstick the exchange benchmark compares the link's server with.
    Returns the port and a function that shuts it down."""
    # A bits entry takes its size from a list of values (a count would be applied twice).
    device = SimDevice(id=0, simdata=(
        [SimData(0, values=[False] * (16 * holding_registers), datatype=DataType.BITS)],
        [SimData(0, values=[False] * (16 * input_registers), datatype=DataType.BITS)],
        [SimData(0, count=holding_registers, values=0, datatype=DataType.REGISTERS)],
        [SimData(0, count=input_registers, values=0, datatype=DataType.REGISTERS)],
    ))

    async def listen() -> ModbusTcpServer:
        server = ModbusTcpServer(device, address=("127.0.0.1", 0))
        await server.serve_forever(background=True)
        return server

    server = loop.run_until_complete(listen())
    sockets = getattr(server.transport, "sockets", None)
    if not sockets:
        raise LinkError("the plain pymodbus server has no listening socket")

    def stop() -> None:
        loop.run_until_complete(server.shutdown())

    return int(sockets[0].getsockname()[1]), stop


class ModbusLinkClient:
    """The PLC's side: a Modbus TCP client that reads and writes whole table ranges."""

    def __init__(self, host: str, port: int, timeout_s: float = 3.0, device_id: int = 1):
        self.host, self.port, self.device_id = host, port, device_id
        self._client = ModbusTcpClient(host, port=port, timeout=timeout_s, retries=0)

    def connect(self) -> bool:
        try:
            return bool(self._client.connect())
        except (OSError, ModbusException):
            return False

    def close(self) -> None:
        self._client.close()

    def read_input_registers(self, address: int, count: int) -> list[int]:
        values: list[int] = []
        while count > 0:
            chunk = min(count, READ_LIMIT)
            values += self._call(self._client.read_input_registers, address, chunk)
            address, count = address + chunk, count - chunk
        return values

    def read_holding_registers(self, address: int, count: int) -> list[int]:
        values: list[int] = []
        while count > 0:
            chunk = min(count, READ_LIMIT)
            values += self._call(self._client.read_holding_registers, address, chunk)
            address, count = address + chunk, count - chunk
        return values

    def write_registers(self, address: int, values: Sequence[int]) -> None:
        self._write_chunks(address, values, range(0, len(values), WRITE_LIMIT))

    def write_registers_last_first(self, address: int, values: Sequence[int]) -> None:
        """Like write_registers, but the chunk holding ``address`` itself goes last."""
        self._write_chunks(address, values, reversed(range(0, len(values), WRITE_LIMIT)))

    def _write_chunks(self, address: int, values: Sequence[int], starts: Iterable[int]) -> None:
        for start in starts:
            chunk = list(values[start: start + WRITE_LIMIT])
            try:
                response = self._client.write_registers(address + start, chunk, device_id=self.device_id)
            except (ModbusException, OSError) as error:
                raise LinkError(f"Modbus server {self.host}:{self.port}: {error}") from None
            if response.isError():
                raise LinkError(f"Modbus server {self.host}:{self.port} refused writing registers"
                                f" {address + start}..{address + start + len(chunk) - 1}:"
                                f" exception {getattr(response, 'exception_code', '?')}")

    def _call(self, method: Callable[..., Any], address: int, count: int) -> list[int]:
        try:
            response = method(address, count=count, device_id=self.device_id)
        except (ModbusException, OSError) as error:
            raise LinkError(f"Modbus server {self.host}:{self.port}: {error}") from None
        if response.isError():
            raise LinkError(f"Modbus server {self.host}:{self.port} refused reading registers"
                            f" {address}..{address + count - 1}: exception {getattr(response, 'exception_code', '?')}")
        return list(response.registers)
