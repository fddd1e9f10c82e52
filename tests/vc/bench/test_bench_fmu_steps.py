"""The FMU benchmark, run very briefly: structure and plausibility of the figures.

No speed assertions (the figures of a short run on a shared machine say nothing); the
figures of full runs are recorded in bench/README.md.  The FMU runs under FMPy in this
process, as ``vc bench --link fmu`` runs it.
"""

from __future__ import annotations

import json
import math
import sys
from pathlib import Path

import pytest

from fmu.export import PythonRuntime
from fmu.unit import PLC_SIGN_OF_LIFE, Causality, NcUnit
from vc.bench import fmu_steps
from vc.bench.fmu_steps import (
    FmuBenchmarkError,
    FmuBenchmarkResult,
    JogDriver,
    inprocess_ports,
    run_fmu_benchmark,
)
from vc.cli.main import main
from vc.config.loader import load_machine

ROOT = Path(__file__).resolve().parents[3]
TURN_MILL = str(ROOT / "scenarios" / "machines" / "turn_mill.yaml")
SECONDS = 0.2  # 20 steps of 10 ms per workload
JOG_VELOCITY = 2000.0  # MD32020 JOG_VELO of the turn-mill's X1, mm/min
JSON_KEYS = {
    "fmu_steps_per_s", "inprocess_steps_per_s", "ratio", "fmu_exchange_steps_per_s",
    "inprocess_exchange_steps_per_s", "exchange_ratio", "fmu_us_per_step", "inprocess_us_per_step",
    "fmu_exchange_us_per_step", "inprocess_exchange_us_per_step", "fmu_realtime_factor", "inprocess_realtime_factor",
    "fmu_exchange_realtime_factor", "inprocess_exchange_realtime_factor", "export_s", "step_ms",
    "ipo_cycles_per_step", "steps", "jog_velocity", "instantiate_ms", "fmu_mb", "glibc",
}


@pytest.fixture(scope="module")
def lines_and_result() -> tuple[list[str], FmuBenchmarkResult]:
    lines: list[str] = []
    result = run_fmu_benchmark(TURN_MILL, seconds=SECONDS, say=lines.append)
    return lines, result


@pytest.fixture(scope="module")
def result(lines_and_result: tuple[list[str], FmuBenchmarkResult]) -> FmuBenchmarkResult:
    return lines_and_result[1]


def test_every_workload_runs_its_steps_and_gives_positive_finite_figures(result: FmuBenchmarkResult) -> None:
    workloads = (result.fmu_step, result.inprocess_step, result.fmu_exchange, result.inprocess_exchange)
    for workload in workloads:
        assert workload.steps == round(SECONDS / 0.010)
        assert workload.step_s == pytest.approx(0.010)
        for figure in (workload.wall_s, workload.steps_per_s, workload.us_per_step, workload.realtime_factor):
            assert math.isfinite(figure) and figure > 0
        assert workload.realtime_factor == pytest.approx(workload.steps_per_s * workload.step_s)
    assert math.isfinite(result.export_s) and result.export_s > 0
    assert result.ipo_cycles_per_step == 5  # 10 ms PLC cycle / 2 ms IPO cycle


def test_the_ratios_are_fmu_over_in_process(result: FmuBenchmarkResult) -> None:
    assert result.ratio == pytest.approx(result.fmu_step.steps_per_s / result.inprocess_step.steps_per_s)
    assert result.exchange_ratio == pytest.approx(
        result.fmu_exchange.steps_per_s / result.inprocess_exchange.steps_per_s)
    assert result.ratio > 0 and result.exchange_ratio > 0


def test_the_nc_jogs_the_first_linear_axis_in_every_workload(result: FmuBenchmarkResult) -> None:
    assert result.jog_axis == "X1"
    # 0.2 s after the key: long since at the JOG velocity (4 m/s^2 reach 33 mm/s in 8 ms)
    assert result.jog_velocity == pytest.approx(JOG_VELOCITY)


def test_over_several_strokes_the_axis_keeps_its_jog_velocity_under_the_hosts_sign_of_life() -> None:
    # 5 s: two reversals, and far beyond the PLC watchdog (MD10100), which the exchange feeds
    result = run_fmu_benchmark(TURN_MILL, seconds=5.0, say=lambda text: None)
    for workload in (result.fmu_step, result.inprocess_step, result.fmu_exchange, result.inprocess_exchange):
        assert workload.jog_velocity == pytest.approx(JOG_VELOCITY)


def test_the_exchange_carries_every_input_and_output_of_the_unit(result: FmuBenchmarkResult) -> None:
    unit = NcUnit(TURN_MILL)
    size = result.exchange_size
    inputs = [variable for variable in unit.variables if variable.causality is Causality.INPUT]
    outputs = [variable for variable in unit.variables if variable.causality is Causality.OUTPUT]
    assert size.set_booleans + size.set_integers + size.set_reals == len(inputs)
    assert size.get_booleans + size.get_integers + size.get_reals == len(outputs)


