"""``vc serve``: the NC and the plant as a server a PLC in another process connects to.

Over Modbus TCP (and S7), or as a node on a CAN bus (``--can BUS``, with the machine file's
``can:`` settings).  Lockstep (default): the NC advances one PLC period per scan the PLC reports
done, so a PLC that can be stepped (``python -m plc_stub``) runs deterministically; time stands
while no PLC answers.  Real time (``--realtime``): the IPO cycles follow the wall clock
(``--speed`` scales it), the PLC scans on its own clock, and the NC watches the PLC's sign of
life (alarm 2000 after MD10100 without one); ``--cpu`` and ``--fifo`` pin the server to CPUs and ask
for real-time scheduling (:mod:`interfaces.links.scheduling`).  An ``observer`` (the session recording of
``--record``) sees every cycle and every action of the operator.  Every ``--stats`` seconds of the
wall clock, also while a scenario runs, and at the end, a line tells the pacing (real time:
overruns, those caused by serving the links, the share of real time the NC kept) and the link
(clients, requests, refused writes, closed connections, for CAN frames and bus faults).

A scenario (``--scenario``) plays the operator for the PLC on the link.  Its ``plc:`` is optional
and names the program the harness asks a PLC that follows it (``python -m plc_stub``) to run
(default ``--program``); a PLC of your own runs its own program.  ``plc: none`` (the scenario as
the PLC) cannot be served.  When the scenario ends the server stops and ``vc serve`` exits with
the scenario's code (0 passed, 1 failed, 2 a problem in the file), after writing ``--junit
FILE``; ``--keep-running`` keeps the machine running after it until Ctrl-C or ``--duration``,
with the same exit code.  Without a scenario the machine runs until Ctrl-C or ``--duration``.
"""

from __future__ import annotations

import asyncio
import contextlib
import os
import signal
import sys
import time as wallclock
from collections.abc import Callable
from dataclasses import dataclass, field

from interfaces.links import link_kind, load
from interfaces.links.can.bus import BusSpec
from interfaces.links.errors import LinkError
from interfaces.links.inprocess import plc_programs
from interfaces.links.modbus.access import ConnectionLimits
from interfaces.links.scheduling import place
from vc.config.loader import load_machine
from vc.config.machine_files import machine_file, unknown_machine
from vc.config.model import MachineConfig
from vc.harness.external_plc import EXTERNAL_PLC_MODULES
from vc.harness.links import Link, LinkMode
from vc.harness.links.modbus import Endpoint, PlcLink
from vc.harness.pacer import RealtimePacer
from vc.scenario.command import EXIT_INTERRUPTED, EXIT_PASSED, run_command
from vc.scenario.language.model import Scenario, external_plc
from vc.simulation.lockstep import Simulation
from vc.simulation.observed import ObservedSimulation, SimulationObserver

# how the operator opens a new session after the session's PLC was lost
NEW_SESSION_HINT = "a restarted PLC gets a new session: press Enter here, or kill -USR1 {pid}"


