"""The exported FMUs (self-contained FMI 2.0 and 3.0, lean): valid for FMPy, the same variables, the
same outputs as the unit in process, clear failures."""

from __future__ import annotations

import json
import os
import subprocess
import sys
import zipfile
from collections.abc import Callable
from pathlib import Path

import numpy as np
import pytest
from fmpy import read_model_description, simulate_fmu
from fmpy.validation import validate_fmu
from fmu_machines import REPOSITORY, TURN_MILL

from fmu.export import ExportResult, PythonRuntime, export_fmu
from fmu.instance import FmuError
from fmu.unit import Causality, Kind, NcUnit
from interfaces.catalog import load_catalog
from interfaces.signals import Direction, expand
from vc.config.loader import load_machine
from vc.located_yaml import SourceError

COMMUNICATION_STEP = 0.01  # one PLC cycle: 5 IPO cycles of 2 ms
REFERENCED = "X1.basic.in.enc1Synchronized"
Y1_REFERENCED = "Y1.basic.in.enc1Synchronized"
Y1_IN_POSITION = "Y1.basic.in.posFineReached"


# ------------------------------------------------------------------------------ the model description


def test_fmpy_validate_finds_no_problem(any_export: ExportResult) -> None:
    assert validate_fmu(str(any_export.path)) == []
    assert read_model_description(str(any_export.path)).fmiVersion == f"{any_export.fmi_version}.0"


def test_every_variant_has_the_same_variables(turn_mill_export: ExportResult, turn_mill_fmi3_export: ExportResult,
                                              turn_mill_lean_export: ExportResult) -> None:
    def variables(export: ExportResult) -> list[tuple[object, ...]]:
        described = read_model_description(str(export.path)).modelVariables
        return [(v.name, v.valueReference, v.causality, v.variability, v.initial or "", v.description,
                 {"Float64": "Real", "Int32": "Integer"}.get(v.type, v.type), _start(v.start))
                for v in described if v.causality != "independent"]

    fmi2 = variables(turn_mill_export)
    assert len(fmi2) == turn_mill_export.inputs + turn_mill_export.outputs + turn_mill_export.parameters
    assert variables(turn_mill_fmi3_export) == fmi2
    assert variables(turn_mill_lean_export) == fmi2
    time = [v for v in read_model_description(str(turn_mill_fmi3_export.path)).modelVariables
            if v.causality == "independent"]
    assert [(v.name, v.valueReference) for v in time] == [("time", len(fmi2))]  # after every other variable


def _start(text: str | None) -> object:
    """A start value as a number or a Boolean: pythonfmu writes 0 where this project writes 0.0."""
    if text in (None, "true", "false"):
        return text
    return float(text)


def test_every_signal_and_plant_point_is_a_variable_with_its_address(turn_mill_fmu: Path) -> None:
    description = read_model_description(str(turn_mill_fmu))
    variables = {variable.name: variable for variable in description.modelVariables}
    machine = load_machine(TURN_MILL)
    for signal in expand(load_catalog(), machine.layout).signals:
        variable = variables[signal.symbol]
        wanted = "input" if signal.direction is Direction.PLC_TO_NC else "output"
        assert (variable.causality, variable.description.split()[0]) == (wanted, str(signal.address))
    for point in machine.plant_io.points:
        variable = variables[point.name]
        wanted = "input" if point.direction is Direction.PLC_TO_PLANT else "output"
        assert (variable.causality, variable.description.split()[0]) == (wanted, str(point.address))
    assert variables["X1.basic.in.enc1Synchronized"].type == "Boolean"
    assert variables["X1.basic.out.feedrateOvrFactor"].type == "Integer"
    assert variables["SP1.spindle.in.sFuncValue"].type == "Real"  # DB31.DBD88, an S7 REAL
    assert variables["X1.position"].variability == "continuous"
    assert variables["X1.startPosition"].causality == "parameter"
    assert float(variables["X1.startPosition"].start) == 150.0  # the machine file's sim: start_position
    assert float(variables["ipoCycle"].start) == 0.002


