"""``vc bench --link modbus``: what the Modbus TCP link costs on this machine, on loopback.

Three measurements, each a function that returns its figures:

* :func:`measure_exchange`: the round trip of one full interface exchange as a PLC makes it
  every scan (read the whole NC-to-PLC table with FC 4, write the whole PLC-to-NC table with
  FC 16, in the largest chunks the protocol allows), from a synchronous Modbus client in this
  process.  It runs against the harness's server and against a bare pymodbus server with the
  same register counts, each in a child process of its own so that both work under the same
  conditions, interleaved in rounds so that drift of the machine (frequency scaling, other
  load) falls on both alike.  The ratio of the medians is what the harness's request action
  (:class:`~interfaces.links.modbus.server.ModbusTables`) adds to pymodbus.
* :func:`measure_lockstep`: the workload of ``vc bench`` (MDA program moving two axes) with
  ``python -m plc_stub`` in its own process on a lockstep link, in simulated seconds per wall
  second, next to the same workload with the PLC in this process.
* :func:`measure_realtime`: the same workload paced at 1x real time on a free-running link
  while ``python -m plc_stub`` scans on its own clock every PLC period: the pacer's period and
  start errors, and whether the NC saw the PLC's sign of life throughout (alarms 2000, 2001).

The bare server is pymodbus itself, the yardstick
(:func:`interfaces.links.modbus.server.start_plain_register_server`).
"""

from __future__ import annotations

import asyncio
import contextlib
import gc
import multiprocessing
import resource
import statistics
import time as wallclock
from collections.abc import Callable
from dataclasses import dataclass
from enum import StrEnum
from multiprocessing.connection import Connection
from typing import Any

from interfaces.catalog import load_catalog
from interfaces.links.errors import LinkError
from interfaces.links.modbus.client import ModbusLinkClient
from interfaces.links.modbus.codec import READ_LIMIT, WRITE_LIMIT, LinkHolding, RegisterMap, Table
from interfaces.links.modbus.server import ModbusServerLink, start_plain_register_server
from interfaces.links.modbus.tables import ModbusTables
from interfaces.signals import expand

# The workload of ``vc bench`` itself, so that the lockstep and real-time figures compare with
# the in-process real-time factor.
from vc.bench.lockstep import Workload, benchmark_machine
from vc.config.loader import load_machine
from vc.config.model import MachineConfig
from vc.core.alarms import Alarm
from vc.harness.external_plc import PlcProcess
from vc.harness.links import LinkMode
from vc.harness.links.modbus import LinkedPlc
from vc.harness.pacer import PacingStats, RealtimePacer, percentile
from vc.simulation.lockstep import Simulation

LOOPBACK = "127.0.0.1"
DEVICE_ID = 1  # both servers answer every unit id; the PLC client asks for 1
EXCHANGE_RATIO_TARGET = 1.3  # harness server / bare pymodbus server, median and p99 of the round trip
PERIOD_ERROR_P99_TARGET_MS = 0.5  # at a 2 ms IPO cycle, with the PLC polling every 10 ms
SIGN_OF_LIFE_ALARMS = (2000, 2001)  # PLC sign of life lost, PLC not started up
_SERVER_START_TIMEOUT_S = 60.0  # a spawned interpreter imports the harness first: seconds on a busy machine
_CLIENT_TIMEOUT_S = 3.0


class ServerKind(StrEnum):
    HARNESS = "harness"  # ModbusServerLink serving ModbusTables, as PlcLink does
    BARE = "bare"  # pymodbus's ModbusTcpServer on its own simulator store


@dataclass(frozen=True, slots=True)
class TableSizes:
    """What a server in a child process needs to know of the machine's tables."""

    nc_to_plc_registers: int
    plc_to_nc_registers: int
    writable: bytes  # per PLC-to-NC byte: where a write lands (RegisterMap.writable)

    @classmethod
    def of(cls, register_map: RegisterMap) -> TableSizes:
        return cls(register_map.registers(Table.NC_TO_PLC), register_map.registers(Table.PLC_TO_NC),
                   register_map.writable)


# ---------------------------------------------------------------------------------- figures