@dataclass(slots=True)
class ServeOptions:
    machine_path: str
    modbus: Endpoint | None = None
    s7: Endpoint | None = None
    can: BusSpec | None = None  # a CAN bus instead of the servers
    allow_remote: bool = False
    allowed_clients: tuple[str, ...] = ()
    allow_writers: tuple[str, ...] = ()  # besides the session's PLC (interfaces/links/modbus/access.py)
    limits: ConnectionLimits = field(default_factory=ConnectionLimits)
    realtime: bool = False
    speed: float | None = 1.0  # None: as fast as possible
    program: str = "basic_machine"  # what the harness asks a PLC that follows it (plc_stub) to run
    scenario: str | None = None
    keep_running: bool = False  # after the scenario, until Ctrl-C or duration_s
    junit: str | None = None  # the scenario's JUnit XML report
    duration_s: float | None = None  # simulated seconds, then stop
    stats_every_s: float = 10.0
    say: Callable[[str], None] = field(default=print)
    observer: SimulationObserver | None = None  # watches the served simulation (vc serve --record)
    machine_given: bool = False  # --machine was given: with a scenario it must be the scenario's machine
    plc_key: int | None = None  # the only session key a PLC's claim may carry (--plc-key-file)
    cpus: frozenset[int] | None = None  # pin the server to these CPUs (--cpu)
    fifo_priority: int | None = None  # SCHED_FIFO at this priority, where permitted (--fifo)

    @property
    def link(self) -> str:
        """The kind of link served (interfaces/links/__init__.py): a CAN bus when ``--can`` names one,
        else Modbus TCP (and S7)."""
        return "can" if self.can is not None else "modbus"


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
    serving: Callable[..., Link] = load(link_kind(options.link).harness)
    mode = LinkMode.FREE_RUNNING if options.realtime else LinkMode.LOCKSTEP
    machine, program, scenario_path = _machine_and_program(options)
    placement = place(options.cpus, options.fifo_priority)
    def on_wait(text: str) -> None:
        say(f"waiting: {text}")

    link = serving(options, mode, on_wait=on_wait,
                   on_notice=lambda text: say(f"{text}; {NEW_SESSION_HINT.format(pid=os.getpid())}"))
    loop = link.loop or asyncio.new_event_loop()  # the pacer's
    if isinstance(link, PlcLink):
        _take_new_session_requests(link, say)
    try:
        ipo_s = Simulation.ipo_seconds(machine)
        simulations: list[Simulation] = []  # one per power-on; the latest is served
        targets: list[Simulation | ObservedSimulation] = []  # the same, as the operator sees them
        realtime = RealtimePacer(loop, ipo_s, options.speed) if options.realtime else None
        pacer = _ReportingPacer(realtime, options.stats_every_s, link,
                                lambda: simulations[-1] if simulations else None, say)
        _banner(options, machine, link, program, mode, say)
        if options.cpus or options.fifo_priority is not None or options.realtime:
            say(f"scheduling: {placement}")

        def power_on(scenario: Scenario | None = None) -> Simulation | ObservedSimulation:
            powered = scenario.machine if scenario else machine
            link.configure_for(powered)
            simulation = Simulation(powered, program, connector=link, pacer=pacer)
            simulations.append(simulation)
            observer = options.observer
            targets.append(simulation if observer is None else ObservedSimulation(simulation, [observer]))
            return targets[-1]

        code = EXIT_PASSED
        try:
            if scenario_path is not None:
                code = run_command([scenario_path], power_on, plc_programs().keys(), junit=options.junit,
                                   default_plc=options.program)
                if code == EXIT_INTERRUPTED:  # Ctrl-C during the scenario ends the server, --keep-running or not
                    say("stopped")
                    return code
                if not options.keep_running:
                    say(f"scenario done (exit code {code}); the server stops (--keep-running keeps the machine"
                        " running)")
                    return code
                say("scenario done; the machine keeps running (Ctrl-C ends)")
            _keep_running(targets[-1] if targets else power_on(), options)
        except KeyboardInterrupt:
            say("stopped")
        finally:
            if realtime is not None:
                say(f"real time: {realtime.stats()}; {placement}")
            if simulations:
                say(f"link: {link.peer_state(simulations[-1])}")
        return code
    finally:
        link.close()
        if loop is not link.loop:
            loop.close()


def _take_new_session_requests(link: PlcLink, say: Callable[[str], None]) -> None:
    """The operator's new session for a restarted PLC (:meth:`PlcLink.open_new_session`): SIGUSR1, or
    Enter when standard input is a terminal.  Both are served by the link's event loop, which runs
    while the harness waits for the PLC and between the cycles of real time."""
    def open_new_session() -> None:
        say(link.open_new_session())

    def line_typed() -> None:
        if not sys.stdin.readline():  # end of input: nothing more to read there
            link.loop.remove_reader(sys.stdin.fileno())
            return
        open_new_session()

    try:
        link.loop.add_signal_handler(signal.SIGUSR1, open_new_session)
    except (ValueError, RuntimeError, NotImplementedError) as error:  # not the main thread, no signals here
        say(f"vc serve: SIGUSR1 cannot open a new session here ({error}); press Enter on the terminal instead")
    with contextlib.suppress(ValueError, OSError, AttributeError):  # no terminal (a pipe, a service, a test)
        if sys.stdin is not None and sys.stdin.isatty():
            link.loop.add_reader(sys.stdin.fileno(), line_typed)


