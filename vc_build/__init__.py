"""Which build of the harness runs, and the guard that never lets a stale compiled module run.

``setup.py`` compiles the hot modules with mypyc where it can and writes ``compiled.json`` beside
this file: the SHA-256 of each compiled module's source at build time.  Each of the packages
``vc``, ``plc_stub`` and ``interfaces`` calls :func:`install` first thing, which puts a finder
in front of Python's own.  For a module of those packages that Python would load from an
extension (``*.so``), the finder decides:

* the compiled build is *valid* (a manifest, every listed source unchanged, ``VC_PURE`` unset):
  the extension loads, as Python would have done anyway;
* otherwise, and for an extension the manifest does not list (left over from an older build),
  the module loads from its ``.py`` source.  All or none: compiled modules call each
  other directly in C, so one edited source makes every compiled module run from source.

So an editable checkout whose developer edits ``vc/core/axis/axis.py`` after ``pip install -e .``
runs the edited Python, and ``vc --version`` says why it is not the compiled build; reinstalling
compiles again.  ``VC_PURE=1`` asks for the pure build on purpose (the test suite runs the
scenario library in both).
"""

from __future__ import annotations

import hashlib
import importlib.abc
import importlib.machinery
import importlib.util
import json
import os
import sys
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from types import ModuleType

PACKAGES = ("vc", "plc_stub", "interfaces")
MANIFEST = Path(__file__).with_name("compiled.json")
PURE_VARIABLE = "VC_PURE"
_ROOT = Path(__file__).resolve().parent.parent  # where the packages are (site-packages or the checkout)


@dataclass(frozen=True, slots=True)
class BuildStatus:
    compiled: bool
    modules: int  # compiled modules in use (0 in the pure build)
    reason: str  # why the pure build runs; "" when compiled
    opt_level: str = ""
    names: frozenset[str] = frozenset()  # the compiled modules in use

    def describe(self) -> str:
        """``compiled (52 modules, mypyc -O3)``, ``pure Python (VC_PURE=1)``, ``pure Python (installed
        with VC_BUILD=pure)``: the pure build always says why."""
        if self.compiled:
            return f"compiled ({self.modules} modules, mypyc -O{self.opt_level})"
        return f"pure Python ({self.reason})"


def _source_of(module: str) -> Path:
    return _ROOT.joinpath(*module.split(".")).with_suffix(".py")


def _check() -> BuildStatus:
    if os.environ.get(PURE_VARIABLE, "") not in ("", "0"):
        return BuildStatus(False, 0, f"{PURE_VARIABLE}={os.environ[PURE_VARIABLE]}")
    try:
        manifest = json.loads(MANIFEST.read_text(encoding="utf-8"))
        modules: dict[str, str] = manifest["modules"]
        opt_level = str(manifest.get("opt_level", ""))
    except FileNotFoundError:
        return BuildStatus(False, 0, f"no compiled build: {MANIFEST.parent.name}/{MANIFEST.name} is missing")
    except (OSError, ValueError, KeyError, TypeError) as error:
        return BuildStatus(False, 0, f"unreadable {MANIFEST.name}: {error}")
    if not modules:  # the pure build's manifest says why (setup.py), e.g. "installed with VC_BUILD=pure"
        return BuildStatus(False, 0, str(manifest.get("pure", "")) or f"{MANIFEST.name} lists no compiled module")
    for module, digest in sorted(modules.items()):
        source = _source_of(module)
        try:
            current = hashlib.sha256(source.read_bytes()).hexdigest()
        except OSError:
            return BuildStatus(False, 0, f"compiled build is stale: {source.name} is missing")
        if current != digest:
            relative = source.relative_to(_ROOT)
            return BuildStatus(False, 0, f"compiled build is stale: {relative} changed since it was built;"
                                         " reinstall (pip install -e .) to compile again")
    return BuildStatus(True, len(modules), "", opt_level, frozenset(modules))


class _SourceWhenNotCompiled(importlib.abc.MetaPathFinder):
    """Loads the harness's modules from source wherever an extension would shadow a source that
    the compiled build does not vouch for."""

    def __init__(self, status: BuildStatus):
        self.status = status

    def find_spec(self, fullname: str, path: Sequence[str] | None,
                  target: ModuleType | None = None) -> importlib.machinery.ModuleSpec | None:
        if fullname in self.status.names or fullname.partition(".")[0] not in PACKAGES:
            return None
        spec = importlib.machinery.PathFinder.find_spec(fullname, path)
        if spec is None or not isinstance(spec.loader, importlib.machinery.ExtensionFileLoader):
            return spec
        source = Path(str(spec.origin)).parent / (fullname.rpartition(".")[2] + ".py")
        if not source.exists():
            return spec
        return importlib.util.spec_from_file_location(fullname, source)


_finder: _SourceWhenNotCompiled | None = None


def install() -> None:
    """Put the guard in front of Python's finders (once per process)."""
    global _finder  # the one piece of process state here: the import system is process-wide
    if _finder is None:
        _finder = _SourceWhenNotCompiled(_check())
        sys.meta_path.insert(0, _finder)


def status() -> BuildStatus:
    install()
    assert _finder is not None
    return _finder.status