@dataclass(frozen=True, slots=True)
class ExchangeFigures:
    """Round trips of one full interface exchange, in microseconds, against both servers."""

    nc_to_plc_registers: int
    plc_to_nc_registers: int
    requests_per_exchange: int
    exchanges: int  # measured per server (after the warm-up)
    rounds: int
    median_us: float  # the harness's server
    p99_us: float
    bare_median_us: float  # the bare pymodbus server
    bare_p99_us: float
    round_ratios: tuple[float, ...]  # ratio of the medians in each round: how steady the ratio is

    @property
    def median_ratio(self) -> float:
        return self.median_us / self.bare_median_us

    @property
    def p99_ratio(self) -> float:
        return self.p99_us / self.bare_p99_us

    @property
    def target_met(self) -> bool:
        return self.median_ratio <= EXCHANGE_RATIO_TARGET and self.p99_ratio <= EXCHANGE_RATIO_TARGET

    def lines(self) -> list[str]:
        return [
            f"exchange: read {self.nc_to_plc_registers} input registers (FC 4) + write {self.plc_to_nc_registers}"
            f" holding registers (FC 16) = {self.requests_per_exchange} requests; {self.exchanges} exchanges per"
            f" server in {self.rounds} interleaved rounds",
            f"  harness server   median {self.median_us:7.1f} us, p99 {self.p99_us:7.1f} us",
            f"  bare pymodbus    median {self.bare_median_us:7.1f} us, p99 {self.bare_p99_us:7.1f} us",
            f"  ratio            median {self.median_ratio:.2f}, p99 {self.p99_ratio:.2f} (target <="
            f" {EXCHANGE_RATIO_TARGET}: {_verdict(self.target_met)}); per round"
            f" {min(self.round_ratios):.2f} .. {max(self.round_ratios):.2f}",
        ]


@dataclass(frozen=True, slots=True)
class LockstepFigures:
    """The ``vc bench`` workload with the PLC in its own process (lockstep) and in this process."""

    machine: str
    simulated_s: float
    wall_s: float
    scans: int  # PLC scans exchanged over the link
    inprocess_simulated_s: float
    inprocess_wall_s: float

    @property
    def realtime_factor(self) -> float:
        return self.simulated_s / self.wall_s

    @property
    def inprocess_realtime_factor(self) -> float:
        return self.inprocess_simulated_s / self.inprocess_wall_s

    @property
    def us_per_scan(self) -> float:
        """Wall time per PLC period, NC and plant included."""
        return self.wall_s / self.scans * 1e6

    def lines(self) -> list[str]:
        return [
            f"lockstep: machine {self.machine}, plc_stub in its own process, {self.simulated_s:.1f} s simulated"
            f" in {self.wall_s:.2f} s wall time ({self.scans} scans, {self.us_per_scan:.0f} us per PLC period)",
            f"  real-time factor {self.realtime_factor:.1f}x (in-process in the same run:"
            f" {self.inprocess_realtime_factor:.1f}x)",
        ]


@dataclass(frozen=True, slots=True)
class RealtimeFigures:
    """Real-time pacing with a free-running PLC in its own process."""

    wall_s: float
    ipo_cycle_ms: float
    plc_period_ms: float
    pacing: PacingStats
    plc_scans: int  # the PLC's own scan counter (its sign of life) at the end; wraps after 65535 (11 min)
    plc_writes: int  # write requests the server accepted from the PLC
    sign_of_life_alarms: tuple[int, ...]  # 2000 / 2001 raised during the run, normally none
    # causes of a late cycle that lie outside the link, to tell them apart from it
    longest_gc_pause_ms: float
    garbage_collections: int
    involuntary_switches: int  # the OS took the CPU from this process

    @property
    def expected_scans(self) -> int:
        return int(self.wall_s * 1000 / self.plc_period_ms)

    @property
    def target_met(self) -> bool:
        return self.pacing.period_error_p99_ms < PERIOD_ERROR_P99_TARGET_MS

    def lines(self) -> list[str]:
        pacing = self.pacing
        alarms = ", ".join(str(number) for number in self.sign_of_life_alarms) or "none"
        return [
            f"real time: {self.wall_s:.1f} s at {self.ipo_cycle_ms:g} ms IPO, plc_stub free-running every"
            f" {self.plc_period_ms:g} ms in its own process",
            f"  period error     p99 {pacing.period_error_p99_ms:.3f} ms, max {pacing.period_error_max_ms:.3f} ms"
            f" (target p99 < {PERIOD_ERROR_P99_TARGET_MS} ms: {_verdict(self.target_met)})",
            f"  start error      median {pacing.error_median_ms:.3f} ms, p99 {pacing.error_p99_ms:.3f} ms,"
            f" max {pacing.error_max_ms:.3f} ms; {pacing.overruns} overruns in {pacing.cycles} cycles"
            f" ({pacing.link_overruns} while serving the link)",
            f"  PLC              {self.plc_scans} scans (expected about {self.expected_scans}),"
            f" {self.plc_writes} write requests; sign-of-life alarms: {alarms}",
            f"  this process     longest GC pause {self.longest_gc_pause_ms:.3f} ms ({self.garbage_collections}"
            f" collections), {self.involuntary_switches} involuntary context switches",
        ]


