"""``vc fmu export``: the NC and the plant of one machine as an FMI 2.0 co-simulation FMU.

The FMU runs in the host's Python, so its modules land in the host's ``sys.modules``.  A
host that has imported this project already (a test, a co-simulation script next to ``vc
run``) would silently lend its own ``vc`` to the FMU, whatever version that is.  The FMU
therefore carries the code it needs under a package of its own, ``vc_fmu_<digest>``: the
modules the slave imports (found by following the imports from ``fmu/slave.py``) are copied
with their project imports rewritten (``from vc.core.nck`` -> ``from vc_fmu_<digest>.vc.core.nck``);
the slave itself becomes the script ``vc_nc_<digest>.py``.  The digest is taken over that
code, so two FMUs of the same code share their modules and different code never meets.

Resources of the FMU::

    vc_nc_<digest>.py        the slave (pythonfmu's entry point)
    vc_fmu_<digest>/         vc, interfaces and fmu as far as the slave needs them, with the
                             signal catalogue
    vc_fmu.json              manifest: model identifier, machine name, machine file
    machine/<file>.yaml      the machine file, as exported
    pythonfmu/               added by pythonfmu

The host needs Python 3.11 or newer with PyYAML (see docs/fmu.md).
"""

from __future__ import annotations

import ast
import hashlib
import importlib.util
import json
import re
import shutil
import sys
import tempfile
from dataclasses import dataclass
from pathlib import Path

from fmu.slave import MANIFEST, FmuError, build_fmu
from fmu.unit import Causality, NcUnit, UnitError
from vc.config.loader import load_machine
from vc.config.machine_files import machine_file

PROJECT_PACKAGES = ("vc", "interfaces", "fmu")
SLAVE_MODULE = "fmu.slave"
CATALOG_PACKAGE = "interfaces.catalog"
_IMPORT = re.compile(r"^(?P<indent>\s*)(?P<keyword>from|import)(?P<space>\s+)(?P<package>vc|interfaces|fmu)(?=[\s.])",
                     re.MULTILINE)


@dataclass(frozen=True, slots=True)
class ExportResult:
    path: Path
    model_identifier: str
    inputs: int
    outputs: int
    parameters: int
    bundle: str


def export_fmu(machine_path: str, output: str) -> ExportResult:
    """Check the machine, bundle the code, let pythonfmu build ``output``; raises ``SourceError``
    for a machine file with problems and :class:`FmuError` when the FMU cannot be built."""
    machine = load_machine(machine_path)
    machine_source = machine_file(machine_path)  # the file itself, also of a packaged machine
    assert machine_source is not None  # load_machine found it
    try:
        unit = NcUnit(machine_path)
    except UnitError as error:
        raise FmuError(str(error)) from None
    model_identifier = _identifier(machine.name)
    files = _bundled_sources()
    digest = _digest(files)
    bundle = f"vc_fmu_{digest}"
    destination = Path(output)
    if destination.suffix != ".fmu":
        raise FmuError(f"{output}: an FMU file name ends with .fmu")
    destination.parent.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory(prefix="vc_fmu_") as staging_text:
        staging = Path(staging_text)
        script = staging / f"vc_nc_{digest}.py"
        for module, source in files.items():
            text = _rebased(source.read_text(encoding="utf-8"), bundle, module)
            if module == SLAVE_MODULE:
                script.write_text(text, encoding="utf-8")
                continue
            target = staging / bundle / _relative_path(module, source)
            target.parent.mkdir(parents=True, exist_ok=True)
            target.write_text(text, encoding="utf-8")
        (staging / bundle / "__init__.py").write_text(f'"""vc harness code inside the FMU ({digest})."""\n')
        _copy_catalog(staging / bundle)
        machine_dir = staging / "machine"
        machine_dir.mkdir()
        shutil.copyfile(machine_source, machine_dir / Path(machine_source).name)
        manifest = staging / MANIFEST
        manifest.write_text(json.dumps({"format": 1, "model": model_identifier, "name": machine.name,
                                        "machine": f"machine/{Path(machine_source).name}"}, indent=2))
        try:
            built = build_fmu(script, [staging / bundle, manifest, machine_dir], destination)
        finally:
            _forget(str(staging), bundle, script.stem)
    counts = {causality: sum(1 for v in unit.variables if v.causality is causality) for causality in Causality}
    return ExportResult(built, model_identifier, counts[Causality.INPUT], counts[Causality.OUTPUT],
                        counts[Causality.PARAMETER], bundle)


def _identifier(name: str) -> str:
    """The model identifier (the binary's file name): the machine name as a C identifier."""
    identifier = re.sub(r"\W", "_", name)
    return identifier if identifier[:1].isalpha() else f"m_{identifier}"


def _bundled_sources() -> dict[str, Path]:
    """Every project module the slave imports, directly or not, with the packages around them."""
    found: dict[str, Path] = {}
    pending = [SLAVE_MODULE]
    while pending:
        module = pending.pop()
        if module in found or module.split(".")[0] not in PROJECT_PACKAGES:
            continue
        try:
            spec = importlib.util.find_spec(module)
        except ModuleNotFoundError:
            continue  # ``from package.module import name``: the name is no module
        if spec is None or spec.origin is None or not spec.origin.endswith(".py"):
            continue  # a name imported from a module, not a module
        found[module] = Path(spec.origin)
        parts = module.split(".")
        pending.extend(".".join(parts[:end]) for end in range(1, len(parts)))
        for node in ast.walk(ast.parse(found[module].read_text(encoding="utf-8"))):
            if isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
                pending.append(node.module)
                pending.extend(f"{node.module}.{alias.name}" for alias in node.names)
            elif isinstance(node, ast.Import):
                pending.extend(alias.name for alias in node.names)
    return dict(sorted(found.items()))


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
