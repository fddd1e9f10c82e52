"""The PLC's end of the Modbus TCP link, whatever runs the program: one implementation of the
handshake of docs/modbus.md, driven by the built-in soft PLC (:class:`RemotePlc`, ``python -m
plc_stub --modbus``, :func:`run_plc`) and by awlsim's hardware module (:mod:`plc_awlsim.hardware`).

:class:`ModbusPlcEnd` configures itself from the server (the link block and the interface
description of :mod:`interfaces.links.modbus.codec`) and follows the server's mode::

    poll the link block
      version 0 (no machine yet)            -> poll again
      a new session or a new boot id        -> the description, the PLC's start (its ``start``),
                                               the claim: HR 1 = the session, HR 2..5 = the key
      the same session after a reconnect    -> the claim again: the program carries on
      lockstep: a new grant in IR 3         -> a scan with the NC-to-PLC table
      free-running: every poll              -> a scan, its counter the sign of life
    after the scan: the PLC-to-NC table, HR 0 = the grant (lockstep) or the counter, written last

A new session (the harness powered the machine on again, started the next scenario, or its
operator opened one) or a new boot id (another harness process, whose sessions count from 1 again)
means a PLC restart: the description is read again and the program starts from its initial state.
The PLC claims every session with its session key (random per process, or ``--key-file``), so a
connection lost and made again to the same session of the same process keeps the program: the key
takes the session back, the program carries on where it was, and in lockstep the outputs of a scan
whose write was lost are sent again instead of the scan running twice.  A claim the server refuses
(another PLC holds the session, or it was closed when its PLC was lost) is said once; the PLC then
waits for the next session.  When no server takes a new connection within
:data:`~interfaces.links.modbus.client.RECONNECT_WINDOW_S` the harness has ended
(:class:`HarnessGone`), and so does the PLC.

In lockstep the harness answers only while it waits for the PLC, and it may pause between two
scans for longer than a real-time PLC would wait (a garbage collection of a long ``vc run``, a
busy host): a request waits :data:`LOCKSTEP_TIMEOUT_S` for its answer there, not the real-time
:data:`TIMEOUT_S`, so that a pause never reconnects in the middle of a session (``--answer-timeout``
sets one time-out for both).  A harness that is gone closes the connection, which ends the wait at once.
"""

from __future__ import annotations

import math
import secrets
import struct
import time as wallclock
from collections.abc import Callable, Mapping
from dataclasses import dataclass

from interfaces.image import ProcessImage
from interfaces.links.description import LinkDescription, PlcSetupError
from interfaces.links.endpoint import parse_endpoint
from interfaces.links.errors import LinkError, RequestRefused
from interfaces.links.modbus.client import RECONNECT_WINDOW_S, ModbusLinkClient
from interfaces.links.modbus.codec import (
    LINK_REGISTERS,
    LINK_VERSION,
    MODE_LOCKSTEP,
    READ_LIMIT,
    WRITE_LIMIT,
    LinkHolding,
    LinkInput,
    RegisterMap,
    Table,
    read_registers,
    registers_text,
    session_key_registers,
)
from interfaces.links.scan_loop import EXIT_NO_HARNESS, EXIT_STOPPED, PlcProcessOptions, exit_code, run_scans
from interfaces.plc import PlcFactory, SoftPlc

_WORD = struct.Struct(">H")
TIMEOUT_S = 3.0  # real time (and before the first session): an answer later than this is a lost server
LOCKSTEP_TIMEOUT_S = 120.0  # lockstep: the harness may pause between scans (module docstring)
NO_MACHINE_PAUSE_S = 0.01  # between two polls while no machine is powered on
REFUSED_PAUSE_S = 0.2  # between two polls while the server refuses this PLC the offered session


class HarnessGone(LinkError):
    """No harness answered within the connect time-out, or the harness has ended."""


