"""The CAN part: noise on the bus of a lockstep scenario and of a real-time NC.

The harness (``vc serve --can``) and the built-in PLC (``python -m plc_stub --can``) on a UDP
multicast channel of their own, while a third node sends (:class:`CanNoise`):

* datagrams that are no frames (random bytes; python-can raised on them and ended the link);
* error frames with random error classes, bus-off among them (the NC's controller must neither
  stop nor stay bus-off: docs/can.md, error frames);
* frames of identifiers the link does not use, classic and FD.

First a lockstep scenario that references X1 (it must still pass, its trace is the in-process one),
then ``vc serve --can --realtime`` for a few seconds.  Neither process may end, print a traceback or
stop the exchange; the real-time NC's overruns and alarms are reported.
"""

from __future__ import annotations

import random
import socket
import threading
import time as wallclock

from interfaces.codec_can import Frame
from interfaces.links.can_bus import CAN_ERR_BUSOFF, BusSpec, CanBus, private_udp_bus
from vc.harness.robustness.campaign import CampaignSettings, Row, Say
from vc.harness.robustness.processes import ServedNc, final_pacing, growth_pct

SCENARIO = "scenarios/referencing/incremental_jog_ref_falling_edge.yaml"
REALTIME_SECONDS = 5.0
PAUSE_S = 0.0005  # between two inputs of the noise
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


def _noisy(serve: list[str], plc: list[str], spec: BusSpec, count: int,
           seed: int) -> tuple[ServedNc, CanNoise, int]:
    """Run ``vc serve`` and the PLC on ``spec`` with noise until the server ends (or is stopped after
    its duration); returns them, the noise and the server's exit code."""
    with ServedNc(serve, plc) as served:
        noise = CanNoise(spec, count, seed)
        noise.start()
        code = served.serve.process.wait(600)
        noise.stop.set()
        noise.join(10)
        plc_alive = served.plc is not None and served.plc.alive
    return served, noise, code if plc_alive else -1


def run_can_noise(settings: CampaignSettings, say: Say) -> Row:
    """The part's row (module docstring)."""
    spec = private_udp_bus()
    half = max(1, settings.can_inputs // 2)
    lockstep, lockstep_noise, lockstep_code = _noisy(["--can", str(spec), "--scenario", SCENARIO, "--duration", "6"],
                                                     ["--can", str(spec)], spec, half, settings.seed)
    passed = any("PASS" in line for line in lockstep.serve.lines)
    say(f"  can lockstep: {lockstep_noise.sent} noise inputs; scenario {'passed' if passed else 'FAILED'};"
        f" vc serve exit {lockstep_code}; {next((line for line in lockstep.serve.lines if 'CAN:' in line), '')}")
    spec = private_udp_bus()
    with ServedNc(["--can", str(spec), "--realtime", "--stats", "30"], ["--can", str(spec)]) as realtime:
        noise = CanNoise(spec, settings.can_inputs - half, settings.seed + 1)
        memory_before = realtime.rss_kb()
        noise.start()
        wallclock.sleep(REALTIME_SECONDS)
        noise.stop.set()
        noise.join(10)
        memory_after = realtime.rss_kb()
        crashes = realtime.crashes()
    pacing = final_pacing(realtime.serve)
    link = next((line for line in reversed(realtime.serve.lines) if line.startswith("link: ")), "")
    alarms = sorted({line.split("alarm ")[1].split()[0] for line in realtime.serve.lines if "  alarm " in line})
    say(f"  can real time: {noise.sent} noise inputs; {link}; alarms: {', '.join(alarms) or 'none'}")
    return Row("CAN (datagrams that are no frames, error frames, stray frames)",
               inputs=lockstep_noise.sent + noise.sent, crashes=crashes + (lockstep_code != 0),
               tracebacks=lockstep.tracebacks() + realtime.tracebacks(), violations=0 if passed else 1,
               rss_growth_pct=growth_pct(sum(memory_before), sum(memory_after)),
               overruns=str(pacing) if pacing else "-",
               notes=f"lockstep scenario {'passed' if passed else 'failed'} under noise; real time: alarms"
                     f" {', '.join(alarms) or 'none'}, {'BUS OFF at the end' if 'BUS OFF' in link else 'on the bus'}")
