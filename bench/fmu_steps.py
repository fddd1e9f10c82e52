"""The FMU benchmark without the console script: ``python bench/fmu_steps.py --seconds 20``.

``vc bench --link fmu`` with the given options (``--machine``, ``--seconds``; see
bench/README.md): a line per figure, then the figures as one JSON object on the last line.
Needs FMPy (the test extra).
"""

from __future__ import annotations

import sys
from collections.abc import Sequence

from vc.cli.main import main as vc


def main(argv: Sequence[str] | None = None) -> int:
    """The options of ``vc bench`` (one declaration of them, in vc/cli/main.py)."""
    return vc(["bench", "--link", "fmu", *(sys.argv[1:] if argv is None else argv)])


if __name__ == "__main__":
    sys.exit(main())
