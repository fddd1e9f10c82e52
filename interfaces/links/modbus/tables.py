"""The bytes the harness's Modbus server serves, and the pymodbus device that hands them every access.

pymodbus decodes each request and answers it through its function (malformed and oversized
requests get their exception responses); a request action hands every data access to
:class:`ModbusTables`, the bytes the harness shares with the simulation.  pymodbus's own store
is sized to the largest tables the convention allows and only buffers the answer: what the
tables do not hold (an address outside the current map, a coil in padding or in the reserved
link registers) gets exception 02 (illegal data address).  Modbus itself has no function that
writes input registers or discrete inputs: the NC-to-PLC table is read-only by construction.
The tables, the link block and the description follow :mod:`interfaces.links.modbus.codec`.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, field

from pymodbus.constants import ExcCodes
from pymodbus.simulator import DataType, SimData, SimDevice

from interfaces.links.errors import LinkError
from interfaces.links.modbus.codec import (
    DESCRIPTION_REGISTER,
    LINK_REGISTERS,
    MAX_DESCRIPTION_BYTES,
    MAX_TABLE_REGISTERS,
    READ_COILS,
    READ_DISCRETE_INPUTS,
    READ_INPUT,
    WRITE_COIL,
    WRITE_COILS,
    LinkInput,
    bits_writable,
    read_registers,
    text_registers,
    words_as_bits,
    write_bits,
    write_registers,
)

_COIL_CODES = (READ_COILS, WRITE_COIL, WRITE_COILS)


@dataclass(slots=True)
class ModbusTables:
    """The bytes the Modbus server serves: the two tables and the description.

    ``nc_to_plc`` and ``plc_to_nc`` are table bytes (register ``r`` = bytes ``2r``, ``2r + 1``);
    ``writable`` marks the PLC-to-NC bytes a write lands in.  ``on_write`` is called with the
    first register and the register count of every accepted PLC write.  ``may_write`` is asked
    before a write whose addresses are valid lands (the server sets it for each request: only
    the session's PLC writes); a write it refuses gets exception 01.
    """

    # before the first session only the link block, all zeros: version 0 says "not ready"
    nc_to_plc: bytearray = field(default_factory=lambda: bytearray(2 * LINK_REGISTERS))
    plc_to_nc: bytearray = field(default_factory=lambda: bytearray(2 * LINK_REGISTERS))
    writable: bytes = bytes(2 * LINK_REGISTERS)
    description: bytes = b""
    on_write: Callable[[int, int], None] = lambda first, count: None
    may_write: Callable[[], bool] = lambda: True
    writes: int = 0  # accepted PLC write requests, for statistics

    def set_description(self, text: bytes) -> None:
        if len(text) > MAX_DESCRIPTION_BYTES:
            raise LinkError(f"the interface description has {len(text)} bytes; the link carries"
                            f" {MAX_DESCRIPTION_BYTES}")
        self.description = text

    @property
    def session(self) -> int:
        """The open session (input register 1); 0 while no machine is powered on (version 0)."""
        if not read_registers(self.nc_to_plc, LinkInput.VERSION, 1)[0]:
            return 0
        return read_registers(self.nc_to_plc, LinkInput.SESSION, 1)[0]

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
            if not self.may_write():
                return ExcCodes.ILLEGAL_FUNCTION
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
        if not self.may_write():
            return ExcCodes.ILLEGAL_FUNCTION
        write_bits(self.plc_to_nc, address, values)
        self.writes += 1
        self.on_write(address // 16, (address % 16 + len(values) + 15) // 16)
        return None


def table_device(tables: ModbusTables) -> SimDevice:
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
