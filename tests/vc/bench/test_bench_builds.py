"""bench/compare_builds.py: the machine's description, the medians and the table; one short run.

No speed targets: the run checks that both builds were measured and the figures are there.
"""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from vc.bench.builds import (
    BENCH_FIGURES,
    Build,
    Samples,
    comparison_table,
    cpu_model,
    figures_of,
    main,
    medians,
    speedup,
)
from vc_build import PURE_VARIABLE
from vc_build import status as build_status

ROOT = Path(__file__).resolve().parents[3]
SCENARIO = "scenarios/foundation/nc_start_without_reference.yaml"


def test_the_cpu_model_comes_from_proc_cpuinfo() -> None:
    x86 = ("processor\t: 0\nvendor_id\t: AuthenticAMD\nmodel name\t: AMD EPYC 7B13\n"
           "processor\t: 1\nmodel name\t: AMD EPYC 7B13\n")
    assert cpu_model(x86) == "AMD EPYC 7B13"
    arm = "processor\t: 0\nBogoMIPS\t: 108.00\nHardware\t: BCM2835\n"
    assert cpu_model(arm) == "BCM2835"  # "processor: 0" is a number, not a model
    assert cpu_model("") != ""


def test_each_build_gets_its_environment(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv(PURE_VARIABLE, "1")
    assert PURE_VARIABLE not in Build.COMPILED.environment()
    monkeypatch.delenv(PURE_VARIABLE)
    assert Build.PURE.environment()[PURE_VARIABLE] == "1"


def test_the_table_gives_median_range_and_speed_up_of_each_figure() -> None:
    samples = Samples()
    for pure, compiled in ((100.0, 20.0), (120.0, 30.0), (90.0, 25.0)):
        samples.add("us_per_cycle", Build.PURE, pure)
        samples.add("us_per_cycle", Build.COMPILED, compiled)
    for pure, compiled in ((10.0, 40.0), (20.0, 80.0)):
        samples.add("realtime_factor", Build.PURE, pure)
        samples.add("realtime_factor", Build.COMPILED, compiled)
    light_us, light_factor = BENCH_FIGURES[0], BENCH_FIGURES[1]
    assert speedup(light_us, samples) == pytest.approx(100 / 25)  # medians 100 and 25
    assert speedup(light_factor, samples) == pytest.approx(60 / 15)  # more is better: compiled / pure
    assert speedup(BENCH_FIGURES[2], samples) is None
    table = comparison_table(BENCH_FIGURES[:3], samples).splitlines()
    assert table[2] == "| vc bench light, us per IPO cycle | 100.0 (90.0-120.0) | 25.0 (20.0-30.0) | 4.00x |"
    assert table[3] == "| vc bench light, real-time factor | 15.0 (10.0-20.0) | 60.0 (40.0-80.0) | 4.00x |"
    assert table[4] == "| vc bench heavy, us per IPO cycle | - | - | - |"
    assert medians(BENCH_FIGURES, samples) == {"pure_us_per_cycle": 100.0, "compiled_us_per_cycle": 25.0,
                                               "pure_realtime_factor": 15.0, "compiled_realtime_factor": 60.0}
    assert [figure.key for figure in figures_of("x/")][-2:] == ["run_j1_s", "run_j2_s"]


def test_one_short_round_measures_both_builds(capsys: pytest.CaptureFixture[str],
                                              monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(ROOT)
    code = main(["--runs", "1", "--seconds", "0.5", "--scenarios", SCENARIO])
    output = capsys.readouterr()
    if not build_status().compiled:  # a pure installation: nothing to compare with
        assert code == 2 and "the compiled build does not run here" in output.err
        return
    assert code == 0, output.err
    lines = output.out.strip().splitlines()
    assert any(line.startswith("machine: ") and " cores, Python " in line for line in lines)
    figures = json.loads(lines[-1])
    for build in ("pure", "compiled"):
        for key in ("us_per_cycle", "realtime_factor", "heavy_us_per_cycle", "heavy_realtime_factor",
                    "run_j1_s", "run_j2_s"):
            assert figures[f"{build}_{key}"] > 0
    assert f"| vc run {SCENARIO} -j 2, wall s | " in output.out
