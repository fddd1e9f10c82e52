"""The built-in programs as a PLC in its own process, a Modbus TCP client of the harness.

The client configures itself from the server (the link block and the interface description
of :mod:`interfaces.codec_modbus`) and follows the server's mode:

* **lockstep**: poll the link block; when the harness grants a scan, read the NC->PLC table,
  run one scan, write the PLC->NC table, then report the scan done.  The order inside the scan
  is the in-process one (:class:`plc_stub.runtime.ScanCycleRuntime`), so the trace is the same.
* **free-running**: scan every PLC period of the wall clock (or ``period_s``): read, scan,
  write, and count the scan-done register up as the sign of life.

A new session (the harness powered the machine on again, started the next scenario, or its
operator opened one) or a new boot id (another harness process, whose sessions count from 1 again)
means a PLC restart: the description is read again and the program starts from its initial state.
The PLC claims every session with its session key (random per process, or ``--key-file``), so a
connection lost and made again to the same session of the same process keeps the program: the key
takes the session back, the program carries on where it was, and in lockstep the outputs of a scan
whose write was lost are sent again instead of the scan running twice.  A claim the server refuses
(another PLC holds the session, or it was closed when its PLC was lost) is said once; the PLC then
waits for the next session.  When no server takes a new connection within
:data:`~interfaces.links.modbus_tcp.RECONNECT_WINDOW_S` the harness has ended, and so does the PLC
(exit code 1).

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
from collections.abc import Callable
from dataclasses import dataclass

from interfaces.codec_modbus import (
    LINK_REGISTERS,
    LINK_VERSION,
    MODE_LOCKSTEP,
    READ_LIMIT,
    LinkHolding,
    LinkInput,
    RegisterMap,
    Table,
    read_registers,
    registers_text,
    session_key_registers,
)
from interfaces.image import ProcessImage
from interfaces.link_description import LinkDescription, PlcSetupError
from interfaces.links.errors import RequestRefused
from interfaces.links.modbus_tcp import RECONNECT_WINDOW_S, LinkError, ModbusLinkClient
from interfaces.plc import SoftPlc
from plc_stub.programs import FACTORIES
from plc_stub.scan_loop import EXIT_NO_HARNESS, EXIT_STOPPED, exit_code, run_scans

_WORD = struct.Struct(">H")
TIMEOUT_S = 3.0  # real time (and before the first session): an answer later than this is a lost server
LOCKSTEP_TIMEOUT_S = 120.0  # lockstep: the harness may pause between scans (module docstring)
REFUSED_PAUSE_S = 0.2  # between two polls while the server refuses this PLC the offered session


@dataclass(slots=True)
class _Session:
    number: int
    boot_id: int  # the harness process's boot id the session belongs to
    lockstep: bool
    description: LinkDescription
    register_map: RegisterMap
    plc: SoftPlc
    interface: ProcessImage
    plant: ProcessImage
    nc_to_plc: bytearray
    plc_to_nc: bytearray
    last_grant: int = 0
    life: int = 0
    # lockstep: the outputs of a scan whose write the link lost, (grant, registers), until they are sent
    unsent: tuple[int, list[int]] | None = None

    @property
    def areas(self) -> dict[str, bytearray]:
        return {**self.interface.areas, **self.plant.areas}


class RemotePlc:
    """One PLC process: ``run`` until stopped (``should_stop``) or the server goes away for good."""

    def __init__(self, client: ModbusLinkClient, program: str | None = None, period_s: float | None = None,
                 log: Callable[[str], None] = lambda text: None, answer_timeout_s: float | None = None,
                 key: int | None = None):
        self.client = client
        self.answer_timeout_s = answer_timeout_s
        self.program = program
        self.period_s = period_s
        self.log = log
        self.session: _Session | None = None
        self.scans = 0
        self._reconnected = False
        # the session key of this process's claims (docs/modbus.md): only this process (or, with the
        # harness's key file, a PLC given the same file) can take its session back after a lost connection
        self.key = key or secrets.randbits(64) or 1
        self._refused: tuple[int, int] | None = None  # (session, boot id) whose claim the server refused

    # ------------------------------------------------------------------ one poll
    def poll(self) -> bool:
        """Read the link block and do what it asks; True if a scan ran."""
        head = self.client.read_input_registers(0, self._poll_count())
        if head[LinkInput.VERSION] == 0:  # the harness has not powered a machine on yet
            wallclock.sleep(0.01)
            return False
        if head[LinkInput.VERSION] != LINK_VERSION:
            raise PlcSetupError(f"the server speaks link version {head[LinkInput.VERSION]}, this PLC {LINK_VERSION}")
        session = self.session
        offered = (head[LinkInput.SESSION], head[LinkInput.BOOT_ID])
        if session is None or (session.number, session.boot_id) != offered:
            if offered == self._refused:  # another PLC's session, or one closed: wait for a new one
                wallclock.sleep(REFUSED_PAUSE_S)
                return False
            # a new session of this harness, or a harness process started since (its sessions count from
            # 1 again): restart the program
            session = self._start_session(head)
            if session is None:
                return False
            head = self.client.read_input_registers(0, self._poll_count())
        elif self._reconnected:
            # the same session of the same harness process after a reconnect: the program carries on
            # with its state; the session is claimed again on this connection, with this process's key
            if not self._claim(session.number, session.boot_id):
                return False
            self.log(f"session {session.number} (boot id {session.boot_id}) goes on after the reconnect")
        self._reconnected = False
        if session.lockstep:
            grant = head[LinkInput.SCAN_GRANT]
            if session.unsent is not None and self._resend(session, grant):
                return True
            if grant == 0 or grant == session.last_grant:
                return False
            self._scan(session, head, grant)
            session.last_grant = grant
            return True
        session.life = session.life % 0xFFFF + 1
        self._scan(session, head, session.life)
        return True

    def _poll_count(self) -> int:
        if self.session is None:
            return LINK_REGISTERS
        return min(READ_LIMIT, self.session.register_map.registers(Table.NC_TO_PLC))

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

    def refused(self, error: RequestRefused) -> None:
        """A write of a scan was refused (the operator opened a new session meanwhile, or another PLC
        holds the session): the next poll reads the link block anew."""
        self.log(f"{error}; reading the link block anew")
        self.session = None

    def _start_session(self, head: list[int]) -> _Session | None:
        length = head[LinkInput.DESCRIPTION_BYTES]
        first = head[LinkInput.DESCRIPTION_START]
        text = registers_text(self.client.read_input_registers(first, math.ceil(length / 2)), length)
        description = LinkDescription.for_plc(text)
        environment, register_map, plc, name = description.start_program(FACTORIES, self.program)
        sizes = register_map.table_bytes
        lockstep = head[LinkInput.MODE] == MODE_LOCKSTEP
        self.client.timeout_s = self.answer_timeout_s or (LOCKSTEP_TIMEOUT_S if lockstep else TIMEOUT_S)
        self.session = _Session(
            head[LinkInput.SESSION], head[LinkInput.BOOT_ID], lockstep, description, register_map, plc,
            ProcessImage(environment.catalog.area_sizes), ProcessImage(environment.plant_io.area_sizes()),
            bytearray(sizes[Table.NC_TO_PLC]), bytearray(sizes[Table.PLC_TO_NC]))
        try:
            claimed = self._claim(head[LinkInput.SESSION], head[LinkInput.BOOT_ID])
        except LinkError:
            self.session = None  # never claimed: after the reconnect it starts again
            raise
        if not claimed:
            return None
        self.log(f"session {self.session.number} (boot id {self.session.boot_id}): machine {description.machine},"
                 f" program {name},"
                 f" {'lockstep' if self.session.lockstep else 'free-running'}")
        return self.session

    def _scan(self, session: _Session, head: list[int], done: int) -> None:
        """Inputs from the server, one scan, outputs and scan-done ``done`` to the server
        (``head``: the registers just read)."""
        total = session.register_map.registers(Table.NC_TO_PLC)
        registers = head[:total]
        if len(registers) < total:
            registers += self.client.read_input_registers(len(registers), total - len(registers))
        buffer = session.nc_to_plc
        buffer[:] = struct.pack(f">{len(registers)}H", *registers)
        areas = session.areas
        session.register_map.fill_areas(Table.NC_TO_PLC, buffer, areas)
        session.plc.scan(session.interface, session.plant)
        outputs = session.plc_to_nc
        session.register_map.fill_table(Table.PLC_TO_NC, areas, outputs)
        _WORD.pack_into(outputs, 2 * LinkHolding.SCAN_DONE, done)
        _WORD.pack_into(outputs, 2 * LinkHolding.SESSION_READY, session.number)
        # The whole table from register 0, the chunk with register 0 last: the scan-done word
        # reaches the server after every output of the scan.
        values = read_registers(outputs, 0, session.register_map.registers(Table.PLC_TO_NC))
        if session.lockstep:
            session.unsent = (done, values)  # until the write is through: a lost link must not run the scan twice
        self.client.write_registers_last_first(0, values)
        session.unsent = None
        self.scans += 1

    def _resend(self, session: _Session, grant: int) -> bool:
        """After a lost link: the outputs of the scan it lost go again while the harness still waits
        for that scan (True); once it granted another, it had taken them (False)."""
        assert session.unsent is not None
        unsent_grant, values = session.unsent
        session.last_grant = unsent_grant
        if grant != unsent_grant:
            session.unsent = None
            return False
        self.client.write_registers_last_first(0, values)
        session.unsent = None
        return True

    # ------------------------------------------------------------------ the loop (plc_stub.scan_loop)
    def run(self, should_stop: Callable[[], bool] = lambda: False) -> None:
        """Poll (lockstep) or scan on the clock (free-running) until ``should_stop``; a lost
        connection raises :class:`LinkError` to the caller, which may reconnect."""
        run_scans(self, self.period_s, should_stop)

    def free_running_period(self) -> float | None:
        session = self.session
        return None if session is None or session.lockstep else session.description.scan_time_s

    def follow(self) -> None:
        self.poll()

    def idle(self, seconds: float) -> None:
        wallclock.sleep(seconds)

    def scan(self) -> None:
        self.poll()

    def reconnected(self) -> None:
        """After a reconnect: the next poll reads the link block anew; the program restarts only when
        the session or the boot id changed (docs/modbus.md, reconnecting)."""
        self._reconnected = True


def run_forever(host: str, port: int, program: str | None, period_s: float | None, connect_timeout_s: float,
                log: Callable[[str], None], should_stop: Callable[[], bool] = lambda: False,
                answer_timeout_s: float | None = None, key: int | None = None) -> int:
    """Connect to the harness and run; the exit code of ``python -m plc_stub``.
    ``connect_timeout_s``: how long the first connection may take (the harness may start after the
    PLC).  A lost connection is made again within :data:`RECONNECT_WINDOW_S`: a harness that still
    runs takes it at once; one that has ended ends the PLC (exit code 1) instead of a retry for the
    whole connect time-out.  ``answer_timeout_s``: how long a request may go unanswered before the
    connection is made again (None: :data:`TIMEOUT_S` in real time, :data:`LOCKSTEP_TIMEOUT_S` in
    lockstep)."""
    client = ModbusLinkClient(host, port, timeout_s=answer_timeout_s or TIMEOUT_S)
    plc = RemotePlc(client, program, period_s, log, answer_timeout_s, key)

    def run() -> int:
        if not client.connect_within(connect_timeout_s, should_stop):
            if should_stop():
                return EXIT_STOPPED
            log(f"no Modbus server at {host}:{port} after {connect_timeout_s:g} s")
            return EXIT_NO_HARNESS
        log(f"connected to {host}:{port}")
        while not should_stop():
            try:
                plc.run(should_stop)
            except RequestRefused as error:
                plc.refused(error)
            except LinkError as error:
                client.close()
                plc.reconnected()
                window = min(RECONNECT_WINDOW_S, connect_timeout_s)
                if not client.connect_within(window, should_stop):
                    if should_stop():
                        break
                    log(f"the harness has gone: {error}, and no server has listened at {host}:{port} since"
                        f" ({window:g} s); stopping")
                    return EXIT_NO_HARNESS
                log(f"link lost: {error}; connected again")
        return EXIT_STOPPED

    try:
        return exit_code(run, log)
    finally:
        client.close()
