"""Modbus TCP: the harness's server (the NC as remote I/O), on pymodbus.

The modules of the Modbus link that import pymodbus are this one, :mod:`~interfaces.links.modbus.tables`
(the bytes served, as a pymodbus device) and :mod:`~interfaces.links.modbus.client` (the PLC's end);
pymodbus's exceptions become :class:`LinkError`.

What the link adds to pymodbus 3.16's server, per connection (:class:`_Connection`):

* **Framing** (:mod:`interfaces.links.modbus.framing`). Every complete request in what arrives is
  answered, once and in its order, also those that arrive while the previous one is served.  A
  header no request has ends the connection after the requests before it are answered.
* **Answers.** Only the functions of the convention are served (FC 1, 2, 3, 4, 5, 6, 15, 16, 22,
  23); every other function code gets exception 01 with its own code | 0x80, a request of a
  served function that pymodbus cannot decode (a count beyond the protocol's limits, a body too
  short) exception 03.  An exception inside the server is answered with exception 04, counted
  and logged with its traceback (logger ``interfaces.links.modbus.server``, level INFO: ``vc
  serve --verbose`` shows it).
* **Ownership and limits** (:mod:`interfaces.links.modbus.access`): while a session is open only the
  session's PLC writes (exception 01 for the others' writes to valid addresses; an address the
  tables do not hold is exception 02 for everybody); connections are limited and idle ones
  closed.
* **Bounded memory per connection.**  Of what a client sent, :data:`PENDING_LIMIT` requests are
  taken out and wait for their answers; the rest waits as bytes, and at :data:`RECEIVE_LIMIT`
  bytes the socket is no longer read (the client's own buffers fill, TCP holds it back).  A
  client that does not take its answers (:data:`ANSWER_LIMIT` bytes of them waiting: asyncio's
  flow control) is served no more and not read until it takes them; that is counted and logged,
  and a connection left so for the idle time-out is closed (its answers dropped).  So a client
  that never reads cannot grow the server (it grew by 350 MB in two minutes).
* **Bounded work per pass of the event loop.** Requests are queued per connection and served
  by one task, the session's PLC first, the other connections in turn, for at most
  :data:`SERVE_SLICE_S` per pass (and at least one request).  So a flood of
  requests cannot hold the loop past the pacer's quiet time before an IPO cycle
  (:mod:`vc.harness.pacer`), and the PLC's exchange never waits behind it.  A share of the time
  for the other clients (a quarter of every 10 ms) was tried as well and dropped: the server then
  slept part of the time, woke late on a busy host, and the NC overran more under a flood, not
  less (bench/README.md).  (New connections are
  not bounded so: asyncio accepts up to 100 in one pass, a few milliseconds for a storm of them;
  a smaller listen backlog made every client of a storm wait for its SYN to be sent again.)

The server runs on an asyncio loop the harness owns and runs whenever it waits (for the PLC's
acknowledgement in lockstep, for the next cycle in real time): one thread, no hand-off.
"""

from __future__ import annotations

import asyncio
import contextlib
import logging
import time as wallclock
from collections import deque
from collections.abc import Callable, Collection
from dataclasses import dataclass
from typing import Any

from pymodbus.constants import ExcCodes
from pymodbus.exceptions import ModbusException
from pymodbus.pdu import ExceptionResponse, ModbusPDU
from pymodbus.pdu.register_message import ReadWriteMultipleRegistersRequest
from pymodbus.server import ModbusTcpServer
from pymodbus.server.requesthandler import ServerRequestHandler
from pymodbus.simulator import DataType, SimData, SimDevice

from interfaces.links.errors import LinkError
from interfaces.links.modbus.access import NO_KEY, AllowList, ConnectionLimits, LinkOwner
from interfaces.links.modbus.codec import (
    MASK_WRITE_REGISTER,
    READ_COILS,
    READ_DISCRETE_INPUTS,
    READ_HOLDING,
    READ_INPUT,
    READ_WRITE_REGISTERS,
    SESSION_KEY_REGISTERS,
    WRITE_COIL,
    WRITE_COILS,
    WRITE_REGISTER,
    WRITE_REGISTERS,
    LinkHolding,
    session_key_of,
)
from interfaces.links.modbus.framing import MBAP, Request, take_requests
from interfaces.links.modbus.tables import ModbusTables, table_device

