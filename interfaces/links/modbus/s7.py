"""S7: the interface data blocks as real S7 data blocks, served by python-snap7.

This is the only module that imports snap7.  An S7 client reads ``DB31.DBX60.4`` as it is:
DB10, DB11, DB19, DB21.., DB31.. are data blocks of their own number and size, the plant inputs
are the process inputs (PE, ``I``), the plant outputs the process outputs (PA, ``Q``).

Write protection, as on the Modbus link: a client may write the PLC->NC byte ranges of the
data blocks and the outputs; a write that touches any other byte (an NC->PLC signal, the
inputs, a byte outside the interface) is refused with the server's S7 error (class 0x84,
code 0x04, "the function cannot be performed") and changes nothing.  A bit write changes only
its bit (python-snap7 would write the whole byte).  A block download (``client.download``)
would replace a whole data block, NC->PLC bytes included: it is refused at its request, with
the same error.  While a session is open only the session's PLC writes
(:mod:`interfaces.links.modbus.access`): the first client that writes owns the link until it
disconnects, unless the link's Modbus PLC owns it already; the others' writes get the same
error.  S7 has no session key: when the owner disconnects its session closes, and the next
writer takes the link only in a new session (a power-on, or the operator's in ``vc serve``).
Sessions are limited as the Modbus connections are: the one idle the longest makes room for a new
client, and one silent for the idle time-out is closed (python-snap7 would keep 64 idle sessions
and lock every further client out).

python-snap7's server serves each client in a thread of its own; the server keeps its own copy
of the bytes, and the harness exchanges them with the simulation once per PLC period
(:meth:`S7ServerLink.publish`, :meth:`S7ServerLink.take_outputs`).
"""

from __future__ import annotations

import contextlib
import logging
import socket
import threading
import time as wallclock
from collections.abc import Collection, Mapping
from dataclasses import dataclass
from typing import Any

from snap7.datatypes import S7Area, S7WordLen
from snap7.error import S7Error
from snap7.server import Server
from snap7.type import SrvArea

from interfaces.links.errors import LinkError
from interfaces.links.modbus.access import NO_KEY, AllowList, ConnectionLimits, LinkOwner
from interfaces.signals import Direction, ExpandedCatalog

# snap7 logs every refused write and every client that leaves: its records go to the
# application's logging (vc serve --verbose), not to standard error by default.
logging.getLogger("snap7").addHandler(logging.NullHandler())

_PLANT_AREAS = {"I": (SrvArea.PE, S7Area.PE), "Q": (SrvArea.PA, S7Area.PA)}
REFUSED = 0x8404  # error class 0x84, code 0x04: the function cannot be performed
Address = tuple[str, int]


@dataclass(slots=True)
class _Session:
    """One client's connection: its socket (to close it) and when it last sent a request."""

    socket: socket.socket
    last_heard: float


