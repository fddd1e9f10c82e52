"""``vc serve``: the NC and the plant as a server a PLC in another process connects to.

Over Modbus TCP (and S7), or as a node on a CAN bus (``--can BUS``, with the machine file's
``can:`` settings).  Lockstep (default): the NC advances one PLC period per scan the PLC reports
done, so a PLC that can be stepped (``python -m plc_stub``) runs deterministically; time stands
while no PLC answers.  Real time (``--realtime``): the IPO cycles follow the wall clock
(``--speed`` scales it), the PLC scans on its own clock, and the NC watches the PLC's sign of
life (alarm 2000 after MD10100 without one).  A scenario (``--scenario``) plays the operator;
afterwards the machine keeps running until Ctrl-C or ``--duration``.  An ``observer`` (the session
recording of ``--record``) sees every cycle and every action of the operator.  Every ``--stats``
seconds, and at the end, a line tells the pacing (real time: overruns, those caused by serving the
links, the share of real time the NC kept) and the link (clients, requests, refused writes, closed
connections, for CAN frames and bus faults).
"""

from __future__ import annotations

import asyncio
import time as wallclock
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Protocol

from interfaces.links.access import ConnectionLimits
from interfaces.links.can_bus import BusSpec
from interfaces.links.errors import LinkError
from interfaces.links.inprocess import plc_programs
from interfaces.plc import PlcEnvironment, SoftPlc
from vc.config.loader import load_machine
from vc.config.model import MachineConfig
from vc.harness.can_link import CanLink
from vc.harness.observed import ObservedSimulation, SimulationObserver
from vc.harness.pacer import RealtimePacer
from vc.harness.plc_link import Endpoint, LinkMode, PlcLink, check_bind
from vc.harness.simulation import Simulation
from vc.scenario.command import EXIT_PASSED, run_command
from vc.scenario.model import Scenario


class ServedLink(Protocol):
    """What ``vc serve`` needs of a link to a PLC in another process (Modbus TCP / S7, or CAN)."""

    @property
    def loop(self) -> asyncio.AbstractEventLoop | None:
        """The link's event loop, which the pacer shares; None: it has none."""

    @property
    def plc_command(self) -> str:
        """How plc_stub follows the harness on this link."""

    @property
    def watched(self) -> str:
        """What the NC watches besides the PLC's sign of life, for the banner."""

    def connect(self, environment: PlcEnvironment, program: str) -> SoftPlc: ...

    def configure_for(self, machine: MachineConfig) -> None:
        """The settings of the machine the next power-on uses."""

    def banner(self, machine: MachineConfig) -> list[str]:
        """Where the link listens and where its map comes from."""

    def peer_state(self, simulation: Simulation) -> str:
        """The PLC's side for the statistics line."""

    def close(self) -> None: ...


@dataclass(slots=True)
class ServeOptions:
    machine_path: str
    modbus: Endpoint | None = None
    s7: Endpoint | None = None
    can: BusSpec | None = None  # a CAN bus instead of the servers
    allow_remote: bool = False
    allowed_clients: tuple[str, ...] = ()
    allow_writers: tuple[str, ...] = ()  # besides the session's PLC (interfaces/links/access.py)
    limits: ConnectionLimits = field(default_factory=ConnectionLimits)
    realtime: bool = False
    speed: float | None = 1.0  # None: as fast as possible
    program: str = "basic_machine"  # what the harness asks a PLC that follows it (plc_stub) to run
    scenario: str | None = None
    duration_s: float | None = None  # simulated seconds, then stop
    stats_every_s: float = 10.0
    say: Callable[[str], None] = field(default=print)
    observer: SimulationObserver | None = None  # watches the served simulation (vc serve --record)


class AlarmWatch:
    """Prints alarms as they come and go (the operator's alarm line)."""

    def __init__(self, simulation: Simulation, say: Callable[[str], None]):
        self.simulation = simulation
        self.say = say
        self._version = -1
        self._shown: set[tuple[int, str, str]] = set()

    def check(self) -> None:
        alarms = self.simulation.nck.alarms
        if alarms.version == self._version:
            return
        self._version = alarms.version
        present = {(alarm.number, alarm.channel, alarm.axis): alarm for alarm in alarms.present}
        at = f"{self.simulation.time_s:9.3f} s"
        for key in sorted(present.keys() - self._shown):
            self.say(f"{at}  alarm {present[key]}")
        for key in sorted(self._shown - present.keys()):
            self.say(f"{at}  alarm {key[0]} cleared")
        self._shown = set(present)


