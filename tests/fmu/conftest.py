"""The FMUs of turn_mill, each exported once per test session (a few seconds each):
self-contained FMI 2.0 (the default of ``vc fmu export``), self-contained FMI 3.0, and lean."""

from __future__ import annotations

from pathlib import Path

import pytest
from fmu_machines import TURN_MILL

from fmu.export import ExportResult, PythonRuntime, export_fmu

VARIANTS = ("fmi2", "fmi3", "lean")


@pytest.fixture(scope="session")
def turn_mill_export(tmp_path_factory: pytest.TempPathFactory) -> ExportResult:
    return export_fmu(TURN_MILL, str(tmp_path_factory.mktemp("fmu") / "turn_mill.fmu"))


@pytest.fixture(scope="session")
def turn_mill_fmu(turn_mill_export: ExportResult) -> Path:
    return turn_mill_export.path


@pytest.fixture(scope="session")
def turn_mill_fmi3_export(tmp_path_factory: pytest.TempPathFactory) -> ExportResult:
    return export_fmu(TURN_MILL, str(tmp_path_factory.mktemp("fmu3") / "turn_mill.fmu"), fmi_version=3)


@pytest.fixture(scope="session")
def turn_mill_lean_export(tmp_path_factory: pytest.TempPathFactory) -> ExportResult:
    return export_fmu(TURN_MILL, str(tmp_path_factory.mktemp("fmu_lean") / "turn_mill.fmu"), PythonRuntime.HOST)


@pytest.fixture(params=VARIANTS)
def any_export(request: pytest.FixtureRequest) -> ExportResult:
    """Each FMU variant in turn."""
    name = {"fmi2": "turn_mill_export", "fmi3": "turn_mill_fmi3_export", "lean": "turn_mill_lean_export"}
    export: ExportResult = request.getfixturevalue(name[request.param])
    return export


@pytest.fixture(params=("fmi2", "lean"))
def fmi2_fmu(request: pytest.FixtureRequest) -> Path:
    """The self-contained and the lean FMI 2.0 FMU in turn: both must behave the same for a host."""
    export: ExportResult = request.getfixturevalue("turn_mill_export" if request.param == "fmi2"
                                                   else "turn_mill_lean_export")
    return export.path
