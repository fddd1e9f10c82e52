"""What an export needs besides the map's rows (pure, no I/O)."""

from __future__ import annotations

from dataclasses import dataclass

from interfaces.links.modbus.codec import RegisterMap


@dataclass(frozen=True, slots=True)
class ExportContext:
    machine: str  # the machine's name, for the headers and the tag table's name
    register_map: RegisterMap  # the machine's Modbus tables (their sizes place the CODESYS channels)
    io_base: int = 0  # the process image view: table byte t is IB / QB (io_base + t)
