"""Test modules of different folders run together: each conftest.py of the suite is imported as the
module ``conftest`` (pytest's prepend import mode, no packages), so a test that imported from it by
name would get whichever folder's conftest came last (``cannot import name 'TURN_MILL' from
'conftest'``).  Shared helpers live in modules of their own name (core_rig, fmu_machines, ...)."""

from __future__ import annotations

import ast
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
TESTS = ROOT / "tests"


def test_no_test_module_imports_a_conftest_by_name() -> None:
    offenders = []
    for path in sorted(TESTS.rglob("*.py")):
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            names = [node.module] if isinstance(node, ast.ImportFrom) else \
                [alias.name for alias in node.names] if isinstance(node, ast.Import) else []
            if "conftest" in names:
                offenders.append(f"{path.relative_to(ROOT)}:{node.lineno}")
    assert not offenders, offenders


@pytest.mark.parametrize("order", ["forward", "reversed"])
def test_a_module_of_each_conftest_folder_collects_together(order: str) -> None:
    """The CI-like command: the test modules of every folder with a conftest.py (those beside it, or
    the first one below it), in one pytest run."""
    modules = []
    for conftest in sorted(TESTS.rglob("conftest.py")):
        beside = sorted(conftest.parent.glob("test_*.py")) or sorted(conftest.parent.rglob("test_*.py"))[:1]
        modules += [str(path.relative_to(ROOT)) for path in beside]
    assert len(modules) >= 3
    if order == "reversed":
        modules.reverse()
    done = subprocess.run([sys.executable, "-m", "pytest", "--collect-only", "-q", "-n", "0", "-p", "no:cacheprovider",
                           *modules], cwd=ROOT, capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stdout[-3000:] + done.stderr[-2000:]
