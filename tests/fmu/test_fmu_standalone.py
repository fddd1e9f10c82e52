"""The self-contained FMU outside of any Python: independent hosts, instances, isolation, failures.

* Ecos's command-line host (``ecos simulate``, a C++ program from the ``ecospy`` package) and
  libcosim (``libcosimpy``: the Open Simulation Platform's C++ library through its Python wrapper)
  play a JOG of X1 through the FMU's inputs; the trajectory must be the unit's in process.  Ecos
  runs with an empty environment (``env -i``).
* Two instances in one host, and an instance freed and made again, as FMPy's low-level API does it.
* The worker's isolation: its interpreter, standard library and PyYAML are the FMU's, whatever the
  host has; a host Python without PyYAML runs the FMU.
* A worker that dies is reported as ``fmi2Fatal`` with the reason, and the host can free the instance.
* The glibc floor of every binary in the FMU, read with ``fmu/elf.py`` and checked against objdump.
"""

from __future__ import annotations

import csv
import os
import shutil
import signal
import subprocess
import sys
import textwrap
import zipfile
from collections.abc import Iterator
from pathlib import Path

import pytest
from fmpy import calloc as fmpy_calloc
from fmpy import extract, read_model_description
from fmpy import free as fmpy_free
from fmpy.fmi2 import (
    FMU2Slave,
    fmi2CallbackAllocateMemoryTYPE,
    fmi2CallbackFreeMemoryTYPE,
    fmi2CallbackFunctions,
    fmi2CallbackLoggerTYPE,
)
from fmu_machines import TURN_MILL

from fmu.elf import needs
from fmu.export import ExportResult
from fmu.unit import NcUnit

TIMEOUT_S = 120
STEP_S = 0.01
STOP_S = 1.0
# The JOG of X1 the independent hosts play, as (time, variable, value): what a basic PLC program sets
# at power-on, the enables once the drives are ready, the plus key held from 0.2 s to 0.7 s.
JOG = [
    (0.0, "Drives.on", True), (0.0, "MODEGROUP.basic.out.jogMode", True),
    (0.0, "CHAN1.basic.out.pathFeedrateOvr", True), (0.0, "CHAN1.basic.out.pathFeedrateOvrFactor", 100),
    (0.0, "X1.basic.out.enc1Activation", True), (0.0, "X1.basic.out.enableOvr", True),
    (0.0, "X1.basic.out.feedrateOvrFactor", 100),
    (0.15, "X1.basic.out.enableCtrl", True), (0.15, "X1.drive.out.enablePulses", True),
    (0.2, "X1.basic.out.traversKeyPlus", True), (0.7, "X1.basic.out.traversKeyPlus", False),
]
JOG_DISTANCE_MM = 2000.0 / 60.0 * 0.5  # MD32020 JOG_VELO 2000 mm/min for 0.5 s
GLIBC_FLOOR_OF_THE_BINARY = (2, 17)  # manylinux2014: the FMU's own C library stays at or below it


def jog_in_process(stop_s: float = STOP_S) -> dict[int, float]:
    """X1.physical after each step (by step count; 0 = after initialisation) of the JOG on the unit."""
    unit = NcUnit(TURN_MILL)
    index = {variable.name: position for position, variable in enumerate(unit.variables)}
    unit.setup(0.0)
    unit.initialize()
    physical = {0: float(unit.get(index["X1.physical"]))}
    for step in range(round(stop_s / STEP_S)):
        for time, name, value in JOG:
            if round(time / STEP_S) == step:
                unit.set(index[name], value)
        unit.step(step * STEP_S, STEP_S)
        physical[step + 1] = float(unit.get(index["X1.physical"]))
    return physical


# ---------------------------------------------------------------------------------------------- Ecos


