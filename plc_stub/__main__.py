"""``python -m plc_stub --modbus HOST:PORT [--program NAME]``: the built-in PLC as its own process.

    --modbus HOST:PORT     the harness's Modbus TCP server (``vc serve`` or ``vc run --link modbus``)
    --program NAME         the program to run (default: the one the harness asks for)
    --period MS            scan period in free-running mode (default: the machine's PLC period)
    --connect-timeout S    give up when no server answers for this long (default 30 s)

Exit codes: 0 stopped (Ctrl-C), 1 no server, 2 the PLC cannot run what the server describes.
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Sequence

from plc_stub.remote import run_forever


def _endpoint(text: str) -> tuple[str, int]:
    host, _, port = text.rpartition(":")
    try:
        number = int(port)
    except ValueError:
        raise argparse.ArgumentTypeError(f"'{text}' is not HOST:PORT (e.g. 127.0.0.1:5020)") from None
    if not 0 < number < 65536:
        raise argparse.ArgumentTypeError(f"'{text}': port {number} is outside 1..65535")
    return host or "127.0.0.1", number


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m plc_stub",
                                     description="The built-in soft PLC as a Modbus TCP client")
    parser.add_argument("--modbus", type=_endpoint, required=True, metavar="HOST:PORT")
    parser.add_argument("--program", help="PLC program (default: the one the harness asks for)")
    parser.add_argument("--period", type=float, metavar="MS", help="scan period in free-running mode, ms")
    parser.add_argument("--connect-timeout", type=float, default=30.0, metavar="S")
    arguments = parser.parse_args(argv)
    host, port = arguments.modbus

    def log(text: str) -> None:
        print(f"plc_stub: {text}", file=sys.stderr, flush=True)

    try:
        return run_forever(host, port, arguments.program, arguments.period / 1000 if arguments.period else None,
                           arguments.connect_timeout, log)
    except KeyboardInterrupt:
        return 0


if __name__ == "__main__":
    sys.exit(main())
