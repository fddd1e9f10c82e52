"""The compiled and the pure build give the same results: the whole library, run once in each
(``VC_PURE=1`` asks for the pure one), passes with the golden traces, and every CSV and VCD trace
is the same to the byte."""

from __future__ import annotations

import filecmp
import os
import subprocess
import sys
from pathlib import Path

import pytest

import vc_build

ROOT = Path(__file__).resolve().parents[2]


def _run_library(trace_dir: Path, **environment: str) -> subprocess.CompletedProcess[str]:
    env = {**os.environ, **environment}
    return subprocess.run([sys.executable, "-m", "vc.cli.main", "run", "scenarios", "-j", "2", "--golden",
                           "tests/golden", "--trace-dir", str(trace_dir)], cwd=ROOT, env=env,
                          capture_output=True, text=True, timeout=1200)


@pytest.mark.timeout(1300)
def test_the_pure_and_the_compiled_build_give_the_same_traces_byte_for_byte(tmp_path: Path) -> None:
    if not vc_build.status().compiled:
        if os.environ.get("VC_REQUIRE_COMPILED"):
            pytest.fail(f"the compiled build does not run here: {vc_build.status().describe()}")
        pytest.skip(f"no compiled build to compare with: {vc_build.status().describe()}")
    compiled, pure = tmp_path / "compiled", tmp_path / "pure"
    compiled_run = _run_library(compiled)
    pure_run = _run_library(pure, VC_PURE="1")
    assert compiled_run.returncode == 0, compiled_run.stdout[-4000:]
    assert pure_run.returncode == 0, pure_run.stdout[-4000:]
    assert "compiled (" in compiled_run.stdout.splitlines()[0]
    assert "pure Python (VC_PURE=1)" in pure_run.stdout.splitlines()[0]
    names = sorted(path.name for path in compiled.iterdir())
    assert names == sorted(path.name for path in pure.iterdir())
    assert len(names) >= 2 * 240  # a CSV and a VCD per scenario
    _, differing, errors = filecmp.cmpfiles(compiled, pure, names, shallow=False)
    assert not differing and not errors, f"traces differ between the builds: {differing[:10]}"
