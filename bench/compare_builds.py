"""The pure-Python and the compiled build side by side: ``python bench/compare_builds.py``.

``vc bench`` (both workloads) and ``vc run scenarios/ -j 1`` / ``-j 2`` in each build, in
alternating rounds (``--runs``, default 3), then a table of the medians with the machine (CPU,
cores, Python) and, as the last line, the medians as one JSON object.  Run it from the
checkout after ``pip install -e .`` compiled the build (vc --version says so); see
bench/README.md and vc/bench/builds.py.
"""

from __future__ import annotations

import sys

from vc.bench.builds import main

if __name__ == "__main__":
    sys.exit(main())
