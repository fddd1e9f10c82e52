"""The built-in PLC in its own process, for ``vc run --link modbus``.

One Modbus server (loopback, ephemeral port) and one ``python -m plc_stub`` process serve the
whole run: every scenario powers its machine on, which opens a new session; the PLC restarts
its program for it, the program the scenario names.  Scenarios without a PLC (``plc: none``)
run in-process as always.
"""

from __future__ import annotations

import subprocess
import sys
from collections.abc import Callable
from types import TracebackType

from vc.harness.plc_link import Endpoint, LinkMode, PlcLink
from vc.harness.simulation import Simulation
from vc.scenario.model import Scenario


class PlcProcess:
    """A ``python -m plc_stub`` process connected to a link (lockstep unless told otherwise) on a
    loopback server with an ephemeral port; a context manager."""

    def __init__(self, mode: LinkMode = LinkMode.LOCKSTEP, first_scan_timeout_s: float = 30.0,
                 scan_timeout_s: float = 10.0):
        self.process: subprocess.Popen[bytes] | None = None
        self.link = PlcLink(mode, modbus=Endpoint("127.0.0.1", 0),
                            first_scan_timeout_s=first_scan_timeout_s, scan_timeout_s=scan_timeout_s,
                            peer_ended=self._ended)
        assert self.link.modbus is not None
        self.process = subprocess.Popen(
            [sys.executable, "-m", "plc_stub", "--modbus", f"127.0.0.1:{self.link.modbus.port}"],
            stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)

    def _ended(self) -> str | None:
        if self.process is None or self.process.poll() is None:
            return None
        message = (self.process.stderr.read() if self.process.stderr else b"").decode(errors="replace").strip()
        return f"the PLC process ended with code {self.process.returncode}" + (f": {message}" if message else "")

    def target_factory(self) -> Callable[[Scenario], Simulation]:
        def make(scenario: Scenario) -> Simulation:
            if scenario.plc_program is None:
                return Simulation(scenario.machine, None)
            return Simulation(scenario.machine, scenario.plc_program, connector=self.link)
        return make

    def close(self) -> None:
        if self.process is not None and self.process.poll() is None:
            self.process.terminate()
            try:
                self.process.wait(timeout=5)
            except subprocess.TimeoutExpired:
                self.process.kill()
                self.process.wait()
        if self.process is not None and self.process.stderr is not None:
            self.process.stderr.close()
        self.link.close()

    def __enter__(self) -> PlcProcess:
        return self

    def __exit__(self, kind: type[BaseException] | None, error: BaseException | None,
                 trace: TracebackType | None) -> None:
        self.close()