@pytest.fixture(scope="module")
def ecos(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """Ecos's command-line host, copied out of the ecospy package (which ships it without execute bit)."""
    try:
        import ecospy
    except ImportError:
        assert not os.environ.get("VC_REQUIRE_ECOS"), "ecospy is required here (VC_REQUIRE_ECOS is set)"
        pytest.skip("ecospy (Ecos) is not installed: pip install -e '.[test]'")
    shipped = Path(ecospy.__file__).parent / "binaries" / "ecos"
    executable = tmp_path_factory.mktemp("ecos") / "ecos"
    shutil.copyfile(shipped, executable)
    executable.chmod(0o755)
    probe = subprocess.run([str(executable), "--version"], capture_output=True, text=True, env={}, timeout=TIMEOUT_S)
    if "libtbb.so.12" in probe.stderr and not os.environ.get("VC_REQUIRE_ECOS"):
        pytest.skip("Ecos needs Debian's libtbb12 (.ci/run installs it)")
    assert probe.returncode == 0, probe.stderr
    return executable


def ecos_scenario() -> str:
    kinds = {bool: "boolean", int: "integer", float: "real"}
    actions = []
    for time in sorted({time for time, _, _ in JOG}):
        variables = "".join(
            f'<ecos:Variable id="instance::{name}"><ecos:{kinds[type(value)]} value="{str(value).lower()}"/>'
            "</ecos:Variable>" for at, name, value in JOG if at == time)
        actions.append(f'<ecos:Action t="{time}">{variables}</ecos:Action>')
    return ('<?xml version="1.0" encoding="UTF-8"?>\n<ecos:Scenario xmlns:ecos="http://github.com/Ecos-platform/ecos">'
            + "".join(actions) + "</ecos:Scenario>\n")


def test_ecos_with_an_empty_environment_runs_the_default_experiment(ecos: Path, turn_mill_fmu: Path,
                                                                   tmp_path: Path) -> None:
    """The issue's acceptance run: ``env -i ecos simulate --path turn_mill.fmu --stepSize 0.01 --stopTime 1``."""
    done = subprocess.run([str(ecos), "simulate", "--path", str(turn_mill_fmu), "--stepSize", "0.01", "--stopTime",
                           "1"], capture_output=True, text=True, env={}, cwd=tmp_path, timeout=TIMEOUT_S)
    assert done.returncode == 0, done.stdout + done.stderr
    with (tmp_path / "turn_mill.csv").open() as table:
        rows = list(csv.DictReader(table, skipinitialspace=True))
    assert len(rows) >= 100
    assert {float(row["instance::X1.physical[REAL]"]) for row in rows} == {150.0}  # no PLC: nothing moves
    assert {row["instance::NC.basic.in.ncReady[BOOL]"] for row in rows} == {"1"}


def test_ecos_with_an_empty_environment_jogs_x1_as_the_unit_in_process(ecos: Path, turn_mill_fmu: Path,
                                                                       tmp_path: Path) -> None:
    (tmp_path / "jog.xml").write_text(ecos_scenario())
    done = subprocess.run([str(ecos), "simulate", "--path", str(turn_mill_fmu), "--stepSize", str(STEP_S),
                           "--stopTime", str(STOP_S), "--scenarioConfig", "jog.xml", "-l", "warn"],
                          capture_output=True, text=True, env={}, cwd=tmp_path, timeout=TIMEOUT_S)
    assert done.returncode == 0, done.stdout + done.stderr
    assert "No variable with id" not in done.stdout + done.stderr
    with (tmp_path / "turn_mill.csv").open() as table:
        rows = list(csv.DictReader(table, skipinitialspace=True))
    expected = jog_in_process()
    trajectory = {round(float(row["time"]) / STEP_S): float(row["instance::X1.physical[REAL]"]) for row in rows}
    assert len(trajectory) >= 99
    mismatches = [f"t={step * STEP_S:g}: Ecos {value}, in process {expected[step]}"
                  for step, value in trajectory.items() if abs(value - expected[step]) > 1e-6]  # Ecos writes %f
    assert not mismatches, "\n".join(mismatches[:10])
    assert max(trajectory.values()) - trajectory[0] == pytest.approx(JOG_DISTANCE_MM, abs=1e-3)


# ---------------------------------------------------------------------------------------------- libcosim

LIBCOSIM_HOST = """
import json, sys
from libcosimpy.CosimExecution import CosimExecution
from libcosimpy.CosimManipulator import CosimManipulator
from libcosimpy.CosimObserver import CosimObserver
from libcosimpy.CosimSlave import CosimLocalSlave

jog, step_s, stop_s = json.loads(sys.argv[2])
execution = CosimExecution.from_step_size(step_size=round(step_s * 1e9))
index = execution.add_local_slave(CosimLocalSlave(fmu_path=sys.argv[1], instance_name="nc"))
observer = CosimObserver.create_last_value()
execution.add_observer(observer)
override = CosimManipulator.create_override()
execution.add_manipulator(override)
reference = {variable.name.decode(): variable.reference for variable in execution.slave_variables(index)}
trajectory = []
for step in range(round(stop_s / step_s)):
    for time, name, value in jog:
        if round(time / step_s) == step:
            setter = override.slave_boolean_values if isinstance(value, bool) else override.slave_integer_values
            setter(index, [reference[name]], [value])
    assert execution.simulate_until(target_time=round((step + 1) * step_s * 1e9))
    trajectory.append(observer.last_real_values(index, [reference["X1.physical"]])[0])
print("trajectory", json.dumps(trajectory))  # libcosim logs to standard output as well
"""


def test_libcosim_jogs_x1_as_the_unit_in_process(turn_mill_fmu: Path) -> None:
    pytest.importorskip("libcosimpy", reason="libcosimpy (libcosim) is not installed: pip install -e '.[test]'")
    import json

    done = subprocess.run([sys.executable, "-c", LIBCOSIM_HOST, str(turn_mill_fmu), json.dumps([JOG, STEP_S, STOP_S])],
                          capture_output=True, text=True, timeout=TIMEOUT_S)
    assert done.returncode == 0, done.stderr[-3000:]
    (line,) = [line for line in done.stdout.splitlines() if line.startswith("trajectory ")]
    trajectory = json.loads(line.removeprefix("trajectory "))
    expected = jog_in_process()
    assert trajectory == [expected[step + 1] for step in range(len(trajectory))]  # after each step, to the bit
    assert trajectory[-1] - expected[0] == pytest.approx(JOG_DISTANCE_MM, abs=1e-3)


# ---------------------------------------------------------------------------------------------- FMPy


class Instance:
    """One instance of the FMU through FMPy's low-level API, with its log."""

    def __init__(self, unzipped: Path, name: str):
        description = read_model_description(str(unzipped))
        self.reference = {variable.name: variable.valueReference for variable in description.modelVariables}
        self.messages: list[tuple[int, str]] = []
        self.slave = FMU2Slave(guid=description.guid, unzipDirectory=str(unzipped),
                               modelIdentifier=description.coSimulation.modelIdentifier, instanceName=name)
        self.callbacks = fmi2CallbackFunctions()  # kept: the FMU calls them as long as it lives
        self.callbacks.logger = fmi2CallbackLoggerTYPE(self._log)
        self.callbacks.allocateMemory = fmi2CallbackAllocateMemoryTYPE(fmpy_calloc)
        self.callbacks.freeMemory = fmi2CallbackFreeMemoryTYPE(fmpy_free)
        self.slave.instantiate(callbacks=self.callbacks, loggingOn=True)

    def _log(self, environment: object, instance: bytes, status: int, category: bytes, message: bytes) -> None:
        self.messages.append((status, message.decode()))

    def start(self, **parameters: float) -> None:
        for name, value in parameters.items():
            self.slave.setReal([self.reference[name]], [value])
        self.slave.setupExperiment(startTime=0.0)
        self.slave.enterInitializationMode()
        self.slave.exitInitializationMode()

    def physical(self) -> float:
        value: float = self.slave.getReal([self.reference["X1.physical"]])[0]
        return value

    def jog_step(self, step: int) -> None:
        for time, name, value in JOG:
            if round(time / STEP_S) == step:
                setter = self.slave.setBoolean if isinstance(value, bool) else self.slave.setInteger
                setter([self.reference[name]], [value])
        self.slave.doStep(currentCommunicationPoint=step * STEP_S, communicationStepSize=STEP_S)


@pytest.fixture(scope="module")
def unzipped(turn_mill_fmu: Path, tmp_path_factory: pytest.TempPathFactory) -> Path:
    return Path(extract(str(turn_mill_fmu), str(tmp_path_factory.mktemp("unzipped"))))


def workers() -> list[int]:
    """This process's children that run an FMU's bundled runtime."""
    children: list[int] = []
    for task in Path(f"/proc/{os.getpid()}/task").iterdir():
        children += [int(pid) for pid in (task / "children").read_text().split()]
    return [pid for pid in children if _cmdline(pid)[:1] and _cmdline(pid)[0].endswith("/runtime/bin/python")]


def _cmdline(pid: int) -> list[str]:
    try:
        return Path(f"/proc/{pid}/cmdline").read_bytes().decode().split("\0")
    except OSError:
        return []


@pytest.fixture
def instances() -> Iterator[list[Instance]]:
    made: list[Instance] = []
    yield made
    for instance in made:
        instance.slave.freeInstance()


def test_two_instances_in_one_host_are_two_independent_ncs(unzipped: Path, instances: list[Instance]) -> None:
    jogging, standing = Instance(unzipped, "jogging"), Instance(unzipped, "standing")
    instances += [jogging, standing]
    jogging.start()
    standing.start(**{"X1.startPosition": 200.0})
    assert len(workers()) == 2  # one worker process each
    expected = jog_in_process(0.8)
    for step in range(80):
        jogging.jog_step(step)
        standing.slave.doStep(currentCommunicationPoint=step * STEP_S, communicationStepSize=STEP_S)
        assert jogging.physical() == expected[step + 1]
        assert standing.physical() == 200.0
    assert jogging.messages == [] and standing.messages == []


def test_an_instance_freed_and_made_again_starts_from_power_on(unzipped: Path) -> None:
    expected = jog_in_process(0.5)
    for attempt in range(2):
        instance = Instance(unzipped, f"attempt{attempt}")
        instance.start()
        for step in range(50):
            instance.jog_step(step)
        assert instance.physical() == expected[50]
        instance.slave.terminate()
        instance.slave.freeInstance()
        assert workers() == []  # the worker ended with its instance


def test_the_worker_runs_the_fmus_own_interpreter_library_and_nothing_of_the_hosts(
        unzipped: Path, instances: list[Instance]) -> None:
    instance = Instance(unzipped, "isolated")
    instances.append(instance)
    instance.start()
    (pid,) = workers()
    arguments = _cmdline(pid)
    assert arguments[1:4] == ["-I", "-S", "-B"]  # isolated, no site, no bytecode written into the FMU
    environment = Path(f"/proc/{pid}/environ").read_bytes().decode().split("\0")
    assert [entry for entry in environment if entry] == [f"LD_LIBRARY_PATH={unzipped}/resources/runtime/lib"]
    mapped = {line.split(maxsplit=5)[5] for line in Path(f"/proc/{pid}/maps").read_text().splitlines()
              if len(line.split(maxsplit=5)) == 6 and line.split(maxsplit=5)[5].startswith("/")}
    foreign = [path for path in mapped if not path.startswith(str(unzipped)) and not _glibc_file(path)]
    assert foreign == [], "the worker mapped files from outside the FMU and glibc"
    assert any(path.startswith(f"{unzipped}/resources/runtime/lib/libpython") for path in mapped) or \
        not any("libpython" in path for path in mapped)


def _glibc_file(path: str) -> bool:
    """glibc's libraries and its locale data (Python coerces an empty locale to C.UTF-8)."""
    name = Path(path).name
    return (name.split(".so")[0] in {"libc", "libm", "ld-linux-x86-64"} or path.startswith("/usr/lib/locale/")
            or "/gconv/" in path)


def test_the_bundled_interpreters_path_is_the_fmus_alone(unzipped: Path) -> None:
    runtime = unzipped / "resources" / "runtime"
    python = runtime / "bin" / "python"
    python.chmod(0o755)  # FMPy's extract drops file modes; the FMU's binary restores the bit the same way
    done = subprocess.run([str(python), "-I", "-S", "-B", "-c",
                           "import sys, json, yaml, math; print(sys.prefix); print(yaml.__file__);"
                           " print(*sys.path, sep='\\n')"],
                          capture_output=True, text=True, env={"LD_LIBRARY_PATH": str(runtime / "lib")},
                          timeout=TIMEOUT_S)
    assert done.returncode == 0, done.stderr
    prefix, yaml_file, *path = done.stdout.splitlines()
    assert prefix.startswith(str(unzipped))
    resources = str(unzipped / "resources")
    assert yaml_file.startswith(f"{resources}/yaml/")
    assert path and all(entry.startswith(resources) for entry in path), path


HOST_WITHOUT_PYYAML = """
import sys
sys.modules["yaml"] = None  # this host's Python has no PyYAML
from fmpy import simulate_fmu
try:
    result = simulate_fmu(FMU, stop_time=0.1, start_values={"X1.startPosition": 42.0}, output=["X1.physical"])
    print(result["X1.physical"][-1])
except Exception as error:
    print(f"failed: {error}")
print(sorted(name for name in sys.modules if name.split(".")[0] in ("vc", "interfaces", "fmu")
             or name.startswith("vc_fmu_")))
"""


def test_a_host_python_without_pyyaml_runs_the_self_contained_fmu_but_not_the_lean_one(
        turn_mill_fmu: Path, turn_mill_lean_export: ExportResult) -> None:
    def run(fmu: Path) -> list[str]:
        done = subprocess.run([sys.executable, "-I", "-c", HOST_WITHOUT_PYYAML.replace("FMU", repr(str(fmu)))],
                              capture_output=True, text=True, timeout=TIMEOUT_S)
        assert done.returncode == 0, done.stderr
        return done.stdout.splitlines()

    assert run(turn_mill_fmu) == ["42.0", "[]"]  # and nothing of the FMU entered the host
    assert run(turn_mill_lean_export.path)[0] == "failed: Failed to instantiate model"


def test_a_worker_that_dies_is_reported_fatal_and_the_instance_can_be_freed(unzipped: Path) -> None:
    instance = Instance(unzipped, "doomed")
    instance.start()
    instance.jog_step(0)
    (pid,) = workers()
    os.kill(pid, signal.SIGKILL)
    with pytest.raises(Exception, match="fatal"):
        instance.jog_step(1)
    assert (4, "fmiDoStep: the NC's worker process ended by signal 9 (Killed)") in instance.messages
    instance.slave.freeInstance()
    assert workers() == []


# ---------------------------------------------------------------------------------------------- portability


def test_the_glibc_floor_of_every_binary_is_what_objdump_reads(turn_mill_export: ExportResult, tmp_path: Path) -> None:
    with zipfile.ZipFile(turn_mill_export.path) as archive:
        archive.extractall(tmp_path)
    binaries = [path for path in tmp_path.rglob("*") if path.is_file() and path.read_bytes()[:4] == b"\x7fELF"]
    floors = {path.relative_to(tmp_path).as_posix(): needs(path).glibc for path in binaries}
    assert floors["binaries/linux64/turn_mill.so"] <= GLIBC_FLOOR_OF_THE_BINARY
    assert needs(tmp_path / "binaries/linux64/turn_mill.so").libraries == ("libc.so.6",)
    assert max(floors.values()) == turn_mill_export.glibc
    objdump = shutil.which("objdump")
    if objdump is not None:  # binutils comes with gcc
        for name in ("binaries/linux64/turn_mill.so", "resources/runtime/bin/python"):
            table = subprocess.run([objdump, "-T", str(tmp_path / name)], capture_output=True, text=True,
                                   check=True, timeout=TIMEOUT_S).stdout
            versions = {tuple(int(part) for part in word.removeprefix("(").removesuffix(")")
                              .removeprefix("GLIBC_").split("."))
                        for word in table.split() if word.strip("()").startswith("GLIBC_")
                        and word.strip("()").removeprefix("GLIBC_").replace(".", "").isdigit()}
            assert max(versions) == floors[name], name
    print(textwrap.indent("\n".join(f"glibc {'.'.join(map(str, floor)) or '-':4}  {name}"
                                    for name, floor in sorted(floors.items(), key=lambda item: item[1])), "  "))
