"""``vc fmu export``: the NC and the plant of one machine as an FMI co-simulation FMU.

Two variants (docs/fmu.md says which to take):

* **self-contained** (the default, FMI 2.0 or 3.0): the FMU's binary is the project's own small C
  library (``fmu/native``, built when the project is installed) and its resources hold a Python
  runtime (``fmu/runtime.py``), PyYAML and the project's code.  At instantiation the binary starts
  the NC as a worker process of that runtime (``fmu/worker.py``) and talks to it over a socket
  pair.  The host needs nothing: no Python, no environment variable.
* **lean** (``--python host``, FMI 2.0): pythonfmu's binary runs the slave (``fmu/slave.py``) in
  the host process's own Python, which must be 3.11+ with PyYAML.  Small, for Python hosts.

Either way the code the FMU runs is copied under a package of its own, ``vc_fmu_<digest>``:
the modules the entry module imports (found by following the imports) with their project
imports rewritten (``from vc.core.nck.nck`` -> ``from vc_fmu_<digest>.vc.core.nck.nck``); the entry
module itself becomes a script.  In the lean FMU this keeps a host that imported this project
(or anything else called ``vc``) from lending the FMU its own modules; the digest is taken
over that code, so two FMUs of the same code share their modules and different code never meets.
Only the ``.py`` sources are copied, also where compiled extension modules of the same name
stand next to them.

Resources of the self-contained FMU::

    vc_nc_worker.py          the worker (fmu/worker.py), started by the binary
    vc_fmu_<digest>/         vc, interfaces and fmu as far as the worker needs them, the catalogue
    yaml/                    PyYAML (pure Python)
    runtime/                 the Python runtime (fmu/runtime.py)
    vc_fmu.json              manifest: model identifier, machine name, machine file, token, FMI version
    machine/<file>.yaml      the machine file, as exported

The lean FMU has ``vc_nc_<digest>.py`` (the slave) and ``pythonfmu/`` instead of the first,
third and fourth.
"""

from __future__ import annotations

import ast
import hashlib
import importlib.machinery
import importlib.util
import json
import re
import shutil
import sys
import tempfile
import uuid
import zipfile
from dataclasses import dataclass
from enum import Enum
from pathlib import Path

from fmu.elf import is_elf, needs_of
from fmu.instance import MANIFEST, FmuError
from fmu.model_description import Identity, model_description
from fmu.runtime import PYTHON, RUNTIME_DIR, add_yaml, bundle_runtime, compile_tree
from fmu.unit import Causality, NcUnit, UnitError
from vc.config.loader import load_machine
from vc.config.machine_files import machine_file

PROJECT_PACKAGES = ("vc", "interfaces", "fmu", "vc_build")
SLAVE_MODULE = "fmu.slave"
WORKER_MODULE = "fmu.worker"
WORKER_SCRIPT = "vc_nc_worker.py"  # the name fmu/native/worker_link.c starts
NATIVE_MODULE = "fmu._vc_fmi"  # the FMU binary, built by setup.py from fmu/native
CATALOG_PACKAGE = "interfaces.catalog"
PLATFORMS = {2: "linux64", 3: "x86_64-linux"}  # the binaries/ folder of each FMI version
DEFAULT_STOP_TIME_S = 10.0
_IMPORT = re.compile(
    r"^(?P<indent>\s*)(?P<keyword>from|import)(?P<space>\s+)(?P<package>vc_build|vc|interfaces|fmu)(?=[\s.])",
    re.MULTILINE)


class PythonRuntime(Enum):
    BUNDLED = "bundled"  # the self-contained FMU
    HOST = "host"  # the lean FMU: pythonfmu, the host's Python


