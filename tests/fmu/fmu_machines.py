"""What the FMU tests share besides their fixtures: the repository and the machine they export.

A module of its own name, imported as ``from fmu_machines import ...`` (pytest's prepend import
mode puts tests/fmu on ``sys.path``), never ``from conftest import ...``: every conftest.py of the
suite is the module ``conftest``, and the one imported last would answer.
"""

from __future__ import annotations

from pathlib import Path

REPOSITORY = Path(__file__).resolve().parents[2]
TURN_MILL = str(REPOSITORY / "scenarios" / "machines" / "turn_mill.yaml")
