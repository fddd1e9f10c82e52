"""The CAN part: noise on the bus of a lockstep scenario and of a real-time NC.

The harness (``vc serve --can``) and the built-in PLC (``python -m plc_stub --can``) on a UDP
multicast channel of their own, while a third node sends (:class:`CanNoise`):

* datagrams that are no frames (random bytes; python-can raised on them and ended the link);
* error frames with random error classes, bus-off among them (the NC's controller must neither
  stop nor stay bus-off: docs/can.md, error frames);
* frames of identifiers the link does not use, classic and FD.

Half of the inputs during a lockstep scenario that references X1 (it must still pass, its trace is
the in-process one; the machine keeps running in lockstep after it), half during ``vc serve --can
--realtime``.  Neither process may end, print a traceback or stop the exchange, and the NC's
controller must be on the bus at the end; the real-time NC's overruns and alarms are reported.
"""

from __future__ import annotations

import contextlib
import random
import socket
import threading
import time as wallclock
from dataclasses import dataclass

from interfaces.links.can.bus import CAN_ERR_BUSOFF, BusSpec, CanBus, private_udp_bus
from interfaces.links.can.codec import Frame
from vc.bench.robustness.campaign import CampaignSettings, Row, Say
from vc.bench.robustness.processes import CampaignError, ServedNc, final_pacing, growth_pct

SCENARIO = "scenarios/referencing/incremental_jog_ref_falling_edge.yaml"
PAUSE_S = 0.0005  # between two inputs of the noise
SCENARIO_TIMEOUT_S = 300.0
# identifiers the link does not use with the default settings (link 0x100..0x102, data from 0x200 and 0x400)
STRAY_IDS = (*range(0x000, 0x100), *range(0x600, 0x800))


class CanNoise(threading.Thread):
    """A node that sends ``count`` random inputs onto the bus (module docstring), then stops."""

    def __init__(self, spec: BusSpec, count: int, seed: int):
        super().__init__(daemon=True)
        self.spec, self.count = spec, count
        self.random = random.Random(seed)
        self.sent = 0
        self.failed = 0  # inputs the noise's own node could not send
        self.stop = threading.Event()

    def run(self) -> None:
        node = CanBus(self.spec, listen=())
        with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as raw:
            raw.setsockopt(socket.IPPROTO_IP, socket.IP_MULTICAST_TTL, 0)  # stays on this host
            try:
                while self.sent < self.count and not self.stop.is_set():
                    try:
                        self._one(node, raw)
                    except Exception:
                        self.failed += 1
                    self.sent += 1
                    wallclock.sleep(PAUSE_S)
            finally:
                node.close()

    def _one(self, node: CanBus, raw: socket.socket) -> None:
        kind = self.random.randrange(3)
        if kind == 0:
            raw.sendto(self.random.randbytes(self.random.randint(1, 200)), (self.spec.channel, self.spec.port))
        elif kind == 1:
            error_class = self.random.choice((CAN_ERR_BUSOFF, self.random.randrange(0x800)))
            node.send_error_frame(error_class, self.random.randbytes(8))
        else:
            fd = self.random.random() < 0.5
            data = self.random.randbytes(self.random.randint(0, 64 if fd else 8))
            node.send(Frame(self.random.choice(STRAY_IDS), data, fd))


@dataclass(frozen=True, slots=True)
class _NoisyRun:
    served: ServedNc
    noise: CanNoise
    crashes: int  # processes that ended before the noise did
    code: int  # vc serve's exit code after Ctrl-C
    rss_growth_pct: float

    def link(self) -> str:
        return next((line for line in reversed(self.served.serve.lines) if line.startswith("link: ")), "")


def _under_noise(serve: list[str], spec: BusSpec, count: int, seed: int, until: str | None = None) -> _NoisyRun:
    """``vc serve`` and the PLC on ``spec`` while ``count`` inputs of noise go onto the bus (and
    until the server prints a line matching ``until``); then Ctrl-C."""
    with ServedNc(serve, ["--can", str(spec)]) as served:
        noise = CanNoise(spec, count, seed)
        memory_before = sum(served.rss_kb())
        noise.start()
        noise.join()
        if until is not None:
            with contextlib.suppress(CampaignError):  # a server that ended is counted below
                served.serve.wait_for(until, SCENARIO_TIMEOUT_S)
        crashes = served.crashes()
        growth = growth_pct(memory_before, sum(served.rss_kb()))
    return _NoisyRun(served, noise, crashes, served.serve.process.returncode, growth)


def run_can_noise(settings: CampaignSettings, say: Say) -> Row:
    """The part's row (module docstring)."""
    half = max(1, settings.can_inputs // 2)
    spec = private_udp_bus()
    lockstep = _under_noise(["--can", str(spec), "--scenario", SCENARIO, "--keep-running"], spec, half, settings.seed,
                            until="^scenario done")
    passed = any("PASS" in line for line in lockstep.served.serve.lines)
    say(f"  can lockstep: {lockstep.noise.sent} noise inputs; scenario {'passed' if passed else 'FAILED'};"
        f" vc serve exit {lockstep.code}; {lockstep.link()}")
    spec = private_udp_bus()
    realtime = _under_noise(["--can", str(spec), "--realtime", "--stats", "30"], spec, settings.can_inputs - half,
                            settings.seed + 1)
    pacing = final_pacing(realtime.served.serve)
    lines = realtime.served.serve.lines
    alarms = sorted({line.split("alarm ")[1].split()[0] for line in lines if "  alarm " in line})
    say(f"  can real time: {realtime.noise.sent} noise inputs; {realtime.link()}; {pacing}; alarms:"
        f" {', '.join(alarms) or 'none'}")
    bus_off = any("BUS OFF" in run.link() for run in (lockstep, realtime))
    runs = (lockstep, realtime)
    return Row("CAN (datagrams that are no frames, error frames, stray frames)",
               inputs=sum(run.noise.sent for run in runs),
               crashes=sum(run.crashes + (run.code != 0) for run in runs),
               tracebacks=sum(run.served.tracebacks() for run in runs), violations=(not passed) + bus_off,
               rss_growth_pct=max((run.rss_growth_pct for run in runs), key=abs),
               overruns=str(pacing) if pacing else "-",
               notes=f"lockstep scenario {'passed' if passed else 'failed'} under noise; real time: alarms"
                     f" {', '.join(alarms) or 'none'}; {'BUS OFF at the end' if bus_off else 'on the bus at the end'}")