@dataclass(frozen=True, slots=True)
class ExportResult:
    path: Path
    model_identifier: str
    inputs: int
    outputs: int
    parameters: int
    bundle: str
    fmi_version: int
    python: PythonRuntime
    glibc: tuple[int, ...]  # the oldest glibc every Linux binary of the FMU runs with

    @property
    def size(self) -> int:
        return self.path.stat().st_size

    def summary(self) -> str:
        kind = ("self-contained, Python runtime inside" if self.python is PythonRuntime.BUNDLED
                else "lean, runs in the host's Python 3.11+ with PyYAML")
        floor = f"; linux64 needs glibc >= {'.'.join(map(str, self.glibc))}" if self.glibc else ""
        return (f"{self.path}: FMI {self.fmi_version}.0 co-simulation FMU '{self.model_identifier}' ({kind}),"
                f" {self.inputs} inputs, {self.outputs} outputs, {self.parameters} parameters"
                f" (code in {self.bundle}); {self.size / 1e6:.1f} MB{floor}")


def export_fmu(machine_path: str, output: str, python: PythonRuntime = PythonRuntime.BUNDLED,
               fmi_version: int = 2) -> ExportResult:
    """Check the machine, bundle the code, build ``output``; raises ``SourceError`` for a machine
    file with problems and :class:`FmuError` when the FMU cannot be built."""
    machine = load_machine(machine_path)
    if fmi_version not in (2, 3):
        raise FmuError(f"FMI {fmi_version}: the FMU is exported for FMI 2.0 or 3.0")
    if python is PythonRuntime.HOST and fmi_version != 2:
        raise FmuError("the lean FMU (--python host) is built by pythonfmu, which knows FMI 2.0 only;"
                       " the self-contained FMU (the default) is FMI 3.0 as well")
    machine_source = machine_file(machine_path)  # the file itself, also of a packaged machine
    assert machine_source is not None  # load_machine found it
    try:
        unit = NcUnit(machine_path)
    except UnitError as error:
        raise FmuError(str(error)) from None
    destination = Path(output)
    if destination.suffix != ".fmu":
        raise FmuError(f"{output}: an FMU file name ends with .fmu")
    model_identifier = _identifier(machine.name)
    entry = WORKER_MODULE if python is PythonRuntime.BUNDLED else SLAVE_MODULE
    files = _bundled_sources(entry)
    digest = _digest(files)
    bundle = f"vc_fmu_{digest}"
    destination.parent.mkdir(parents=True, exist_ok=True)
    manifest = {"format": 1, "model": model_identifier, "name": machine.name,
                "machine": f"machine/{Path(machine_source).name}"}
    with tempfile.TemporaryDirectory(prefix="vc_fmu_") as staging_text:
        resources = Path(staging_text) / "resources"
        resources.mkdir()
        script = resources / (WORKER_SCRIPT if python is PythonRuntime.BUNDLED else f"vc_nc_{digest}.py")
        _copy_code(files, entry, bundle, digest, script, resources / bundle)
        machine_dir = resources / "machine"
        machine_dir.mkdir()
        shutil.copyfile(machine_source, machine_dir / Path(machine_source).name)
        if python is PythonRuntime.HOST:
            from fmu.slave import build_fmu

            (resources / MANIFEST).write_text(json.dumps(manifest, indent=2))
            try:
                built = build_fmu(script, [resources / bundle, resources / MANIFEST, machine_dir], destination)
            finally:
                _forget(str(resources), bundle, script.stem)
        else:
            manifest |= {"token": _token(digest, machine_dir, fmi_version), "fmi": [fmi_version]}
            (resources / MANIFEST).write_text(json.dumps(manifest, indent=2))
            _build_self_contained(Path(staging_text), unit, manifest, fmi_version)
            built = _zip_fmu(Path(staging_text), destination)
    counts = {causality: sum(1 for v in unit.variables if v.causality is causality) for causality in Causality}
    return ExportResult(built, model_identifier, counts[Causality.INPUT], counts[Causality.OUTPUT],
                        counts[Causality.PARAMETER], bundle, fmi_version, python, glibc_floor(built))


