"""A second importer of the turn_mill FMU: the C host of ``c_host/fmu_host.c``, not FMPy's Python API.

The host loads the FMU's binary with dlopen() as a simulation tool written in C would, and plays the
PLC of a JOG of X1 (drives on, JOG mode, overrides, enables, traverse key plus held for a while).
It prints what it did and what the FMU answered as records (see the head of ``fmu_host.c``); the
tests check the motion against X1's machine data, the refused 3 ms step, and that replaying the same
records in-process through :class:`fmu.unit.NcUnit` gives the very same numbers (``%.17g``).

The FMU is the self-contained one (the default of ``vc fmu export``) and the host runs with an empty
environment (``env -i``): no Python, no ``PATH``, no preload; the FMU brings its own runtime.
"""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import zipfile
from dataclasses import dataclass
from pathlib import Path

import fmpy
import pytest
from fmpy import read_model_description

from fmu.instance import MANIFEST
from fmu.unit import Kind, NcUnit, UnitError
from vc.config import md_dictionary as MD
from vc.config.loader import load_machine

HOST_SOURCE = Path(__file__).parent / "c_host" / "fmu_host.c"
TIMEOUT_S = 120  # the host needs about a second; this only keeps a hung FMU from hanging the run
START_POSITION_MM = 120.0  # X1.startPosition given to the host: the parameter path is exercised too
KEY = "X1.basic.out.traversKeyPlus"
REFUSED_MESSAGE = "is not a whole number of IPO cycles"
HOST_KINDS = {"Real", "Integer", "Boolean"}  # the types the host's variables file knows
SETTLING_S = 0.1  # after the key is pressed: the actual velocity follows the ramp through the position loop


@dataclass(frozen=True, slots=True)
class Record:
    """One line of the host's standard output: ``kind key=value ...``, values as the host printed them."""

    kind: str
    fields: dict[str, str]

    @property
    def time(self) -> float:
        return float(self.fields["t"])

    def number(self, name: str) -> float:
        return float(self.fields[name])


@dataclass(frozen=True, slots=True)
class HostRun:
    records: list[Record]
    stderr: str

    def of_kind(self, kind: str) -> list[Record]:
        return [record for record in self.records if record.kind == kind]

    def sample_at(self, time: float) -> Record:
        return min(self.of_kind("sample"), key=lambda record: abs(record.time - time))


# ---------------------------------------------------------------------------------------------- fixtures


