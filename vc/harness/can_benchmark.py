"""``vc bench --link can``: what the CAN link costs, on a virtual bus and on UDP multicast.

Two measurements per bus, each a function that returns its figures:

* :func:`measure_throughput`: frames per second through the adapter (:class:`CanBus`).  The
  harness's side sends bursts as it does every PLC period (the turn_mill exchange: 15 data
  frames of up to 64 bytes and the link frame) to a peer that counts them and answers with one
  frame; the next burst waits for that answer, so no frame is lost to a full socket buffer.  The
  peer is a second node in this process (virtual) or a spawned process (UDP multicast).
* :func:`measure_lockstep`: the workload of ``vc bench`` (MDA program moving two axes) with the
  PLC behind the CAN link in lockstep: on the virtual bus with the node in this process, on UDP
  multicast with ``python -m plc_stub --can`` in its own process; then the same workload with
  the PLC in this process.  The difference per IPO cycle is what the link adds; frames per
  second count what the harness sent and received on the bus.
"""

from __future__ import annotations

import multiprocessing
import time as wallclock
from collections.abc import Callable
from dataclasses import dataclass
from multiprocessing.connection import Connection

from interfaces.codec_can import Frame
from interfaces.links.can_bus import BusSpec, CanBus, private_udp_bus, private_virtual_bus
from interfaces.links.errors import LinkError
from vc.harness.benchmark import Workload, benchmark_machine
from vc.harness.can_link import CanLinkedPlc, VirtualCanPlc
from vc.harness.external_plc import CanPlcProcess
from vc.harness.simulation import Simulation

BURST_IDS = tuple(range(0x200, 0x210))  # 16 data frames, as the turn_mill NC sends per period (docs/can.md)
BURST_END, ANSWER = 0x100, 0x101
_FRAME = bytes(range(64))
_PEER_START_TIMEOUT_S = 60.0
_ANSWER_TIMEOUT_S = 5.0


@dataclass(frozen=True, slots=True)
class ThroughputFigures:
    bus: str
    frames: int  # frames moved: the bursts and the answers
    wall_s: float

    @property
    def frames_per_s(self) -> float:
        return self.frames / self.wall_s

    def line(self) -> str:
        return (f"  {self.bus:<14} {self.frames_per_s:9.0f} frames/s ({self.frames} frames in bursts of"
                f" {len(BURST_IDS) + 1} with an answer, {self.wall_s:.2f} s)")


@dataclass(frozen=True, slots=True)
class LockstepFigures:
    bus: str
    cycles: int
    ipo_cycle_us: int
    wall_s: float
    frames: int  # sent and received by the harness's node
    inprocess_wall_s: float  # the same number of cycles with the PLC in process

    @property
    def us_per_cycle(self) -> float:
        return self.wall_s / self.cycles * 1e6

    @property
    def added_us_per_cycle(self) -> float:
        return (self.wall_s - self.inprocess_wall_s) / self.cycles * 1e6

    @property
    def frames_per_s(self) -> float:
        return self.frames / self.wall_s

    @property
    def realtime_factor(self) -> float:
        return self.cycles * self.ipo_cycle_us / 1e6 / self.wall_s

    def line(self) -> str:
        return (f"  {self.bus:<14} {self.us_per_cycle:6.1f} us per IPO cycle, {self.added_us_per_cycle:+6.1f} us over"
                f" in process ({self.inprocess_wall_s / self.cycles * 1e6:.1f}); {self.frames_per_s:6.0f} frames/s"
                f" ({self.frames / self.cycles:.1f} per IPO cycle); {self.realtime_factor:.1f}x real time")


@dataclass(frozen=True, slots=True)
class CanBenchmark:
    throughput: tuple[ThroughputFigures, ...]
    lockstep: tuple[LockstepFigures, ...]

    def figures(self) -> dict[str, float]:
        """The figures as ``vc bench --link can`` prints them in its JSON line."""
        result: dict[str, float] = {}
        for item in self.throughput:
            result[f"{item.bus}_frames_per_s"] = round(item.frames_per_s)
        for figures in self.lockstep:
            result[f"{figures.bus}_lockstep_us_per_cycle"] = round(figures.us_per_cycle, 1)
            result[f"{figures.bus}_added_us_per_cycle"] = round(figures.added_us_per_cycle, 1)
            result[f"{figures.bus}_lockstep_frames_per_s"] = round(figures.frames_per_s)
            result[f"{figures.bus}_lockstep_realtime_factor"] = round(figures.realtime_factor, 1)
        return result