@dataclass(frozen=True, slots=True)
class LinkBenchmark:
    exchange: ExchangeFigures
    lockstep: LockstepFigures
    realtime: RealtimeFigures

    def figures(self) -> dict[str, float | int | bool]:
        """The figures as ``vc bench --link modbus`` prints them in its JSON line."""
        exchange, lockstep, realtime = self.exchange, self.lockstep, self.realtime
        return {
            "exchange_median_us": round(exchange.median_us, 1),
            "exchange_p99_us": round(exchange.p99_us, 1),
            "bare_median_us": round(exchange.bare_median_us, 1),
            "bare_p99_us": round(exchange.bare_p99_us, 1),
            "exchange_ratio": round(exchange.median_ratio, 3),
            "exchange_p99_ratio": round(exchange.p99_ratio, 3),
            "exchange_target_met": exchange.target_met,
            "lockstep_realtime_factor": round(lockstep.realtime_factor, 2),
            "inprocess_realtime_factor": round(lockstep.inprocess_realtime_factor, 1),
            "realtime_period_error_p99_ms": round(realtime.pacing.period_error_p99_ms, 4),
            "realtime_period_error_max_ms": round(realtime.pacing.period_error_max_ms, 4),
            "realtime_start_error_median_ms": round(realtime.pacing.error_median_ms, 4),
            "realtime_start_error_p99_ms": round(realtime.pacing.error_p99_ms, 4),
            "realtime_overruns": realtime.pacing.overruns,
            "realtime_link_overruns": realtime.pacing.link_overruns,
            "realtime_cycles": realtime.pacing.cycles,
            "realtime_plc_scans": realtime.plc_scans,
            "realtime_sign_of_life_alarms": len(realtime.sign_of_life_alarms),
            "realtime_longest_gc_pause_ms": round(realtime.longest_gc_pause_ms, 3),
            "realtime_involuntary_switches": realtime.involuntary_switches,
            "realtime_target_met": realtime.target_met,
            "realtime_seconds": round(realtime.wall_s, 2),
        }


def _verdict(met: bool) -> str:
    return "met" if met else "MISSED"


def run_link_benchmark(machine_path: str, realtime_seconds: float = 60.0, lockstep_seconds: float = 10.0,
                       exchanges: int = 2000, say: Callable[[str], None] = print) -> LinkBenchmark:
    """All three measurements one after the other; each one's lines are said as soon as it ends."""
    exchange = measure_exchange(machine_path, exchanges)
    for line in exchange.lines():
        say(line)
    lockstep = measure_lockstep(machine_path, lockstep_seconds)
    for line in lockstep.lines():
        say(line)
    realtime = measure_realtime(machine_path, realtime_seconds)
    for line in realtime.lines():
        say(line)
    return LinkBenchmark(exchange, lockstep, realtime)


# ---------------------------------------------------------------------------------- exchange round trip


def register_map_of(machine: MachineConfig) -> RegisterMap:
    """The machine's tables, built as PlcLink.connect builds them at power-on."""
    return RegisterMap.build(expand(load_catalog(), machine.layout), machine.plant_io.area_sizes())


