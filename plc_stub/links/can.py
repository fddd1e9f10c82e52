"""The built-in programs as a PLC on a CAN bus (``python -m plc_stub --can BUS``).

The node (:mod:`interfaces.links.can_plc`) configures itself from the harness's description and
follows its mode (the loop of :mod:`plc_stub.scan_loop`): in lockstep it handles frames as they
come and scans on every grant; free-running it scans every PLC period of the wall clock (or
``period_s``) and handles frames in between.  A new session (the harness powered the machine
on again) restarts the program.  The PLC gives up when no harness has been heard for
``idle_timeout_s``.
"""

from __future__ import annotations

import time as wallclock
from collections.abc import Callable

from interfaces.codec_can import DEFAULT_LINK_ID
from interfaces.links.can_bus import BusSpec, CanBus
from interfaces.links.can_plc import CanPlcNode
from interfaces.links.errors import LinkError
from plc_stub.programs import FACTORIES
from plc_stub.scan_loop import EXIT_NO_HARNESS, EXIT_STOPPED, exit_code, run_scans

POLL_S = 0.1


class _Silent(LinkError):
    """No harness heard on the bus for the idle time-out."""


class _CanTransport:
    """The node on its bus as :func:`~plc_stub.scan_loop.run_scans` drives it; gives up (:class:`_Silent`)
    when no harness has been heard for ``idle_timeout_s``."""

    def __init__(self, node: CanPlcNode, bus: CanBus, idle_timeout_s: float):
        self.node = node
        self.bus = bus
        self.idle_timeout_s = idle_timeout_s
        self._heard_at = wallclock.monotonic()
        self._received = bus.received

    def free_running_period(self) -> float | None:
        session = self.node.session
        return session.description.scan_time_s if session is not None and self.node.free_running else None

    def follow(self) -> None:
        self.idle(POLL_S)

    def idle(self, seconds: float) -> None:
        self.node.service(seconds)
        if self.bus.received != self._received:
            self._received, self._heard_at = self.bus.received, wallclock.monotonic()
        elif wallclock.monotonic() - self._heard_at > self.idle_timeout_s:
            raise _Silent(f"no harness heard on {self.bus.spec} for {self.idle_timeout_s:g} s")

    def scan(self) -> None:
        self.node.scan()


def run_on_can(bus_text: str, program: str | None, period_s: float | None, idle_timeout_s: float,
               log: Callable[[str], None], link_id: int = DEFAULT_LINK_ID,
               should_stop: Callable[[], bool] = lambda: False) -> int:
    """Run until stopped; the exit code of ``python -m plc_stub --can``: 0 stopped, 1 no bus or no
    harness heard, 2 the PLC cannot run what the harness describes."""
    try:
        bus = CanBus(BusSpec.parse(bus_text))
    except LinkError as error:
        log(str(error))
        return EXIT_NO_HARNESS
    node = CanPlcNode(bus, FACTORIES, link_id=link_id, program=program, log=log)
    log(f"listening on the CAN bus {bus.spec}, link frames from 0x{link_id:03X}")

    def run() -> int:
        try:
            run_scans(_CanTransport(node, bus, idle_timeout_s), period_s, should_stop)
        except _Silent as silent:
            log(str(silent))
            return EXIT_NO_HARNESS
        except LinkError as error:
            log(f"bus lost: {error}")
            return EXIT_NO_HARNESS
        return EXIT_STOPPED

    try:
        return exit_code(run, log)
    finally:
        bus.close()
