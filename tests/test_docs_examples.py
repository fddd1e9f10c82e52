"""The scenarios the README and docs/scenarios.md show a new user run and pass as printed: copied
from the page into a file of their own, away from the library, and run as ``vc run FILE`` does."""

from __future__ import annotations

import io
import re
from pathlib import Path

import pytest
from rich.console import Console

from interfaces.links.inprocess import plc_programs
from vc.harness.targets import simulation_for
from vc.scenario.command import EXIT_PASSED, run_command

ROOT = Path(__file__).resolve().parents[1]
EXAMPLES = {
    "readme": (ROOT / "README.md", "A scenario, the way a commissioning engineer writes it"),
    "scenarios_md_first": (ROOT / "docs" / "scenarios.md", "## A first scenario"),
}


def _example(page: Path, heading: str) -> str:
    """The first YAML block after ``heading`` on the page."""
    text = page.read_text(encoding="utf-8").split(heading, 1)[1]
    found = re.search(r"```yaml\n(.*?)```", text, flags=re.DOTALL)
    assert found is not None, f"{page.name}: no YAML example after {heading!r}"
    return found.group(1)


@pytest.mark.parametrize("name", sorted(EXAMPLES))
def test_the_example_scenario_passes_as_printed(name: str, tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    page, heading = EXAMPLES[name]
    path = tmp_path / f"{name}.yaml"
    path.write_text(_example(page, heading), encoding="utf-8")
    monkeypatch.chdir(tmp_path)
    output = io.StringIO()
    code = run_command([path.name], simulation_for, plc_programs().keys(),
                       console=Console(file=output, width=200))  # type: ignore[arg-type]
    assert code == EXIT_PASSED, output.getvalue()
