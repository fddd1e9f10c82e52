"""The FMU benchmark without the command line: ``python bench/fmu_steps.py --seconds 20``.

The same measurement and output as ``vc bench --link fmu`` (see bench/README.md): a line per
figure, then the figures as one JSON object on the last line.  Needs FMPy (the test extra).
"""

from __future__ import annotations

import argparse
import json
import sys
from collections.abc import Sequence

from vc.harness.fmu_benchmark import run_fmu_benchmark

DEFAULT_MACHINE = "scenarios/machines/turn_mill.yaml"


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description="FMU steps per second under FMPy against in process"
                                                 " (bench/README.md)")
    parser.add_argument("--machine", default=DEFAULT_MACHINE, help=f"machine YAML file (default {DEFAULT_MACHINE})")
    parser.add_argument("--seconds", type=float, default=20.0,
                        help="simulated seconds per workload (default 20)")
    arguments = parser.parse_args(argv)
    result = run_fmu_benchmark(arguments.machine, arguments.seconds, say=lambda text: print(text, flush=True))
    print(json.dumps(result.figures()))
    return 0


if __name__ == "__main__":
    sys.exit(main())
