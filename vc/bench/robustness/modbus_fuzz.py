"""The Modbus part: frames of every kind against ``vc serve --realtime`` while the built-in PLC drives it.

The fuzzer is a raw-socket client (it must send what no Modbus library would).  Its kinds of
input, each a share of the frames asked for:

* in step with the byte stream (a valid MBAP header, so every frame is a request and must get
  exactly one answer, in order, under its transaction id and its function code or code | 0x80):
  random PDUs, every function code with bodies of several lengths, out-of-range counts and
  addresses of the served functions, requests split over segments, pipelined batches of 2 to
  100 requests;
* out of step (no answer is due; the server must survive and serve the next client): random bytes,
  headers whose length is wrong, requests cut short, each on a connection of its own;
* 200 connections at once (each request answered, or the connection closed because the server
  is full), and 100 idle half-open connections (a started header, then silence) that must not keep
  a client out and must be closed by the idle time-out.

The fuzzer never owns the session (the PLC does): every write it makes must be refused, and one
that is taken is a rule violation, as is an unserved function code answered without exception 01,
or an answer under the wrong transaction or function.
"""

from __future__ import annotations

import random
import socket
import struct
import time as wallclock
from collections.abc import Callable
from dataclasses import dataclass

from interfaces.links.modbus.server import SERVED_FUNCTIONS, WRITE_FUNCTIONS
from vc.bench.robustness.campaign import CampaignSettings, Row, Say
from vc.bench.robustness.processes import ServedNc, final_pacing, growth_pct

ANSWER_TIMEOUT_S = 5.0
IDLE_TIMEOUT_S = 2.0  # the server's --idle-timeout in this part: the half-open connections must go
HALF_OPEN = 100
CONNECTIONS = 200
TABLE_REGISTERS = 325  # turn_mill's NC-to-PLC table, for addresses around its end
# the protocol's count limits of the served functions
COUNT_LIMITS = {1: 2000, 2: 2000, 3: 125, 4: 125, 15: 1968, 16: 123, 23: 125}


def _frame(transaction: int, pdu: bytes, unit: int = 1, length: int | None = None, protocol: int = 0) -> bytes:
    return struct.pack(">HHHB", transaction & 0xFFFF, protocol, len(pdu) + 1 if length is None else length,
                       unit) + pdu


@dataclass(slots=True)
class _Tally:
    frames: int = 0
    lost: int = 0
    hangs: int = 0
    violations: int = 0
    refused_connections: int = 0  # closed by the server as it was full (expected)

    def __str__(self) -> str:
        """The running totals as the progress lines show them."""
        return (f"so far {self.frames} frames, {self.lost} lost, {self.hangs} hangs, {self.violations} rule"
                f" violations, {self.refused_connections} connections closed by the server when full")


class _Wire:
    """A raw connection that collects whole answers by their MBAP length."""

    def __init__(self, port: int):
        self.socket = socket.create_connection(("127.0.0.1", port), timeout=ANSWER_TIMEOUT_S)
        self.socket.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
        self.buffer = b""
        self.closed = False

    def send(self, data: bytes) -> bool:
        try:
            self.socket.sendall(data)
        except OSError:
            self.closed = True
        return not self.closed

    def answers(self, count: int, timeout_s: float = ANSWER_TIMEOUT_S) -> list[bytes]:
        found: list[bytes] = []
        deadline = wallclock.monotonic() + timeout_s
        while len(found) < count:
            while len(self.buffer) >= 6 and len(self.buffer) >= 6 + struct.unpack_from(">H", self.buffer, 4)[0]:
                end = 6 + struct.unpack_from(">H", self.buffer, 4)[0]
                found.append(self.buffer[:end])
                self.buffer = self.buffer[end:]
            left = deadline - wallclock.monotonic()
            if len(found) >= count or left <= 0 or self.closed:
                break
            self.socket.settimeout(left)
            try:
                chunk = self.socket.recv(65536)
            except TimeoutError:
                break
            except OSError:
                chunk = b""
            if not chunk:
                self.closed = True
            self.buffer += chunk
        return found

    def close(self) -> None:
        self.socket.close()