def run_can_benchmark(machine_path: str, simulated_seconds: float = 10.0, frames: int = 20000,
                      say: Callable[[str], None] = print) -> CanBenchmark:
    """Both measurements on both buses; each line is said as soon as it is measured."""
    say("throughput (adapter, bursts as one PLC period of turn_mill):")
    throughput = []
    for spec in (private_virtual_bus(), private_udp_bus()):
        figures = measure_throughput(spec, frames)
        say(figures.line())
        throughput.append(figures)
    say(f"lockstep (the vc bench workload, {simulated_seconds:g} s simulated):")
    lockstep = []
    for kind in ("virtual", "udp_multicast"):
        result = measure_lockstep(machine_path, kind, simulated_seconds)
        say(result.line())
        lockstep.append(result)
    return CanBenchmark(tuple(throughput), tuple(lockstep))


# ---------------------------------------------------------------------------------- throughput


class _Counter:
    """The peer: counts data frames and answers every burst end with one frame."""

    def __init__(self, spec: BusSpec):
        self.bus = CanBus(spec, listen=(*BURST_IDS, BURST_END))
        self.counted = 0

    def serve(self, timeout: float) -> bool:
        """Handle the frames there are (waiting up to ``timeout`` for the first); False when none came."""
        frame = self.bus.receive(timeout)
        if frame is None:
            return False
        while frame is not None:
            if frame.can_id == BURST_END:
                self.bus.send(Frame(ANSWER, self.counted.to_bytes(4, "big").ljust(8, b"\0")))
            else:
                self.counted += 1
            frame = self.bus.receive(0)
        return True


def count_until_told(spec: BusSpec, connection: Connection) -> None:
    """The child process of the UDP measurement: count and answer until the parent says stop."""
    counter = _Counter(spec)
    connection.send("ready")
    try:
        while not connection.poll():
            counter.serve(0.05)
    finally:
        counter.bus.close()
        connection.close()


def measure_throughput(spec: BusSpec, frames: int = 20000, warmup_bursts: int = 50) -> ThroughputFigures:
    """``frames`` data frames in bursts, against a peer in this process (virtual) or a child (UDP)."""
    sender = CanBus(spec, listen=(ANSWER,))
    local = _Counter(spec) if spec.kind == "virtual" else None
    child, connection = None, None
    if local is None:
        context = multiprocessing.get_context("spawn")
        connection, child_end = context.Pipe()
        child = context.Process(target=count_until_told, args=(spec, child_end), daemon=True)
        child.start()
        child_end.close()
        if not connection.poll(_PEER_START_TIMEOUT_S):
            raise LinkError(f"the counting peer on {spec} did not start")
        connection.recv()
    try:
        def burst() -> None:
            for can_id in BURST_IDS:
                sender.send(Frame(can_id, _FRAME))
            sender.send(Frame(BURST_END, bytes(8)))
            deadline = wallclock.monotonic() + _ANSWER_TIMEOUT_S
            while True:
                if local is not None:
                    local.serve(0)
                if sender.receive(0 if local is not None else 0.5) is not None:
                    return
                if wallclock.monotonic() > deadline:
                    raise LinkError(f"no answer from the counting peer on {spec}")

        for _ in range(warmup_bursts):
            burst()
        bursts = max(1, frames // len(BURST_IDS))
        began = wallclock.perf_counter()
        for _ in range(bursts):
            burst()
        wall = wallclock.perf_counter() - began
    finally:
        sender.close()
        if local is not None:
            local.bus.close()
        if connection is not None and child is not None:
            connection.send("stop")
            child.join(5)
            connection.close()
    return ThroughputFigures(spec.kind, bursts * (len(BURST_IDS) + 2), wall)


# ---------------------------------------------------------------------------------- lockstep


def _timed(simulation: Simulation, cycles: int) -> tuple[float, int]:
    workload = Workload(simulation)
    began = wallclock.perf_counter()
    done = workload.run(cycles)
    return wallclock.perf_counter() - began, done


def measure_lockstep(machine_path: str, kind: str, simulated_seconds: float = 10.0) -> LockstepFigures:
    """The workload over the CAN link on ``kind`` (virtual or udp_multicast), then in this process."""
    machine = benchmark_machine(machine_path)
    cycles = round(simulated_seconds / Simulation.ipo_seconds(machine))
    run: VirtualCanPlc | CanPlcProcess = VirtualCanPlc() if kind == "virtual" else CanPlcProcess()
    with run:
        simulation = run.simulation(machine, "basic_machine")
        assert isinstance(simulation.plc, CanLinkedPlc)
        bus = run.link.bus
        before = bus.sent + bus.received
        wall, done = _timed(simulation, cycles)
        frames = bus.sent + bus.received - before
    local_wall, local_done = _timed(Simulation(machine, "basic_machine"), cycles)
    return LockstepFigures(kind, done, simulation.ipo_cycle_us, wall, frames, local_wall * done / local_done)