def test_output_start_values_are_the_power_on_state(turn_mill_fmu: Path) -> None:
    description = read_model_description(str(turn_mill_fmu))
    starts = {variable.name: variable.start for variable in description.modelVariables}
    assert starts["NC.basic.in.ncReady"] == "true"
    assert starts["X1.basic.in.enc1Synchronized"] == "false"
    assert float(starts["X1.physical"]) == 150.0 and float(starts["Z1.physical"]) == 300.0
    assert starts["EStop.chainOk"] == "true"


def test_value_references_follow_the_units_variables(turn_mill_fmu: Path, turn_mill_export: ExportResult) -> None:
    description = read_model_description(str(turn_mill_fmu))
    unit = NcUnit(TURN_MILL)
    assert [(v.valueReference, v.name) for v in description.modelVariables] == \
        [(index, variable.name) for index, variable in enumerate(unit.variables)]
    counts = (turn_mill_export.inputs, turn_mill_export.outputs, turn_mill_export.parameters)
    assert counts == tuple(sum(1 for v in unit.variables if v.causality is c)
                           for c in (Causality.INPUT, Causality.OUTPUT, Causality.PARAMETER))


def test_the_self_contained_fmu_carries_the_machine_its_code_pyyaml_and_a_python_runtime(
        turn_mill_fmu: Path, turn_mill_export: ExportResult) -> None:
    with zipfile.ZipFile(turn_mill_fmu) as archive:
        names = archive.namelist()
        manifest = json.loads(archive.read("resources/vc_fmu.json"))
        machine = archive.read("resources/machine/turn_mill.yaml")
        python = archive.getinfo("resources/runtime/bin/python")
        description = read_model_description(str(turn_mill_fmu))
        bundle = turn_mill_export.bundle
        for name in names:
            if name.startswith(f"resources/{bundle}/") and name.endswith(".py"):
                text = archive.read(name).decode()
                assert "from vc." not in text and "from interfaces." not in text, name
    assert manifest["model"] == "turn_mill" and manifest["machine"] == "machine/turn_mill.yaml"
    assert manifest["token"] == description.guid and manifest["fmi"] == [2]
    assert machine == Path(TURN_MILL).read_bytes()
    assert f"resources/{bundle}/vc/core/nck/nck.py" in names
    assert f"resources/{bundle}/vc/core/nck/__pycache__/nck.{sys.implementation.cache_tag}.pyc" in names
    assert f"resources/{bundle}/interfaces/catalog/db31_axis.yaml" in names
    assert "resources/vc_nc_worker.py" in names and "resources/yaml/composer.py" in names
    assert "binaries/linux64/turn_mill.so" in names
    assert python.external_attr >> 16 == 0o100755  # executable for hosts that restore file modes
    assert "resources/runtime/bin/python._pth" in names
    assert f"resources/runtime/lib/python{sys.version_info.major}{sys.version_info.minor}.zip" in names
    assert not [name for name in names if "/vc/scenario/" in name or "/plc_stub/" in name]  # only what the NC needs
    assert not [name for name in names if "pythonfmu" in name]
    assert turn_mill_export.size < 40e6


def test_the_lean_fmu_carries_the_machine_and_its_code_under_a_name_of_its_own(
        turn_mill_lean_export: ExportResult) -> None:
    with zipfile.ZipFile(turn_mill_lean_export.path) as archive:
        names = archive.namelist()
        manifest = json.loads(archive.read("resources/vc_fmu.json"))
        bundle = turn_mill_lean_export.bundle
        for name in names:
            if name.startswith(f"resources/{bundle}/") and name.endswith(".py"):
                text = archive.read(name).decode()
                assert "from vc." not in text and "from interfaces." not in text, name
    assert manifest["model"] == "turn_mill" and manifest["machine"] == "machine/turn_mill.yaml"
    assert f"resources/{bundle}/vc/core/nck/nck.py" in names
    assert f"resources/vc_nc_{bundle.removeprefix('vc_fmu_')}.py" in names
    assert "binaries/linux64/turn_mill.so" in names
    assert not [name for name in names if "/vc/scenario/" in name or "/plc_stub/" in name]
    assert not [name for name in names if "/runtime/" in name or "/yaml/" in name]  # the host's Python runs it


