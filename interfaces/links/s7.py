"""S7: the interface data blocks as real S7 data blocks, served by python-snap7.

This is the only module that imports snap7.  An S7 client reads ``DB31.DBX60.4`` as it is:
DB10, DB11, DB19, DB21.., DB31.. are data blocks of their own number and size, the plant inputs
are the process inputs (PE, ``I``), the plant outputs the process outputs (PA, ``Q``).

Write protection, as on the Modbus link: a client may write the PLC->NC byte ranges of the
data blocks and the outputs; a write that touches any other byte (an NC->PLC signal, the
inputs, a byte outside the interface) is refused with the server's S7 error (class 0x84,
code 0x04, "the function cannot be performed") and changes nothing.  A bit write changes only
its bit (python-snap7 would write the whole byte).  The server keeps its own copy of the bytes;
the harness exchanges them with the simulation once per PLC period
(:meth:`S7ServerLink.publish`, :meth:`S7ServerLink.take_outputs`).
"""

from __future__ import annotations

import contextlib
import ipaddress
import logging
import socket
from collections.abc import Collection, Mapping
from typing import Any

from snap7.datatypes import S7Area, S7WordLen
from snap7.error import S7Error
from snap7.server import Server
from snap7.type import SrvArea

from interfaces.links.modbus_tcp import LinkError, parse_allowed_clients
from interfaces.signals import Direction, ExpandedCatalog

logging.getLogger("snap7").setLevel(logging.CRITICAL)

_PLANT_AREAS = {"I": (SrvArea.PE, S7Area.PE), "Q": (SrvArea.PA, S7Area.PA)}


class _ProtectedServer(Server):
    """snap7's server with the link's write protection, bit writes and allow-list."""

    def __init__(self, link: S7ServerLink):
        super().__init__(log=False)
        self.link = link

    def _handle_client(self, client_socket: socket.socket, address: tuple[str, int]) -> None:
        if not self.link.admits(address[0]):
            self.link.refused += 1
            client_socket.close()  # the handler then fails the ISO handshake and cleans up
        super()._handle_client(client_socket, address)

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
        if not self.link.may_write(area, db_number, start, len(write_data)):
            return False
        written: bool = super()._write_to_memory_area(area, db_number, start, write_data)
        if written:
            self.link.outputs_written = True
        return written


class S7ServerLink:
    """The S7 server of the harness (see the module docstring)."""

    def __init__(self, host: str, port: int, allowed: Collection[str] = ()):
        self.host, self.port = host, port
        self.allowed = parse_allowed_clients(allowed)
        self.refused = 0
        self.outputs_written = False
        self.areas: dict[str, bytearray] = {}  # "DB31", "I", "Q" -> the bytes the server serves
        self._writable: dict[tuple[S7Area, int], bytes] = {}
        self._inputs: list[tuple[str, int, int]] = []  # NC->PLC ranges and the plant inputs
        self._outputs: list[tuple[str, int, int]] = []  # PLC->NC ranges and the plant outputs
        self._server = _ProtectedServer(self)

    def admits(self, peer: str) -> bool:
        if not self.allowed:
            return True
        try:
            return any(ipaddress.ip_address(peer) in network for network in self.allowed)
        except ValueError:
            return False

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
        """NC->PLC bytes and plant inputs from the simulation into the served blocks."""
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
