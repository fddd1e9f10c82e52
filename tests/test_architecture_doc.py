"""docs/architecture.md is the living design: every repository path it names exists, every
package of vc/core and every module and package of vc/ is described in it, its pictures of the NC
core and of vc/scenario draw the layers of their contracts (and the layer numbers the packages state
are those), and what it says of the published states, of what the coverage and the readers import,
of the build guard, of the signal groups and of a new export holds."""

from __future__ import annotations

import ast
import dataclasses
import importlib
import re
import tomllib
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
DOC = ROOT / "docs" / "architecture.md"
# a path in backticks: a/b.py, a/b/, a/b/c.md (no placeholders such as <technology>)
PATH = re.compile(r"`((?:[A-Za-z_][\w.]*/)+(?:[\w.]+\.(?:py|md|yaml|toml))?)`")


def test_every_path_the_architecture_names_exists() -> None:
    named = PATH.findall(DOC.read_text(encoding="utf-8"))
    assert len(named) > 20
    missing = [path for path in named if "*" not in path and not (ROOT / path).exists()]
    assert not missing, f"docs/architecture.md names paths that do not exist: {missing}"


def test_every_package_of_the_nc_core_is_in_the_picture() -> None:
    text = DOC.read_text(encoding="utf-8")
    packages = sorted(p.name for p in (ROOT / "vc" / "core").iterdir() if (p / "__init__.py").exists())
    assert len(packages) == 13
    assert [name for name in packages if f"\n{name}/" not in text] == []


def _module_names(package: Path) -> list[str]:
    return sorted(".".join(path.relative_to(ROOT).with_suffix("").parts) for path in package.rglob("*.py")
                  if path.name != "__init__.py")


def test_every_state_machine_declared_in_the_core_is_published_by_its_row() -> None:
    """'A new state machine': a declaration beside its enum and its row in PUBLISHED, nothing else."""
    from vc.core.nck.state_view import PUBLISHED, STATE_MACHINES
    from vc.core.state_machine import StateMachine, Variants

    published = {id(machine) for machine in STATE_MACHINES} | {id(row.declaration) for row in PUBLISHED}
    declared: set[int] = set()
    for name in _module_names(ROOT / "vc" / "core"):
        for attribute, value in vars(importlib.import_module(name)).items():
            machines = value.machines if isinstance(value, Variants) else (value,)
            if isinstance(value, (StateMachine, Variants)) and machines[0].module == name:
                assert id(value) in published, f"{name}.{attribute} is declared but has no row in PUBLISHED"
                declared.update(id(machine) for machine in machines)
    # and each published state machine is declared at the top level of the module it names
    assert [machine.name for machine in STATE_MACHINES if id(machine) not in declared] == []


def test_the_coverage_imports_nothing_of_the_nc_core() -> None:
    """The coverage reads the NC through vc/simulation/published.py; a forbidden contract keeps it so."""
    for name in _module_names(ROOT / "vc" / "coverage"):
        tree = ast.parse((ROOT / (name.replace(".", "/") + ".py")).read_text(encoding="utf-8"))
        imported = [node.module or "" for node in ast.walk(tree) if isinstance(node, ast.ImportFrom)]
        imported += [alias.name for node in ast.walk(tree) if isinstance(node, ast.Import) for alias in node.names]
        assert [module for module in imported if module.startswith("vc.core")] == [], name
    contracts = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))["tool"]["importlinter"]
    assert any(contract["type"] == "forbidden" and contract["source_modules"] == ["vc.coverage"]
               and "vc.core" in contract["forbidden_modules"] for contract in contracts["contracts"])


def test_every_signal_group_is_keyword_only() -> None:
    from interfaces import signal_groups
    from interfaces.group_codec import declared_signals

    groups = [value for value in vars(signal_groups).values()
              if isinstance(value, type) and dataclasses.is_dataclass(value) and declared_signals(value)]
    assert len(groups) >= 20
    assert [group.__name__ for group in groups
            if not all(field.kw_only for field in dataclasses.fields(group))] == []


