"""The loop of a PLC in its own process, whatever carries the interface (Modbus TCP, CAN).

The transport says whether a session runs on the PLC's own clock; while none does (no session
yet, or lockstep) the loop lets the transport follow the harness, which grants each scan.
Free-running, it scans every period of the wall clock and gives the time in between to the
transport (to sleep, or to take frames as they arrive).  A scan that comes late does not make
the next ones hurry: the clock never runs more than one period behind.
"""

from __future__ import annotations

import time as wallclock
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import Protocol

from interfaces.links.description import PlcSetupError
from interfaces.plc import PlcFactory

EXIT_STOPPED = 0  # python -m plc_stub: stopped (Ctrl-C)
EXIT_NO_HARNESS = 1  # no server, no bus, or no harness heard
EXIT_CANNOT_RUN = 2  # the PLC cannot run what the harness describes


@dataclass(frozen=True, slots=True)
class PlcProcessOptions:
    """How ``python -m plc_stub`` runs on a link; each technology reads what concerns it."""

    program: str | None = None  # None: the one the harness asks for
    period_s: float | None = None  # free-running: instead of the machine's PLC period
    connect_timeout_s: float = 30.0
    answer_timeout_s: float | None = None  # Modbus: None, by mode (interfaces/links/modbus/plc_end.py)
    key: int | None = None  # Modbus: the session key; None, a random one of this process
    link_id: int | None = None  # CAN: the NC link frame's identifier; None, the default


class PlcEndRunner(Protocol):
    """A technology's PLC process (``plc_end`` of its row in interfaces/links/__init__.py)."""

    def __call__(self, address: str, programs: Mapping[str, PlcFactory], options: PlcProcessOptions,
                 log: Callable[[str], None], should_stop: Callable[[], bool] = ...) -> int:
        """Run soft PLC ``programs`` on the link at ``address`` until stopped; the exit code of
        ``python -m plc_stub``.  An address of the wrong form is
        :class:`~interfaces.links.errors.BadAddress` before anything runs (or, where
        only opening it tells, exit code 1)."""


class PlcTransport(Protocol):
    def free_running_period(self) -> float | None:
        """Seconds between two scans of a session on the PLC's own clock; None: no such session."""

    def follow(self) -> None:
        """No free-running session: do what the harness asks (start a session, run a granted scan),
        waiting a little for it."""

    def idle(self, seconds: float) -> None:
        """Free-running: spend at most ``seconds`` until the next scan."""

    def scan(self) -> None:
        """Free-running: one scan."""


def run_scans(transport: PlcTransport, period_s: float | None, should_stop: Callable[[], bool]) -> None:
    """Follow the harness or scan on the clock (``period_s``: instead of the session's) until
    ``should_stop``; errors of the transport go to the caller."""
    next_scan = wallclock.perf_counter()
    while not should_stop():
        period = transport.free_running_period()
        if period is None:
            transport.follow()
            continue
        now = wallclock.perf_counter()
        if now < next_scan:
            transport.idle(next_scan - now)
            continue
        period = period_s or period
        next_scan = max(next_scan + period, now - period)
        transport.scan()


def exit_code(run: Callable[[], int], log: Callable[[str], None]) -> int:
    """``run``'s exit code, or :data:`EXIT_CANNOT_RUN` when the PLC cannot run what the harness describes."""
    try:
        return run()
    except PlcSetupError as error:
        log(f"cannot run: {error}")
        return EXIT_CANNOT_RUN
