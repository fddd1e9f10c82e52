"""An awlsim hardware module that is the harness's Modbus TCP client (``vc serve --modbus``,
``vc run`` with an awlsim scenario).

awlsim calls ``readInputs`` before and ``writeOutputs`` after every OB 1; the module does the
link's work there, as docs/modbus.md ("Lockstep with a third-party PLC") states it::

    readInputs                                              writeOutputs
      link block: no machine yet -> poll again                (a scan was granted)
      new session -> description, HR 1 = session,               PLC-to-NC table = QB base ..
                     warm restart (OB 100, no OB 1)             HR 0 = the grant (lockstep) or
      lockstep: IR 3 grant new? -> NC-to-PLC table              the scan counter (real time),
                     into IB base .., clock = NC time           written last
      real time: at the next PLC period, likewise

* **Process image.** Table byte t of the NC-to-PLC table is input byte ``inputAddressBase + t``,
  table byte t of the PLC-to-NC table output byte ``outputAddressBase + t`` (the symbol tables
  of ``vc map --format awlsim`` and ``s7`` use the same view).  The link block is IB base + 0..31:
  IW 2 the session, ID 8 the NC cycle count; QW 0 and QW 2 (scan done, session ready) are the
  module's: what the program writes there is overwritten.
* **Warm restart** on every new session (a power-on of the machine, the next scenario): the
  process images, bit memory, timers and counters are cleared and OB 100 runs, as on an S7
  warm restart; data blocks keep their values.  The first session is the CPU's start-up.
* **Time.** The CPU's clock is the NC's (:mod:`plc_awlsim.clock`), in both modes.
* **Real time.** A scan every PLC period of the wall clock (input registers 6 and 7); the
  scan counter in HR 0 is the sign of life the NC watches.

A lost connection is made again within a short window (a harness that still runs takes it at
once) and the session that follows restarts the program; when no server listens any more the
harness has ended and so does the PLC (:class:`HarnessGone`).  ``connectTimeout`` is how long the
first connection may take.  Parameters (awlsim's hardware module parameters): ``host`` (127.0.0.1), ``port``
(5020), ``connectTimeout`` (30 s), ``keyFile`` (the session key of ``vc serve --plc-key-file``; default a
random key of this process) and awlsim's own ``inputAddressBase``, ``outputAddressBase``.
"""

from __future__ import annotations

import secrets
import struct
import time as wallclock
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any, ClassVar

from interfaces.codec_modbus import (
    LINK_REGISTERS,
    LINK_VERSION,
    MODE_LOCKSTEP,
    READ_LIMIT,
    LinkHolding,
    LinkInput,
    registers_text,
    session_key_registers,
)
from interfaces.errors import VcError
from interfaces.links.access import key_file
from interfaces.links.errors import LinkError, RequestRefused
from interfaces.links.modbus_tcp import RECONNECT_WINDOW_S, ModbusLinkClient
from plc_awlsim.awlsim_api import (
    AbstractHardwareInterface,
    AwlSimError,
    HwParamDesc_float,
    HwParamDesc_int,
    HwParamDesc_str,
    MaintenanceRequest,
)
from plc_awlsim.clock import NcClock, follow_nc

_WORD = struct.Struct(">H")
POLL_PAUSE_S = 0.01  # between polls while no machine is powered on


class HarnessGone(VcError):
    """No harness answered within the connect time-out, or the harness has ended.

    Not an awlsim error: awlsim reports the errors of hardware modules and runs its next cycle, so
    the bridge would retry for ever; this one ends ``AwlSim.runCycle`` and the PLC process."""


@dataclass(slots=True)
class Session:
    """What the harness said at a power-on."""

    number: int
    lockstep: bool
    nc_to_plc_bytes: int
    plc_to_nc_bytes: int
    ipo_cycle_us: int
    plc_cycle_ipo: int
    description: bytes  # the interface description (UTF-8 JSON, interfaces/link_description.py)

    @property
    def scan_time_s(self) -> float:
        return self.ipo_cycle_us * self.plc_cycle_ipo / 1_000_000


