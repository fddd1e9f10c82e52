"""``python -m plc_awlsim --modbus HOST:PORT PROGRAM.awl [--symbols FILE] [--io-base N] [--mnemonics en|de]``

    PROGRAM.awl          the STL program (OB 1, OB 100, FCs, FBs, DBs as an awlsim source)
    --modbus HOST:PORT   the harness's Modbus TCP server (``vc serve``; ``vc run`` starts this itself)
    --symbols FILE       the symbol table (awlsim .csv or STEP 7 .asc; default: the machine's, as
                         ``vc map --format awlsim`` gives it)
    --io-base N          table byte t is IB / QB N + t (default 0)
    --mnemonics en|de    English (I, Q, A, SD) or German (E, A, U, SE) mnemonics (default en)
    --key-file FILE      claim sessions with the key in FILE (``vc serve --plc-key-file FILE``)
    --connect-timeout S  give up when no harness answers for this long (default 30 s); a connection
                         lost later is made again within 2 s, else the harness has ended and so does
                         the PLC (exit code 1)

Exit codes: 0 stopped (Ctrl-C), 1 no harness, 2 the program or its symbols cannot run.
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Sequence
from pathlib import Path

from interfaces.links.endpoint import parse_endpoint
from interfaces.links.errors import LinkError
from interfaces.links.modbus.access import key_file


def _endpoint(text: str) -> tuple[str, int]:
    try:
        return parse_endpoint(text)
    except ValueError as error:
        raise argparse.ArgumentTypeError(str(error)) from None


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m plc_awlsim",
                                     description="An STL program in awlsim as the harness's PLC over Modbus TCP")
    parser.add_argument("program", type=Path, help="the STL program (.awl)")
    parser.add_argument("--modbus", type=_endpoint, default=("127.0.0.1", 5020), metavar="HOST:PORT")
    parser.add_argument("--symbols", type=Path, metavar="FILE")
    parser.add_argument("--io-base", type=int, default=0, metavar="N")
    parser.add_argument("--mnemonics", choices=("en", "de"), default="en")
    parser.add_argument("--connect-timeout", type=float, default=30.0, metavar="S")
    parser.add_argument("--key-file", metavar="FILE", help="claim sessions with the key in FILE"
                        " (vc serve --plc-key-file FILE)")
    arguments = parser.parse_args(argv)

    def log(text: str) -> None:
        print(f"plc_awlsim: {text}", file=sys.stderr, flush=True)

    try:
        from plc_awlsim.runner import run
    except ImportError as error:
        log(f"awlsim is not installed ({error}): pip install 'vc-harness[awlsim]'")
        return 2
    host, port = arguments.modbus
    if arguments.key_file:
        try:
            key_file(arguments.key_file)  # made now when missing; a bad one is a problem before anything runs
        except LinkError as error:
            log(str(error))
            return 2
    try:
        return run(host, port, arguments.program, arguments.symbols, arguments.io_base, arguments.mnemonics,
                   arguments.connect_timeout, log, arguments.key_file)
    except KeyboardInterrupt:
        return 0


if __name__ == "__main__":
    sys.exit(main())
