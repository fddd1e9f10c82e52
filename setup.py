"""The build: the hot modules of the harness compiled with mypyc, or the pure-Python package; and
the self-contained FMU's binary.

Metadata lives in pyproject.toml; this file only adds the compiled parts.

* The FMU's binary (fmu/native, C11) is built as ``fmu/_vc_fmi*.so`` wherever a C compiler is
  found, in either build: it is no Python extension (it never links libpython and is never
  imported), it only travels with the package; ``vc fmu export`` copies it into each FMU.
  Without a compiler the installation still succeeds and the export says what is missing.

* Which modules: what runs every IPO cycle, chosen by profile (``COMPILED`` below): the NC core,
  the plant, the soft PLC's runtime and programs, and the pure interface modules.  The simulation loop
  (vc/simulation/lockstep.py) stays Python: it checks PLC objects against runtime-checkable protocols,
  which compiled code cannot do, and costs a handful of calls per cycle.  Everything else
  (loaders, CLI, links, reports) stays Python: it runs once per scenario or waits on sockets.
* When: on ``pip install`` (editable or not) where a C compiler, the Python headers and mypyc are
  found.  Otherwise, or with ``VC_BUILD=pure``, the package installs as pure Python.  Either way
  the build says what it does in one line (``announce``) before it starts: pip hides a build's
  output until it fails (``-q`` or not), and compiling takes a minute or more.
* Never stale: the build writes ``vc_build/compiled.json``, the SHA-256 of every compiled
  module's source (the pure build writes there why it is pure, so ``vc --version`` can say it).
  At import ``vc_build`` compares them with the sources beside the extensions;
  if one differs (a developer edited a file after ``pip install -e .``), every compiled module
  is loaded from its source instead, all or none, because compiled modules call each other
  directly and must never be mixed with edited ones.  ``vc --version`` tells which build runs.
  ``pip install -e .`` again with unchanged sources (the same manifest) reuses the extensions in
  the checkout instead of compiling them again.
* Each build owns its manifest: a wheel or a non-editable install (``pip wheel .``, ``pip install
  .``) writes it into the build only; the checkout's manifest belongs to the editable install, and
  only an editable build removes or rewrites it.
"""

from __future__ import annotations

import hashlib
import json
import os
import shutil
import sys
import sysconfig
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path
from typing import Any

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext
from setuptools.command.build_py import build_py

ROOT = Path(__file__).resolve().parent
MANIFEST = Path("vc_build") / "compiled.json"
COMPILED_PACKAGES = ("vc", "plc_stub", "interfaces")  # where compiled modules live (fmu/ holds the FMU binary)
GROUP = "vc_harness"  # the shared library: vc_harness__mypyc.*.so
OPT_LEVEL = os.environ.get("VC_MYPYC_OPT_LEVEL", "3")
# the setup.py commands that build code; pip's metadata steps run setup.py too, and mypyc's type
# check and C generation (about 15 s) is not needed there
BUILDING = {"build", "build_ext", "bdist_wheel", "editable_wheel", "develop", "install"}

# What runs every IPO cycle.  interfaces/plc.py stays Python: its protocols are runtime-checkable
# (isinstance on a PLC object), which compiled classes cannot be.
COMPILED = (
    "vc/core/**/*.py",
    "vc/plant/*.py",
    "vc/config/machine_data.py",  # read dozens of times per IPO cycle by the spindles and couplings
    "plc_stub/runtime.py",
    "plc_stub/io.py",
    "plc_stub/blocks.py",
    "plc_stub/programs/*.py",
    "interfaces/address.py",
    "interfaces/bit_access.py",
    "interfaces/image.py",
    "interfaces/plant_io.py",
    "interfaces/exchange.py",
    "interfaces/signal_groups.py",  # the NC's inputs subclass these dataclasses: native bases for native classes
)


NATIVE = "fmu/native"
FMU_BINARY = [Extension(
    "fmu._vc_fmi",
    sources=[f"{NATIVE}/worker_link.c", f"{NATIVE}/fmi2.c", f"{NATIVE}/fmi3.c"],
    include_dirs=[NATIVE, f"{NATIVE}/include"],
    # only the FMI functions are exported (FMI2_Export / FMI3_Export); glibc 2.17 is the floor
    extra_compile_args=["-std=c11", "-fvisibility=hidden", "-Wall", "-Wextra", "-Werror"],
    optional=True,
)] if sys.platform.startswith("linux") else []