class HardwareInterface(AbstractHardwareInterface):  # type: ignore[misc]  # awlsim is not annotated
    name = "vcmodbus"
    description = "The VC harness's NC and machine over its Modbus TCP link (lockstep or real time)"
    paramDescs: ClassVar[list[Any]] = [
        HwParamDesc_str("host", defaultValue="127.0.0.1", description="the harness's Modbus server"),
        HwParamDesc_int("port", defaultValue=5020, minValue=1, maxValue=65535, description="its port"),
        HwParamDesc_float("connectTimeout", defaultValue=30.0, minValue=0.1,
                          description="seconds to wait for the harness before giving up"),
        HwParamDesc_str("keyFile", defaultValue="",
                        description="claim sessions with the key in this file (vc serve --plc-key-file)"),
    ]

    def __init__(self, sim: Any, parameters: dict[str, Any] | None = None):
        super().__init__(sim=sim, parameters=parameters or {})
        self.host: str = self.getParamValueByName("host")
        self.port: int = self.getParamValueByName("port")
        self.connect_timeout_s: float = self.getParamValueByName("connectTimeout")
        self.clock = NcClock()
        self.client: ModbusLinkClient | None = None
        self.session: Session | None = None
        self.scans = 0  # OB 1 scans run in this session
        self._granted: int | None = None  # the scan-done value of the scan between readInputs and writeOutputs
        self._last_grant = 0
        self._next_scan = 0.0
        self._restart_due = False  # a session began: the next readInputs restarts the program
        self._starting = False  # the CPU's start-up: its readInputs before OB 100 takes no scan
        # the session key of this bridge's claims (docs/modbus.md): after a lost connection only this
        # process can take its session back
        path = self.getParamValueByName("keyFile")
        self.key = key_file(path) if path else secrets.randbits(64) or 1
        self.log: Callable[[str], None] = lambda text: None  # python -m plc_awlsim sets its own

    # ------------------------------------------------------------------ awlsim's calls
    def doStartup(self) -> None:
        if self.client is None:
            follow_nc(self.cpu, self.clock)
            self.client = ModbusLinkClient(self.host, self.port)
            self._connect()
            self.wait_for_session()
        self._restart_due = False  # the CPU's start-up runs OB 100 now ...
        self._starting = True  # ... after a readInputs that must not take a granted scan

    def doShutdown(self) -> None:
        if self.client is not None:
            self.client.close()
            self.client = None

    def readInputs(self) -> None:
        """Wait until a scan may run and put the NC-to-PLC table into the input image (module docstring)."""
        if self._starting:
            self._starting = False
            return
        while True:
            session = self.session
            if self._restart_due or session is None:
                self.wait_for_session()
                self._warm_restart()
            assert session is not None
            head = self._read(0, min(READ_LIMIT, session.nc_to_plc_bytes // 2))
            if head[LinkInput.VERSION] == 0 or head[LinkInput.SESSION] != session.number:
                self._restart_due = True
                continue
            if session.lockstep:
                grant = head[LinkInput.SCAN_GRANT]
                if grant == 0 or grant == self._last_grant:
                    continue
                self._last_grant = grant
                self._take_inputs(session, head, grant)
                return
            now = wallclock.perf_counter()
            if now < self._next_scan:
                wallclock.sleep(self._next_scan - now)
                continue
            self._next_scan = max(self._next_scan + session.scan_time_s, now - session.scan_time_s)
            self._take_inputs(session, head, (self.scans % 0xFFFF) + 1)
            return

    def writeOutputs(self) -> None:
        """The output image into the PLC-to-NC table, the scan-done word last (module docstring)."""
        session, done = self.session, self._granted
        if session is None or done is None or self.client is None:
            return  # OB 100: no scan was granted
        outputs = bytearray(self.cpu.fetchOutputRange(self.outputAddressBase, session.plc_to_nc_bytes))
        _WORD.pack_into(outputs, 2 * LinkHolding.SCAN_DONE, done)
        _WORD.pack_into(outputs, 2 * LinkHolding.SESSION_READY, session.number)
        values = list(struct.unpack(f">{len(outputs) // 2}H", outputs))
        try:
            self.client.write_registers_last_first(0, values)
        except LinkError:
            self._restart_due = True  # readInputs reconnects
        self._granted = None

    # ------------------------------------------------------------------ the link
    def wait_for_session(self) -> Session:
        """Poll until the harness has powered a machine on; claim its session (HR 1 = session, HR 2..5
        = the key).  A session whose claim the server refuses (another PLC holds it, or it was closed
        when its PLC was lost) is passed by: the bridge waits for a new one."""
        refused: tuple[int, int] | None = None
        while True:
            head = self._read(0, LINK_REGISTERS)
            if head[LinkInput.VERSION] == 0 or (head[LinkInput.SESSION], head[LinkInput.BOOT_ID]) == refused:
                wallclock.sleep(POLL_PAUSE_S)
                continue
            if head[LinkInput.VERSION] != LINK_VERSION:
                raise AwlSimError(f"the harness speaks link version {head[LinkInput.VERSION]},"
                                  f" this bridge {LINK_VERSION}")
            length = head[LinkInput.DESCRIPTION_BYTES]
            description = registers_text(self._read(head[LinkInput.DESCRIPTION_START], (length + 1) // 2), length)
            self.session = Session(head[LinkInput.SESSION], head[LinkInput.MODE] == MODE_LOCKSTEP,
                                   2 * head[LinkInput.NC_TO_PLC_REGISTERS], 2 * head[LinkInput.PLC_TO_NC_REGISTERS],
                                   head[LinkInput.IPO_CYCLE_US], head[LinkInput.PLC_CYCLE_IPO], description)
            self._fit_process_images(self.session)
            try:
                self._write(LinkHolding.SESSION_READY, [self.session.number, *session_key_registers(self.key)])
            except RequestRefused:
                refused = (head[LinkInput.SESSION], head[LinkInput.BOOT_ID])
                self.log(f"session {refused[0]}: the server refused this PLC's claim (another PLC holds the session,"
                         " or it was closed when its PLC was lost); waiting for a new session")
                continue
            self._last_grant = 0
            self.scans = 0
            self._next_scan = wallclock.perf_counter()
            return self.session

    def _take_inputs(self, session: Session, head: list[int], done: int) -> None:
        total = session.nc_to_plc_bytes // 2
        registers = head[:total] + (self._read(len(head), total - len(head)) if len(head) < total else [])
        self.cpu.storeInputRange(self.inputAddressBase, bytearray(struct.pack(f">{total}H", *registers)))
        self.clock.set_cycles(registers[LinkInput.NC_CYCLE_HIGH] << 16 | registers[LinkInput.NC_CYCLE_HIGH + 1],
                              registers[LinkInput.IPO_CYCLE_US])
        self.scans += 1
        self._granted = done

    def _warm_restart(self) -> None:
        """A new session: clear the process images, bit memory, timers and counters, then OB 100
        (awlsim runs the start-up OBs on this request and skips the OB 1 of this cycle)."""
        self._restart_due = False
        self._granted = None
        self.clock.set_cycles(0, 1)
        self.cpu.reallocate(force=True)
        raise MaintenanceRequest(MaintenanceRequest.TYPE_SOFTREBOOT, "new session: warm restart")

    def _fit_process_images(self, session: Session) -> None:
        specs = self.cpu.getSpecs()
        if specs.nrInputs < self.inputAddressBase + session.nc_to_plc_bytes:
            specs.setNrInputs(self.inputAddressBase + session.nc_to_plc_bytes)
        if specs.nrOutputs < self.outputAddressBase + session.plc_to_nc_bytes:
            specs.setNrOutputs(self.outputAddressBase + session.plc_to_nc_bytes)

    def _read(self, address: int, count: int) -> list[int]:
        while True:
            try:
                assert self.client is not None
                return self.client.read_input_registers(address, count)
            except RequestRefused:
                raise  # an answer: the link stands
            except LinkError as error:
                self._reconnect(error)

    def _write(self, address: int, values: list[int]) -> None:
        while True:
            try:
                assert self.client is not None
                self.client.write_registers(address, values)
                return
            except RequestRefused:
                raise  # an answer: the link stands
            except LinkError as error:
                self._reconnect(error)

    def _reconnect(self, error: LinkError) -> None:
        """After a lost connection: connect again within :data:`RECONNECT_WINDOW_S` (a harness that
        still runs takes it at once); the next session restarts the program.  No server: the
        harness has ended (:class:`HarnessGone`)."""
        assert self.client is not None
        self.client.close()
        self._restart_due = True
        window = min(RECONNECT_WINDOW_S, self.connect_timeout_s)
        if not self.client.connect_within(window):
            raise HarnessGone(f"the harness has gone: {error}, and no server has listened at {self.host}:{self.port}"
                              f" since ({window:g} s)")

    def _connect(self) -> None:
        assert self.client is not None
        if not self.client.connect_within(self.connect_timeout_s):
            raise HarnessGone(f"no Modbus server at {self.host}:{self.port} after {self.connect_timeout_s:g} s")