class _ProtectedServer(Server):
    """snap7's server with the link's write protection, ownership, bit writes, downloads refused,
    allow-list and session limits."""

    def __init__(self, link: S7ServerLink):
        # python-snap7 refuses clients beyond its own limit before the link can make room for
        # them: its limit is the link's plus room for the newcomers the link then decides on
        super().__init__(log=False, max_clients=2 * link.limits.max_clients)
        self.link = link
        self._writer = threading.local()  # the client whose write request this thread serves

    def _handle_client(self, client_socket: socket.socket, address: Address) -> None:
        if not self.link.admit(client_socket, address):
            client_socket.close()  # the handler then fails the ISO handshake and cleans up
        try:
            super()._handle_client(client_socket, address)
        finally:
            self.link.forget(address)

    def _process_request(self, request_data: bytes, client_address: Address) -> bytes | None:
        self.link.heard(client_address)
        return super()._process_request(request_data, client_address)

    def _handle_request_download(self, request: dict[str, Any], client_address: Address) -> bytes:
        self.link.refused_downloads += 1
        return self._build_error_response(request, REFUSED)

    def _handle_write_area(self, request: dict[str, Any], client_address: Address) -> bytes:
        self._writer.address = client_address
        return super()._handle_write_area(request, client_address)

    def _parse_address_specification(self, addr_spec: bytes) -> dict[str, Any]:
        parsed: dict[str, Any] = super()._parse_address_specification(addr_spec)
        if parsed and parsed.get("word_len") == S7WordLen.BIT and len(addr_spec) >= 12:
            parsed["bit"] = int.from_bytes(addr_spec[9:12], "big") % 8
        return parsed

    def _parse_write_address(self, request: dict[str, Any]) -> tuple[S7Area, int, int, int, bytearray] | None:
        parsed = super()._parse_write_address(request)
        spec = request.get("parameters", {}).get("address_spec", {})
        if parsed is None or spec.get("word_len") != S7WordLen.BIT:
            return parsed
        area, db_number, start, _count, data = parsed
        current = self.memory_areas.get((area, db_number))
        if current is None or start >= len(current):
            return parsed
        mask = 1 << spec.get("bit", 0)
        byte = current[start] | mask if data[0] & 1 else current[start] & ~mask & 0xFF
        return area, db_number, start, 1, bytearray([byte])

    def _write_to_memory_area(self, area: S7Area, db_number: int, start: int, write_data: bytearray) -> bool:
        writer: Address = getattr(self._writer, "address", ("", 0))
        if not self.link.may_write(area, db_number, start, len(write_data)) or \
                not self.link.owner.may_write(("s7", writer), writer[0], claim=NO_KEY):
            return False
        written: bool = super()._write_to_memory_area(area, db_number, start, write_data)
        if written:
            self.link.outputs_written = True
        return written


