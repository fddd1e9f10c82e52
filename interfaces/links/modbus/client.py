"""The PLC's Modbus TCP client (pymodbus): whole table ranges in chunks the protocol allows, and
pymodbus's exceptions as :class:`~interfaces.links.errors.LinkError` in words."""

from __future__ import annotations

import logging
import time as wallclock
from collections.abc import Callable, Iterable, Sequence
from typing import Any

from pymodbus.client import ModbusTcpClient
from pymodbus.exceptions import ConnectionException, ModbusException, ModbusIOException

from interfaces.links.errors import LinkError, RequestRefused
from interfaces.links.modbus.codec import (
    READ_LIMIT,
    WRITE_LIMIT,
)

CONNECT_PAUSE_S = 0.1  # a client's pause between two connection attempts
# a PLC's client after a lost connection: a harness that still runs takes a new one at once; when none
# does within this window the harness has ended, and so does the PLC process
RECONNECT_WINDOW_S = 2.0

# pymodbus logs every failed connection attempt at error level: its records go to the application's
# logging, not to standard error by default (the PLC says in its own words why it stops).
logging.getLogger("pymodbus").addHandler(logging.NullHandler())


class ModbusLinkClient:
    """The PLC's side: a Modbus TCP client that reads and writes whole table ranges."""

    def __init__(self, host: str, port: int, timeout_s: float = 3.0, device_id: int = 1):
        self.host, self.port, self.device_id = host, port, device_id
        self._client = ModbusTcpClient(host, port=port, timeout=timeout_s, retries=0)

    @property
    def timeout_s(self) -> float:
        """How long a request waits for its answer (and a connect for the server)."""
        return float(self._client.comm_params.timeout_connect or 0.0)

    @timeout_s.setter
    def timeout_s(self, seconds: float) -> None:
        self._client.comm_params.timeout_connect = seconds

    def connect(self) -> bool:
        try:
            return bool(self._client.connect())
        except (OSError, ModbusException):
            return False

    def connect_within(self, seconds: float, should_stop: Callable[[], bool] = lambda: False) -> bool:
        """Connect, trying again every :data:`CONNECT_PAUSE_S` for up to ``seconds`` (or until
        ``should_stop``); False when no server took the connection in that time."""
        deadline = wallclock.monotonic() + seconds
        while not should_stop():
            if self.connect():
                return True
            if wallclock.monotonic() >= deadline:
                return False
            wallclock.sleep(CONNECT_PAUSE_S)
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
                raise self._lost(error) from None
            if response.isError():
                raise RequestRefused(f"Modbus server {self.host}:{self.port} refused writing registers"
                                f" {address + start}..{address + start + len(chunk) - 1}:"
                                f" exception {getattr(response, 'exception_code', '?')}")

    def _call(self, method: Callable[..., Any], address: int, count: int) -> list[int]:
        try:
            response = method(address, count=count, device_id=self.device_id)
        except (ModbusException, OSError) as error:
            raise self._lost(error) from None
        if response.isError():
            raise RequestRefused(f"Modbus server {self.host}:{self.port} refused reading registers"
                            f" {address}..{address + count - 1}: exception {getattr(response, 'exception_code', '?')}")
        return list(response.registers)

    def _lost(self, error: Exception) -> LinkError:
        """A request that got no answer, in words (pymodbus's own messages name its internals)."""
        if isinstance(error, ConnectionException | ConnectionError):
            what = "the server closed the connection"
        elif isinstance(error, ModbusIOException):
            what = f"no answer within {self.timeout_s:g} s"
        elif isinstance(error, OSError):
            what = error.strerror or type(error).__name__
        else:
            what = str(error)
        return LinkError(f"Modbus server {self.host}:{self.port}: {what}")
