"""The CAN link benchmarks without the command line: ``python bench/can_link.py --seconds 10``.

The same measurements and output as ``vc bench --link can`` (see bench/README.md): a line per
figure, then the figures as one JSON object on the last line.
"""

from __future__ import annotations

import argparse
import json
import sys
from collections.abc import Sequence

from vc.harness.can_benchmark import run_can_benchmark

DEFAULT_MACHINE = "scenarios/machines/turn_mill.yaml"


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description="Benchmarks of the CAN link (bench/README.md)")
    parser.add_argument("--machine", default=DEFAULT_MACHINE, help=f"machine YAML file (default {DEFAULT_MACHINE})")
    parser.add_argument("--seconds", type=float, default=10.0,
                        help="simulated seconds of the lockstep workload per bus (default 10)")
    parser.add_argument("--frames", type=int, default=20000,
                        help="frames of the throughput measurement per bus (default 20000)")
    arguments = parser.parse_args(argv)
    result = run_can_benchmark(arguments.machine, arguments.seconds, frames=arguments.frames,
                               say=lambda text: print(text, flush=True))
    print(json.dumps(result.figures()))
    return 0


# The guard matters beyond style: the UDP peer runs in a spawned process, which imports this
# file again under another name and must not start a benchmark of its own.
if __name__ == "__main__":
    sys.exit(main())