@dataclass(frozen=True, slots=True)
class Session:
    """A session of the harness as its link block and its description say (docs/modbus.md)."""

    number: int
    boot_id: int  # the harness process's boot id the session belongs to
    lockstep: bool
    nc_to_plc_registers: int
    plc_to_nc_registers: int
    ipo_cycle_us: int
    plc_cycle_ipo: int
    description: bytes  # the interface description (UTF-8 JSON, interfaces/links/description.py)

    @property
    def scan_time_s(self) -> float:
        return self.ipo_cycle_us * self.plc_cycle_ipo / 1_000_000


@dataclass(frozen=True, slots=True)
class Scan:
    """A scan the harness grants (lockstep) or the PLC's clock asks for (free-running)."""

    done: int  # what HR 0 reports when it is done: the grant, or the scan counter
    inputs: list[int]  # the NC-to-PLC table, register by register


class ModbusPlcEnd:
    """The handshake of the PLC's end over ``client`` (module docstring).  ``start`` is called with
    each new session before it is claimed: the PLC (re)starts its program for it there, and a
    :class:`~interfaces.links.description.PlcSetupError` it raises leaves the session unclaimed."""

    def __init__(self, client: ModbusLinkClient, start: Callable[[Session], None], *,
                 log: Callable[[str], None] = lambda text: None, answer_timeout_s: float | None = None,
                 key: int | None = None):
        self.client = client
        self.start = start
        self.log = log
        self.answer_timeout_s = answer_timeout_s
        # the session key of this process's claims (docs/modbus.md): only this process (or, with the
        # harness's key file, a PLC given the same file) can take its session back after a lost connection
        self.key = key or secrets.randbits(64) or 1
        self.session: Session | None = None
        self.last_grant = 0
        self._life = 0  # free-running: the scan counter, the sign of life
        # lockstep: the outputs of a scan whose write the link lost, (grant, registers), until they are sent
        self._unsent: tuple[int, list[int]] | None = None
        # the PLC-to-NC table as the server holds it from this connection's last complete write in the
        # session (None: not known, the next write is the whole table); a chunk equal to it is not sent
        self._held: list[int] | None = None
        self._reconnected = False
        self._refused: tuple[int, int] | None = None  # (session, boot id) whose claim the server refused

    # ------------------------------------------------------------------ one poll
    def poll(self) -> Scan | None:
        """Read the link block and do what it asks: the scan to run now, or None."""
        return self._poll(scan_at_start=True)

    def wait_for_session(self, should_stop: Callable[[], bool] = lambda: False) -> Session | None:
        """Poll until a session is claimed (None when stopped first); the scans it grants are left to
        :meth:`poll` (the PLC may have to restart first)."""
        while self.session is None and not should_stop():
            self._poll(scan_at_start=False)
        return self.session

    def _poll(self, scan_at_start: bool) -> Scan | None:
        head = self.client.read_input_registers(0, self._poll_count())
        if head[LinkInput.VERSION] == 0:  # the harness has not powered a machine on yet
            wallclock.sleep(NO_MACHINE_PAUSE_S)
            return None
        if head[LinkInput.VERSION] != LINK_VERSION:
            raise PlcSetupError(f"the server speaks link version {head[LinkInput.VERSION]}, this PLC {LINK_VERSION}")
        session = self.session
        offered = (head[LinkInput.SESSION], head[LinkInput.BOOT_ID])
        if session is None or (session.number, session.boot_id) != offered:
            if offered == self._refused:  # another PLC's session, or one closed: wait for a new one
                wallclock.sleep(REFUSED_PAUSE_S)
                return None
            # a new session of this harness, or a harness process started since (its sessions count from
            # 1 again): restart the program
            session = self._start_session(head)
            if session is None:
                return None
            self._reconnected = False  # claimed on this connection
            if not scan_at_start:
                return None
            head = self.client.read_input_registers(0, self._poll_count())
        elif self._reconnected:
            # the same session of the same harness process after a reconnect: the program carries on
            # with its state; the session is claimed again on this connection, with this process's key
            if not self._claim(session.number, session.boot_id):
                return None
            self.log(f"session {session.number} (boot id {session.boot_id}) goes on after the reconnect")
        self._reconnected = False
        if not session.lockstep:
            self._life = self._life % 0xFFFF + 1
            return Scan(self._life, self._inputs(session, head))
        grant = head[LinkInput.SCAN_GRANT]
        if self._unsent is not None and self._resend(grant):
            return None
        if grant == 0 or grant == self.last_grant:
            return None
        self.last_grant = grant
        return Scan(grant, self._inputs(session, head))

    def _poll_count(self) -> int:
        return LINK_REGISTERS if self.session is None else min(READ_LIMIT, self.session.nc_to_plc_registers)

    def _inputs(self, session: Session, head: list[int]) -> list[int]:
        total = session.nc_to_plc_registers
        registers = head[:total]
        if len(registers) < total:
            registers += self.client.read_input_registers(len(registers), total - len(registers))
        return registers

    def _start_session(self, head: list[int]) -> Session | None:
        length = head[LinkInput.DESCRIPTION_BYTES]
        description = registers_text(
            self.client.read_input_registers(head[LinkInput.DESCRIPTION_START], math.ceil(length / 2)), length)
        lockstep = head[LinkInput.MODE] == MODE_LOCKSTEP
        session = Session(head[LinkInput.SESSION], head[LinkInput.BOOT_ID], lockstep,
                          head[LinkInput.NC_TO_PLC_REGISTERS], head[LinkInput.PLC_TO_NC_REGISTERS],
                          head[LinkInput.IPO_CYCLE_US], head[LinkInput.PLC_CYCLE_IPO], description)
        self.session = None
        self.start(session)
        self.client.timeout_s = self.answer_timeout_s or (LOCKSTEP_TIMEOUT_S if lockstep else TIMEOUT_S)
        self.session, self.last_grant, self._life, self._unsent, self._held = session, 0, 0, None, None
        try:
            claimed = self._claim(session.number, session.boot_id)
        except LinkError:
            self.session = None  # never claimed: after the reconnect it starts again
            raise
        return session if claimed else None

    def _claim(self, number: int, boot_id: int) -> bool:
        """Claim session ``number`` on this connection (holding register 1 = the session, 2..5 = the
        key); False when the server refuses it: then this PLC waits for a new session."""
        try:
            self.client.write_registers(LinkHolding.SESSION_READY, [number, *session_key_registers(self.key)])
        except RequestRefused:
            self.session = None
            self._refused = (number, boot_id)
            self.log(f"session {number}: the server refused this PLC's claim (another PLC holds the session, or it"
                     " was closed when its PLC was lost); waiting for a new session: the next power-on, or the"
                     " operator's (vc serve: Enter or SIGUSR1)")
            return False
        self._refused = None
        return True

    # ------------------------------------------------------------------ after a scan
    def finish(self, scan: Scan, outputs: bytearray) -> None:
        """Report ``scan`` done with the PLC-to-NC table ``outputs`` (its bytes; HR 0 and HR 1 are
        the link's).  The whole table from register 0, the chunk with register 0 last: the scan-done
        word reaches the server after every output of the scan."""
        session = self.session
        assert session is not None
        _WORD.pack_into(outputs, 2 * LinkHolding.SCAN_DONE, scan.done)
        _WORD.pack_into(outputs, 2 * LinkHolding.SESSION_READY, session.number)
        values = read_registers(outputs, 0, session.plc_to_nc_registers)
        if session.lockstep:
            self._unsent = (scan.done, values)  # until the write is through: a lost link must not run the scan twice
        self._write_outputs(values)
        self._unsent = None

    def _write_outputs(self, values: list[int]) -> None:
        """The PLC-to-NC table in chunks, the one holding register 0 (the scan-done word) last; a chunk
        the server already holds from the last scan is left out (docs/modbus.md, step 4): most scans
        change a few bits, and each request left out is a round trip fewer per scan."""
        held, self._held = self._held, None  # unknown until every chunk of this scan is through
        for start in reversed(range(0, len(values), WRITE_LIMIT)):
            chunk = values[start: start + WRITE_LIMIT]
            if start and held is not None and held[start: start + WRITE_LIMIT] == chunk:
                continue
            self.client.write_registers(start, chunk)
        self._held = values

    def _resend(self, grant: int) -> bool:
        """After a lost link: the outputs of the scan it lost go again while the harness still waits
        for that scan (True); once it granted another, it had taken them (False)."""
        assert self._unsent is not None
        unsent_grant, values = self._unsent
        self.last_grant = unsent_grant
        if grant != unsent_grant:
            self._unsent = None
            return False
        self._held = None
        self.client.write_registers_last_first(0, values)
        self._unsent = None
        self._held = values
        return True

    # ------------------------------------------------------------------ the connection
    def refused(self, error: RequestRefused) -> None:
        """A write of a scan was refused (the operator opened a new session meanwhile, or another PLC
        holds the session): the next poll reads the link block anew."""
        self.log(f"{error}; reading the link block anew")
        self.session, self._held = None, None

    def connect(self, timeout_s: float, should_stop: Callable[[], bool] = lambda: False) -> None:
        """The first connection, within ``timeout_s`` (the harness may start after the PLC)."""
        if not self.client.connect_within(timeout_s, should_stop) and not should_stop():
            raise HarnessGone(f"no Modbus server at {self.client.host}:{self.client.port} after {timeout_s:g} s")

    def reconnect(self, error: LinkError, connect_timeout_s: float,
                  should_stop: Callable[[], bool] = lambda: False) -> None:
        """After a lost connection: a new one within :data:`RECONNECT_WINDOW_S` (a harness that still runs
        takes it at once); the next poll reads the link block anew and restarts the program only when
        the session or the boot id changed.  No server: the harness has ended (:class:`HarnessGone`)."""
        self.client.close()
        self._reconnected = True
        self._held = None  # a write the link lost may have reached the server in part
        window = min(RECONNECT_WINDOW_S, connect_timeout_s)
        if not self.client.connect_within(window, should_stop) and not should_stop():
            raise HarnessGone(f"the harness has gone: {error}, and no server has listened at {self.client.host}:"
                              f"{self.client.port} since ({window:g} s)")

    def forget_session(self) -> None:
        """The PLC cannot go on with its session (it lost its program's state): the next poll starts
        the session the harness offers anew, with the PLC's start."""
        self.session, self._unsent, self._held = None, None, None


