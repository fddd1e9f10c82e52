"""``vc bench --link can``: what the CAN link costs, on a virtual bus and on UDP multicast.

Two measurements per bus, each a function that returns its figures:

* :func:`measure_throughput`: frames per second through the adapter (:class:`CanBus`).  The
  harness's side sends bursts as it does every PLC period (:func:`burst_of`: the machine's
  NC-to-PLC data frames with their identifiers and lengths, then its NC link frame; turn_mill: 16
  data frames of up to 64 bytes) to a peer that counts them and answers with the PLC link
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

from interfaces.catalog import load_catalog
from interfaces.links.can.bus import BusSpec, CanBus, private_udp_bus, private_virtual_bus
from interfaces.links.can.codec import CanLayout, Frame
from interfaces.links.errors import LinkError
from interfaces.signals import Direction, expand
from vc.bench.lockstep import Workload, benchmark_machine
from vc.config.loader import load_machine
from vc.config.model import MachineConfig
from vc.harness.external_plc import CanPlcProcess
from vc.harness.links.can import CanLinkedPlc, VirtualCanPlc
from vc.simulation.lockstep import Simulation

_PEER_START_TIMEOUT_S = 60.0
_ANSWER_TIMEOUT_S = 5.0


@dataclass(frozen=True, slots=True)
class Burst:
    """What the NC sends a PLC period: data frames (identifier, length), then the link frame
    ``end``; the peer answers each burst with ``answer``."""

    data: tuple[tuple[int, int], ...]
    end: int
    answer: int

    def frames(self) -> list[Frame]:
        return [Frame(can_id, bytes(range(length))) for can_id, length in self.data] + [Frame(self.end, bytes(8))]


def burst_of(machine: MachineConfig) -> Burst:
    """The burst of ``machine``: its NC-to-PLC frame table with its ``can:`` settings."""
    settings = machine.can.settings
    layout = CanLayout.build(expand(load_catalog(), machine.layout), machine.plant_io.area_sizes(), settings)
    return Burst(tuple((slot.can_id, slot.length) for slot in layout.slots[Direction.NC_TO_PLC]),
                 settings.nc_link_id, settings.plc_link_id)


@dataclass(frozen=True, slots=True)
class ThroughputFigures:
    bus: str
    frames: int  # frames moved: the bursts and the answers
    wall_s: float
    burst: int  # frames a burst: data frames and the link frame

    @property
    def frames_per_s(self) -> float:
        return self.frames / self.wall_s

    def line(self) -> str:
        return (f"  {self.bus:<14} {self.frames_per_s:9.0f} frames/s ({self.frames} frames in bursts of"
                f" {self.burst} with an answer, {self.wall_s:.2f} s)")


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
    burst = burst_of(load_machine(machine_path))
    say(f"throughput (adapter, bursts as one PLC period of the machine: {len(burst.data)} data frames):")
    throughput = []
    for spec in (private_virtual_bus(), private_udp_bus()):
        figures = measure_throughput(spec, burst, frames)
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

    def __init__(self, spec: BusSpec, burst: Burst):
        self.bus = CanBus(spec, listen=(*(can_id for can_id, _ in burst.data), burst.end))
        self.burst = burst
        self.counted = 0

    def serve(self, timeout: float) -> bool:
        """Handle the frames there are (waiting up to ``timeout`` for the first); False when none came."""
        frame = self.bus.receive(timeout)
        if frame is None:
            return False
        while frame is not None:
            if frame.can_id == self.burst.end:
                self.bus.send(Frame(self.burst.answer, self.counted.to_bytes(4, "big").ljust(8, b"\0")))
            else:
                self.counted += 1
            frame = self.bus.receive(0)
        return True


def count_until_told(spec: BusSpec, burst: Burst, connection: Connection) -> None:
    """The child process of the UDP measurement: count and answer until the parent says stop."""
    counter = _Counter(spec, burst)
    connection.send("ready")
    try:
        while not connection.poll():
            counter.serve(0.05)
    finally:
        counter.bus.close()
        connection.close()


def measure_throughput(spec: BusSpec, burst: Burst, frames: int = 20000,
                       warmup_bursts: int = 50) -> ThroughputFigures:
    """``frames`` data frames in bursts, against a peer in this process (virtual) or a child (UDP)."""
    sender = CanBus(spec, listen=(burst.answer,))
    local = _Counter(spec, burst) if spec.kind == "virtual" else None
    child, connection = None, None
    if local is None:
        context = multiprocessing.get_context("spawn")
        connection, child_end = context.Pipe()
        child = context.Process(target=count_until_told, args=(spec, burst, child_end), daemon=True)
        child.start()
        child_end.close()
        if not connection.poll(_PEER_START_TIMEOUT_S):
            raise LinkError(f"the counting peer on {spec} did not start")
        connection.recv()
    try:
        outgoing = burst.frames()

        def send_burst() -> None:
            for frame in outgoing:
                sender.send(frame)
            deadline = wallclock.monotonic() + _ANSWER_TIMEOUT_S
            while True:
                if local is not None:
                    local.serve(0)
                if sender.receive(0 if local is not None else 0.5) is not None:
                    return
                if wallclock.monotonic() > deadline:
                    raise LinkError(f"no answer from the counting peer on {spec}")

        for _ in range(warmup_bursts):
            send_burst()
        bursts = max(1, frames // len(burst.data))
        began = wallclock.perf_counter()
        for _ in range(bursts):
            send_burst()
        wall = wallclock.perf_counter() - began
    finally:
        sender.close()
        if local is not None:
            local.bus.close()
        if connection is not None and child is not None:
            connection.send("stop")
            child.join(5)
            connection.close()
    return ThroughputFigures(spec.kind, bursts * (len(outgoing) + 1), wall, len(outgoing))


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