class S7ServerLink:
    """The S7 server of the harness (see the module docstring).

    ``owner``: who may write, shared with the link's Modbus server (by default one of its own);
    ``limits``: sessions and idle time-out."""

    def __init__(self, host: str, port: int, allowed: Collection[str] = (), *, owner: LinkOwner | None = None,
                 limits: ConnectionLimits | None = None):
        self.host, self.port = host, port
        self.allowed = AllowList(allowed)
        self.owner = owner if owner is not None else LinkOwner()
        self.limits = limits if limits is not None else ConnectionLimits()
        self.refused = 0  # clients refused by the allow-list
        self.full = 0  # clients refused because every session was busy
        self.evicted = 0  # idle sessions closed to make room
        self.idle_closed = 0  # sessions closed after the idle time-out
        self.refused_downloads = 0
        self.outputs_written = False
        self.areas: dict[str, bytearray] = {}  # "DB31", "I", "Q" -> the bytes the server serves
        self._writable: dict[tuple[S7Area, int], bytes] = {}
        self._inputs: list[tuple[str, int, int]] = []  # NC->PLC ranges and the plant inputs
        self._outputs: list[tuple[str, int, int]] = []  # PLC->NC ranges and the plant outputs
        self._sessions: dict[Address, _Session] = {}
        self._sessions_lock = threading.Lock()
        self._swept = wallclock.monotonic()
        self._server = _ProtectedServer(self)

    def start(self) -> None:
        try:
            self._server.start_to(self.host, self.port)
        except (S7Error, OSError, ValueError) as error:
            raise LinkError(f"cannot serve S7 on {self.host}:{self.port}: {error}") from None
        if self.port == 0 and self._server.server_socket is not None:
            self.port = int(self._server.server_socket.getsockname()[1])

    def close(self) -> None:
        with contextlib.suppress(Exception):
            self._server.stop()

    @property
    def clients(self) -> int:
        return len(self._sessions)

    def describe(self) -> str:
        """The statistics line's part of this server."""
        closed = [f"{count} {why}" for count, why in (
            (self.refused, "not on the allow-list"), (self.full, "while every session was busy"),
            (self.evicted, "idle to make room"), (self.idle_closed, "idle for the time-out")) if count]
        text = f"S7: {self.clients} client(s)"
        if self.refused_downloads:
            text += f", {self.refused_downloads} block download(s) refused"
        return text + (", sessions closed: " + ", ".join(closed) if closed else "")

    # ------------------------------------------------------------------ sessions of clients
    def admit(self, client: socket.socket, address: Address) -> bool:
        """A new client: the allow-list, then the limit (the session idle the longest makes room)."""
        if not self.allowed.admits(address[0]):
            self.refused += 1
            return False
        self.close_idle()
        with self._sessions_lock:
            if len(self._sessions) >= self.limits.max_clients:
                idle = [(session.last_heard, peer) for peer, session in self._sessions.items()
                        if not self.owner.owns(("s7", peer))]
                if not idle:
                    self.full += 1
                    return False
                _, longest = min(idle)
                self._end(longest)
                self.evicted += 1
            self._sessions[address] = _Session(client, wallclock.monotonic())
        return True

    def heard(self, address: Address) -> None:
        session = self._sessions.get(address)
        if session is not None:
            session.last_heard = wallclock.monotonic()

    def forget(self, address: Address) -> None:
        with self._sessions_lock:
            self._sessions.pop(address, None)
        self.owner.release(("s7", address))

    def close_idle(self) -> None:
        """Close the sessions that sent nothing for the idle time-out."""
        now = wallclock.monotonic()
        self._swept = now
        with self._sessions_lock:
            for address in [peer for peer, session in self._sessions.items()
                            if now - session.last_heard > self.limits.idle_timeout_s]:
                self._end(address)
                self.idle_closed += 1

    def _end(self, address: Address) -> None:
        """Close a session from outside its thread: the thread's receive ends, it cleans up."""
        session = self._sessions.pop(address)
        self.owner.release(("s7", address))
        with contextlib.suppress(OSError):
            session.socket.shutdown(socket.SHUT_RDWR)

    # ------------------------------------------------------------------ sessions and exchange
    def open_session(self, catalog: ExpandedCatalog, plant_sizes: Mapping[str, int]) -> None:
        """Register the data blocks and the process image of a (new) machine."""
        for key in list(self.areas):
            server_area, number = self._server_area(key)
            self._server.unregister_area(server_area, number)
        self.areas = {key: bytearray(size) for key, size in catalog.area_sizes.items()}
        self.areas.update({key: bytearray(plant_sizes.get(key, 0)) for key in _PLANT_AREAS})
        outputs = catalog.byte_ranges(Direction.PLC_TO_NC)
        self._inputs = [*catalog.byte_ranges(Direction.NC_TO_PLC), ("I", 0, len(self.areas["I"]))]
        self._outputs = [*outputs, ("Q", 0, len(self.areas["Q"]))]
        self._writable = {}
        for key, data in self.areas.items():
            server_area, number = self._server_area(key)
            self._server.register_area(server_area, number, data)
            mask = bytearray(len(data))
            for area, start, stop in self._outputs:
                if area == key:
                    mask[start:stop] = b"\xff" * (stop - start)
            self._writable[(self._s7_area(key), number)] = bytes(mask)
        self.outputs_written = False

    @staticmethod
    def _server_area(key: str) -> tuple[SrvArea, int]:
        if key in _PLANT_AREAS:
            return _PLANT_AREAS[key][0], 0
        return SrvArea.DB, int(key[2:])

    @staticmethod
    def _s7_area(key: str) -> S7Area:
        return _PLANT_AREAS[key][1] if key in _PLANT_AREAS else S7Area.DB

    def may_write(self, area: S7Area, number: int, start: int, count: int) -> bool:
        mask = self._writable.get((area, number if area == S7Area.DB else 0))
        return mask is not None and start + count <= len(mask) and all(mask[start: start + count])

    def publish(self, areas: Mapping[str, bytearray]) -> None:
        """NC->PLC bytes and plant inputs from the simulation into the served blocks (and, once a
        second, the idle sessions closed)."""
        if wallclock.monotonic() - self._swept > 1.0:
            self.close_idle()
        for key, start, stop in self._inputs:
            self.areas[key][start:stop] = areas[key][start:stop]

    def take_outputs(self, areas: Mapping[str, bytearray]) -> bool:
        """The PLC's writes since the last exchange into the simulation; False if there were none."""
        if not self.outputs_written:
            return False
        self.outputs_written = False
        for key, start, stop in self._outputs:
            areas[key][start:stop] = self.areas[key][start:stop]
        return True

    def mirror_outputs(self, areas: Mapping[str, bytearray]) -> None:
        """Show what another link's PLC wrote, so an S7 client sees the whole interface."""
        for key, start, stop in self._outputs:
            self.areas[key][start:stop] = areas[key][start:stop]
