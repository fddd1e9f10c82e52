"""The PLC's end of the Modbus link (interfaces/links/modbus/plc_end.py) against a link block held in
memory: the one handshake plc_stub and awlsim's bridge both drive.  (Against the harness's server:
tests/interfaces/links/modbus/test_modbus_plc_end.py, tests/vc/harness/links/test_modbus.py, and the
awlsim example's golden trace: tests/plc_awlsim/.)"""

from __future__ import annotations

import pytest

from interfaces.links.errors import RequestRefused
from interfaces.links.modbus import plc_end
from interfaces.links.modbus.codec import (
    LINK_VERSION,
    MODE_FREE_RUNNING,
    MODE_LOCKSTEP,
    LinkHolding,
    LinkInput,
    session_key_registers,
)
from interfaces.links.modbus.plc_end import ModbusPlcEnd, Session

NC_TO_PLC, PLC_TO_NC = 20, 18  # registers of the tables, the link block included
KEY = 0x0123_4567_89AB_CDEF


class _Server:
    """A link block in memory, as a :class:`~interfaces.links.modbus.client.ModbusLinkClient` reads it."""

    def __init__(self, mode: int = MODE_LOCKSTEP, grant: int = 1):
        self.inputs = [0] * 64
        self.inputs[LinkInput.VERSION] = LINK_VERSION
        self.inputs[LinkInput.SESSION], self.inputs[LinkInput.BOOT_ID] = 1, 7
        self.inputs[LinkInput.MODE], self.inputs[LinkInput.SCAN_GRANT] = mode, grant
        self.inputs[LinkInput.IPO_CYCLE_US], self.inputs[LinkInput.PLC_CYCLE_IPO] = 2000, 5
        self.inputs[LinkInput.NC_TO_PLC_REGISTERS] = NC_TO_PLC
        self.inputs[LinkInput.PLC_TO_NC_REGISTERS] = PLC_TO_NC
        self.inputs[16:NC_TO_PLC] = [0xA1, 0xA2, 0xA3, 0xA4]
        self.writes: list[tuple[int, list[int]]] = []
        self.refuse = False
        self.timeout_s = 3.0
        self.host, self.port = "127.0.0.1", 5020

    def read_input_registers(self, address: int, count: int) -> list[int]:
        return self.inputs[address: address + count]

    def write_registers(self, address: int, values: list[int]) -> None:
        if self.refuse:
            raise RequestRefused("refused: exception 1")
        self.writes.append((address, list(values)))

    write_registers_last_first = write_registers


def _end(server: _Server, started: list[Session]) -> ModbusPlcEnd:
    return ModbusPlcEnd(server, started.append, key=KEY)  # type: ignore[arg-type]


def test_a_new_session_is_started_then_claimed_with_the_key_and_its_grant_runs_once() -> None:
    server, started = _Server(), []
    end = _end(server, started)
    scan = end.poll()
    assert [session.number for session in started] == [1]
    assert server.writes == [(LinkHolding.SESSION_READY, [1, *session_key_registers(KEY)])]
    assert scan is not None and scan.done == 1 and scan.inputs[16:] == [0xA1, 0xA2, 0xA3, 0xA4]
    assert len(scan.inputs) == NC_TO_PLC
    assert end.poll() is None  # the same grant: no second scan
    assert server.timeout_s == plc_end.LOCKSTEP_TIMEOUT_S


def test_waiting_for_a_session_leaves_the_grant_to_the_next_poll() -> None:
    """awlsim's bridge waits for the session, restarts its CPU, then polls: the grant the harness gave
    meanwhile must still be there (taken while waiting, it was lost and lockstep stood still)."""
    server, started = _Server(), []
    end = _end(server, started)
    assert end.wait_for_session() is started[0]
    scan = end.poll()
    assert scan is not None and scan.done == 1