def serve(options: ServeOptions) -> int:
    say = options.say
    if options.can is not None and (options.modbus or options.s7):
        raise LinkError("serve either a CAN bus or Modbus TCP / S7, not both")
    modbus = options.modbus if options.modbus or options.s7 or options.can else Endpoint("127.0.0.1", 5020)
    for endpoint in (modbus, options.s7):
        if endpoint is not None:
            check_bind(endpoint, options.allow_remote)
    machine, program, scenario_path = _machine_and_program(options)
    mode = LinkMode.FREE_RUNNING if options.realtime else LinkMode.LOCKSTEP
    def on_wait(text: str) -> None:
        say(f"waiting: {text}")

    link: ServedLink
    if options.can is not None:
        link = CanLink(mode, options.can, first_scan_timeout_s=None, scan_timeout_s=None, on_wait=on_wait)
    else:
        link = PlcLink(mode, modbus=modbus, s7=options.s7, allowed_clients=options.allowed_clients,
                       allow_writers=options.allow_writers, limits=options.limits, first_scan_timeout_s=None,
                       scan_timeout_s=None, on_wait=on_wait)
    loop = link.loop or asyncio.new_event_loop()  # the pacer's
    try:
        ipo_s = Simulation.ipo_seconds(machine)
        pacer = RealtimePacer(loop, ipo_s, options.speed) if options.realtime else None
        _banner(options, machine, link, program, mode, say)
        simulations: list[Simulation | ObservedSimulation] = []

        def power_on(scenario: Scenario | None = None) -> Simulation | ObservedSimulation:
            powered = scenario.machine if scenario else machine
            link.configure_for(powered)
            simulation = Simulation(powered, program, connector=link, pacer=pacer)
            observer = options.observer
            simulations.append(simulation if observer is None else ObservedSimulation(simulation, [observer]))
            return simulations[-1]

        code = EXIT_PASSED
        try:
            if scenario_path is not None:
                code = run_command([scenario_path], power_on, plc_programs().keys())
                say("scenario done; the machine keeps running (Ctrl-C ends)")
            _keep_running(simulations[-1] if simulations else power_on(), pacer, link, options)
        except KeyboardInterrupt:
            say("stopped")
        if pacer is not None:
            say(f"real time: {pacer.stats()}")
        if simulations:
            last = simulations[-1]
            say(f"link: {link.peer_state(last if isinstance(last, Simulation) else last.simulation)}")
        return code
    finally:
        link.close()
        if loop is not link.loop:
            loop.close()


def _machine_and_program(options: ServeOptions) -> tuple[MachineConfig, str, str | None]:
    if options.scenario is None:
        return load_machine(options.machine_path), options.program, None
    from vc.scenario.loader import load_scenarios

    (scenario,) = load_scenarios([options.scenario], plc_programs().keys())
    return scenario.machine, scenario.plc_program or options.program, options.scenario


def _banner(options: ServeOptions, machine: MachineConfig, link: ServedLink, program: str, mode: LinkMode,
            say: Callable[[str], None]) -> None:
    say(f"machine {machine.name} ({machine.source})")
    for line in link.banner(machine):
        say(line)
    if mode is LinkMode.LOCKSTEP:
        say(f"lockstep: the NC advances one PLC period per scan the PLC reports done; a PLC that follows the"
            f" harness runs '{program}' ({link.plc_command})")
    else:
        speed = "as fast as possible" if options.speed is None else f"{options.speed:g} x real time"
        say(f"real time, {speed}; the NC watches the PLC's sign of life (alarm 2000){link.watched}")


def _keep_running(target: Simulation | ObservedSimulation, pacer: RealtimePacer | None, link: ServedLink,
                  options: ServeOptions) -> None:
    """Step until the duration is over; every ``--stats`` seconds of the wall clock the pacing of
    the cycles since the last line (real time) and the link's state."""
    simulation = target if isinstance(target, Simulation) else target.simulation
    alarms = AlarmWatch(simulation, options.say)
    stop_cycle = None if options.duration_s is None else round(options.duration_s / simulation.ipo_cycle_s)
    next_stats = wallclock.monotonic() + options.stats_every_s
    while stop_cycle is None or simulation.cycle < stop_cycle:
        target.step(1)
        alarms.check()
        if wallclock.monotonic() >= next_stats:
            next_stats += options.stats_every_s
            pacing = f"{pacer.take_window()}; " if pacer is not None else ""
            options.say(f"{simulation.time_s:9.3f} s  {pacing}{link.peer_state(simulation)}")