WRITE_FUNCTIONS = frozenset({WRITE_COIL, WRITE_REGISTER, WRITE_COILS, WRITE_REGISTERS, MASK_WRITE_REGISTER,
                             READ_WRITE_REGISTERS})
SERVED_FUNCTIONS = frozenset({READ_COILS, READ_DISCRETE_INPUTS, READ_HOLDING, READ_INPUT}) | WRITE_FUNCTIONS
SERVE_SLICE_S = 0.0002  # requests served per pass of the event loop, in time
PENDING_LIMIT = 16  # requests of one connection taken out of its bytes and waiting for their answers
RECEIVE_LIMIT = 16 * 1024  # bytes of one connection waiting to be taken before its socket is no longer read
# A Ctrl-C that interrupts the event loop in the middle of a task's step leaves that task pending with
# nothing to wake it (cancelled or not), and the harness then never ended waiting for it: each wait of
# the server's close for its tasks gets this long (asyncio.wait, which neither cancels nor waits again)
SHUTDOWN_TIMEOUT_S = 2.0
ANSWER_LIMIT = 64 * 1024  # answers of one connection not yet taken by its client before it is no longer served

log = logging.getLogger(__name__)
# pymodbus logs every refused request and every dropped connection at warning/error level: its
# records go to the application's logging (vc serve --verbose), not to standard error by default.
logging.getLogger("pymodbus").addHandler(logging.NullHandler())

def session_claim(pdu: ModbusPDU, session: int) -> int | None:
    """The session key of a register write that puts ``session`` into holding register 1 (session
    ready), the PLC's claim of the session (:mod:`interfaces.links.modbus.access`); None when the write
    claims nothing.  The key is holding registers 2..5 of the same request, high word first
    (:data:`~interfaces.links.modbus.access.NO_KEY` when the request does not write all four)."""
    if pdu.function_code in (WRITE_REGISTER, WRITE_REGISTERS):
        first, values = pdu.address, pdu.registers
    elif isinstance(pdu, ReadWriteMultipleRegistersRequest):
        first, values = pdu.write_address, pdu.write_registers
    else:
        return None
    index = LinkHolding.SESSION_READY - first
    if session == 0 or not 0 <= index < len(values) or values[index] != session:
        return None
    key = LinkHolding.SESSION_KEY - first
    if key + SESSION_KEY_REGISTERS > len(values):
        return NO_KEY
    return session_key_of(values[key: key + SESSION_KEY_REGISTERS])



def _anybody() -> bool:
    return True


@dataclass(slots=True)
class ServerCounters:
    """What the server did, for ``vc serve``'s statistics."""

    requests: int = 0  # requests answered
    exceptions: int = 0  # of them with an exception response
    failures: int = 0  # of them with exception 04: the server failed (logged)
    framing_errors: int = 0  # connections closed after a header no request has
    refused: int = 0  # connections closed because of the allow-list
    full: int = 0  # connections closed because every connection was busy
    evicted: int = 0  # idle connections closed to make room for a new one
    idle_closed: int = 0  # connections closed after the idle time-out
    stalls: int = 0  # times a client left its answers untaken and was no longer read
    stalled_closed: int = 0  # connections closed after leaving their answers untaken for the idle time-out

    def describe(self) -> str:
        parts = [f"{self.requests} requests"]
        if self.exceptions:
            parts.append(f"{self.exceptions} exception responses")
        if self.failures:
            parts.append(f"{self.failures} failed in the server (exception 04; --verbose shows why)")
        if self.stalls:
            parts.append(f"{self.stalls} times a client did not take its answers (not read meanwhile)")
        closed = [f"{count} {why}" for count, why in (
            (self.refused, "not on the allow-list"), (self.full, "while every connection was busy"),
            (self.evicted, "idle to make room"), (self.idle_closed, "idle for the time-out"),
            (self.stalled_closed, "with answers untaken for the time-out"),
            (self.framing_errors, "after a malformed header")) if count]
        if closed:
            parts.append("connections closed: " + ", ".join(closed))
        return ", ".join(parts)


