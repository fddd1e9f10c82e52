"""The built-in programs as a PLC on a CAN bus (``python -m plc_stub --can BUS``).

The node (:mod:`interfaces.links.can_plc`) configures itself from the harness's description and
follows its mode: in lockstep it handles frames as they come and scans on every grant; free-running
it scans every PLC period of the wall clock (or ``period_s``) and handles frames in between.  A new
session (the harness powered the machine on again) restarts the program.  The PLC gives up when
no harness has been heard for ``idle_timeout_s``.
"""

from __future__ import annotations

import time as wallclock
from collections.abc import Callable

from interfaces.codec_can import DEFAULT_LINK_ID
from interfaces.links.can_bus import BusSpec, CanBus
from interfaces.links.can_plc import CanPlcNode, PlcSetupError
from interfaces.links.errors import LinkError
from plc_stub.programs import REGISTRY

POLL_S = 0.1


def run_on_can(bus_text: str, program: str | None, period_s: float | None, idle_timeout_s: float,
               log: Callable[[str], None], link_id: int = DEFAULT_LINK_ID,
               should_stop: Callable[[], bool] = lambda: False) -> int:
    """Run until stopped; the exit code of ``python -m plc_stub --can``: 0 stopped, 1 no bus or no
    harness heard, 2 the PLC cannot run what the harness describes."""
    try:
        bus = CanBus(BusSpec.parse(bus_text))
    except LinkError as error:
        log(str(error))
        return 1
    node = CanPlcNode(bus, REGISTRY, link_id=link_id, program=program, log=log)
    log(f"listening on the CAN bus {bus.spec}, link frames from 0x{link_id:03X}")
    heard = wallclock.monotonic()
    next_scan = wallclock.perf_counter()
    try:
        while not should_stop():
            received = bus.received
            session = node.session
            if session is None or not node.free_running:
                node.service(POLL_S)
            else:
                now = wallclock.perf_counter()
                if now < next_scan:
                    node.service(next_scan - now)
                else:
                    period = period_s or session.description.scan_time_s
                    next_scan = max(next_scan + period, now - period)
                    node.scan()
            if bus.received != received:
                heard = wallclock.monotonic()
            elif wallclock.monotonic() - heard > idle_timeout_s:
                log(f"no harness heard on {bus.spec} for {idle_timeout_s:g} s")
                return 1
    except PlcSetupError as error:
        log(f"cannot run: {error}")
        return 2
    except LinkError as error:
        log(f"bus lost: {error}")
        return 1
    finally:
        bus.close()
    return 0