def test_the_driver_writes_what_basic_machine_would_and_reverses_the_keys() -> None:
    unit = NcUnit(TURN_MILL)
    driver = JogDriver(inprocess_ports(unit), load_machine(TURN_MILL))
    by_name = {variable.name: index for index, variable in enumerate(unit.variables)}
    enables = ("X1.basic.out.enableCtrl", "X1.drive.out.enablePulses", "X1.basic.out.enc1Activation",
               "SP3.basic.out.enableCtrl", "MODEGROUP.basic.out.jogMode", "Drives.on")
    assert {by_name[name] for name in enables} <= set(driver.switched_on)
    assert by_name["X1.basic.out.feedrateOvrFactor"] in driver.at_100_percent
    assert by_name[PLC_SIGN_OF_LIFE] not in driver.at_100_percent  # the power-up is no PLC: the NC does not watch
    booleans = dict(zip(driver.boolean_inputs, driver.boolean_values, strict=True))
    integers = dict(zip(driver.integer_inputs, driver.integer_values, strict=True))
    assert all(booleans[by_name[name]] for name in enables)
    assert integers[by_name["X1.basic.out.feedrateOvrFactor"]] == 100
    assert booleans[by_name["NC.basic.out.emergencyStop"]] is False
    signs_of_life = []
    for step in range(3):
        driver.prepare(step)
        signs_of_life.append(driver.integer_values[driver.integer_inputs.index(by_name[PLC_SIGN_OF_LIFE])])
    assert signs_of_life == [1, 2, 3]  # changes with every exchange, as a PLC's with every scan
    stroke = driver.steps_per_stroke
    assert stroke == 200  # 2 s of 10 ms steps
    assert driver.keys(0) == [True, False] and driver.keys(stroke - 1) == [True, False]
    assert driver.keys(stroke) == [False, True] and driver.keys(2 * stroke) == [True, False]
    assert driver.reverses(0) and driver.reverses(stroke) and not driver.reverses(1)
    assert driver.samples_velocity(stroke // 2) and not driver.samples_velocity(0)


def test_the_benchmark_says_both_workloads_and_their_ratios(
        lines_and_result: tuple[list[str], FmuBenchmarkResult]) -> None:
    lines, _ = lines_and_result
    text = "\n".join(lines)
    assert text.startswith("machine turn_mill: FMU exported in")
    assert "FMU: self-contained, " in text and "start-up: fmi2Instantiate " in text
    assert "step: doStep only" in text and "exchange: per step one call per batch" in text
    assert text.count("FMU (FMPy)") == 2 and text.count("in process") >= 2
    assert text.count("ratio FMU / in process") == 2


def test_the_fmu_leaves_nothing_of_its_deleted_folder_in_this_process(result: FmuBenchmarkResult) -> None:
    assert not [entry for entry in sys.path if "vc_fmu_bench_" in entry]
    assert not [name for name, module in sys.modules.items()
                if "vc_fmu_bench_" in (getattr(module, "__file__", None) or "")]


def test_the_cli_prints_the_figures_as_the_last_line_in_json(
        result: FmuBenchmarkResult, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]) -> None:
    asked: dict[str, object] = {}

    def measured(machine_path: str, seconds: float, **options: object) -> FmuBenchmarkResult:
        asked.update(machine_path=machine_path, seconds=seconds, python=options["python"])
        return result  # the benchmark ran once, for the whole module

    monkeypatch.setattr(fmu_steps, "run_fmu_benchmark", measured)
    assert main(["bench", "--link", "fmu", "--machine", TURN_MILL, "--seconds", "3", "--python", "host"]) == 0
    assert asked == {"machine_path": TURN_MILL, "seconds": 3.0, "python": PythonRuntime.HOST}
    figures = json.loads(capsys.readouterr().out.strip().splitlines()[-1])
    assert set(figures) == JSON_KEYS
    for name, value in figures.items():
        assert isinstance(value, int | float) and math.isfinite(value) and value > 0, name
    assert figures["ratio"] == pytest.approx(figures["fmu_steps_per_s"] / figures["inprocess_steps_per_s"], rel=1e-2)
    assert figures["exchange_ratio"] == pytest.approx(
        figures["fmu_exchange_steps_per_s"] / figures["inprocess_exchange_steps_per_s"], rel=1e-2)
    assert figures["step_ms"] == 10.0 and figures["ipo_cycles_per_step"] == 5 and figures["steps"] == 20


def test_the_cli_defaults_to_20_simulated_seconds(
        result: FmuBenchmarkResult, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]) -> None:
    asked: list[float] = []

    def measured(machine_path: str, seconds: float, **options: object) -> FmuBenchmarkResult:
        asked.append(seconds)
        return result

    monkeypatch.setattr(fmu_steps, "run_fmu_benchmark", measured)
    assert main(["bench", "--link", "fmu", "--machine", TURN_MILL]) == 0
    assert asked == [20.0]


def test_without_fmpy_the_benchmark_says_how_to_install_it(
        monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]) -> None:
    monkeypatch.setitem(sys.modules, "fmpy", None)  # makes ``import fmpy`` raise ImportError
    with pytest.raises(FmuBenchmarkError, match=r"pip install -e '\.\[test\]'"):
        run_fmu_benchmark(TURN_MILL, seconds=SECONDS, say=lambda text: None)
    assert main(["bench", "--link", "fmu", "--machine", TURN_MILL]) == 2
    assert "install the test extra" in capsys.readouterr().err