def measure_exchange(machine_path: str, exchanges: int = 2000, rounds: int = 10,
                     warmup: int = 100) -> ExchangeFigures:
    """``exchanges`` full exchanges against each server, in ``rounds`` alternating rounds."""
    if exchanges < rounds or rounds < 1:
        raise ValueError(f"{exchanges} exchanges cannot be split into {rounds} rounds")
    sizes = TableSizes.of(register_map_of(load_machine(machine_path)))
    per_round = exchanges // rounds
    with contextlib.ExitStack() as stack:
        servers = {kind: stack.enter_context(ServerProcess(kind, sizes)) for kind in ServerKind}
        clients = {kind: stack.enter_context(ExchangeClient(server.port, sizes)) for kind, server in servers.items()}
        for client in clients.values():
            client.timed(warmup)  # connections, the servers' first requests, the caches of both sides
        samples: dict[ServerKind, list[float]] = {kind: [] for kind in ServerKind}
        round_ratios = []
        for number in range(rounds):
            # alternate which server goes first, so that neither always follows the other's load
            order = list(ServerKind) if number % 2 == 0 else list(reversed(ServerKind))
            medians: dict[ServerKind, float] = {}
            for kind in order:
                times = clients[kind].timed(per_round)
                samples[kind] += times
                medians[kind] = statistics.median(times)
            round_ratios.append(medians[ServerKind.HARNESS] / medians[ServerKind.BARE])
    harness, bare = samples[ServerKind.HARNESS], samples[ServerKind.BARE]
    return ExchangeFigures(
        sizes.nc_to_plc_registers, sizes.plc_to_nc_registers, clients[ServerKind.HARNESS].requests,
        len(harness), rounds, statistics.median(harness), percentile(harness, 0.99),
        statistics.median(bare), percentile(bare, 0.99), tuple(round_ratios))


