"""``python -m plc_stub --modbus HOST:PORT | --can BUS [--program NAME]``: the built-in PLC as its own process.

One option per link of the registry (interfaces/links/__init__.py), which runs the PLC's end of that link.

    --modbus HOST:PORT     the harness's Modbus TCP server (``vc serve`` or ``vc run --link modbus``)
    --can BUS              the CAN bus the harness is on (``vc run --link can``): udp_multicast[:GROUP:PORT],
                           socketcan[:INTERFACE] (interfaces/links/can/bus.py)
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

from interfaces.links import LINKS, load
from interfaces.links.errors import BadAddress, LinkError
from interfaces.links.modbus.access import key_file
from interfaces.links.scan_loop import EXIT_CANNOT_RUN, PlcEndRunner, PlcProcessOptions
from interfaces.links.scheduling import SchedulingError, parse_cpus, parse_priority, place
from plc_stub.programs import FACTORIES

T = TypeVar("T")


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
                                     description="The built-in soft PLC as the PLC's end of a link to the harness")
    link = parser.add_mutually_exclusive_group(required=True)
    for kind in LINKS.values():
        link.add_argument(f"--{kind.name}", metavar=kind.address, help=kind.address_help)
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
    name, address = next((name, getattr(arguments, name)) for name in LINKS if getattr(arguments, name) is not None)

    def log(text: str) -> None:
        print(f"plc_stub: {text}", file=sys.stderr, flush=True)

    if arguments.cpu or arguments.fifo:
        log(f"scheduling: {place(arguments.cpu, arguments.fifo)}")
    try:
        options = PlcProcessOptions(
            program=arguments.program, period_s=arguments.period / 1000 if arguments.period else None,
            connect_timeout_s=arguments.connect_timeout, answer_timeout_s=arguments.answer_timeout,
            key=key_file(arguments.key_file) if arguments.key_file else None, link_id=arguments.can_link_id)
        run: PlcEndRunner = load(LINKS[name].plc_end)
        return run(address, FACTORIES, options, log)
    except BadAddress as error:
        parser.error(f"argument --{name}: {error}")
    except LinkError as error:  # the key file
        log(str(error))
        return EXIT_CANNOT_RUN
    except KeyboardInterrupt:
        return 0


if __name__ == "__main__":
    sys.exit(main())