def compiled_sources() -> list[str]:
    found = {str(path.relative_to(ROOT)) for pattern in COMPILED for path in ROOT.glob(pattern)}
    return sorted(path for path in found if not path.endswith("__init__.py"))


def module_name(source: str) -> str:
    return source[: -len(".py")].replace("/", ".")


def source_digest(path: Path) -> str:
    return hashlib.sha256(path.read_bytes()).hexdigest()


def pure_manifest_text(reason: str) -> str:
    """The manifest of the pure build: no compiled module, and why (``vc --version`` shows it)."""
    why = f"installed with {reason}" if reason.startswith("VC_BUILD=") else f"not compiled at install: {reason}"
    return json.dumps({"format": 1, "modules": {}, "pure": why}, indent=1, sort_keys=True) + "\n"


def manifest_text(sources: list[str]) -> str:
    from mypy.version import __version__ as mypy_version

    modules = {module_name(source): source_digest(ROOT / source) for source in sources}
    return json.dumps({"format": 1, "group": GROUP, "opt_level": OPT_LEVEL, "mypyc": mypy_version,
                       "python": sysconfig.get_config_var("EXT_SUFFIX"), "modules": modules},
                      indent=1, sort_keys=True) + "\n"


def announce(line: str) -> None:
    """One line for whoever runs the install, on their terminal: pip captures the build's standard
    output and error and shows them only when the build fails or with ``-v``, so a build that
    compiles for a minute would otherwise look hung under ``pip install -q``.  Without a terminal
    (CI, a pipe, a detached session) the line goes to standard error, where ``pip -v`` shows it."""
    try:
        with open("/dev/tty", "w", encoding="utf-8") as terminal:
            terminal.write(line + "\n")
        return
    except OSError:
        pass
    print(line, file=sys.stderr)


def why_not_compiled() -> str | None:
    """None when this machine can compile; otherwise the reason, in words."""
    if os.environ.get("VC_BUILD", "").lower() == "pure":
        return "VC_BUILD=pure"
    if sys.implementation.name != "cpython":
        return f"{sys.implementation.name} is not CPython"
    compiler = (sysconfig.get_config_var("CC") or "cc").split()[0]
    if shutil.which(compiler) is None:
        return f"no C compiler ({compiler}) found"
    include = sysconfig.get_paths().get("include", "")
    if not (Path(include) / "Python.h").exists():
        return f"no Python headers (Python.h) in {include}"
    try:
        import mypyc.build  # noqa: F401
    except ImportError:
        return "mypyc is not installed"
    return None


class ParallelBuildExt(build_ext):
    """build_ext that compiles one extension's C files on every core: mypyc's shared library is
    one extension of many files, which distutils would compile one after the other."""

    def build_extension(self, ext: Any) -> None:
        compiler = self.compiler
        serial_compile = compiler.compile

        def parallel_compile(sources: list[str], *args: Any, **kwargs: Any) -> list[str]:
            if len(sources) < 2:
                return list(serial_compile(sources, *args, **kwargs))
            with ThreadPoolExecutor(max_workers=os.cpu_count() or 1) as pool:
                parts = pool.map(lambda source: serial_compile([source], *args, **kwargs), sources)
                return [obj for part in parts for obj in part]

        compiler.compile = parallel_compile
        try:
            super().build_extension(ext)
        finally:
            compiler.compile = serial_compile


class ReuseInPlaceBuildExt(ParallelBuildExt):
    """build_ext that takes the compiled modules already in the checkout (reusable_in_place said
    they belong to these sources) and builds only the rest (the FMU's binary)."""

    def build_extension(self, ext: Any) -> None:
        if ext.sources:
            super().build_extension(ext)
            return
        target = Path(self.get_ext_fullpath(ext.name))
        target.parent.mkdir(parents=True, exist_ok=True)
        source = ROOT / self.get_ext_filename(ext.name)
        if source.resolve() != target.resolve():
            shutil.copyfile(source, target)


