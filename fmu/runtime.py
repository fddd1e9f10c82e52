"""The Python runtime inside the self-contained FMU: the interpreter that runs the export, trimmed.

Layout under ``resources/runtime``::

    bin/python              the interpreter's executable (sys._base_executable)
    bin/python._pth         sys.path, exactly: the zipped standard library, its extension modules,
                            the resources folder (the project's code, PyYAML); a ._pth file also
                            keeps the interpreter from looking for its prefix elsewhere
    lib/libpython3.X.so.1.0 when the interpreter is built shared (stripped when ``strip`` exists)
    lib/python3X.zip        the standard library as compiled modules, stored uncompressed (so that
                            zipimport needs no zlib; the FMU's own zip compresses it)
    lib/python3.X/lib-dynload/  the standard library's extension modules that need nothing but
                            glibc and zlib (no OpenSSL, libffi, ...: nothing the NC uses)
    lib/libz.so.1           zlib, which binascii and zlib need (the system's, as this Python loads it)

Packages the NC never imports (tests, GUI, build tools) are left out.  The FMU's binary runs the
interpreter with ``-I -S -B`` and an environment of its own (see ``fmu/native/worker_link.c``).
"""

from __future__ import annotations

import importlib.util
import py_compile
import shutil
import subprocess
import sys
import sysconfig
import tempfile
import zipfile
from pathlib import Path

from fmu.elf import GLIBC_LIBRARIES, ElfError, Needs, needs
from fmu.instance import FmuError

RUNTIME_DIR = "runtime"
BUNDLED_LIBRARIES = {"libz.so.1": "zlib"}  # system library -> the module whose import maps it here
PYTHON = "bin/python"
LEFT_OUT = frozenset({"test", "idlelib", "tkinter", "turtledemo", "lib2to3", "ensurepip", "distutils", "pydoc_data",
                      "venv", "site-packages", "dist-packages", "__phello__", "turtle.py", "unittest",
                      "sqlite3", "curses", "dbm"})
_PYC_TAG = sys.implementation.cache_tag


def bundle_runtime(target: Path) -> None:
    """Copy the interpreter running this export, trimmed, into ``target`` (the runtime directory)."""
    version = f"{sys.version_info.major}.{sys.version_info.minor}"
    executable = Path(getattr(sys, "_base_executable", sys.executable)).resolve()
    stdlib = Path(sysconfig.get_paths()["stdlib"])
    lib = target / "lib"
    dynload_target = lib / f"python{version}" / "lib-dynload"
    dynload_target.mkdir(parents=True)
    (target / "bin").mkdir()
    python = target / PYTHON
    shutil.copyfile(executable, python)
    python.chmod(0o755)
    shared = _shared_libpython()
    if shared is not None:
        copied = lib / shared.name
        shutil.copyfile(shared, copied)
        _strip(copied)
    elif "libpython" in " ".join(_needs(python).libraries):
        raise FmuError(f"{executable} needs a shared libpython that sysconfig does not name: cannot bundle it")
    zip_name = f"python{sys.version_info.major}{sys.version_info.minor}.zip"
    _zip_stdlib(stdlib, lib / zip_name)
    dynload = Path(sysconfig.get_config_var("DESTSHARED") or stdlib / "lib-dynload")
    allowed = GLIBC_LIBRARIES | set(BUNDLED_LIBRARIES) | ({shared.name} if shared else set())
    wanted: set[str] = set()
    for module in sorted(dynload.glob("*.so")):
        if module.name.startswith(("_test", "xx", "_xx", "_ctypes_test")):
            continue
        libraries = set(_needs(module).libraries)
        if libraries <= allowed:
            shutil.copyfile(module, dynload_target / module.name)
            _strip(dynload_target / module.name)
            wanted |= libraries & set(BUNDLED_LIBRARIES)
    for library in sorted(wanted):
        shutil.copyfile(_loaded_library(library), lib / library)
    (target / "bin" / "python._pth").write_text(
        f"../lib/{zip_name}\n../lib/python{version}/lib-dynload\n../..\n", encoding="utf-8")


def add_yaml(resources: Path) -> None:
    """PyYAML's pure-Python package (the project's loader is the pure SafeLoader anyway)."""
    spec = importlib.util.find_spec("yaml")
    if spec is None or not spec.submodule_search_locations:
        raise FmuError("PyYAML is not installed in the Python that runs the export")
    package = Path(next(iter(spec.submodule_search_locations)))
    for source in sorted(package.glob("*.py")):
        target = resources / "yaml" / source.name
        target.parent.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(source, target)


def compile_tree(directory: Path) -> None:
    """__pycache__ next to every module, unchecked (the FMU's files never change): no compiling at
    instantiation, and the worker writes nothing (-B) into the host's unpacked FMU."""
    for source in sorted(directory.rglob("*.py")):
        py_compile.compile(str(source), cfile=str(source.parent / "__pycache__" / f"{source.stem}.{_PYC_TAG}.pyc"),
                           dfile=str(source.relative_to(directory)), doraise=True,
                           invalidation_mode=py_compile.PycInvalidationMode.UNCHECKED_HASH)


def _shared_libpython() -> Path | None:
    if not sysconfig.get_config_var("Py_ENABLE_SHARED"):
        return None
    library = Path(sysconfig.get_config_var("LIBDIR") or "", sysconfig.get_config_var("INSTSONAME") or "")
    if not library.is_file():
        raise FmuError(f"this Python is built shared, but its library {library} is missing")
    return library


def _loaded_library(name: str) -> Path:
    """The file of a system library as the dynamic loader found it for this process."""
    importlib.import_module(BUNDLED_LIBRARIES[name])
    for line in Path("/proc/self/maps").read_text().splitlines():
        path = Path(line.split(maxsplit=5)[-1])
        if path.is_absolute() and path.name.startswith(name):
            return path
    raise FmuError(f"cannot find {name} (needed by the standard library's extension modules) in this process")


def _needs(path: Path) -> Needs:
    try:
        return needs(path)
    except ElfError as error:
        raise FmuError(str(error)) from None


def _strip(library: Path) -> None:
    """Debug symbols out (libpython: 23 MB to 5.5 MB, the extension modules 11 MB to 3); a copy
    without ``strip`` (binutils) stays as it is."""
    strip = shutil.which("strip")
    if strip is not None:
        subprocess.run([strip, "--strip-unneeded", str(library)], check=False, capture_output=True, timeout=120)


def _zip_stdlib(stdlib: Path, archive: Path) -> None:
    """Each module of the standard library as its compiled form, under its module path."""
    with zipfile.ZipFile(archive, "w", zipfile.ZIP_STORED) as bundle, \
            tempfile.TemporaryDirectory(prefix="vc_fmu_pyc_") as scratch:
        for source in sorted(stdlib.rglob("*.py")):
            relative = source.relative_to(stdlib)
            if relative.parts[0] in LEFT_OUT or "__pycache__" in relative.parts or relative.parts[0].startswith(
                    "config-") or relative.parts[0] == "lib-dynload":
                continue
            if any(part in ("test", "tests", "idle_test") for part in relative.parts[:-1]):
                continue
            compiled = source.parent / "__pycache__" / f"{source.stem}.{_PYC_TAG}.pyc"
            if not compiled.is_file() or compiled.stat().st_mtime < source.stat().st_mtime:
                compiled = Path(scratch) / "module.pyc"
                py_compile.compile(str(source), cfile=str(compiled), dfile=str(relative), doraise=True)
            bundle.write(compiled, relative.with_suffix(".pyc").as_posix())
