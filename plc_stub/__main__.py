"""``python -m plc_stub --modbus HOST:PORT | --can BUS [--program NAME]``: the built-in PLC as its own process.

    --modbus HOST:PORT     the harness's Modbus TCP server (``vc serve`` or ``vc run --link modbus``)
    --can BUS              the CAN bus the harness is on (``vc run --link can``): udp_multicast[:GROUP:PORT],
                           socketcan[:INTERFACE] (interfaces/links/can_bus.py)
    --can-link-id ID       the harness's NC link frame identifier (default 0x100, the machine file's can.ids.link)
    --program NAME         the program to run (default: the one the harness asks for)
    --period MS            scan period in free-running mode (default: the machine's PLC period)
    --connect-timeout S    give up when no server answers (no harness is heard on the bus) for this long
                           (default 30 s); over Modbus a connection lost later is made again within 2 s,
                           else the harness has ended and so does the PLC
    --answer-timeout S     Modbus: wait this long for the answer to a request before the connection counts
                           as lost and is made again (default 3 s in real time, 120 s in lockstep)
    --key-file FILE        Modbus: claim sessions with the key in FILE (``vc serve --plc-key-file FILE``);
                           default: a random key of this process
    --cpu LIST             pin the PLC to these CPUs (interfaces/links/scheduling.py)
    --fifo PRIORITY        SCHED_FIFO real-time scheduling at PRIORITY 1..99 where permitted

Exit codes: 0 stopped (Ctrl-C), 1 no server (no bus, no harness heard), 2 the PLC cannot run what the
harness describes.
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Callable, Sequence
from typing import TypeVar

from interfaces.links.access import key_file
from interfaces.links.endpoint import parse_endpoint
from interfaces.links.errors import LinkError
from interfaces.links.scheduling import SchedulingError, parse_cpus, parse_priority, place
from plc_stub.links.can import run_on_can
from plc_stub.links.modbus import run_forever
from plc_stub.scan_loop import EXIT_CANNOT_RUN

T = TypeVar("T")


def _endpoint(text: str) -> tuple[str, int]:
    try:
        return parse_endpoint(text)
    except ValueError as error:
        raise argparse.ArgumentTypeError(str(error)) from None


def _identifier(text: str) -> int:
    try:
        number = int(text, 0)
    except ValueError:
        raise argparse.ArgumentTypeError(f"'{text}' is not a CAN identifier (e.g. 0x100)") from None
    if not 0 <= number <= 0x7FD:
        raise argparse.ArgumentTypeError(f"'{text}': the link frames need 0 .. 0x7FD")
    return number


def _scheduling(parse: Callable[[str], T]) -> Callable[[str], T]:
    def argument(text: str) -> T:
        try:
            return parse(text)
        except SchedulingError as error:
            raise argparse.ArgumentTypeError(str(error)) from None
    return argument


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m plc_stub",
                                     description="The built-in soft PLC as a Modbus TCP client or a node on a CAN bus")
    link = parser.add_mutually_exclusive_group(required=True)
    link.add_argument("--modbus", type=_endpoint, metavar="HOST:PORT")
    link.add_argument("--can", metavar="BUS", help="udp_multicast[:GROUP:PORT] or socketcan[:INTERFACE]")
    parser.add_argument("--can-link-id", type=_identifier, default=0x100, metavar="ID",
                        help="identifier of the NC link frame (default 0x100)")
    parser.add_argument("--program", help="PLC program (default: the one the harness asks for)")
    parser.add_argument("--period", type=float, metavar="MS", help="scan period in free-running mode, ms")
    parser.add_argument("--connect-timeout", type=float, default=30.0, metavar="S")
    parser.add_argument("--answer-timeout", type=float, default=None, metavar="S",
                        help="Modbus: seconds to wait for an answer before reconnecting (default 3 in real time,"
                             " 120 in lockstep)")
    parser.add_argument("--key-file", metavar="FILE",
                        help="Modbus: claim sessions with the key in FILE (vc serve --plc-key-file FILE)")
    parser.add_argument("--cpu", type=_scheduling(parse_cpus), metavar="LIST", help="pin the PLC to these CPUs")
    parser.add_argument("--fifo", type=_scheduling(parse_priority), metavar="PRIORITY",
                        help="SCHED_FIFO real-time scheduling at PRIORITY 1..99 where permitted")
    arguments = parser.parse_args(argv)
    period_s = arguments.period / 1000 if arguments.period else None

    def log(text: str) -> None:
        print(f"plc_stub: {text}", file=sys.stderr, flush=True)

    if arguments.cpu or arguments.fifo:
        log(f"scheduling: {place(arguments.cpu, arguments.fifo)}")
    try:
        if arguments.can is not None:
            return run_on_can(arguments.can, arguments.program, period_s, arguments.connect_timeout, log,
                              arguments.can_link_id)
        host, port = arguments.modbus
        return run_forever(host, port, arguments.program, period_s, arguments.connect_timeout, log,
                           answer_timeout_s=arguments.answer_timeout,
                           key=key_file(arguments.key_file) if arguments.key_file else None)
    except LinkError as error:  # the key file
        log(str(error))
        return EXIT_CANNOT_RUN
    except KeyboardInterrupt:
        return 0


if __name__ == "__main__":
    sys.exit(main())