class _Connection(ServerRequestHandler):
    """One client connection: its requests as they arrive (module docstring); the link answers them."""

    def __init__(self, owner: _Server, *args: Any):
        super().__init__(owner, *args)
        self.link = owner.link
        self.peer = ""
        self.admitted = False
        self.received = bytearray()
        self.requests: deque[Request] = deque()
        self.queued = False  # waits in the link's queue of connections to serve
        self.paused = False  # its socket is not read until its requests are answered
        self.stalled_since: float | None = None  # its client has not taken its answers since then
        self.close_when_answered = False  # a malformed header followed the queued requests
        self.last_active = wallclock.monotonic()  # it last sent something, or one of its requests was answered

    def callback_connected(self) -> None:
        peer = self.transport.get_extra_info("peername") if self.transport else None
        self.peer = str(peer[0]) if peer else ""
        if not self.link.admit(self):
            self.transport.close()
            return
        self.admitted = True
        if (stream := self.stream) is not None:
            stream.set_write_buffer_limits(high=ANSWER_LIMIT)
        super().callback_connected()

    def callback_disconnected(self, exc: Exception | None) -> None:
        if self.admitted:
            self.admitted = False
            self.link.forget(self)
        super().callback_disconnected(exc)

    def data_received(self, data: bytes) -> None:
        """Instead of pymodbus's buffer, which keeps one request and drops the rest (module docstring)."""
        if not self.admitted or self.close_when_answered:
            return
        self.last_active = wallclock.monotonic()
        self.received += data
        self.take()

    def take(self) -> None:
        """Requests out of the bytes that arrived, while fewer than :data:`PENDING_LIMIT` wait for their
        answers; the socket is not read while that many wait or :data:`RECEIVE_LIMIT` bytes do."""
        room = PENDING_LIMIT - len(self.requests)
        if room > 0 and len(self.received) >= MBAP.size and not self.close_when_answered:
            requests, problem = take_requests(self.received, room)
            self.requests.extend(requests)
            if problem is not None:
                self.link.malformed(self, problem)  # the requests before it are answered, then it closes
        if len(self.requests) >= PENDING_LIMIT or len(self.received) >= RECEIVE_LIMIT:
            self.pause()
        if self.requests:
            self.link.ready(self)

    def answered(self) -> None:
        """A request was answered: take the next ones; read the socket again when little waits."""
        self.last_active = wallclock.monotonic()
        self.take()
        if len(self.requests) <= PENDING_LIMIT // 2 and len(self.received) < RECEIVE_LIMIT // 2:
            self.resume()

    # the transport's flow control: its buffer of answers passed ANSWER_LIMIT, or drained again
    def pause_writing(self) -> None:
        """The client does not take its answers: no more are made, and its socket is not read, until
        it does (module docstring); counted and logged."""
        self.stalled_since = wallclock.monotonic()
        self.pause()
        self.link.stalled(self)

    def resume_writing(self) -> None:
        self.stalled_since = None
        if self.requests:
            self.link.ready(self)
        self.answered()

    @property
    def stalled(self) -> bool:
        return self.stalled_since is not None

    @property
    def stream(self) -> asyncio.Transport | None:
        """The connection's transport while it is open."""
        transport = self.transport
        return transport if isinstance(transport, asyncio.Transport) and not transport.is_closing() else None

    def pause(self) -> None:
        if not self.paused and (stream := self.stream) is not None:
            self.paused = True
            stream.pause_reading()

    def resume(self) -> None:
        if self.paused and (stream := self.stream) is not None and not self.close_when_answered \
                and not self.stalled:
            self.paused = False
            stream.resume_reading()

    def write(self, frame: bytes) -> None:
        if (stream := self.stream) is not None:
            stream.write(frame)

    def disconnect(self) -> None:
        """Close the connection; the link forgets it when the transport reports it lost.  Answers its
        client has not taken are dropped (a close would wait for them to be taken)."""
        stream = self.stream
        if stream is not None and self.stalled:
            stream.abort()
        elif self.transport is not None:
            self.transport.close()


class _Server(ModbusTcpServer):
    def __init__(self, link: ModbusServerLink, device: SimDevice, address: tuple[str, int]):
        self.link = link
        super().__init__(device, address=address)

    def callback_new_connection(self) -> _Connection:
        return _Connection(self, self.trace_packet, self.trace_pdu, self.trace_connect)