def test_every_step_of_the_machine_reader_is_in_the_picture() -> None:
    text = DOC.read_text(encoding="utf-8")
    modules = sorted(p.name for p in (ROOT / "vc" / "config" / "reader").glob("*.py") if p.name != "__init__.py")
    assert len(modules) == 6
    assert [name for name in modules if name not in text] == []


LINKS_PACKAGE = ROOT / "interfaces" / "links"


def _imported_modules(path: Path) -> list[str]:
    tree = ast.parse(path.read_text(encoding="utf-8"))
    imported = [node.module or "" for node in ast.walk(tree) if isinstance(node, ast.ImportFrom)]
    return imported + [alias.name for node in ast.walk(tree) if isinstance(node, ast.Import) for alias in node.names]


def test_every_technology_folder_of_the_links_has_its_row_and_every_row_resolves() -> None:
    """'A new link': one folder under interfaces/links/ and its row in LINKS, whose names all resolve."""
    from interfaces.links import LINKS, load

    folders = sorted(p.name for p in LINKS_PACKAGE.iterdir() if (p / "__init__.py").exists())
    assert folders == sorted(kind.package.rsplit(".", 1)[1] for kind in LINKS.values()) == ["can", "modbus"]
    for name, kind in LINKS.items():
        assert kind.package == f"interfaces.links.{name}"
        assert (LINKS_PACKAGE / name / "plc_end.py").exists()
        for reference in (kind.plc_end, kind.harness, kind.plc_process, kind.in_process):
            if reference is not None:
                assert callable(load(reference)), reference


def test_only_the_registry_names_every_link_technology() -> None:
    """The registry imports no technology (it loads a row's names when that link is chosen), and a
    technology's modules import neither the registry nor another technology."""
    from interfaces.links import LINKS

    packages = [kind.package for kind in LINKS.values()]
    registry = _imported_modules(LINKS_PACKAGE / "__init__.py")
    assert [module for module in registry if module.startswith("interfaces.links")] == []
    for package in packages:
        for path in (ROOT / package.replace(".", "/")).glob("*.py"):
            imported = _imported_modules(path)
            assert "interfaces.links" not in imported, path
            others = [module for module in imported for other in packages
                      if other != package and module.startswith(other)]
            assert others == [], path
    contracts = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))["tool"]["importlinter"]
    for package in packages:
        assert any(contract["type"] == "forbidden" and contract["source_modules"] == [package]
                   and sorted(contract["forbidden_modules"]) == sorted(set(packages) - {package})
                   for contract in contracts["contracts"]), f"no contract keeps {package} to itself"


def test_the_architecture_names_the_steps_of_a_new_link_as_the_registry_has_them() -> None:
    from interfaces.links import LinkKind

    text = DOC.read_text(encoding="utf-8")
    section = text[text.index("- **A new link**"): text.index("- **A new scenario step**")]
    assert "`interfaces/links/__init__.py`" in section and "`interfaces/links/<technology>/`" in section
    rows = [field.name for field in dataclasses.fields(LinkKind)]
    assert [name for name in ("plc_end", "harness", "plc_process", "in_process") if name not in rows] == []
    assert re.findall(r"\n  (\d)\. ", section) == ["1", "2", "3", "4", "5"]


# -- the package table ------------------------------------------------------------------------

PROJECT = ("vc", "interfaces", "plc_stub", "fmu", "vc_build", "plc_awlsim", "awlsimhw_vcmodbus")


def _package_table() -> dict[str, tuple[str, str]]:
    """The rows of the package table: package -> (what it is, what it may import)."""
    section = DOC.read_text(encoding="utf-8").split("## The packages", 1)[1].split("\n## ", 1)[0]
    rows = [line.split(" | ") for line in section.splitlines() if line.startswith("| `")]
    return {row[0].removeprefix("| `").removesuffix("`"): (row[1], row[2].removesuffix(" |")) for row in rows}


def _imports(path: Path) -> set[str]:
    """Every module of the project that a file imports, at its top or inside a function."""
    tree = ast.parse(path.read_text(encoding="utf-8"))
    imported = {node.module or "" for node in ast.walk(tree) if isinstance(node, ast.ImportFrom) and not node.level}
    imported |= {alias.name for node in ast.walk(tree) if isinstance(node, ast.Import) for alias in node.names}
    return {name for name in imported if name.split(".")[0] in PROJECT}