class _Fuzzer:
    def __init__(self, port: int, generator: random.Random):
        self.port = port
        self.random = generator
        self.tally = _Tally()
        self._transaction = 0

    def _next_transaction(self) -> int:
        self._transaction = (self._transaction + 1) & 0xFFFF
        return self._transaction

    # ------------------------------------------------------------------ requests that must be answered
    def answered(self, wire: _Wire, pdus: list[bytes], send: Callable[[bytes], None] | None = None) -> None:
        """Send ``pdus`` as requests (at once, or through ``send``) and check the answers."""
        transactions = [self._next_transaction() for _ in pdus]
        data = b"".join(_frame(transaction, pdu, unit=self.random.randrange(256))
                        for transaction, pdu in zip(transactions, pdus, strict=True))
        self.tally.frames += len(pdus)
        if send is not None:
            send(data)
        elif not wire.send(data):
            self.tally.lost += len(pdus)
            return
        answers = wire.answers(len(pdus))
        self.tally.lost += len(pdus) - len(answers)
        for transaction, pdu, answer in zip(transactions, pdus, answers, strict=False):
            self._check(transaction, pdu, answer)

    def _check(self, transaction: int, pdu: bytes, answer: bytes) -> None:
        function = pdu[0]
        answered_function = answer[7] if len(answer) > 7 else -1
        wrong = struct.unpack_from(">H", answer)[0] != transaction or answered_function not in (function,
                                                                                               function | 0x80)
        if function not in SERVED_FUNCTIONS:
            wrong = wrong or answer[7:9] != bytes([function | 0x80, 0x01])
        elif function in WRITE_FUNCTIONS:
            wrong = wrong or not answered_function & 0x80  # a foreign write was taken
        self.tally.violations += wrong

    def random_pdus(self, count: int) -> None:
        wire = _Wire(self.port)
        for start in range(0, count, 20):
            batch = [bytes([self.random.randrange(256)]) + self.random.randbytes(self.random.randrange(253))
                     for _ in range(min(20, count - start))]
            self.answered(wire, batch)
        wire.close()

    def every_function_code(self, count: int) -> None:
        wire = _Wire(self.port)
        bodies = (b"", b"\x00", b"\x00\x10\x00\x01", b"\x00\x10\x00\x01\x02\x00\x00")
        sent = 0
        while sent < count:
            for function in range(256):
                batch = [bytes([function]) + body for body in (*bodies, self.random.randbytes(252))][: count - sent]
                self.answered(wire, batch)
                sent += len(batch)
                if sent >= count:
                    break
        wire.close()

    def counts_and_addresses(self, count: int) -> None:
        wire = _Wire(self.port)
        addresses = (0, 15, 16, TABLE_REGISTERS - 1, TABLE_REGISTERS, 4095, 4096, 4097, 65534, 65535)
        functions = (1, 2, 3, 4, 5, 6, 15, 16, 22, 23)
        for start in range(0, count, 20):
            batch = [self._out_of_range(self.random.choice(functions), self.random.choice(addresses))
                     for _ in range(min(20, count - start))]
            self.answered(wire, batch)
        wire.close()

    def _out_of_range(self, function: int, address: int) -> bytes:
        limit = COUNT_LIMITS.get(function, 1)
        count = self.random.choice((0, 1, limit, limit + 1, 65535, self.random.randrange(65536)))
        if self.random.random() < 0.5:
            address = self.random.randrange(65536)
        if function in (1, 2, 3, 4):
            return struct.pack(">BHH", function, address, count)
        if function == 5:
            return struct.pack(">BHH", function, address, self.random.choice((0, 0xFF00, 0x1234)))
        if function == 6:
            return struct.pack(">BHH", function, address, self.random.randrange(65536))
        if function == 22:
            return struct.pack(">BHHH", function, address, self.random.randrange(65536), self.random.randrange(65536))
        size = (count + 7) // 8 if function == 15 else 2 * count
        size = self.random.choice((size, size + 1, max(0, size - 1), self.random.randrange(256))) & 0xFF
        payload = self.random.randbytes(min(size, 240))
        if function == 23:
            return struct.pack(">BHHHHB", function, address, count, address, count, size) + payload
        return struct.pack(">BHHB", function, address, count, size) + payload

    def splits(self, count: int) -> None:
        wire = _Wire(self.port)

        def in_pieces(data: bytes) -> None:
            while data:
                piece = self.random.randint(1, 9)
                wire.send(data[:piece])
                data = data[piece:]
                wallclock.sleep(self.random.choice((0.0, 0.0, 0.0005)))

        for start in range(0, count, 4):
            batch = [self._valid_request() for _ in range(min(4, count - start))]
            self.answered(wire, batch, send=in_pieces)
        wire.close()

    def pipelined(self, count: int) -> None:
        wire = _Wire(self.port)
        sent = 0
        while sent < count:
            batch = [self._valid_request() for _ in range(min(self.random.randint(2, 100), count - sent))]
            self.answered(wire, batch)
            sent += len(batch)
        wire.close()

    def _valid_request(self) -> bytes:
        function = self.random.choice((1, 2, 3, 4, 4, 4, 16))
        if function == 16:  # refused: the fuzzer is not the session's PLC
            return struct.pack(">BHHB", 16, 16, 2, 4) + self.random.randbytes(4)
        limit = 125 if function in (3, 4) else 2000
        address = self.random.randrange(16 if function in (3, 4) else 256)
        return struct.pack(">BHH", function, address, self.random.randint(1, limit))

    # ------------------------------------------------------------------ input out of step with the stream
    def out_of_step(self, count: int, make: Callable[[_Fuzzer], bytes]) -> None:
        """Each frame ``make`` makes on a connection of its own; every 50 a client must still be served."""
        for index in range(count):
            try:
                wire = _Wire(self.port)
            except OSError:
                self.tally.hangs += 1
                continue
            wire.send(make(self))
            wire.answers(1, timeout_s=0.002)  # take what comes at once; no answer is due
            wire.close()
            self.tally.frames += 1
            if index % 50 == 49:
                self.probe()

    def random_bytes(self) -> bytes:
        return self.random.randbytes(self.random.randint(1, 300))

    def wrong_length(self) -> bytes:
        pdu = bytes([self.random.randrange(256)]) + self.random.randbytes(self.random.randrange(20))
        length = self.random.choice((0, 1, len(pdu), len(pdu) + 2, 255, 256, 65535, self.random.randrange(65536)))
        return _frame(self._next_transaction(), pdu, length=length, protocol=self.random.choice((0, 0, 0, 1, 0xFFFF)))

    def truncated(self) -> bytes:
        whole = _frame(self._next_transaction(), self._valid_request())
        return whole[: self.random.randrange(1, len(whole))]

    def probe(self) -> None:
        """A new client must get its answer."""
        try:
            wire = _Wire(self.port)
        except OSError:
            self.tally.hangs += 1
            return
        if not wire.send(_frame(self._next_transaction(), struct.pack(">BHH", 4, 0, 2))) or not wire.answers(1):
            self.tally.hangs += 1
        wire.close()

    # ------------------------------------------------------------------ connections
    def many_connections(self, count: int) -> None:
        """``count`` connections at once, each with one request: answered, or closed as the server is full."""
        wires: list[_Wire] = []
        for _ in range(count):
            try:
                wires.append(_Wire(self.port))
            except OSError:
                self.tally.refused_connections += 1
        for wire in wires:
            wire.send(_frame(self._next_transaction(), struct.pack(">BHH", 4, 0, 1)))
        for wire in wires:
            answered = wire.answers(1)
            if answered:
                continue
            if wire.closed:
                self.tally.refused_connections += 1
            else:
                self.tally.lost += 1
            wire.close()
        for wire in wires:
            wire.close()
        self.tally.frames += count

    def half_open(self, count: int) -> None:
        """``count`` connections with a started header, then silence: a client is still served, and
        the idle time-out closes them all."""
        wires = []
        for _ in range(count):
            try:
                wire = _Wire(self.port)
            except OSError:
                self.tally.refused_connections += 1
                continue
            wire.send(_frame(self._next_transaction(), b"\x04\x00")[: self.random.randint(1, 7)])
            wires.append(wire)
        self.tally.frames += count
        self.probe()
        deadline = wallclock.monotonic() + IDLE_TIMEOUT_S + 5.0
        for wire in wires:
            wire.answers(1, timeout_s=max(0.0, deadline - wallclock.monotonic()))
            self.tally.hangs += not wire.closed  # still open long after the idle time-out
            wire.close()


