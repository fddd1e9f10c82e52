"""An awlsim hardware module that is the harness's Modbus TCP client (``vc serve --modbus``,
``vc run`` with an awlsim scenario).

awlsim calls ``readInputs`` before and ``writeOutputs`` after every OB 1; there the module drives
the PLC's end of the link that ``python -m plc_stub`` drives as well
(:class:`~interfaces.links.modbus.plc_end.ModbusPlcEnd`: session, claim with the key, grant,
scan done), as docs/modbus.md ("Lockstep with a third-party PLC") states it::

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
once) and the session that follows restarts the program (the CPU's state of the lost scan is not
kept); when no server listens any more the harness has ended and so does the PLC
(:class:`~interfaces.links.modbus.plc_end.HarnessGone`).  ``connectTimeout`` is how long the
first connection may take.  Parameters (awlsim's hardware module parameters): ``host`` (127.0.0.1), ``port``
(5020), ``connectTimeout`` (30 s), ``keyFile`` (the session key of ``vc serve --plc-key-file``; default a
random key of this process) and awlsim's own ``inputAddressBase``, ``outputAddressBase``.
"""

from __future__ import annotations

import struct
import time as wallclock
from collections.abc import Callable
from typing import Any, ClassVar

from interfaces.links.errors import LinkError, RequestRefused
from interfaces.links.modbus.access import key_file
from interfaces.links.modbus.client import ModbusLinkClient
from interfaces.links.modbus.codec import LinkInput
from interfaces.links.modbus.plc_end import ModbusPlcEnd, Scan, Session
from plc_awlsim.awlsim_api import (
    AbstractHardwareInterface,
    HwParamDesc_float,
    HwParamDesc_int,
    HwParamDesc_str,
    MaintenanceRequest,
)
from plc_awlsim.clock import NcClock, follow_nc


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
        self.end: ModbusPlcEnd | None = None
        self.scans = 0  # OB 1 scans run in this session
        self._granted: Scan | None = None  # the scan between readInputs and writeOutputs
        self._pending: Scan | None = None  # a scan granted with a new session: it runs after the warm restart
        self._restarted_for: Session | None = None  # the session the program was (re)started for
        self._next_scan = 0.0
        self._starting = False  # the CPU's start-up: its readInputs before OB 100 takes no scan
        # the session key of this bridge's claims (docs/modbus.md): after a lost connection only this
        # process can take its session back
        path = self.getParamValueByName("keyFile")
        self.key = key_file(path) if path else None
        self.log: Callable[[str], None] = lambda text: None  # python -m plc_awlsim sets its own

    @property
    def session(self) -> Session | None:
        """The session the program runs for."""
        return self._restarted_for

    # ------------------------------------------------------------------ awlsim's calls
    def doStartup(self) -> None:
        if self.end is None:
            follow_nc(self.cpu, self.clock)
            self.end = ModbusPlcEnd(ModbusLinkClient(self.host, self.port), self._fit_process_images,
                                    log=self.log, key=self.key)
            self.end.connect(self.connect_timeout_s)
            self._restart_for(self._link(self.end.wait_for_session))
        self._starting = True  # the CPU's start-up runs OB 100 now, after a readInputs that takes no scan

    def doShutdown(self) -> None:
        if self.end is not None:
            self.end.client.close()
            self.end = None

    def readInputs(self) -> None:
        """Wait until a scan may run and put the NC-to-PLC table into the input image (module docstring)."""
        if self._starting:
            self._starting = False
            return
        end = self.end
        assert end is not None
        while True:
            scan, self._pending = self._pending, None
            if scan is None:
                self._pace()
                scan = self._link(end.poll)
            if end.session is not self._restarted_for:
                self._pending = scan
                self._warm_restart()
            if scan is not None:
                self._take_inputs(scan)
                return

    def writeOutputs(self) -> None:
        """The output image into the PLC-to-NC table, the scan-done word last (module docstring)."""
        end, scan = self.end, self._granted
        if end is None or scan is None or end.session is None:
            return  # OB 100: no scan was granted
        outputs = bytearray(self.cpu.fetchOutputRange(self.outputAddressBase, 2 * end.session.plc_to_nc_registers))
        self._granted = None
        try:
            end.finish(scan, outputs)
        except RequestRefused as error:
            end.refused(error)
        except LinkError as error:
            self._reconnect(error)

    # ------------------------------------------------------------------ the link
    def _link(self, request: Callable[[], Any]) -> Any:
        """``request`` of the PLC's end; a lost connection is made again (:meth:`_reconnect`) and the
        request repeated, a refused write makes the end read the link block anew."""
        end = self.end
        assert end is not None
        while True:
            try:
                return request()
            except RequestRefused as error:
                end.refused(error)
            except LinkError as error:
                self._reconnect(error)

    def _reconnect(self, error: LinkError) -> None:
        """After a lost connection: a new one within the reconnect window; the next session restarts the
        program.  No server: the harness has ended (:class:`HarnessGone`)."""
        assert self.end is not None
        self.end.reconnect(error, self.connect_timeout_s)
        self.end.forget_session()

    def _pace(self) -> None:
        """Real time: a scan every PLC period of the wall clock (lockstep: the harness's grant paces)."""
        session = self.end.session if self.end is not None else None
        if session is None or session.lockstep:
            return
        now = wallclock.perf_counter()
        if now < self._next_scan:
            wallclock.sleep(self._next_scan - now)
            now = wallclock.perf_counter()
        self._next_scan = max(self._next_scan + session.scan_time_s, now - session.scan_time_s)

    def _take_inputs(self, scan: Scan) -> None:
        registers = scan.inputs
        self.cpu.storeInputRange(self.inputAddressBase, bytearray(struct.pack(f">{len(registers)}H", *registers)))
        self.clock.set_cycles(registers[LinkInput.NC_CYCLE_HIGH] << 16 | registers[LinkInput.NC_CYCLE_HIGH + 1],
                              registers[LinkInput.IPO_CYCLE_US])
        self.scans += 1
        self._granted = scan

    def _restart_for(self, session: Session | None) -> None:
        self._restarted_for = session
        self.scans = 0
        self._next_scan = wallclock.perf_counter()

    def _warm_restart(self) -> None:
        """A new session: clear the process images, bit memory, timers and counters, then OB 100
        (awlsim runs the start-up OBs on this request and skips the OB 1 of this cycle)."""
        assert self.end is not None
        self._restart_for(self._link(self.end.wait_for_session))
        self._granted = None
        self.clock.set_cycles(0, 1)
        self.cpu.reallocate(force=True)
        raise MaintenanceRequest(MaintenanceRequest.TYPE_SOFTREBOOT, "new session: warm restart")

    def _fit_process_images(self, session: Session) -> None:
        """The PLC's start of a session (before its claim): process images that hold both tables."""
        specs = self.cpu.getSpecs()
        nc_to_plc, plc_to_nc = 2 * session.nc_to_plc_registers, 2 * session.plc_to_nc_registers
        if specs.nrInputs < self.inputAddressBase + nc_to_plc:
            specs.setNrInputs(self.inputAddressBase + nc_to_plc)
        if specs.nrOutputs < self.outputAddressBase + plc_to_nc:
            specs.setNrOutputs(self.outputAddressBase + plc_to_nc)