def test_without_the_binary_built_at_installation_the_export_says_what_to_do(monkeypatch: pytest.MonkeyPatch,
                                                                            tmp_path: Path) -> None:
    import fmu.export

    monkeypatch.setattr(fmu.export, "NATIVE_MODULE", "fmu._vc_fmi_never_built")
    with pytest.raises(FmuError, match=r"install a C compiler .*; or export the lean FMU with --python host"):
        export_fmu(TURN_MILL, str(tmp_path / "no_binary.fmu"))
    assert not (tmp_path / "no_binary.fmu").exists()


def test_the_export_copies_the_python_source_where_a_compiled_module_stands_beside_it(tmp_path: Path) -> None:
    from importlib.machinery import EXTENSION_SUFFIXES, ModuleSpec

    from fmu.export import _python_source

    compiled = tmp_path / f"nck{EXTENSION_SUFFIXES[0]}"
    compiled.write_bytes(b"\x7fELF")
    (tmp_path / "nck.py").write_text("CYCLE = 1\n")
    assert _python_source(ModuleSpec("vc.core.nck.nck", None, origin=str(compiled))) == tmp_path / "nck.py"
    assert _python_source(ModuleSpec("vc.core.nck.nck", None, origin=str(tmp_path / "nck.py"))) == tmp_path / "nck.py"
    (tmp_path / "nck.py").unlink()
    assert _python_source(ModuleSpec("vc.core.nck.nck", None, origin=str(compiled))) is None


def test_the_same_code_and_machine_give_the_same_token(tmp_path: Path, turn_mill_export: ExportResult) -> None:
    again = export_fmu(TURN_MILL, str(tmp_path / "again.fmu"))
    assert read_model_description(str(again.path)).guid == read_model_description(str(turn_mill_export.path)).guid


def test_a_machine_file_with_problems_is_refused_with_its_location(tmp_path: Path) -> None:
    broken = tmp_path / "broken.yaml"
    broken.write_text(Path(TURN_MILL).read_text().replace("MD32000 MAX_AX_VELO: 30000", "MD32000 MAX_AX_VELO: -5", 1))
    with pytest.raises(SourceError) as raised:
        export_fmu(str(broken), str(tmp_path / "broken.fmu"))
    assert "broken.yaml:" in str(raised.value) and "MD32000" in str(raised.value)
    assert not (tmp_path / "broken.fmu").exists()


def test_the_command_line_exports_and_says_what_it_wrote(tmp_path: Path) -> None:
    output = tmp_path / "cli" / "mill.fmu"
    done = subprocess.run([sys.executable, "-m", "vc.cli.main", "fmu", "export", "--machine",
                           str(REPOSITORY / "scenarios/machines/mill_3axis.yaml"), "-o", str(output)],
                          capture_output=True, text=True, timeout=120, cwd=tmp_path)
    assert done.returncode == 0, done.stderr
    assert f"{output}: FMI 2.0 co-simulation FMU 'mill_3axis' (self-contained" in done.stdout
    assert "linux64 needs glibc >= 2." in done.stdout
    assert validate_fmu(str(output)) == []


def test_the_command_line_exports_fmi_3_and_refuses_a_lean_fmi_3_fmu(tmp_path: Path) -> None:
    def export(*options: str) -> subprocess.CompletedProcess[str]:
        return subprocess.run([sys.executable, "-m", "vc.cli.main", "fmu", "export", "--machine",
                               str(REPOSITORY / "scenarios/machines/mill_3axis.yaml"), "-o", str(tmp_path / "m.fmu"),
                               *options], capture_output=True, text=True, timeout=120, cwd=tmp_path)

    done = export("--fmi", "3")
    assert done.returncode == 0, done.stderr
    assert "FMI 3.0 co-simulation FMU 'mill_3axis' (self-contained" in done.stdout
    assert validate_fmu(str(tmp_path / "m.fmu")) == []
    refused = export("--fmi", "3", "--python", "host")
    assert refused.returncode == 2
    assert "vc fmu export: the lean FMU (--python host) is built by pythonfmu, which knows FMI 2.0 only" \
        in refused.stderr