# the in-step kinds and their shares of the frames asked for; the out-of-step kinds take the rest
_IN_STEP: tuple[tuple[str, float, Callable[[_Fuzzer, int], None]], ...] = (
    ("random PDUs", 0.35, _Fuzzer.random_pdus),
    ("every function code", 0.05, _Fuzzer.every_function_code),
    ("counts and addresses", 0.15, _Fuzzer.counts_and_addresses),
    ("splits", 0.05, _Fuzzer.splits),
    ("pipelining", 0.25, _Fuzzer.pipelined),
)
_OUT_OF_STEP: tuple[tuple[str, float, Callable[[_Fuzzer], bytes]], ...] = (
    ("random bytes", 0.06, _Fuzzer.random_bytes),
    ("wrong lengths", 0.06, _Fuzzer.wrong_length),
    ("truncation", 0.03, _Fuzzer.truncated),
)


def run_modbus_fuzz(settings: CampaignSettings, say: Say) -> Row:
    """The part's row (module docstring)."""
    frames = settings.modbus_frames
    with ServedNc(["--realtime", "--idle-timeout", str(IDLE_TIMEOUT_S), "--stats", "2"]) as served:
        fuzzer = _Fuzzer(served.modbus_port, random.Random(settings.seed))
        memory_before = served.rss_kb()
        for name, share, fuzz in _IN_STEP:
            before = fuzzer.tally.frames
            fuzz(fuzzer, max(1, round(share * frames)))
            say(f"  modbus {name}: {fuzzer.tally.frames - before} frames; {fuzzer.tally}")
        for name, share, make in _OUT_OF_STEP:
            before = fuzzer.tally.frames
            fuzzer.out_of_step(max(1, round(share * frames)), make)
            say(f"  modbus {name}: {fuzzer.tally.frames - before} frames; {fuzzer.tally}")
        fuzzer.many_connections(CONNECTIONS)
        say(f"  modbus {CONNECTIONS} connections at once; {fuzzer.tally}")
        fuzzer.half_open(HALF_OPEN)
        say(f"  modbus {HALF_OPEN} idle half-open connections; {fuzzer.tally}")
        fuzzer.probe()
        memory_after = served.rss_kb()
        crashes = served.crashes()
    pacing = final_pacing(served.serve)
    tally = fuzzer.tally
    return Row("Modbus fuzz (vc serve --realtime, plc_stub connected)", inputs=tally.frames, crashes=crashes,
               hangs=tally.hangs, tracebacks=served.tracebacks(), lost_requests=tally.lost,
               violations=tally.violations, rss_growth_pct=growth_pct(memory_before[0], memory_after[0]),
               overruns=str(pacing) if pacing else "-",
               notes=f"{tally.refused_connections} connections closed by the server when full (limit 64)")