def _within(module: str, allowed: list[str]) -> bool:
    return any(module == name or module.startswith(name + ".") for name in allowed)


def test_every_module_and_package_of_vc_is_in_the_package_table() -> None:
    table = _package_table()
    parts = sorted(path.stem for path in (ROOT / "vc").iterdir()
                   if (path.suffix == ".py" and path.name != "__init__.py") or (path / "__init__.py").exists())
    assert len(parts) >= 12
    assert [f"vc.{name}" for name in parts if f"vc.{name}" not in table] == []


def test_the_readers_and_the_escaping_import_what_the_table_says() -> None:
    """vc/input_limits.py, vc/escaping.py, vc/located_yaml.py, vc/bounded_json.py: their column names
    the project's modules each may import ("nothing of the project": none)."""
    table = _package_table()
    for name in ("vc.input_limits", "vc.escaping", "vc.located_yaml", "vc.bounded_json"):
        column = table[name][1]
        allowed = [] if column == "nothing of the project" else re.findall(r"`([\w.]+)`", column)
        assert column == "nothing of the project" or allowed, name
        imported = _imports(ROOT / (name.replace(".", "/") + ".py"))
        assert sorted(module for module in imported if not _within(module, allowed)) == [], name


def test_the_coverage_imports_what_the_table_says() -> None:
    """Of vc.simulation only the published states and alarms and the run it observes; the scenario
    model; the readers; interfaces (and vc itself, for where its sources lie)."""
    row = _package_table()["vc.coverage"][1]
    allowed = ["vc.simulation.published", "vc.simulation.lockstep", "vc.simulation.observed", "vc.scenario.language",
               "vc.located_yaml", "vc.bounded_json", "interfaces"]
    named = ["`vc/simulation/published.py`", "`lockstep.py`", "`observed.py`", "`vc.scenario.language`",
             "`vc.located_yaml`", "`vc.bounded_json`", "`interfaces`", "never `vc.core`"]
    assert [text for text in named if text not in row] == []
    imported = set().union(*(_imports(path) for path in (ROOT / "vc" / "coverage").rglob("*.py")))
    foreign = {module for module in imported if module != "vc" and not _within(module, ["vc.coverage"])}
    assert sorted(module for module in foreign if not _within(module, allowed)) == []


def test_the_packages_with_compiled_modules_install_the_build_guard_first() -> None:
    """vc_build's row: the packages that hold compiled modules (setup.py's COMPILED_PACKAGES, where
    every pattern of COMPILED lies) install the guard as their first statement; they are the ones
    the row names, and no other package holds a compiled module."""
    setup = {target.id: ast.literal_eval(node.value) for node in ast.parse((ROOT / "setup.py").read_text()).body
             if isinstance(node, ast.Assign) for target in node.targets if isinstance(target, ast.Name)
             and target.id in ("COMPILED_PACKAGES", "COMPILED")}
    packages, compiled = setup["COMPILED_PACKAGES"], setup["COMPILED"]
    assert sorted({pattern.split("/")[0] for pattern in compiled}) == sorted(packages)
    row = _package_table()["vc_build"][0]
    holding = re.search(r"hold compiled modules \(([^)]*)\)", row)
    assert holding is not None and re.findall(r"`(\w+)`", holding.group(1)) == list(packages)
    for package in packages:
        body = ast.parse((ROOT / package / "__init__.py").read_text(encoding="utf-8")).body
        body = body[1:] if body and isinstance(body[0], ast.Expr) and isinstance(body[0].value, ast.Constant) else body
        first, second = body[0], body[1]
        assert isinstance(first, ast.ImportFrom) and first.module == "vc_build", package
        assert isinstance(second, ast.Expr) and isinstance(second.value, ast.Call), package
        assert ast.unparse(second.value.func) == (first.names[0].asname or first.names[0].name), package


# -- layers: the doc's pictures and numbers are those of the contracts -------------------------

