"""The flood part: many Modbus connections reading back to back while the NC runs in real time.

``vc serve --realtime`` with the built-in PLC connected; ``connections`` clients in threads of
this process each read 125 input registers, send the next request as soon as the answer is in,
for ``seconds``, after :data:`QUIET_S` of the same without the flood (what the host's other work
costs the NC, for comparison).  The server answers its PLC first and bounds its work per pass of the event loop
(interfaces/links/modbus/server.py), so the NC keeps its period: the row gives the overruns of the
flood's cycles (those caused by serving the links apart), the share of real time the NC kept,
the requests answered per second and whether the PLC's sign of life stayed (alarm 2000).
"""

from __future__ import annotations

import re
import socket
import struct
import threading
import time as wallclock
from dataclasses import dataclass

from vc.bench.robustness.campaign import CampaignSettings, Row, Say
from vc.bench.robustness.processes import ServedNc, growth_pct

READ = struct.pack(">HHHBBHH", 1, 0, 6, 1, 4, 0, 125)  # FC 4, 125 input registers from 0
ANSWER_BYTES = 9 + 2 * 125
QUIET_S = 10.0  # measured before the flood (at most as long as it), for comparison
STATS_S = 1.0  # the server's statistics line: one per second, so the flood's own seconds can be picked
WINDOW = re.compile(r"^\s*[\d.]+ s  (\d+) cycles: .*; (\d+) overruns \((\d+) while serving the links\);"
                    r" NC at ([\d.]+) %")


@dataclass(frozen=True, slots=True)
class _Pacing:
    """The pacing of some seconds, from vc serve's statistics lines."""

    cycles: int
    overruns: int
    link_overruns: int
    share: float  # percent of real time the NC kept

    @classmethod
    def of(cls, lines: list[str]) -> _Pacing:
        windows = [match for line in lines if (match := WINDOW.search(line))]
        cycles = sum(int(match.group(1)) for match in windows)
        share = sum(int(match.group(1)) * float(match.group(4)) for match in windows) / cycles if cycles else 0.0
        return cls(cycles, sum(int(match.group(2)) for match in windows),
                   sum(int(match.group(3)) for match in windows), share)

    def __str__(self) -> str:
        return (f"{self.overruns} overruns in {self.cycles} cycles = {100 * self.overruns / max(1, self.cycles):.2f} %,"
                f" NC at {self.share:.1f} %")


class _Reader(threading.Thread):
    def __init__(self, port: int, until: float):
        super().__init__(daemon=True)
        self.port, self.until = port, until
        self.answers = 0
        self.lost = 0

    def run(self) -> None:
        try:
            with socket.create_connection(("127.0.0.1", self.port), timeout=5.0) as wire:
                wire.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
                while wallclock.monotonic() < self.until:
                    wire.sendall(READ)
                    received = 0
                    while received < ANSWER_BYTES:
                        chunk = wire.recv(4096)
                        if not chunk:
                            self.lost += 1
                            return
                        received += len(chunk)
                    self.answers += 1
        except OSError:
            self.lost += 1


def run_flood(settings: CampaignSettings, say: Say) -> Row:
    """The part's row (module docstring)."""
    quiet_s = min(QUIET_S, settings.flood_seconds)
    with ServedNc(["--realtime", "--stats", str(STATS_S)]) as served:
        wallclock.sleep(2.0)  # the PLC's first scans
        quiet_line = len(served.serve.lines)
        wallclock.sleep(quiet_s)  # the same host without the flood: what its other work costs the NC
        memory_before = served.rss_kb()
        first_line = len(served.serve.lines)
        began = wallclock.monotonic()
        readers = [_Reader(served.modbus_port, began + settings.flood_seconds)
                   for _ in range(settings.flood_connections)]
        for reader in readers:
            reader.start()
        for reader in readers:
            reader.join(settings.flood_seconds + 30)
        elapsed = wallclock.monotonic() - began
        last_line = len(served.serve.lines)
        memory_after = served.rss_kb()
        crashes = served.crashes()
    quiet = _Pacing.of(served.serve.lines[quiet_line + 1: first_line])
    flood = _Pacing.of(served.serve.lines[first_line + 1: last_line])
    cycles, overruns, link_overruns, share = flood.cycles, flood.overruns, flood.link_overruns, flood.share
    answers = sum(reader.answers for reader in readers)
    alarms = sorted({line.split("alarm ")[1].split()[0] for line in served.serve.lines if "  alarm " in line})
    say(f"  flood: {answers / elapsed:.0f} requests/s from {len(readers)} connections; {overruns} overruns in"
        f" {cycles} cycles ({link_overruns} while serving the links), NC at {share:.1f} % of real time;"
        f" alarms: {', '.join(alarms) or 'none'}; the {quiet_s:g} s before without the flood: {quiet}")
    return Row(f"Modbus flood ({len(readers)} connections reading back to back, {settings.flood_seconds:g} s)",
               inputs=answers, crashes=crashes, tracebacks=served.tracebacks(),
               lost_requests=sum(reader.lost for reader in readers),
               rss_growth_pct=growth_pct(memory_before[0], memory_after[0]),
               overruns=f"{overruns} of {cycles} = {100 * overruns / max(1, cycles):.2f} % ({link_overruns} by the"
                        " links)",
               notes=f"{answers / elapsed:.0f} requests/s answered; NC at {share:.1f} % of real time; alarms:"
                     f" {', '.join(alarms) or 'none'}; without the flood just before: {quiet}")
