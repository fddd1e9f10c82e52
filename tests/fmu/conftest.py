"""The FMU of turn_mill, exported once per test session (about a second)."""

from __future__ import annotations

from pathlib import Path

import pytest

from fmu.export import ExportResult, export_fmu

REPOSITORY = Path(__file__).resolve().parents[2]
TURN_MILL = str(REPOSITORY / "scenarios" / "machines" / "turn_mill.yaml")


@pytest.fixture(scope="session")
def turn_mill_export(tmp_path_factory: pytest.TempPathFactory) -> ExportResult:
    return export_fmu(TURN_MILL, str(tmp_path_factory.mktemp("fmu") / "turn_mill.fmu"))


@pytest.fixture(scope="session")
def turn_mill_fmu(turn_mill_export: ExportResult) -> Path:
    return turn_mill_export.path