class ModbusServerLink:
    """The harness's Modbus TCP server on ``loop`` (started with :meth:`start`).

    ``allowed``: the allow-list of clients; ``owner``: who may write (shared with the other servers
    of the link; by default one of its own); ``limits``: connections and idle time-out."""

    def __init__(self, tables: ModbusTables, host: str, port: int, loop: asyncio.AbstractEventLoop,
                 allowed: Collection[str] = (), *, owner: LinkOwner | None = None,
                 limits: ConnectionLimits | None = None):
        self.tables = tables
        self.host = host
        self.loop = loop
        self.allowed = AllowList(allowed)
        self.owner = owner if owner is not None else LinkOwner()
        self.limits = limits if limits is not None else ConnectionLimits()
        self.counters = ServerCounters()
        self._requested_port = port
        self._server: _Server | None = None
        self._connections: list[_Connection] = []
        self._waiting: deque[_Connection] = deque()  # connections with requests, in turn
        self._work = asyncio.Event()
        self._answering: asyncio.Task[None] | None = None
        self._sweep: asyncio.TimerHandle | None = None

    @property
    def clients(self) -> int:
        """Connected, admitted clients."""
        return len(self._connections)

    def held_bytes(self) -> int:
        """What the server holds for its clients: bytes received and not yet taken as requests, and
        answers their clients have not taken yet (both bounded per connection: module docstring)."""
        return sum(len(connection.received) + (connection.stream.get_write_buffer_size() if connection.stream else 0)
                   for connection in self._connections)

    def start(self) -> None:
        async def listen() -> _Server:
            server = _Server(self, table_device(self.tables), (self.host, self._requested_port))
            await server.serve_forever(background=True)
            return server

        try:
            self._server = self.loop.run_until_complete(listen())
        except (OSError, RuntimeError, ModbusException) as error:
            raise LinkError(f"cannot serve Modbus TCP on {self.host}:{self._requested_port}: {error}") from None
        self._answering = self.loop.create_task(self._answer_requests())
        self._sweep = self.loop.call_later(self._sweep_period(), self._close_idle)

    @property
    def port(self) -> int:
        """The port the server listens on (the ephemeral one when 0 was asked for)."""
        if self._server is None or self._server.transport is None:
            return self._requested_port
        sockets = getattr(self._server.transport, "sockets", None)  # an asyncio Server's listening sockets
        return int(sockets[0].getsockname()[1]) if sockets else self._requested_port

    def close(self) -> None:
        if self._sweep is not None:
            self._sweep.cancel()
            self._sweep = None
        if self._answering is not None:
            self._answering.cancel()
            with contextlib.suppress(BaseException):
                self.loop.run_until_complete(asyncio.wait({self._answering}, timeout=SHUTDOWN_TIMEOUT_S))
            self._answering = None
        if self._server is not None:
            with contextlib.suppress(Exception):
                shutdown = self.loop.create_task(self._server.shutdown())
                self.loop.run_until_complete(asyncio.wait({shutdown}, timeout=SHUTDOWN_TIMEOUT_S))
            self._server = None

    def describe(self) -> str:
        """The statistics line's part of this server."""
        return f"Modbus: {self.clients} client(s), {self.counters.describe()}"

    # ------------------------------------------------------------------ connections
    def admit(self, connection: _Connection) -> bool:
        """A new connection: the allow-list, then the limit (the longest idle one makes room)."""
        if not self.allowed.admits(connection.peer):
            self.counters.refused += 1
            return False
        if len(self._connections) >= self.limits.max_clients and not self._make_room():
            self.counters.full += 1
            return False
        self._connections.append(connection)
        return True

    def _make_room(self) -> bool:
        idle = [connection for connection in self._connections
                if (not connection.requests or connection.stalled) and not self.owner.owns(connection)]
        if not idle:
            return False
        longest = min(idle, key=lambda connection: connection.last_active)
        self._drop(longest)
        self.counters.evicted += 1
        return True

    def _drop(self, connection: _Connection) -> None:
        if connection in self._connections:
            self._connections.remove(connection)
        connection.requests.clear()
        self.owner.release(connection)
        connection.disconnect()

    def forget(self, connection: _Connection) -> None:
        """A connection is gone: its requests with it, and its ownership of the link."""
        if connection in self._connections:
            self._connections.remove(connection)
        connection.requests.clear()
        self.owner.release(connection)

    def _sweep_period(self) -> float:
        return min(1.0, self.limits.idle_timeout_s / 4)

    def _close_idle(self) -> None:
        silent_since = wallclock.monotonic() - self.limits.idle_timeout_s
        for connection in list(self._connections):
            if connection.stalled_since is not None and connection.stalled_since < silent_since:
                log.info("Modbus: closing the connection of %s: it has not taken its answers for %g s",
                         connection.peer, self.limits.idle_timeout_s)
                self._drop(connection)
                self.counters.stalled_closed += 1
            elif connection.last_active < silent_since and not connection.requests:
                self._drop(connection)
                self.counters.idle_closed += 1
        self._sweep = self.loop.call_later(self._sweep_period(), self._close_idle)

    def stalled(self, connection: _Connection) -> None:
        """``connection``'s client does not take its answers (:meth:`_Connection.pause_writing`)."""
        self.counters.stalls += 1
        log.info("Modbus: %s does not take its answers (%d bytes waiting): its requests are not read until it"
                 " does", connection.peer, connection.stream.get_write_buffer_size() if connection.stream else 0)

    def malformed(self, connection: _Connection, problem: str) -> None:
        """A header no request has: answer what came before it, then close."""
        self.counters.framing_errors += 1
        log.info("Modbus: closing the connection of %s after %s", connection.peer, problem)
        connection.close_when_answered = True
        connection.pause()
        if not connection.requests:
            self._drop(connection)

    # ------------------------------------------------------------------ answering
    def ready(self, connection: _Connection) -> None:
        """``connection`` has requests to answer."""
        if not connection.queued:
            connection.queued = True
            self._waiting.append(connection)
        self._work.set()

    def _next(self) -> _Connection | None:
        """The connection whose request is answered next: the session's PLC first, then in turn."""
        owner = self.owner.owner
        if isinstance(owner, _Connection) and owner.requests and owner.admitted and not owner.stalled:
            return owner
        while self._waiting:
            connection = self._waiting.popleft()
            connection.queued = False
            if connection.requests and connection.admitted and not connection.stalled:
                return connection
        return None

    async def _answer_requests(self) -> None:
        """The task that answers every request (module docstring: bounded work per pass)."""
        while True:
            began = wallclock.perf_counter()
            while (connection := self._next()) is not None:
                await self._answer(connection, connection.requests.popleft())
                if not connection.requests and connection.close_when_answered:
                    self._drop(connection)
                else:
                    connection.answered()
                if wallclock.perf_counter() - began >= SERVE_SLICE_S:
                    break
            if not self._waiting:
                self._work.clear()
                await self._work.wait()
            else:
                await asyncio.sleep(0)  # the rest in the next pass: the loop serves its other work first

    async def _answer(self, connection: _Connection, request: Request) -> None:
        try:
            response = await self._response(connection, request)
        except Exception as error:  # whatever pymodbus raises on a request is the server's failure
            response = self._failure(connection, request, error)
        response.transaction_id, response.dev_id = request.transaction, request.unit
        try:
            frame = connection.framer.buildFrame(response)
        except Exception as error:  # a response pymodbus cannot encode is the server's failure
            frame = connection.framer.buildFrame(self._failure(connection, request, error))
        self.counters.requests += 1
        if response.function_code & 0x80:
            self.counters.exceptions += 1
        connection.write(frame)

    async def _response(self, connection: _Connection, request: Request) -> ModbusPDU:
        function = request.pdu[0]
        if function not in SERVED_FUNCTIONS:
            return ExceptionResponse(function, ExcCodes.ILLEGAL_FUNCTION)
        assert self._server is not None  # requests come only while it serves
        pdu = self._server.decoder.decode(request.pdu)
        if pdu is None:  # a count beyond the protocol's limits, a body too short
            return ExceptionResponse(function, ExcCodes.ILLEGAL_VALUE)
        session = self.tables.session
        if function in WRITE_FUNCTIONS and session:  # only the session's PLC: asked where a write lands
            claim = session_claim(pdu, session)
            self.tables.may_write = lambda: self.owner.may_write(connection, connection.peer, claim)
        try:
            # pymodbus's own handler passes its SimCore where the PDUs name a ModbusServerContext
            context: Any = self._server.context
            return await pdu.datastore_update(context, request.unit)
        except Exception as error:
            return self._failure(connection, request, error)
        finally:
            self.tables.may_write = _anybody

    def _failure(self, connection: _Connection, request: Request, error: Exception) -> ModbusPDU:
        self.counters.failures += 1
        log.info("Modbus: exception 04 to %s for function %d (%s)", connection.peer, request.pdu[0],
                 error, exc_info=error)
        return ExceptionResponse(request.pdu[0], ExcCodes.DEVICE_FAILURE)


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