@dataclass(slots=True)
class _Program:
    """The soft PLC of one session, with its images and tables."""

    description: LinkDescription
    name: str
    register_map: RegisterMap
    plc: SoftPlc
    interface: ProcessImage
    plant: ProcessImage
    nc_to_plc: bytearray
    plc_to_nc: bytearray

    @property
    def areas(self) -> dict[str, bytearray]:
        return {**self.interface.areas, **self.plant.areas}


class RemotePlc:
    """Soft PLC ``programs`` (:class:`~interfaces.plc.SoftPlc`) as one PLC process over the link:
    ``run`` until stopped (``should_stop``) or the server goes away for good."""

    def __init__(self, client: ModbusLinkClient, programs: Mapping[str, PlcFactory], program: str | None = None,
                 period_s: float | None = None, log: Callable[[str], None] = lambda text: None,
                 answer_timeout_s: float | None = None, key: int | None = None):
        self.programs = programs
        self.program = program
        self.period_s = period_s
        self.log = log
        self.end = ModbusPlcEnd(client, self._start, log=log, answer_timeout_s=answer_timeout_s, key=key)
        self._running: _Program | None = None
        self.scans = 0

    @property
    def session(self) -> Session | None:
        return self.end.session

    def _start(self, session: Session) -> None:
        description = LinkDescription.for_plc(session.description)
        environment, register_map, plc, name = description.start_program(self.programs, self.program)
        sizes = register_map.table_bytes
        self._running = _Program(description, name, register_map, plc,
                                 ProcessImage(environment.catalog.area_sizes),
                                 ProcessImage(environment.plant_io.area_sizes()),
                                 bytearray(sizes[Table.NC_TO_PLC]), bytearray(sizes[Table.PLC_TO_NC]))
        self.log(f"session {session.number} (boot id {session.boot_id}): machine {description.machine},"
                 f" program {name}, {'lockstep' if session.lockstep else 'free-running'}")

    def poll(self) -> bool:
        """Read the link block and do what it asks; True if a scan ran."""
        scan = self.end.poll()
        if scan is None:
            return False
        running = self._running
        assert running is not None
        buffer = running.nc_to_plc
        buffer[:] = struct.pack(f">{len(scan.inputs)}H", *scan.inputs)
        areas = running.areas
        running.register_map.fill_areas(Table.NC_TO_PLC, buffer, areas)
        running.plc.scan(running.interface, running.plant)
        running.register_map.fill_table(Table.PLC_TO_NC, areas, running.plc_to_nc)
        self.end.finish(scan, running.plc_to_nc)
        self.scans += 1
        return True

    # ------------------------------------------------------------------ the loop (interfaces.links.scan_loop)
    def run(self, should_stop: Callable[[], bool] = lambda: False) -> None:
        """Poll (lockstep) or scan on the clock (free-running) until ``should_stop``; a lost
        connection raises :class:`LinkError` to the caller, which may reconnect."""
        run_scans(self, self.period_s, should_stop)

    def free_running_period(self) -> float | None:
        session = self.end.session
        return None if session is None or session.lockstep else session.scan_time_s

    def follow(self) -> None:
        self.poll()

    def idle(self, seconds: float) -> None:
        wallclock.sleep(seconds)

    def scan(self) -> None:
        self.poll()