# ------------------------------------------------------------------------------ simulation: FMU == unit


class PlcLessHost:
    """A host that plays the PLC's part for one axis: enables, JOG-REF, the plus key, the cam.
    The inclined Y1 of turn_mill goes first (its minus key, its cam): X1 may be referenced only
    while Y1 stands at its reference point (seed 000 L375)."""

    def __init__(self, read: Callable[[str], float | int | bool]):
        self.read = read

    def inputs(self, time: float) -> dict[str, float | int | bool]:
        override = int(self.read("MCP.feedOverride"))
        return {
            "Drives.on": True,
            "NC.basic.out.emergencyStop": False,
            "MODEGROUP.basic.out.jogMode": True,
            "MODEGROUP.basic.out.refPoint": time >= 0.05,
            "CHAN1.basic.out.pathFeedrateOvr": True,
            "CHAN1.basic.out.pathFeedrateOvrFactor": override,
            "X1.basic.out.enc1Activation": True,
            "X1.basic.out.enableCtrl": bool(self.read("Drives.ready")),
            "X1.drive.out.enablePulses": bool(self.read("Drives.ready")),
            "X1.basic.out.enableOvr": True,
            "X1.basic.out.feedrateOvrFactor": override,
            "Y1.basic.out.enc1Activation": True,
            "Y1.basic.out.enableCtrl": bool(self.read("Drives.ready")),
            "Y1.drive.out.enablePulses": bool(self.read("Drives.ready")),
            "Y1.basic.out.enableOvr": True,
            "Y1.basic.out.feedrateOvrFactor": override,
            # JOG-REF: a key is held until its axis is referenced (MD11300 = 0); X1 after Y1 stands
            "Y1.basic.out.traversKeyMinus": time >= 0.1 and not self.read(Y1_REFERENCED),
            "Y1.basic.out.refPointApproachCam": bool(self.read("Y1.refCam")),
            "X1.basic.out.traversKeyPlus": bool(self.read(Y1_REFERENCED)) and bool(self.read(Y1_IN_POSITION))
            and not self.read(REFERENCED),
            "X1.basic.out.refPointApproachCam": bool(self.read("X1.refCam")),  # wired through, one step late
        }


def _run_in_process(stop_time: float) -> tuple[dict[str, list[float]], dict[str, list[float | int | bool]]]:
    """The host's sequence on the unit itself; returns the outputs per communication point and
    the inputs it set (the input table for the FMU)."""
    unit = NcUnit(TURN_MILL)
    index = {variable.name: position for position, variable in enumerate(unit.variables)}
    outputs = [v for v in unit.variables if v.causality is Causality.OUTPUT]
    host = PlcLessHost(lambda name: unit.get(index[name]))
    unit.setup(0.0)
    unit.initialize()
    recorded: dict[str, list[float]] = {"time": [0.0]}
    for variable in outputs:
        recorded[variable.name] = [float(unit.get(index[variable.name]))]
    table: dict[str, list[float | int | bool]] = {"time": []}
    steps = round(stop_time / COMMUNICATION_STEP)
    for step in range(steps):
        time = step * COMMUNICATION_STEP
        table["time"].append(time)
        for name, value in host.inputs(time).items():
            unit.set(index[name], value)
            table.setdefault(name, []).append(value)
        unit.step(time, COMMUNICATION_STEP)
        recorded["time"].append(unit.time)
        for variable in outputs:
            recorded[variable.name].append(float(unit.get(index[variable.name])))
    return recorded, table


def _input_array(table: dict[str, list[float | int | bool]], unit: NcUnit) -> np.ndarray:
    kinds = {variable.name: variable.kind for variable in unit.variables}
    types = {Kind.BOOLEAN: np.bool_, Kind.INTEGER: np.int32, Kind.REAL: np.float64}
    dtype = [("time", np.float64)] + [(name, types[kinds[name]]) for name in table if name != "time"]
    rows = list(zip(*table.values(), strict=True))
    return np.array(rows, dtype=dtype)


