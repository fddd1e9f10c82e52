"""PLCs in their own process: the built-in PLC for ``vc run --link modbus`` and ``vc run --link can``,
and the external PLCs of scenarios (``plc: awlsim:PROGRAM.awl``) in every run.

One link and one ``python -m plc_stub`` process serve the whole run: every scenario powers its
machine on, which opens a new session; the PLC restarts its program for it, the program the
scenario names.  Over Modbus the link is a server on loopback with an ephemeral port; over CAN a
bus (by default a UDP multicast channel of its own on this host) that carries each machine's
``can:`` settings.  Scenarios without a PLC (``plc: none``) run in-process as always; scenarios
that ask for a CAN link run over a virtual bus in this process when the run's link is not CAN.

An external PLC (:class:`ExternalPlcs`) gets a lockstep Modbus link of its own on an ephemeral
loopback port and a process of its own per scenario (``python -m plc_awlsim --modbus HOST:PORT
PROGRAM`` for awlsim): a fresh PLC for every scenario, so that its trace does not depend on the
scenarios run before it; a power cycle within the scenario is a new session, a warm restart of
that PLC.
"""

from __future__ import annotations

import subprocess
import sys
from abc import ABC, abstractmethod
from collections.abc import Callable, Sequence
from types import TracebackType
from typing import Generic, Self, TypeVar

from interfaces.links.can.bus import BusSpec, private_udp_bus
from vc.config.model import MachineConfig
from vc.harness.links import Link, LinkMode
from vc.harness.links.can import CanLink
from vc.harness.links.modbus import Endpoint, PlcLink
from vc.harness.targets import simulation_for
from vc.scenario.language.model import Scenario
from vc.simulation.lockstep import Pacer, Simulation

# plc: KIND:FILE -> the module run as ``python -m MODULE --modbus HOST:PORT FILE``
EXTERNAL_PLC_MODULES = {"awlsim": "plc_awlsim"}


class _PlcChild:
    """A ``python -m MODULE`` process (plc_stub by default); its standard error tells why it ended."""

    def __init__(self, arguments: Sequence[str], module: str = "plc_stub"):
        self.process = subprocess.Popen([sys.executable, "-m", module, *arguments],
                                        stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)

    def ended(self) -> str | None:
        if self.process.poll() is None:
            return None
        message = (self.process.stderr.read() if self.process.stderr else b"").decode(errors="replace").strip()
        return f"the PLC process ended with code {self.process.returncode}" + (f": {message}" if message else "")

    def close(self) -> None:
        if self.process.poll() is None:
            self.process.terminate()
            try:
                self.process.wait(timeout=5)
            except subprocess.TimeoutExpired:
                self.process.kill()
                self.process.wait()
        if self.process.stderr is not None:
            self.process.stderr.close()


LinkType = TypeVar("LinkType", bound=Link)


class ChildPlcRun(ABC, Generic[LinkType]):
    """A PLC in a child process over a link of one technology: what every technology shares is the
    link, the child process, its end and the context manager; each gives the targets of its run."""

    link: LinkType
    _child: _PlcChild | None = None

    @property
    def process(self) -> subprocess.Popen[bytes] | None:
        """The PLC process (None before the first power-on of a CAN run)."""
        return None if self._child is None else self._child.process

    def _ended(self) -> str | None:
        return None if self._child is None else self._child.ended()

    def _close_child(self) -> None:
        if self._child is not None:
            self._child.close()
            self._child = None

    @abstractmethod
    def target_factory(self) -> Callable[[Scenario], Simulation]:
        """The run's targets: the scenarios with a PLC program over the link, the others in-process."""

    def close(self) -> None:
        self._close_child()
        self.link.close()

    def __enter__(self) -> Self:
        return self

    def __exit__(self, kind: type[BaseException] | None, error: BaseException | None,
                 trace: TracebackType | None) -> None:
        self.close()


