"""The CAN link benchmarks without the console script: ``python bench/can_link.py --seconds 10``.

``vc bench --link can`` with the given options (``--machine``, ``--seconds``, ``--frames``; see
bench/README.md): a line per figure, then the figures as one JSON object on the last line.
"""

from __future__ import annotations

import sys
from collections.abc import Sequence

from vc.cli.main import main as vc


def main(argv: Sequence[str] | None = None) -> int:
    """The options of ``vc bench`` (one declaration of them, in vc/cli/main.py)."""
    return vc(["bench", "--link", "can", *(sys.argv[1:] if argv is None else argv)])


# The guard matters beyond style: the UDP peer runs in a spawned process, which imports this
# file again under another name and must not start a benchmark of its own.
if __name__ == "__main__":
    sys.exit(main())