def test_fmpy_simulation_references_x1_exactly_as_the_unit_in_process(any_export: ExportResult) -> None:
    turn_mill_fmu = any_export.path
    stop_time = 9.0  # Y1 first (about 4 s), then X1
    expected, table = _run_in_process(stop_time)
    referenced_at = expected["time"][expected[REFERENCED].index(1.0)]
    assert 4.0 < referenced_at < stop_time  # the table really references X1 (after Y1) ...
    assert expected["X1.position"][-1] == pytest.approx(273.0, abs=1e-3)  # ... to MD34100 = 273
    result = simulate_fmu(str(turn_mill_fmu), start_time=0.0, stop_time=stop_time,
                          output_interval=COMMUNICATION_STEP, input=_input_array(table, NcUnit(TURN_MILL)),
                          output=[name for name in expected if name != "time"])
    assert len(result) == len(expected["time"])
    assert np.allclose(result["time"], expected["time"], rtol=0, atol=1e-9)
    different = [name for name in expected if name != "time"
                 and not np.array_equal(result[name].astype(np.float64), np.array(expected[name]))]
    assert different == []  # every output, every communication point, bit for bit


# ------------------------------------------------------------------------------ failures through the FMI logger


def _simulate_in_subprocess(fmu: Path, code: str) -> subprocess.CompletedProcess[str]:
    """FMPy in a process of its own, so that a failure could never take the test runner with it."""
    script = f"""
import sys
from fmpy import simulate_fmu
messages = []
def logger(component, instance, status, category, message):
    messages.append((status, message.decode()))
try:
{code}
    outcome = "ok"
except Exception as error:
    outcome = f"raised {{type(error).__name__}}: {{error}}"
print(outcome)
for status, message in messages:
    print(f"log {{status}}: {{message}}")
"""
    return subprocess.run([sys.executable, "-c", script.replace("FMU", repr(str(fmu)))],
                          capture_output=True, text=True, timeout=120)


def test_a_step_that_is_no_whole_number_of_ipo_cycles_is_refused_through_the_logger(fmi2_fmu: Path) -> None:
    done = _simulate_in_subprocess(fmi2_fmu, "    simulate_fmu(FMU, stop_time=0.02, output_interval=0.003,"
                                                  " logger=logger, debug_logging=True, output=['X1.position'])")
    assert done.returncode == 0, done.stderr
    reason = ("the communication step 0.003 s is not a whole number of IPO cycles of 2 ms;"
              " use a multiple such as 0.004 s")
    assert f"log 3: {reason}" in done.stdout.splitlines()  # fmi2Error, with the unit's reason
    assert f"turn_mill: {reason}" in done.stderr  # also for a host that has logging off


def test_the_fmu_answers_a_refused_step_with_discard_and_goes_on(turn_mill_fmu: Path, tmp_path: Path) -> None:
    from fmpy import extract
    from fmpy.fmi2 import FMU2Slave

    description = read_model_description(str(turn_mill_fmu))
    reference = {variable.name: variable.valueReference for variable in description.modelVariables}
    slave = FMU2Slave(guid=description.guid, unzipDirectory=extract(str(turn_mill_fmu), str(tmp_path)),
                      modelIdentifier=description.coSimulation.modelIdentifier, instanceName="refused")
    slave.instantiate()
    slave.setupExperiment(startTime=0.0)
    slave.enterInitializationMode()
    slave.exitInitializationMode()
    slave.doStep(currentCommunicationPoint=0.0, communicationStepSize=0.01)
    with pytest.raises(Exception, match="discard"):
        slave.doStep(currentCommunicationPoint=0.01, communicationStepSize=0.003)
    slave.doStep(currentCommunicationPoint=0.01, communicationStepSize=0.01)  # the NC is still at t = 0.01 s
    assert slave.getBoolean([reference["NC.basic.in.ncReady"]]) == [True]
    with pytest.raises(Exception, match="discard"):
        slave.doStep(currentCommunicationPoint=0.5, communicationStepSize=0.01)  # a jump ahead
    slave.terminate()
    slave.freeInstance()


