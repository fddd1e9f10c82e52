"""docs/architecture.md is the living design: every repository path it names exists, every
package of vc/core is described in it, and what it says of the published states, of the coverage's
imports and of the signal groups holds."""

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
    assert len(packages) == 12
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
