"""The Modbus TCP link benchmarks without the command line: ``python bench/modbus_link.py --seconds 60``.

The same measurements and output as ``vc bench --link modbus`` (see bench/README.md): a line
per figure, then the figures as one JSON object on the last line.
"""

from __future__ import annotations

import argparse
import json
import sys
from collections.abc import Sequence

from vc.harness.link_benchmark import run_link_benchmark

DEFAULT_MACHINE = "scenarios/machines/turn_mill.yaml"


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description="Benchmarks of the Modbus TCP link (bench/README.md)")
    parser.add_argument("--machine", default=DEFAULT_MACHINE, help=f"machine YAML file (default {DEFAULT_MACHINE})")
    parser.add_argument("--seconds", type=float, default=60.0, help="wall seconds of real-time pacing (default 60)")
    parser.add_argument("--lockstep-seconds", type=float, default=10.0,
                        help="simulated seconds of the lockstep run (default 10)")
    parser.add_argument("--exchanges", type=int, default=2000,
                        help="full interface exchanges per server, in 10 rounds (default 2000)")
    arguments = parser.parse_args(argv)
    result = run_link_benchmark(arguments.machine, realtime_seconds=arguments.seconds,
                                lockstep_seconds=arguments.lockstep_seconds, exchanges=arguments.exchanges,
                                say=lambda text: print(text, flush=True))
    print(json.dumps(result.figures()))
    return 0


# The guard matters beyond style: the servers run in spawned processes, which import this
# file again under another name and must not start a benchmark of their own.
if __name__ == "__main__":
    sys.exit(main())
