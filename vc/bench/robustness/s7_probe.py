"""The S7 part: writes, block downloads, idle sessions and garbage against ``vc serve --s7``.

``vc serve --realtime --modbus --s7`` with the built-in PLC on Modbus, which owns the link; a
python-snap7 client (a real S7 client) then tries, with random areas, blocks, offsets, sizes and
data:

* writes into every area (the interface blocks, a block that does not exist, inputs, outputs,
  markers): each must be refused, since the session's PLC is the Modbus client; one that is taken
  is a rule violation;
* block downloads of the interface blocks (``client.download``): each must be refused;
* reads: each must be answered, with the data or the server's error;
* more idle sessions than the server keeps (70, the limit is 64): a client that connects after
  them must still be served;
* garbage on the ISO-on-TCP port: random bytes, a wrong TPKT, a connection request followed by
  random bytes: the server must go on serving.

A request without an answer (the client's connection or time-out error) is a lost request.
"""

from __future__ import annotations

import contextlib
import random
import socket
import struct
import time as wallclock

import snap7
from snap7.error import S7ConnectionError, S7TimeoutError
from snap7.type import Areas

from vc.bench.robustness.campaign import CampaignSettings, Row, Say
from vc.bench.robustness.processes import ServedNc, final_pacing, growth_pct

IDLE_SESSIONS = 70
BLOCKS = (10, 11, 19, 21, 31, 32, 33, 34, 35, 36, 40)  # turn_mill's interface blocks and one it has not
AREAS = (Areas.DB, Areas.DB, Areas.DB, Areas.PE, Areas.PA, Areas.MK)
COTP_CONNECTION_REQUEST = bytes.fromhex("0300001611e00000000100c0010ac1020100c2020102")
LOST = (S7ConnectionError, S7TimeoutError, TimeoutError, ConnectionError)


class _Probe:
    def __init__(self, port: int, generator: random.Random):
        self.port = port
        self.random = generator
        self.inputs = 0
        self.lost = 0
        self.hangs = 0
        self.violations = 0
        self.client = self._connect()

    def _connect(self) -> snap7.client.Client:
        client = snap7.client.Client()
        client.connect("127.0.0.1", 0, 1, self.port)
        return client

    def _again(self) -> None:
        """After a lost request: a new session (the old one may be broken)."""
        with contextlib.suppress(Exception):
            self.client.disconnect()
        try:
            self.client = self._connect()
        except Exception:
            self.hangs += 1

    def write(self) -> None:
        area = self.random.choice(AREAS)
        block = self.random.choice(BLOCKS) if area == Areas.DB else 0
        data = bytearray(self.random.randbytes(self.random.randint(1, 64)))
        self.inputs += 1
        try:
            self.client.write_area(area, block, self.random.randrange(400), data)
        except LOST:
            self.lost += 1
            self._again()
        except Exception:
            return  # refused: the session's PLC is the Modbus client
        else:
            self.violations += 1

    def download(self) -> None:
        self.inputs += 1
        try:
            self.client.download(bytearray(self.random.randbytes(self.random.randint(1, 400))),
                                 self.random.choice(BLOCKS))
        except LOST:
            self.lost += 1
            self._again()
        except Exception:
            return  # refused
        else:
            self.violations += 1

    def read(self) -> None:
        area = self.random.choice(AREAS)
        block = self.random.choice(BLOCKS) if area == Areas.DB else 0
        self.inputs += 1
        try:
            self.client.read_area(area, block, self.random.randrange(400), self.random.randint(1, 200))
        except LOST:
            self.lost += 1
            self._again()
        except Exception:
            return  # the server's error: an answer

    def garbage(self) -> None:
        self.inputs += 1
        kind = self.random.randrange(3)
        data = (self.random.randbytes(self.random.randint(1, 300)) if kind == 0 else
                struct.pack(">BBH", self.random.choice((0, 2, 3)), 0, self.random.randrange(65536))
                + self.random.randbytes(20) if kind == 1 else
                COTP_CONNECTION_REQUEST + self.random.randbytes(self.random.randint(1, 100)))
        with contextlib.suppress(OSError), socket.create_connection(("127.0.0.1", self.port), timeout=2) as wire:
            wire.sendall(data)
            wire.settimeout(0.01)
            with contextlib.suppress(OSError):
                wire.recv(1024)

    def served(self) -> bool:
        """A new client connects and reads."""
        try:
            client = self._connect()
            client.db_read(31, 60, 1)
            client.disconnect()
        except Exception:
            return False
        return True

    def idle_sessions(self) -> None:
        idle = []
        for _ in range(IDLE_SESSIONS):
            try:
                idle.append(self._connect())
            except Exception:
                continue  # the server made room by closing an older one, or was busy
        self.inputs += IDLE_SESSIONS
        self.hangs += not self.served()
        for client in idle:
            with contextlib.suppress(Exception):
                client.disconnect()


def run_s7_probe(settings: CampaignSettings, say: Say) -> Row:
    """The part's row (module docstring)."""
    with ServedNc(["--realtime", "--s7", "127.0.0.1:0", "--stats", "30"]) as served:
        probe = _Probe(served.s7_port, random.Random(settings.seed))
        memory_before = served.rss_kb()
        kinds = (probe.write, probe.write, probe.read, probe.read, probe.download, probe.garbage)
        for index in range(settings.s7_requests):
            probe.random.choice(kinds)()
            if index % 200 == 199:
                probe.hangs += not probe.served()
        say(f"  s7: {probe.inputs} requests, {probe.lost} lost, {probe.violations} violations")
        probe.idle_sessions()
        say(f"  s7: {IDLE_SESSIONS} idle sessions, then a client: {'served' if not probe.hangs else 'locked out'}")
        wallclock.sleep(0.5)
        probe.hangs += not probe.served()
        with contextlib.suppress(Exception):
            probe.client.disconnect()
        memory_after = served.rss_kb()
        crashes = served.crashes()
    link = next((line for line in reversed(served.serve.lines) if line.startswith("link: ")), "")
    pacing = final_pacing(served.serve)
    return Row("S7 (writes, downloads, reads, idle sessions, garbage)", inputs=probe.inputs, crashes=crashes,
               hangs=probe.hangs, tracebacks=served.tracebacks(), lost_requests=probe.lost,
               violations=probe.violations, rss_growth_pct=growth_pct(memory_before[0], memory_after[0]),
               overruns=str(pacing) if pacing else "-",
               notes=link.split("; S7: ")[-1].split(";")[0] if "S7: " in link else "")