class PlcProcess(ChildPlcRun[PlcLink]):
    """A ``python -m plc_stub`` process (or ``module`` with ``arguments`` after the endpoint) connected
    to a Modbus TCP link (lockstep unless told otherwise) on a loopback server with an ephemeral
    port; a context manager."""

    def __init__(self, mode: LinkMode = LinkMode.LOCKSTEP, first_scan_timeout_s: float = 30.0,
                 scan_timeout_s: float = 10.0, module: str = "plc_stub", arguments: Sequence[str] = (),
                 s7: Endpoint | None = None):
        """``s7``: serve the data blocks over S7 as well (``vc serve --s7``); ``arguments``: more
        options of ``python -m plc_stub`` (or of ``module``)."""
        self.link = PlcLink(mode, modbus=Endpoint("127.0.0.1", 0), s7=s7,
                            first_scan_timeout_s=first_scan_timeout_s, scan_timeout_s=scan_timeout_s,
                            peer_ended=self._ended)
        assert self.link.modbus is not None
        self._child = _PlcChild(["--modbus", f"127.0.0.1:{self.link.modbus.port}", *arguments], module=module)

    @classmethod
    def for_run(cls, address: str | None) -> PlcProcess:
        """``vc run --link modbus`` (its row in interfaces/links/__init__.py): the server on an ephemeral
        loopback port, whatever ``address`` says."""
        return cls()

    def target_factory(self) -> Callable[[Scenario], Simulation]:
        def make(scenario: Scenario) -> Simulation:
            if scenario.plc_program is None or scenario.link is not None:
                return simulation_for(scenario)
            return Simulation(scenario.machine, scenario.plc_program, connector=self.link)
        return make


class CanPlcProcess(ChildPlcRun[CanLink]):
    """A ``python -m plc_stub --can`` process on a CAN bus with the harness (lockstep unless told
    otherwise); by default a UDP multicast channel no other run on this host uses.  The process is
    started at the first power-on, and again for a machine whose link frames have other identifiers."""

    def __init__(self, mode: LinkMode = LinkMode.LOCKSTEP, first_scan_timeout_s: float = 30.0,
                 scan_timeout_s: float = 10.0, bus: BusSpec | None = None):
        self.bus = bus or private_udp_bus()
        self.link = CanLink(mode, self.bus, first_scan_timeout_s=first_scan_timeout_s,
                            scan_timeout_s=scan_timeout_s, peer_ended=self._ended)
        self._link_id: int | None = None

    @classmethod
    def for_run(cls, address: str | None) -> CanPlcProcess:
        """``vc run --link can`` (its row in interfaces/links/__init__.py): on the bus ``address`` (``vc run
        --can-bus``), by default a UDP multicast channel of the run's own."""
        return cls(bus=BusSpec.parse(address) if address else None)

    def simulation(self, machine: MachineConfig, program: str, pacer: Pacer | None = None) -> Simulation:
        """A power-on of ``machine`` (with its ``can:`` settings) and ``program`` in the process, over
        the bus; the process starts now if it does not run for these link identifiers."""
        self.link.configure_for(machine)
        link_id = self.link.config.settings.link_id
        if self._child is None or link_id != self._link_id:
            self._close_child()
            self._child = _PlcChild(["--can", str(self.bus), "--can-link-id", hex(link_id)])
            self._link_id = link_id
        return Simulation(machine, program, connector=self.link, pacer=pacer)

    def target_factory(self) -> Callable[[Scenario], Simulation]:
        def make(scenario: Scenario) -> Simulation:
            if scenario.plc_program is None:
                return simulation_for(scenario)
            return self.simulation(scenario.machine, scenario.plc_program)
        return make


class ExternalPlcs:
    """The external PLCs of a run's scenarios (module docstring): ``wrap`` a target factory, and
    each scenario with ``plc: KIND:FILE`` runs against its own PLC process over its own link;
    the others go to the wrapped factory.  A context manager: the last PLC ends with it."""

    def __init__(self, first_scan_timeout_s: float = 60.0, scan_timeout_s: float = 10.0):
        self.first_scan_timeout_s = first_scan_timeout_s
        self.scan_timeout_s = scan_timeout_s
        self.runs = 0  # external PLC processes started
        self._current: PlcProcess | None = None

    def wrap(self, make: Callable[[Scenario], Simulation]) -> Callable[[Scenario], Simulation]:
        def target(scenario: Scenario) -> Simulation:
            external = scenario.external_plc
            if external is None:
                return make(scenario)
            self.close()
            kind, program = external
            self._current = PlcProcess(LinkMode.LOCKSTEP, self.first_scan_timeout_s, self.scan_timeout_s,
                                       module=EXTERNAL_PLC_MODULES[kind], arguments=[program])
            self.runs += 1
            return Simulation(scenario.machine, scenario.plc, connector=self._current.link)
        return target

    def close(self) -> None:
        if self._current is not None:
            self._current.close()
            self._current = None

    def __enter__(self) -> Self:
        return self

    def __exit__(self, kind: type[BaseException] | None, error: BaseException | None,
                 trace: TracebackType | None) -> None:
        self.close()
