"""The build guard: an extension runs only while the compiled build vouches for its source.

A small package ``vc`` is laid out in a temporary folder with one module both as source and as a
real extension (compiled here with the C compiler), beside a copy of ``vc_build``; a fresh
interpreter without site-packages imports it and says which one ran."""

from __future__ import annotations

import hashlib
import json
import os
import shutil
import subprocess
import sys
import sysconfig
from pathlib import Path

import pytest

import vc_build

EXTENSION_C = """
#include <Python.h>
static struct PyModuleDef module = {PyModuleDef_HEAD_INIT, "fast", NULL, -1, NULL};
PyMODINIT_FUNC PyInit_fast(void) {
    PyObject *m = PyModule_Create(&module);
    PyModule_AddStringConstant(m, "WHO", "compiled");
    return m;
}
"""
SOURCE = 'WHO = "source"\n'
PROBE = "import vc.fast, vc_build; print(vc.fast.WHO); print(vc_build.status().describe())"


@pytest.fixture
def tree(tmp_path: Path) -> Path:
    compiler = shutil.which("gcc") or shutil.which("cc")
    if compiler is None:
        if os.environ.get("VC_REQUIRE_GCC"):
            pytest.fail("no C compiler, and VC_REQUIRE_GCC is set")
        pytest.skip("no C compiler")
    shutil.copytree(Path(vc_build.__file__).parent, tmp_path / "vc_build",
                    ignore=shutil.ignore_patterns("compiled.json", "__pycache__"))
    package = tmp_path / "vc"
    package.mkdir()
    (package / "__init__.py").write_text("from vc_build import install\n\ninstall()\n")
    (package / "fast.py").write_text(SOURCE)
    (tmp_path / "fast.c").write_text(EXTENSION_C)
    suffix = sysconfig.get_config_var("EXT_SUFFIX")
    subprocess.run([compiler, "-shared", "-fPIC", f"-I{sysconfig.get_paths()['include']}", str(tmp_path / "fast.c"),
                    "-o", str(package / f"fast{suffix}")], check=True, timeout=120)
    _write_manifest(tmp_path, SOURCE)
    return tmp_path


def _write_manifest(tree: Path, source: str) -> None:
    digest = hashlib.sha256(source.encode()).hexdigest()
    (tree / "vc_build" / "compiled.json").write_text(json.dumps({"format": 1, "opt_level": "3",
                                                                   "modules": {"vc.fast": digest}}))


def _probe(tree: Path, **environment: str) -> list[str]:
    env = {"PATH": os.environ.get("PATH", ""), "PYTHONPATH": str(tree), **environment}
    done = subprocess.run([sys.executable, "-S", "-c", PROBE], env=env, cwd=tree, capture_output=True, text=True,
                          timeout=60, check=True)
    return done.stdout.splitlines()


def test_the_extension_runs_while_the_manifest_vouches_for_its_source(tree: Path) -> None:
    assert _probe(tree) == ["compiled", "compiled (1 modules, mypyc -O3)"]


def test_an_edited_source_runs_as_source_and_the_build_says_why(tree: Path) -> None:
    (tree / "vc" / "fast.py").write_text('WHO = "source"  # edited\n')
    who, build = _probe(tree)
    assert who == "source"
    assert build.startswith("pure Python (compiled build is stale: vc/fast.py changed since it was built")


def test_vc_pure_asks_for_the_source(tree: Path) -> None:
    assert _probe(tree, VC_PURE="1") == ["source", "pure Python (VC_PURE=1)"]


def test_an_extension_the_manifest_does_not_list_never_runs(tree: Path) -> None:
    (tree / "vc_build" / "compiled.json").unlink()  # a manifest lost: the pure build, and it says why
    assert _probe(tree) == ["source", "pure Python (no compiled build: vc_build/compiled.json is missing)"]


def test_the_pure_build_says_why_it_is_pure(tree: Path) -> None:
    # the manifest setup.py writes for VC_BUILD=pure pip install -e . over an older compiled build
    (tree / "vc_build" / "compiled.json").write_text(json.dumps({"format": 1, "modules": {},
                                                                   "pure": "installed with VC_BUILD=pure"}))
    assert _probe(tree) == ["source", "pure Python (installed with VC_BUILD=pure)"]


def test_an_unreadable_manifest_means_the_pure_build(tree: Path) -> None:
    (tree / "vc_build" / "compiled.json").write_text("{not json")
    who, build = _probe(tree)
    assert who == "source" and build.startswith("pure Python (unreadable compiled.json")


def test_this_installation_is_the_compiled_build_where_ci_asks_for_it_and_else_says_why_not() -> None:
    build = vc_build.status()
    if os.environ.get("VC_REQUIRE_COMPILED"):
        assert build.compiled, build.describe()
    else:  # a machine without a compiler installs the pure build; VC_PURE, VC_BUILD=pure ask for it
        assert build.compiled or build.reason, build.describe()