def manifest_command(base: type[Any], text: str) -> type[Any]:
    """``base`` that also writes the manifest ``text`` into the build (and, for an editable
    install, beside the sources).  The text is taken before mypyc reads the sources, so a file
    edited during the build makes the build stale rather than vouched for."""

    class WithManifest(base):  # type: ignore[misc, valid-type]
        def run(self) -> None:
            super().run()
            targets = [Path(self.build_lib) / MANIFEST] if getattr(self, "build_lib", None) else []
            if getattr(self, "inplace", False) or getattr(self, "editable_mode", False):
                targets.append(ROOT / MANIFEST)
            for target in targets:
                target.parent.mkdir(parents=True, exist_ok=True)
                target.write_text(text, encoding="utf-8")

    return WithManifest


def builds_in_place() -> bool:
    """An editable install (PEP 660 ``editable_wheel``, the older ``develop``) or ``build_ext
    --inplace``: the build whose extensions and manifest live in the checkout itself."""
    arguments = sys.argv[1:]
    return bool({"editable_wheel", "develop"}.intersection(arguments)) or (
        "build_ext" in arguments and ("--inplace" in arguments or "-i" in arguments))


def reusable_in_place(text: str) -> bool:
    """An editable install whose checkout already holds the extensions of exactly these sources
    (the manifest beside them says so): ``pip install -e .`` again need not compile again."""
    if not builds_in_place():
        return False
    manifest = ROOT / MANIFEST
    if not manifest.exists() or manifest.read_text(encoding="utf-8") != text:
        return False
    suffix = sysconfig.get_config_var("EXT_SUFFIX") or ".so"
    modules = json.loads(text)["modules"]
    return (ROOT / f"{GROUP}__mypyc{suffix}").exists() and all(
        (ROOT / (module.replace(".", "/") + suffix)).exists() for module in modules)


def remove_stale_extensions(modules: set[str]) -> None:
    """An editable checkout keeps the compiled module shims beside the sources: remove those of
    modules this build does not compile (a module moved or renamed since the last build), so that
    no extension stands where no source is and nothing finds a module that no longer exists."""
    if not builds_in_place():
        return
    suffix = sysconfig.get_config_var("EXT_SUFFIX") or ".so"
    for package in COMPILED_PACKAGES:
        for shim in (ROOT / package).rglob(f"*{suffix}"):
            module = ".".join(shim.relative_to(ROOT).with_name(shim.name[: -len(suffix)]).parts)
            if module not in modules:
                shim.unlink()


def build() -> None:
    reason = why_not_compiled()
    building = bool(BUILDING.intersection(sys.argv[1:]))  # not a metadata step (egg_info, dist_info)
    if building:
        remove_stale_extensions(set() if reason is not None else set(map(module_name, compiled_sources())))
    if reason is not None:
        if building and builds_in_place():
            (ROOT / MANIFEST).unlink(missing_ok=True)  # until it is written anew: it vouches for no extension
        if building:
            announce(f"vc-harness: installing the pure-Python build ({reason})")
        pure = pure_manifest_text(reason)
        setup(ext_modules=FMU_BINARY, cmdclass={"build_py": manifest_command(build_py, pure)})
        return
    if not building:  # metadata only: no C needed
        setup(ext_modules=FMU_BINARY)
        return
    sources = compiled_sources()
    text = manifest_text(sources)
    if reusable_in_place(text):
        announce("vc-harness: the compiled modules in the checkout match their sources: not compiled again")
        reused = [Extension(name, sources=[]) for name in (f"{GROUP}__mypyc", *map(module_name, sources))]
        setup(ext_modules=[*FMU_BINARY, *reused],
              cmdclass={"build_ext": manifest_command(ReuseInPlaceBuildExt, text)})
        return
    if builds_in_place():
        # an earlier editable build's: written anew when this one ends (a wheel's is in its build only)
        (ROOT / MANIFEST).unlink(missing_ok=True)
    announce(f"vc-harness: compiling {len(sources)} modules with mypyc - about a minute on two idle cores, up to"
             " three when they are busy (VC_BUILD=pure installs without compiling)")
    from mypyc.build import mypycify

    extensions = mypycify(sources, opt_level=OPT_LEVEL, multi_file=True, group_name=GROUP)
    setup(ext_modules=[*FMU_BINARY, *extensions],
          cmdclass={"build_ext": manifest_command(ParallelBuildExt, text),
                    "build_py": manifest_command(build_py, text)})

build()
