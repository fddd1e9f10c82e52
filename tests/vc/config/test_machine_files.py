"""Machines by name from any directory: package data, resolution, and a real wheel."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
import sysconfig
import zipfile
from pathlib import Path

import pytest

from vc.config.loader import load_machine
from vc.config.machine_files import DEFAULT_MACHINE, machine_file, packaged_machines
from vc.located_yaml import SourceError

ROOT = Path(__file__).resolve().parents[3]


def test_the_project_machines_are_packaged_and_the_scenario_library_reaches_the_same_files() -> None:
    assert packaged_machines() == ["gantry_mill", "mill_3axis", "mill_5axis", "turn_mill"]
    for name in packaged_machines():
        packaged = machine_file(name)
        assert packaged is not None and Path(packaged).is_file()
        # one home: scenarios/machines is the package's directory under another name
        assert (ROOT / "scenarios" / "machines" / f"{name}.yaml").resolve() == Path(packaged).resolve()


def test_a_name_loads_from_any_directory_and_keeps_the_name_as_source(tmp_path: Path,
                                                                       monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(tmp_path)
    machine = load_machine(DEFAULT_MACHINE)
    assert (machine.name, machine.source) == ("turn_mill", "turn_mill")
    assert [axis.name for axis in machine.axes] == ["X1", "Z1", "Y1", "SP1", "SP2", "SP3"]


def test_paths_stay_paths(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    copy = tmp_path / "mine.yaml"
    shutil.copyfile(ROOT / "vc" / "machines" / "mill_3axis.yaml", copy)
    monkeypatch.chdir(tmp_path)
    assert machine_file("mine.yaml") == "mine.yaml"
    assert load_machine("mine.yaml").source == "mine.yaml"
    assert machine_file("sub/turn_mill.yaml") == "sub/turn_mill.yaml"  # a path, even when it names no file
    with pytest.raises(SourceError) as error:
        load_machine("sub/turn_mill.yaml")
    assert "sub/turn_mill.yaml:1:1: cannot read the file" in str(error.value)


def test_an_unknown_name_lists_the_packaged_machines() -> None:
    assert machine_file("lathe") is None
    with pytest.raises(SourceError) as error:
        load_machine("lathe")
    assert str(error.value) == ("lathe:1:1: no machine file 'lathe' and no packaged machine of that name"
                                " (packaged: gantry_mill, mill_3axis, mill_5axis, turn_mill)")


def test_a_built_wheel_ships_the_machines_and_vc_map_finds_them_by_name(tmp_path: Path) -> None:
    """A plain (non-editable) install: build the wheel from a copy of the sources (pure Python: no
    setup.py, so nothing is compiled), install it into
    a directory of its own and run ``vc map --machine turn_mill`` from elsewhere with only that
    installation of the project on the path (``-S``: not the editable one of this environment)."""
    source = tmp_path / "source"
    source.mkdir()
    for name in ("pyproject.toml", "README.md"):
        shutil.copyfile(ROOT / name, source / name)
    for package in ("vc", "interfaces", "plc_stub", "fmu", "vc_build", "plc_awlsim", "awlsimhw_vcmodbus"):
        shutil.copytree(ROOT / package, source / package, ignore=shutil.ignore_patterns("__pycache__"))
    wheels = tmp_path / "wheels"
    subprocess.run([sys.executable, "-m", "pip", "wheel", "--no-build-isolation", "--no-deps", "-q",
                    "-w", str(wheels), str(source)], check=True, capture_output=True, timeout=240)
    (wheel,) = wheels.glob("vc_harness-*.whl")
    with zipfile.ZipFile(wheel) as archive:
        shipped = set(archive.namelist())
    assert {"vc/machines/turn_mill.yaml", "vc/machines/mill_3axis.yaml", "vc/machines/mill_5axis.yaml",
            "vc/machines/gantry_mill.yaml", "interfaces/catalog/db31_axis.yaml"} <= shipped

    installed = tmp_path / "installed"
    subprocess.run([sys.executable, "-m", "pip", "install", "--no-deps", "-q", "--target", str(installed),
                    str(wheel)], check=True, capture_output=True, timeout=240)
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    environment = {**os.environ, "PYTHONPATH": os.pathsep.join([str(installed), sysconfig.get_paths()["purelib"]])}
    result = subprocess.run([sys.executable, "-S", "-c", "import vc.cli.main as m, sys; sys.exit(m.main())",
                             "map", "--machine", "turn_mill", "--format", "csv"],
                            cwd=elsewhere, env=environment, capture_output=True, text=True, timeout=120)
    assert result.returncode == 0, result.stderr
    assert "X1.basic.in.enc1Synchronized,DB31.DBX60.4,nc_to_plc,bool,discrete_input,3092," in result.stdout
    where = subprocess.run([sys.executable, "-S", "-c", "from vc.config.machine_files import machine_file;"
                            " print(machine_file('turn_mill'))"], cwd=elsewhere, env=environment,
                           capture_output=True, text=True, timeout=60)
    assert Path(where.stdout.strip()).parent == installed / "vc" / "machines"