@pytest.fixture(scope="module")
def c_host(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """``fmu_host.c`` compiled with the warnings as errors, against FMPy's FMI 2.0 headers."""
    gcc = shutil.which("gcc")
    if gcc is None and not os.environ.get("VC_REQUIRE_GCC"):
        pytest.skip("gcc is not installed: the C host cannot be built (.ci/run requires it)")
    assert gcc is not None, "gcc is required here (VC_REQUIRE_GCC is set)"
    fmi_headers = Path(fmpy.__file__).parent / "c-code"
    assert (fmi_headers / "fmi2Functions.h").is_file(), f"FMPy ships no FMI 2.0 headers in {fmi_headers}"
    executable = tmp_path_factory.mktemp("c_host") / "fmu_host"
    command = [gcc, "-std=c11", "-Wall", "-Wextra", "-Werror", "-O1", f"-I{fmi_headers}", str(HOST_SOURCE),
               "-ldl", "-o", str(executable)]
    compiled = subprocess.run(command, capture_output=True, text=True, timeout=TIMEOUT_S, check=False)
    assert compiled.returncode == 0, f"{' '.join(command)} failed:\n{compiled.stderr}"
    return executable


@pytest.fixture(scope="module")
def unzipped_fmu(turn_mill_fmu: Path, tmp_path_factory: pytest.TempPathFactory) -> Path:
    directory = tmp_path_factory.mktemp("turn_mill_unzipped")
    with zipfile.ZipFile(turn_mill_fmu) as archive:
        archive.extractall(directory)
    return directory


@pytest.fixture(scope="module")
def machine_file(unzipped_fmu: Path) -> str:
    """The machine file inside the FMU: what the FMU runs, and so what the reference runs."""
    resources = unzipped_fmu / "resources"
    manifest = json.loads((resources / MANIFEST).read_text(encoding="utf-8"))
    return str(resources / manifest["machine"])


@pytest.fixture(scope="module")
def variables_file(unzipped_fmu: Path) -> Path:
    """What the host would read from modelDescription.xml, in the host's line format (no XML in C)."""
    description = read_model_description(str(unzipped_fmu))
    lines = [f"# from {unzipped_fmu / 'modelDescription.xml'}",
             f"modelIdentifier {description.coSimulation.modelIdentifier}",
             f"guid {description.guid}"]
    lines += [f"variable {variable.valueReference} {variable.type} {variable.name}"
              for variable in description.modelVariables if variable.type in HOST_KINDS]
    path = unzipped_fmu.parent / "variables.txt"
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")
    return path


EMPTY_ENVIRONMENT: dict[str, str] = {}  # env -i


@pytest.fixture(scope="module")
def host_run(c_host: Path, unzipped_fmu: Path, variables_file: Path) -> HostRun:
    command = [str(c_host), str(unzipped_fmu), str(variables_file), f"X1.startPosition={START_POSITION_MM:g}"]
    try:
        finished = subprocess.run(command, capture_output=True, text=True, env=EMPTY_ENVIRONMENT,
                                  timeout=TIMEOUT_S, check=False)
    except subprocess.TimeoutExpired as timeout:
        stderr = timeout.stderr.decode(errors="replace") if isinstance(timeout.stderr, bytes) else timeout.stderr
        pytest.fail(f"the C host did not finish within {TIMEOUT_S} s; its stderr:\n{stderr}")
    assert finished.returncode == 0, (
        f"the C host exited with {finished.returncode}; its stderr:\n{finished.stderr}\n"
        f"last records:\n{''.join(finished.stdout.splitlines(keepends=True)[-5:])}")
    records = [_parse(line) for line in finished.stdout.splitlines() if line.strip()]
    assert records[-1].kind == "done", f"the host's output ends early; its stderr:\n{finished.stderr}"
    return HostRun(records, finished.stderr)


def _parse(line: str) -> Record:
    kind, *pairs = line.split()
    fields = {}
    for pair in pairs:
        name, separator, value = pair.partition("=")
        assert separator, f"not a key=value field: {pair!r} in {line!r}"
        fields[name] = value
    return Record(kind, fields)


# ---------------------------------------------------------------------------------------------- the motion


def test_the_host_jogs_x1_plus_at_the_jog_velocity_for_as_long_as_the_key_is_held(
        host_run: HostRun, machine_file: str) -> None:
    x1 = next(axis for axis in load_machine(machine_file).axes if axis.name == "X1")
    jog_velocity_mm_min = x1.md.float(MD.JOG_VELO)  # MD32020; the host sets both overrides to 100 %
    jog_velocity = jog_velocity_mm_min / 60.0  # mm/s
    acceleration = x1.md.float(MD.MAX_AX_ACCEL, 0) * 1000.0  # MD32300, m/s^2 -> mm/s^2
    # Each ramp (up when the key is pressed, down when it is let go) lacks at most v^2 / 2a.
    ramp_allowance = jog_velocity**2 / acceleration
    key_records = [record for record in host_run.of_kind("set") if KEY in record.fields]
    assert [record.fields[KEY] for record in key_records] == ["1", "0"], host_run.stderr
    pressed, released = (record.time for record in key_records)
    first, last = host_run.of_kind("sample")[0], host_run.of_kind("sample")[-1]

    assert first.number("X1.physical") == START_POSITION_MM  # the parameter took effect
    assert first.fields["X1.basic.in.posCtrlActive"] == "0"  # no controller enable yet
    moved = last.number("X1.physical") - first.number("X1.physical")
    assert moved > 0.0, f"X1 did not move in the plus direction; stderr:\n{host_run.stderr}"
    assert abs(moved - jog_velocity * (released - pressed)) <= ramp_allowance, (
        f"X1 moved {moved} mm with the key held {released - pressed:g} s at {jog_velocity_mm_min:g} mm/min")
    # The NC's actual value (unreferenced X1 counts from 0) moved with the slide.
    assert last.number("X1.position") - first.number("X1.position") == pytest.approx(moved, abs=1e-9)

    # Once the ramp (v / a = 8 ms) and the position control loop have settled, X1 travels at the JOG
    # velocity until the key is let go.
    steady = [record for record in host_run.of_kind("sample") if pressed + SETTLING_S <= record.time <= released]
    assert len(steady) >= 10, "the key was not held long enough to check the steady JOG velocity"
    for record in steady:
        assert record.number("X1.velocity") == pytest.approx(jog_velocity_mm_min, rel=1e-6), record
        assert record.fields["X1.basic.in.posCtrlActive"] == "1"
    travelled = steady[-1].number("X1.physical") - steady[0].number("X1.physical")
    assert travelled == pytest.approx(jog_velocity * (steady[-1].time - steady[0].time), abs=1e-9)

    assert last.number("X1.velocity") == 0.0
    assert last.fields["X1.basic.in.isStationary"] == "1"
    assert last.fields["MODEGROUP.basic.in.jogModeActive"] == "1"
    assert last.fields["Drives.ready"] == "1"


def test_a_step_that_is_no_whole_number_of_ipo_cycles_is_discarded_logged_and_the_fmu_carries_on(
        host_run: HostRun) -> None:
    steps = host_run.records
    refused = [index for index, record in enumerate(steps) if record.kind == "step" and record.fields["status"] != "0"]
    assert len(refused) == 1, f"expected exactly one refused step; stderr:\n{host_run.stderr}"
    step = steps[refused[0]]
    assert step.fields["status"] == "2"  # fmi2Discard: the instance stays usable
    assert float(step.fields["h"]) == pytest.approx(0.003)
    logged = [line for line in host_run.stderr.splitlines() if line.startswith("[fmu log]")]
    assert any("status=3 (fmi2Error)" in line and REFUSED_MESSAGE in line for line in logged), host_run.stderr
    assert len(logged) == 1, f"the FMU logged more than the refused step:\n{host_run.stderr}"

    # The host steps again from the same communication point, and the NC goes on from where it stood.
    retried, after = steps[refused[0] + 1], steps[refused[0] + 2]
    assert (retried.kind, retried.fields["status"], retried.time) == ("step", "0", step.time)
    before = host_run.sample_at(step.time)
    assert before.time == step.time and after.kind == "sample"
    assert after.time == pytest.approx(step.time + float(retried.fields["h"]), abs=1e-12)
    velocity = before.number("X1.velocity") / 60.0  # mm/s, X1 is in the steady JOG
    assert after.number("X1.physical") - before.number("X1.physical") == pytest.approx(velocity * 0.01, abs=1e-9)
    assert host_run.of_kind("sample")[-1].time > after.time  # and many more steps followed


# ---------------------------------------------------------------------------------------------- same numbers


def test_the_c_host_trace_equals_the_same_inputs_run_in_process_through_the_unit(
        host_run: HostRun, machine_file: str) -> None:
    """Replay the host's records on :class:`NcUnit`: every sampled value must print the same with %.17g."""
    unit = NcUnit(machine_file)
    index = {variable.name: position for position, variable in enumerate(unit.variables)}
    compared: list[float] = []
    mismatches: list[str] = []
    for record in host_run.records:
        if record.kind == "parameter":
            ((name, text),) = record.fields.items()
            unit.set(index[name], float(text))
        elif record.kind == "initialized":
            unit.setup(record.time)
            unit.initialize()
        elif record.kind == "set":
            name, text = next((name, text) for name, text in record.fields.items() if name != "t")
            unit.set(index[name], _value(unit.variables[index[name]].kind, text))
        elif record.kind == "step":
            step_size = float(record.fields["h"])
            if record.fields["status"] == "0":
                unit.step(record.time, step_size)
            else:
                with pytest.raises(UnitError, match=REFUSED_MESSAGE):
                    unit.step(record.time, step_size)
        elif record.kind == "sample":
            compared.append(record.time)
            for name, text in record.fields.items():
                if name == "t":
                    continue
                expected = _printed(unit.get(index[name]))
                if text != expected:
                    mismatches.append(f"t={record.time:g} {name}: C host {text}, in-process {expected}")
    assert not mismatches, "\n".join(mismatches[:20])
    # Every sample was compared (after initialisation and after each accepted step): power-on, the
    # enables, both ramps, the steps around the refused one, standstill.
    accepted = [record for record in host_run.of_kind("step") if record.fields["status"] == "0"]
    assert len(compared) == 1 + len(accepted)
    assert compared[0] == 0.0 and compared[-1] >= 0.8


def _value(kind: Kind, text: str) -> float | int | bool:
    if kind is Kind.BOOLEAN:
        return text == "1"
    if kind is Kind.INTEGER:
        return int(text)
    return float(text)


def _printed(value: float | int | bool) -> str:
    """A value as the C host prints it: Booleans 0/1, Reals with %.17g (Python's and C's agree)."""
    if isinstance(value, bool):
        return str(int(value))
    return f"{value:.17g}"