def glibc_floor(fmu_path: Path) -> tuple[int, ...]:
    """The newest glibc version any Linux binary in the FMU needs (its own and the bundled runtime's)."""
    floors: list[tuple[int, ...]] = []
    with zipfile.ZipFile(fmu_path) as archive:
        for name in archive.namelist():
            linux = name.startswith(tuple(f"binaries/{platform}/" for platform in PLATFORMS.values()))
            if linux or name.startswith(f"resources/{RUNTIME_DIR}/"):
                data = archive.read(name)
                if is_elf(data):
                    floors.append(needs_of(data, name).glibc)
    return max(floors, default=())


def native_library() -> Path:
    """The FMU binary built at installation; :class:`FmuError` with what to do when it is missing."""
    spec = importlib.util.find_spec(NATIVE_MODULE)
    if spec is None or spec.origin is None:
        raise FmuError("the self-contained FMU's binary (fmu/native, built when the project is installed) is"
                       " missing: install a C compiler (Debian: apt-get install gcc) and install the project"
                       " again (pip install -e .); or export the lean FMU with --python host")
    return Path(spec.origin)


def _build_self_contained(staging: Path, unit: NcUnit, manifest: dict[str, object], fmi_version: int) -> None:
    """Binary, runtime, PyYAML and model description next to the resources."""
    resources = staging / "resources"
    binary = staging / "binaries" / PLATFORMS[fmi_version] / f"{manifest['model']}.so"
    binary.parent.mkdir(parents=True)
    shutil.copyfile(native_library(), binary)
    add_yaml(resources)
    compile_tree(resources)
    bundle_runtime(resources / RUNTIME_DIR)
    identity = Identity(str(manifest["model"]), str(manifest["token"]), str(manifest["name"]),
                        f"{manifest['name']}: SINUMERIK-style NC and machine plant; the PLC connects through the"
                        " NC/PLC interface signals (self-contained: the NC runs in a Python runtime inside the FMU)",
                        DEFAULT_STOP_TIME_S)
    (staging / "modelDescription.xml").write_bytes(model_description(unit, fmi_version, identity))


def _zip_fmu(staging: Path, destination: Path) -> Path:
    """The FMU archive; the runtime's interpreter keeps its execute bit for hosts that restore it."""
    executable = f"resources/{RUNTIME_DIR}/{PYTHON}"
    with zipfile.ZipFile(destination, "w", zipfile.ZIP_DEFLATED, compresslevel=6) as archive:
        for path in sorted(staging.rglob("*")):
            if path.is_dir():
                continue
            name = path.relative_to(staging).as_posix()
            info = zipfile.ZipInfo.from_file(path, name)
            info.compress_type = zipfile.ZIP_DEFLATED
            info.external_attr = (0o100755 if name == executable else 0o100644) << 16
            with path.open("rb") as source, archive.open(info, "w") as target:
                shutil.copyfileobj(source, target, 1 << 20)
    return destination


def _token(digest: str, machine_dir: Path, fmi_version: int) -> str:
    """The GUID / instantiation token: the same code, machine and FMI version give the same token."""
    content = hashlib.sha256(digest.encode())
    for path in sorted(machine_dir.iterdir()):
        content.update(path.read_bytes())
    content.update(str(fmi_version).encode())
    return "{" + str(uuid.uuid5(uuid.NAMESPACE_URL, f"vc-harness-fmu:{content.hexdigest()}")) + "}"


def _copy_code(files: dict[str, Path], entry: str, bundle: str, digest: str, script: Path, bundle_dir: Path) -> None:
    for module, source in files.items():
        text = _rebased(source.read_text(encoding="utf-8"), bundle, module)
        if module == entry:
            script.write_text(text, encoding="utf-8")
            continue
        target = bundle_dir / _relative_path(module, source)
        target.parent.mkdir(parents=True, exist_ok=True)
        target.write_text(text, encoding="utf-8")
    (bundle_dir / "__init__.py").write_text(f'"""vc harness code inside the FMU ({digest})."""\n')
    _copy_catalog(bundle_dir)