def test_the_outputs_go_with_the_scan_done_and_the_session_words_of_the_link() -> None:
    server, started = _Server(grant=9), []
    end = _end(server, started)
    scan = end.poll()
    assert scan is not None
    outputs = bytearray(range(2 * PLC_TO_NC))
    end.finish(scan, outputs)
    address, values = server.writes[-1]
    assert address == 0 and len(values) == PLC_TO_NC
    assert values[LinkHolding.SCAN_DONE] == 9 and values[LinkHolding.SESSION_READY] == 1
    assert values[2:] == [outputs[2 * r] << 8 | outputs[2 * r + 1] for r in range(2, PLC_TO_NC)]



def _scan_and_finish(end: ModbusPlcEnd, server: _Server, grant: int, outputs: bytearray) -> list[int]:
    """Grant ``grant``, run its scan with ``outputs``; the addresses written, in order."""
    server.inputs[LinkInput.SCAN_GRANT] = grant
    scan = end.poll()
    assert scan is not None and scan.done == grant
    server.writes.clear()
    end.finish(scan, outputs)
    return [address for address, _ in server.writes]


def test_a_large_table_goes_in_chunks_with_register_0_last_and_unchanged_chunks_are_not_sent_again() -> None:
    """Each left-out chunk is a Modbus round trip fewer per scan (the server holds the registers for the
    session); register 0, the scan-done word, goes every scan, and after a refused write the whole table."""
    server, started = _Server(), []
    server.inputs[LinkInput.PLC_TO_NC_REGISTERS] = 300  # three requests of at most 123 registers
    end = _end(server, started)
    outputs = bytearray(600)
    assert _scan_and_finish(end, server, 1, outputs) == [246, 123, 0]
    assert _scan_and_finish(end, server, 2, outputs) == [0]
    outputs[2 * 130 + 1] = 1  # a bit of register 130 changed
    assert _scan_and_finish(end, server, 3, outputs) == [123, 0]
    assert server.writes[0][1][130 - 123] == 1
    assert _scan_and_finish(end, server, 4, outputs) == [0]
    server.refuse = True  # the session's write refused (another PLC took it): the table is not known
    with pytest.raises(RequestRefused):
        _scan_and_finish(end, server, 5, outputs)
    end.refused(RequestRefused("refused"))
    server.refuse = False
    assert _scan_and_finish(end, server, 6, outputs) == [246, 123, 0]


def test_free_running_every_poll_is_a_scan_counted_as_the_sign_of_life() -> None:
    server, started = _Server(mode=MODE_FREE_RUNNING, grant=0), []
    end = _end(server, started)
    assert [scan.done for scan in (end.poll(), end.poll(), end.poll()) if scan is not None] == [1, 2, 3]
    assert server.timeout_s == plc_end.TIMEOUT_S


def test_a_refused_claim_is_said_once_and_the_end_waits_for_a_new_session(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(plc_end.wallclock, "sleep", lambda seconds: None)
    server, started, said = _Server(), [], []
    end = ModbusPlcEnd(server, started.append, log=said.append, key=KEY)  # type: ignore[arg-type]
    server.refuse = True
    assert end.poll() is None and end.poll() is None and end.session is None
    assert len(started) == 1 and len(said) == 1 and "refused this PLC's claim" in said[0]
    server.inputs[LinkInput.SESSION] = 2  # the next power-on
    server.refuse = False
    assert end.poll() is not None and end.session is not None and end.session.number == 2


def test_a_new_boot_id_is_a_new_session_though_its_number_is_the_same() -> None:
    server, started = _Server(), []
    end = _end(server, started)
    end.poll()
    server.inputs[LinkInput.BOOT_ID] = 8  # another harness process: its sessions count from 1 again
    end.poll()
    assert [(session.number, session.boot_id) for session in started] == [(1, 7), (1, 8)]


def test_another_link_version_stops_the_plc_before_it_claims_anything() -> None:
    server, started = _Server(), []
    server.inputs[LinkInput.VERSION] = LINK_VERSION + 1
    with pytest.raises(plc_end.PlcSetupError, match=f"link version {LINK_VERSION + 1}, this PLC {LINK_VERSION}"):
        _end(server, started).poll()
    assert started == [] and server.writes == []