def test_a_machine_that_does_not_load_fails_instantiation_with_its_location(fmi2_fmu: Path, tmp_path: Path) -> None:
    turn_mill_fmu = fmi2_fmu
    damaged = tmp_path / "damaged.fmu"
    with zipfile.ZipFile(turn_mill_fmu) as source, zipfile.ZipFile(damaged, "w") as target:
        for item in source.infolist():
            data = source.read(item)
            if item.filename == "resources/machine/turn_mill.yaml":
                data = data.replace(b"MD32000 MAX_AX_VELO: 30000", b"MD32000 MAX_AX_VELO: [1, 2", 1)
            target.writestr(item, data)
    done = _simulate_in_subprocess(damaged, "    simulate_fmu(FMU, stop_time=0.02, logger=logger, debug_logging=True)")
    assert done.returncode == 0, done.stderr
    assert done.stdout.splitlines()[0] == "raised Exception: Failed to instantiate model"
    assert "log 4: " in done.stdout and "the machine does not load" in done.stdout, done.stdout
    assert "turn_mill.yaml:" in done.stdout  # with file, line and column of the problem


def test_bad_parameters_end_initialisation_with_the_reason(fmi2_fmu: Path) -> None:
    done = _simulate_in_subprocess(fmi2_fmu, "    simulate_fmu(FMU, stop_time=0.02, logger=logger,"
                                                  " debug_logging=True, start_values={'ipoCycle': 5.0})")
    assert done.returncode == 0, done.stderr
    assert "fmi2ExitInitializationMode failed with status 4 (fatal)" in done.stdout.splitlines()[0]
    assert "<FMU parameters>:1:" in done.stdout and "MD10050" in done.stdout, done.stdout
    assert "<FMU parameters>:1:" in done.stderr


def test_a_value_out_of_range_is_reported_and_not_taken(fmi2_fmu: Path) -> None:
    done = _simulate_in_subprocess(fmi2_fmu, "    simulate_fmu(FMU, stop_time=0.02, logger=logger,"
                                                  " start_values={'X1.basic.out.feedrateOvrFactor': 300})")
    assert done.returncode == 0, done.stderr
    assert done.stdout.splitlines()[0] == "ok"  # the simulation goes on
    assert "X1.basic.out.feedrateOvrFactor is a byte; 300 is outside 0..255; the value was not taken" in done.stderr


# ------------------------------------------------------------------------------ module shadowing


SHADOWING_HOST = """
import sys, types
# the host has its own modules called vc and interfaces (an older harness, or anything else)
for name in ("vc", "interfaces", "fmu"):
    sys.modules[name] = types.ModuleType(name)
sys.modules["vc"].__path__ = []
from fmpy import simulate_fmu
result = simulate_fmu(FMU, stop_time=0.1, start_values={"X1.startPosition": 42.0}, output=["X1.physical"])
print(result["X1.physical"][-1])
print(sorted({name.split(".")[0] for name in sys.modules if name.startswith("vc_fmu_")}))
print(type(sys.modules["vc"]).__name__, hasattr(sys.modules["vc"], "core"))
"""


def test_a_host_with_its_own_vc_modules_does_not_shadow_the_fmu(any_export: ExportResult) -> None:
    done = subprocess.run([sys.executable, "-c", SHADOWING_HOST.replace("FMU", repr(str(any_export.path)))],
                          capture_output=True, text=True, timeout=120, env={**os.environ, "PYTHONPATH": ""})
    assert done.returncode == 0, done.stderr
    physical, bundles, host_vc = done.stdout.splitlines()
    assert float(physical) == 42.0
    # the lean FMU's code lives in the host's Python under its own name; the self-contained one's never
    # enters the host
    assert bundles == repr([any_export.bundle] if any_export.python is PythonRuntime.HOST else [])
    assert host_vc == "module False"  # the host's vc is untouched


def test_a_host_that_imported_the_project_runs_the_lean_fmu_beside_it(turn_mill_lean_export: ExportResult) -> None:
    import vc.core.nck.nck

    result = simulate_fmu(str(turn_mill_lean_export.path), stop_time=0.05, output=["X1.physical"])
    assert result["X1.physical"][-1] == 150.0
    bundled = [module for name, module in sys.modules.items() if name.endswith(".vc.core.nck.nck")]
    assert bundled and all(module is not vc.core.nck.nck for module in bundled)
