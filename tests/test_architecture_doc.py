"""docs/architecture.md is the living design: every repository path it names exists, and every
package of vc/core is described in it."""

from __future__ import annotations

import re
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
    assert len(packages) == 11
    assert [name for name in packages if f"\n{name}/" not in text] == []