def _layers_contract(container: str) -> list[list[str]]:
    contracts = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))["tool"]["importlinter"]
    (contract,) = [c for c in contracts["contracts"] if c["type"] == "layers" and c["containers"] == [container]]
    return [[name.strip() for name in layer.split("|")] for layer in contract["layers"]]


def _picture(heading: str) -> list[str]:
    """The lines of the first code block under a heading of docs/architecture.md."""
    section = DOC.read_text(encoding="utf-8").split(f"\n## {heading}", 1)[1].split("\n## ", 1)[0]
    return section.split("```", 2)[1].splitlines()[1:]


def test_the_nc_core_picture_draws_the_layers_of_the_contract() -> None:
    """One package a line; a `|` after consecutive packages puts them in one layer."""
    layers: list[list[str]] = []
    beside = False
    for line in _picture("The NC core"):
        match = re.match(r"(\w+)/\s+(\|)?", line)
        if match is None:
            continue
        if match.group(2) and beside:
            layers[-1].append(match.group(1))
        else:
            layers.append([match.group(1)])
        beside = bool(match.group(2))
    assert layers == _layers_contract("vc.core")


def test_the_layer_numbers_of_the_nc_core_are_those_of_the_contract() -> None:
    """Each package of vc/core says its layer in its docstring ("layer N of vc/core"), and
    vc/core/__init__.py lists the layers, numbered as the contract orders them."""
    layers = _layers_contract("vc.core")
    number = {package: position for position, layer in enumerate(layers, 1) for package in layer}
    for package, position in number.items():
        docstring = ast.get_docstring(ast.parse((ROOT / "vc" / "core" / package / "__init__.py").read_text())) or ""
        assert re.findall(r"layer (\d+) of vc/core", docstring) == [str(position)], package
    listing = ast.get_docstring(ast.parse((ROOT / "vc" / "core" / "__init__.py").read_text())) or ""
    listed = [re.findall(r"``(\w+)``", line.split("  ")[0] if "``" in line else "")
              for line in re.findall(r"^\d+\. (.*)$", listing, flags=re.MULTILINE)]
    assert listed == layers


def test_the_scenario_picture_draws_the_layers_of_the_contract() -> None:
    """The picture of vc/scenario: its subpackages top to bottom as the contract orders them, every
    module of each named, and a contract that leaves no module of vc/scenario out of a layer."""
    picture = _picture("Scenarios (`vc/scenario`)")
    drawn = [match.group(1) for line in picture if (match := re.match(r"(\w+)(?:/|\.py)\s", line))]
    assert [[name] for name in drawn] == _layers_contract("vc.scenario")
    contracts = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))["tool"]["importlinter"]
    assert [c.get("exhaustive") for c in contracts["contracts"] if c.get("containers") == ["vc.scenario"]] == [True]
    text = "\n".join(picture)
    for package in drawn:
        folder = ROOT / "vc" / "scenario" / package
        modules = [f"{path.name}/" if path.is_dir() else path.name for path in folder.iterdir()
                   if path.name not in ("__init__.py", "__pycache__")] if folder.is_dir() else []
        assert [name for name in modules if name not in text] == [], package


# -- where to add: a new export for a PLC tool ------------------------------------------------

def test_every_export_follows_the_steps_of_a_new_export() -> None:
    """Each format of EXPORTS: its function in interfaces/exports/, the module under a no-I/O
    contract, its row in docs/plc_tools.md with its file suffix, and a test that runs it."""
    from interfaces.exports import EXPORTS

    contracts = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))["tool"]["importlinter"]
    pure = [c["source_modules"] for c in contracts["contracts"] if c["type"] == "forbidden"
            and "socket" in c["forbidden_modules"] and "os" in c["forbidden_modules"]]
    tools = (ROOT / "docs" / "plc_tools.md").read_text(encoding="utf-8")
    tests = (ROOT / "tests" / "interfaces" / "exports" / "test_exports.py").read_text(encoding="utf-8")
    assert len(EXPORTS) >= 5
    for name, export in EXPORTS.items():
        module = export.write.__module__
        assert module.startswith("interfaces.exports."), name
        assert any(_within(module, sources) for sources in pure), name
        assert f"| `{name}` | `{export.suffix}`" in tools, name
        assert export.write.__name__ in tests, name
