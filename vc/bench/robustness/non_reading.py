"""The non-reading part: clients that pipeline requests and never take their answers.

``vc serve --realtime`` with the built-in PLC connected and an ``--idle-timeout`` of a quarter of
the part (at least :data:`IDLE_TIMEOUT_MIN_S`); up to :data:`CONNECTIONS` raw connections (each
with a small receive buffer, set before it connects) send reads of 125 input registers back to
back, 259 bytes of answer for every 12 bytes of request, and never read, for twice the flood's
seconds (the kernel's buffers take about 4 MB of answers per connection before the server's own
would fill); a connection the server closes is made again, so the abuse goes on for the whole
part.  Meanwhile a well-behaved client reads once every :data:`PROBE_PERIOD_S`.

The server's resident memory (RSS) is sampled throughout.  Rule violations: growth beyond what the
server may hold for the connections (:data:`~interfaces.links.modbus.server.RECEIVE_LIMIT` bytes
received, one read of the socket, :data:`~interfaces.links.modbus.server.ANSWER_LIMIT` bytes of
answers each, and :data:`MARGIN_KB` for the allocator).  A request of the well-behaved client
without an answer is a lost request.  Alarm 2000 is a figure, as in the flood part: on a busy host
the PLC's sign of life may stand for MD10100 while both processes wait for a core.  The notes say how often the server
stopped serving a connection for its untaken answers and how many it closed for them.  Before the server stopped reading
such clients it grew by 350 MB in two minutes.
"""

from __future__ import annotations

import re
import socket
import struct
import threading
import time as wallclock

from interfaces.links.errors import LinkError
from interfaces.links.modbus.client import ModbusLinkClient
from interfaces.links.modbus.server import ANSWER_LIMIT, RECEIVE_LIMIT
from vc.bench.robustness.campaign import CampaignSettings, Row, Say
from vc.bench.robustness.processes import ServedNc, final_pacing

READ = struct.pack(">HHHBBHH", 1, 0, 6, 1, 4, 0, 125)  # FC 4, 125 input registers from 0
BATCH = READ * 1000
SOCKET_READ_KB = 256  # what asyncio reads from a socket at once
MARGIN_KB = 16 * 1024  # the allocator's and the statistics' own growth
SAMPLE_S = 0.5
PROBE_PERIOD_S = 0.05
CONNECTIONS = 8
IDLE_TIMEOUT_MIN_S = 5.0  # the PLC starting its program may be silent for a second or two
STALLS = re.compile(r"(\d+) times a client did not take its answers")
UNTAKEN_CLOSED = re.compile(r"(\d+) with answers untaken for the time-out")


class _Hog(threading.Thread):
    """One connection after another that sends and never reads (module docstring)."""

    def __init__(self, port: int, until: float):
        super().__init__(daemon=True)
        self.port, self.until = port, until
        self.sent = 0  # bytes of requests
        self.closed_by_server = 0

    def _connect(self) -> socket.socket:
        wire = socket.socket(socket.AF_INET, socket.SOCK_STREAM)
        wire.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, 4096)  # before connecting: the window it offers
        wire.connect(("127.0.0.1", self.port))
        wire.setblocking(False)
        return wire

    def run(self) -> None:
        wire = self._connect()
        waiting = b""
        while wallclock.monotonic() < self.until:
            waiting = waiting or BATCH
            try:
                done = wire.send(waiting)
                self.sent, waiting = self.sent + done, waiting[done:]
            except BlockingIOError:
                wallclock.sleep(0.002)
            except OSError:  # the server closed it: the next connection
                self.closed_by_server += 1
                wire.close()
                wire, waiting = self._connect(), b""
        wire.close()


class _Probe(threading.Thread):
    """The well-behaved client: one read at a time, each answered or lost."""

    def __init__(self, port: int, until: float):
        super().__init__(daemon=True)
        self.client = ModbusLinkClient("127.0.0.1", port, timeout_s=5.0)
        self.until = until
        self.answered = 0
        self.lost = 0

    def run(self) -> None:
        self.client.connect()
        while wallclock.monotonic() < self.until:
            try:
                self.client.read_input_registers(0, 16)
                self.answered += 1
            except LinkError:
                self.lost += 1
                self.client.close()
                self.client.connect()
            wallclock.sleep(PROBE_PERIOD_S)
        self.client.close()


def run_non_reading(settings: CampaignSettings, say: Say) -> Row:
    """The part's row (module docstring)."""
    seconds = 2 * settings.flood_seconds
    idle_timeout = max(IDLE_TIMEOUT_MIN_S, seconds / 4)
    connections = min(CONNECTIONS, settings.flood_connections)
    bound_kb = connections * (RECEIVE_LIMIT // 1024 + SOCKET_READ_KB + ANSWER_LIMIT // 1024) + MARGIN_KB
    with ServedNc(["--realtime", "--idle-timeout", f"{idle_timeout:g}", "--stats", "5"]) as served:
        wallclock.sleep(2.0)  # the PLC's first scans
        before = served.rss_kb()[0]
        until = wallclock.monotonic() + seconds
        hogs = [_Hog(served.modbus_port, until) for _ in range(connections)]
        probe = _Probe(served.modbus_port, until)
        for thread in (*hogs, probe):
            thread.start()
        most = before
        while wallclock.monotonic() < until:
            most = max(most, served.rss_kb()[0])
            wallclock.sleep(SAMPLE_S)
        for thread in (*hogs, probe):
            thread.join(30)
        most = max(most, served.rss_kb()[0])
        crashes = served.crashes()
    growth_kb = most - before
    pacing = final_pacing(served.serve)
    link = next((line for line in reversed(served.serve.lines) if line.startswith("link: ")), "")
    closed = int(match.group(1)) if (match := UNTAKEN_CLOSED.search(link)) else 0
    stalls = int(match.group(1)) if (match := STALLS.search(link)) else 0
    alarms = sorted({line.split("alarm ")[1].split()[0] for line in served.serve.lines if "  alarm " in line})
    sent = sum(hog.sent for hog in hogs)
    violations = int(growth_kb > bound_kb)
    say(f"  non-reading: {connections} connections sent {sent // 1024} kB of requests ({sent // len(READ)} reads)"
        f" and read nothing; server RSS {before} -> at most {most} kB (+{growth_kb} kB, bound {bound_kb} kB);"
        f" {stalls} times not served for untaken answers, {closed} connections closed for them; the probe:"
        f" {probe.answered} answered, {probe.lost} lost")
    return Row(f"Non-reading clients ({connections} connections pipelining reads, never reading, {seconds:g} s)",
               inputs=sent // len(READ), crashes=crashes, tracebacks=served.tracebacks(), lost_requests=probe.lost,
               violations=violations, rss_growth_pct=100.0 * growth_kb / before if before else 0.0,
               overruns=str(pacing) if pacing else "-",
               notes=f"server RSS {before} -> at most {most} kB (+{growth_kb} kB; bound {bound_kb} kB);"
                     f" {stalls} times a connection was served no more for its untaken answers, {closed} closed"
                     f" for answers untaken for {idle_timeout:g} s; a client reading"
                     f" meanwhile: {probe.answered} answered, {probe.lost} lost; alarms: {', '.join(alarms) or 'none'}")
