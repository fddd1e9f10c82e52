"""The file part of the robustness campaign: ``python bench/robustness_files.py --count 2000 --seed 1``.

Mutated scenario and machine files through ``vc run`` (code and the list of mutations in
vc/bench/robustness/files.py; bench/README.md).  Prints every bad outcome, then a table of the
figures and, as its last line, the figures as one JSON object.  Exit code 1 if any outcome was bad.

Other campaigns call :func:`run_file_mutations` (``count``, ``seed``, ``say``) and get the figures.
"""

from __future__ import annotations

import sys

from vc.bench.robustness.files import main, run_file_mutations, table

__all__ = ["run_file_mutations", "table"]

if __name__ == "__main__":
    sys.exit(main())