def _identifier(name: str) -> str:
    """The model identifier (the binary's file name): the machine name as a C identifier."""
    identifier = re.sub(r"\W", "_", name)
    return identifier if identifier[:1].isalpha() else f"m_{identifier}"


def _bundled_sources(entry: str) -> dict[str, Path]:
    """Every project module ``entry`` imports, directly or not, with the packages around them."""
    found: dict[str, Path] = {}
    pending = [entry]
    while pending:
        module = pending.pop()
        if module in found or module.split(".")[0] not in PROJECT_PACKAGES:
            continue
        try:
            spec = importlib.util.find_spec(module)
        except ModuleNotFoundError:
            continue  # ``from package.module import name``: the name is no module
        source = _python_source(spec)
        if source is None:
            continue  # a name imported from a module, not a module
        found[module] = source
        parts = module.split(".")
        pending.extend(".".join(parts[:end]) for end in range(1, len(parts)))
        for node in ast.walk(ast.parse(found[module].read_text(encoding="utf-8"))):
            if isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
                pending.append(node.module)
                pending.extend(f"{node.module}.{alias.name}" for alias in node.names)
            elif isinstance(node, ast.Import):
                pending.extend(alias.name for alias in node.names)
    return dict(sorted(found.items()))


def _python_source(spec: importlib.machinery.ModuleSpec | None) -> Path | None:
    """The module's ``.py`` file; for a module of the compiled build, the source beside it (the
    FMU carries Python, whatever build exported it)."""
    if spec is None or spec.origin is None:
        return None
    origin = Path(spec.origin)
    if origin.suffix == ".py":
        return origin
    if any(origin.name.endswith(suffix) for suffix in importlib.machinery.EXTENSION_SUFFIXES):
        source = origin.with_name(spec.name.rpartition(".")[2] + ".py")
        return source if source.is_file() else None
    return None


def _relative_path(module: str, source: Path) -> Path:
    parts = module.split(".")
    return Path(*parts, "__init__.py") if source.name == "__init__.py" else Path(*parts[:-1], f"{parts[-1]}.py")


def _rebased(text: str, bundle: str, module: str) -> str:
    """``text`` with its project imports moved under ``bundle``; checked so none is missed."""
    rebased = _IMPORT.sub(lambda m: f"{m['indent']}{m['keyword']}{m['space']}{bundle}.{m['package']}", text)
    for node in ast.walk(ast.parse(rebased)):
        names = [node.module or ""] if isinstance(node, ast.ImportFrom) else \
            [alias.name for alias in node.names] if isinstance(node, ast.Import) else []
        for name in names:
            if name.split(".")[0] in PROJECT_PACKAGES:
                raise FmuError(f"{module}: the import of {name} cannot be moved into the FMU's package")
    return rebased


def _digest(files: dict[str, Path]) -> str:
    digest = hashlib.sha256()
    for module, source in files.items():
        digest.update(module.encode())
        digest.update(source.read_bytes())
    catalog = _catalog_dir()
    for yaml_file in sorted(catalog.glob("*.yaml")):
        digest.update(yaml_file.read_bytes())
    return digest.hexdigest()[:12]


def _catalog_dir() -> Path:
    spec = importlib.util.find_spec(CATALOG_PACKAGE)
    assert spec is not None and spec.origin is not None
    return Path(spec.origin).parent


def _copy_catalog(bundle_dir: Path) -> None:
    target = bundle_dir / Path(*CATALOG_PACKAGE.split("."))
    for yaml_file in sorted(_catalog_dir().glob("*.yaml")):
        shutil.copyfile(yaml_file, target / yaml_file.name)


def _forget(staging: str, bundle: str, script_module: str) -> None:
    """pythonfmu imports the slave while building: leave this process as it was."""
    while staging in sys.path:
        sys.path.remove(staging)
    for name in [name for name in sys.modules if name == script_module or name.split(".")[0] == bundle]:
        del sys.modules[name]