class ExchangeClient:
    """A synchronous Modbus client that makes full interface exchanges, as a PLC does each scan."""

    def __init__(self, port: int, sizes: TableSizes):
        self.port = port
        self._client = ModbusLinkClient(LOOPBACK, port, timeout_s=_CLIENT_TIMEOUT_S)
        self._inputs = sizes.nc_to_plc_registers
        # a pattern rather than zeros, so that the harness's server really changes its table
        self._outputs = [(register * 0x0101) & 0xFFFF for register in range(sizes.plc_to_nc_registers)]
        self.requests = -(-self._inputs // READ_LIMIT) + -(-len(self._outputs) // WRITE_LIMIT)

    def __enter__(self) -> ExchangeClient:
        if not self._client.connect():
            raise LinkError(f"no Modbus server answers on {LOOPBACK}:{self.port}")
        return self

    def __exit__(self, *exception: object) -> None:
        self._client.close()

    def exchange(self) -> None:
        """Read every input register, write every holding register, in the largest chunks."""
        if len(self._client.read_input_registers(0, self._inputs)) != self._inputs:
            raise LinkError(f"Modbus server {LOOPBACK}:{self.port} answered a short read")
        self._client.write_registers(0, self._outputs)

    def timed(self, count: int) -> list[float]:
        """Round trips of ``count`` exchanges in microseconds."""
        times = []
        clock = wallclock.perf_counter_ns
        for _ in range(count):
            began = clock()
            self.exchange()
            times.append((clock() - began) / 1000)
        return times


class ServerProcess:
    """A Modbus server in a spawned child process (a fresh interpreter: nothing inherited from
    this one), on 127.0.0.1 and an ephemeral port; a context manager that stops it cleanly."""

    def __init__(self, kind: ServerKind, sizes: TableSizes):
        context = multiprocessing.get_context("spawn")
        self.kind = kind
        self._connection, child_end = context.Pipe()
        self.process = context.Process(target=serve_until_told, args=(kind, sizes, child_end),
                                        name=f"modbus-{kind}-server", daemon=True)
        self.process.start()
        child_end.close()  # so that the parent's end sees the end of the pipe if the child dies
        try:
            self.port = self._receive_port()
        except BaseException:
            self.close()
            raise

    def _receive_port(self) -> int:
        try:
            if not self._connection.poll(_SERVER_START_TIMEOUT_S):
                raise LinkError(f"the {self.kind} server did not start within {_SERVER_START_TIMEOUT_S:.0f} s")
            message = self._connection.recv()
        except EOFError:
            raise LinkError(f"the {self.kind} server process ended with code {self.process.exitcode}") from None
        if isinstance(message, str):
            raise LinkError(message)
        return int(message)

    def close(self) -> None:
        with contextlib.suppress(OSError):
            self._connection.send("stop")
        self.process.join(5)
        if self.process.is_alive():
            self.process.terminate()
            self.process.join(5)
        self._connection.close()

    def __enter__(self) -> ServerProcess:
        return self

    def __exit__(self, *exception: object) -> None:
        self.close()


def serve_until_told(kind: ServerKind, sizes: TableSizes, connection: Connection) -> None:
    """The child process: start the server, send its port (or why it could not start), serve
    until the parent sends anything or goes away (either makes the pipe readable)."""
    loop = asyncio.new_event_loop()
    try:
        try:
            port, stop = (_start_harness_server if kind is ServerKind.HARNESS else _start_bare_server)(sizes, loop)
        except Exception as error:  # whatever keeps the server from starting, the parent reports it
            connection.send(f"the {kind} server cannot start: {error}")
            return
        connection.send(port)
        loop.add_reader(connection.fileno(), loop.stop)
        try:
            loop.run_forever()
        finally:
            loop.remove_reader(connection.fileno())
            stop()
    finally:
        loop.close()
        connection.close()


def _start_harness_server(sizes: TableSizes, loop: asyncio.AbstractEventLoop) -> tuple[int, Callable[[], None]]:
    tables = ModbusTables(bytearray(2 * sizes.nc_to_plc_registers), bytearray(2 * sizes.plc_to_nc_registers),
                          sizes.writable)
    link = ModbusServerLink(tables, LOOPBACK, 0, loop)
    link.start()
    return link.port, link.close


def _start_bare_server(sizes: TableSizes, loop: asyncio.AbstractEventLoop) -> tuple[int, Callable[[], None]]:
    return start_plain_register_server(loop, sizes.nc_to_plc_registers, sizes.plc_to_nc_registers)


# ---------------------------------------------------------------------------------- lockstep


def measure_lockstep(machine_path: str, simulated_seconds: float = 10.0) -> LockstepFigures:
    """The workload with ``python -m plc_stub`` on a lockstep link, then in this process."""
    machine = benchmark_machine(machine_path)
    cycles = round(simulated_seconds / Simulation.ipo_seconds(machine))
    with PlcProcess() as process:
        linked = Simulation(machine, "basic_machine", connector=process.link)
        workload = Workload(linked)
        assert isinstance(linked.plc, LinkedPlc)
        scans_before = linked.plc.scans
        began = wallclock.perf_counter()
        done = workload.run(cycles)
        wall = wallclock.perf_counter() - began
        scans = linked.plc.scans - scans_before
    local = Simulation(machine, "basic_machine")
    local_workload = Workload(local)
    began = wallclock.perf_counter()
    local_done = local_workload.run(cycles)
    local_wall = wallclock.perf_counter() - began
    ipo_s = Simulation.ipo_seconds(machine)
    return LockstepFigures(machine.name, done * ipo_s, wall, scans, local_done * ipo_s, local_wall)


# ---------------------------------------------------------------------------------- real time


class _GcWatch:
    """The longest garbage-collection pause while it is installed (a late cycle's usual suspect)."""

    def __init__(self) -> None:
        self.longest_s = 0.0
        self.collections = 0
        self._began = 0.0

    def __call__(self, phase: str, info: dict[str, Any]) -> None:
        if phase == "start":
            self._began = wallclock.perf_counter()
        else:
            self.collections += 1
            self.longest_s = max(self.longest_s, wallclock.perf_counter() - self._began)

    def __enter__(self) -> _GcWatch:
        gc.callbacks.append(self)
        return self

    def __exit__(self, *exception: object) -> None:
        gc.callbacks.remove(self)


def measure_realtime(machine_path: str, wall_seconds: float = 60.0) -> RealtimeFigures:
    """The workload paced at 1x real time while ``python -m plc_stub`` scans on its own clock."""
    machine = benchmark_machine(machine_path)
    ipo_s = Simulation.ipo_seconds(machine)
    with PlcProcess(LinkMode.FREE_RUNNING) as process:
        link = process.link
        pacer = RealtimePacer(link.loop, ipo_s, speed=1.0)
        simulation = Simulation(machine, "basic_machine", connector=link, pacer=pacer)
        workload = Workload(simulation)  # the PLC process starts meanwhile: the workload needs its scans
        pacer.take_window()  # the power-on before the workload does not count
        switches_before = resource.getrusage(resource.RUSAGE_SELF).ru_nivcsw
        with _GcWatch() as collections:
            began = wallclock.perf_counter()
            workload.run(round(wall_seconds / ipo_s))
            wall = wallclock.perf_counter() - began
        switches = resource.getrusage(resource.RUSAGE_SELF).ru_nivcsw - switches_before
        alarms: list[Alarm] = list(simulation.nck.alarms.history)
        return RealtimeFigures(
            wall, ipo_s * 1000, machine.plc_cycle_ipo * ipo_s * 1000, pacer.take_window(),
            link.holding_register(LinkHolding.SCAN_DONE), link.tables.writes,
            tuple(alarm.number for alarm in alarms if alarm.number in SIGN_OF_LIFE_ALARMS),
            collections.longest_s * 1000, collections.collections, switches)