def _machine_and_program(options: ServeOptions) -> tuple[MachineConfig, str, str | None]:
    if options.scenario is None:
        return load_machine(options.machine_path), options.program, None
    from vc.scenario.language.loader import load_scenarios

    (scenario,) = load_scenarios([options.scenario], plc_programs().keys(), default_plc=options.program)
    if scenario.plc_program is None:
        raise LinkError(f"{options.scenario}: plc: none makes the scenario the PLC; a served scenario plays the"
                        " operator for the PLC on the link (leave plc: out, or name the program plc_stub runs)")
    if options.machine_given:
        _check_same_machine(options.machine_path, options.scenario, scenario.machine)
    return scenario.machine, scenario.plc_program, options.scenario


def _check_same_machine(reference: str, scenario_path: str, machine: MachineConfig) -> None:
    """``--machine`` with ``--scenario`` must name the scenario's machine: the scenario's machine is
    what runs, and a PLC configured for the machine given would meet another one."""
    given, runs = machine_file(reference), machine_file(machine.source)  # a scenario's machine may be a name too
    if given is None:
        raise LinkError(unknown_machine(reference))
    if runs is None or not os.path.exists(given) or not os.path.samefile(given, runs):
        raise LinkError(f"--machine {reference} names another machine than the scenario {scenario_path}, which runs"
                        f" {machine.name} ({machine.source}): leave --machine out, or give the scenario's machine")


def _banner(options: ServeOptions, machine: MachineConfig, link: Link, program: str, mode: LinkMode,
            say: Callable[[str], None]) -> None:
    say(f"machine {machine.name} ({machine.source})")
    for line in link.banner(machine):
        say(line)
    if mode is LinkMode.LOCKSTEP:
        say(f"lockstep: the NC advances one PLC period per scan the PLC reports done; {_who_follows(link, program)}")
    else:
        speed = "as fast as possible" if options.speed is None else f"{options.speed:g} x real time"
        say(f"real time, {speed}; the NC watches the PLC's sign of life (alarm 2000){link.watched}")


def _who_follows(link: Link, program: str) -> str:
    """Which PLC the scenario expects and how to start it."""
    external = external_plc(program)
    if external is None:
        return f"a PLC that follows the harness runs '{program}' ({link.plc_command})"
    kind, path = external
    where = str(link.modbus.port) if isinstance(link, PlcLink) and link.modbus is not None else "PORT"
    return (f"the scenario's PLC is {kind} with {path}: python -m {EXTERNAL_PLC_MODULES[kind]} --modbus"
            f" 127.0.0.1:{where} {path}")


def _keep_running(target: Simulation | ObservedSimulation, options: ServeOptions) -> None:
    """Step until the duration is over (the statistics come from the pacer)."""
    simulation = target if isinstance(target, Simulation) else target.simulation
    alarms = AlarmWatch(simulation, options.say)
    stop_cycle = None if options.duration_s is None else round(options.duration_s / simulation.ipo_cycle_s)
    while stop_cycle is None or simulation.cycle < stop_cycle:
        target.step(1)
        alarms.check()


class _ReportingPacer:
    """Paces the cycles to the wall clock in real time (none in lockstep) and prints, every
    ``every_s`` wall seconds from inside the cycle, the pacing since the last line (real time) and
    the link's state: so the lines come while a scenario runs too."""

    def __init__(self, pacer: RealtimePacer | None, every_s: float, link: Link,
                 current: Callable[[], Simulation | None], say: Callable[[str], None]):
        self.pacer = pacer
        self.every_s = every_s
        self.link = link
        self.current = current  # the simulation of the latest power-on
        self.say = say
        self._next = wallclock.monotonic() + every_s

    def wait_next_cycle(self) -> None:
        if self.pacer is not None:
            self.pacer.wait_next_cycle()
        if wallclock.monotonic() < self._next:
            return
        self._next += self.every_s
        simulation = self.current()
        if simulation is not None:
            pacing = f"{self.pacer.take_window()}; " if self.pacer is not None else ""
            self.say(f"{simulation.time_s:9.3f} s  {pacing}{self.link.peer_state(simulation)}")