def run_plc(address: str, programs: Mapping[str, PlcFactory], options: PlcProcessOptions,
            log: Callable[[str], None], should_stop: Callable[[], bool] = lambda: False) -> int:
    """Connect to the harness's server at ``address`` (HOST:PORT) and run the soft PLC ``programs``; the
    exit code of ``python -m plc_stub --modbus``.  ``options.connect_timeout_s``: how long the first
    connection may take (the harness may start after the PLC).  A lost connection is made again within
    :data:`RECONNECT_WINDOW_S`: a harness that still runs takes it at once; one that has ended ends the
    PLC (exit code 1) instead of a retry for the whole connect time-out.  ``options.answer_timeout_s``:
    how long a request may go unanswered before the connection is made again (None: :data:`TIMEOUT_S`
    in real time, :data:`LOCKSTEP_TIMEOUT_S` in lockstep)."""
    host, port = parse_endpoint(address)
    connect_timeout_s, answer_timeout_s = options.connect_timeout_s, options.answer_timeout_s
    client = ModbusLinkClient(host, port, timeout_s=answer_timeout_s or TIMEOUT_S)
    plc = RemotePlc(client, programs, options.program, options.period_s, log, answer_timeout_s, options.key)

    def run() -> int:
        try:
            plc.end.connect(connect_timeout_s, should_stop)
        except HarnessGone as gone:
            log(str(gone))
            return EXIT_NO_HARNESS
        if should_stop():
            return EXIT_STOPPED
        log(f"connected to {host}:{port}")
        while not should_stop():
            try:
                plc.run(should_stop)
            except RequestRefused as error:
                plc.end.refused(error)
            except LinkError as error:
                try:
                    plc.end.reconnect(error, connect_timeout_s, should_stop)
                except HarnessGone as gone:
                    log(f"{gone}; stopping")
                    return EXIT_NO_HARNESS
                if not should_stop():
                    log(f"link lost: {error}; connected again")
        return EXIT_STOPPED

    try:
        return exit_code(run, log)
    finally:
        client.close()
