"""The pure-Python and the compiled build side by side on this machine (bench/compare_builds.py).

Both builds come from the same checkout: the compiled one is what ``pip install -e .`` built,
the pure one the same sources with ``VC_PURE=1`` (vc_build).  Each measurement runs in a fresh
``python -m vc.cli.main`` process of this interpreter:

* ``vc bench --seconds S``: both workloads (light and heavy), µs per IPO cycle and real-time
  factor from its JSON line, whose ``build`` must name the build asked for;
* ``vc run PATH -j 1`` and ``-j 2``: the wall time of the scenario library, taken around the
  process (start-up included), in each build.

The machine is shared and noisy, so the runs alternate: each round runs every measurement once
in each build, the build that goes first swapping from round to round (pure, compiled, then
compiled, pure ...), and the table gives each figure's median over the rounds with its range.
The header names the CPU (/proc/cpuinfo), the cores this process may use, the Python version
and the load average before and after.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import statistics
import subprocess
import sys
import time
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from enum import StrEnum

from interfaces.errors import VcError
from vc_build import PURE_VARIABLE

DEFAULT_RUNS = 3
DEFAULT_BENCH_SECONDS = 30.0
DEFAULT_SCENARIOS = "scenarios/"
JOBS = (1, 2)
EXIT_FAILED = 1
EXIT_PROBLEMS = 2


class Build(StrEnum):
    PURE = "pure"
    COMPILED = "compiled"

    def environment(self) -> dict[str, str]:
        environment = {name: value for name, value in os.environ.items() if name != PURE_VARIABLE}
        if self is Build.PURE:
            environment[PURE_VARIABLE] = "1"
        return environment


@dataclass(frozen=True, slots=True)
class Figure:
    """One row of the table: a name, its unit, and whether more is better."""

    key: str
    label: str
    higher_is_better: bool


BENCH_FIGURES = (
    Figure("us_per_cycle", "vc bench light, us per IPO cycle", False),
    Figure("realtime_factor", "vc bench light, real-time factor", True),
    Figure("heavy_us_per_cycle", "vc bench heavy, us per IPO cycle", False),
    Figure("heavy_realtime_factor", "vc bench heavy, real-time factor", True),
)


def run_figure(jobs: int, path: str) -> Figure:
    return Figure(f"run_j{jobs}_s", f"vc run {path} -j {jobs}, wall s", False)


class ComparisonError(VcError):
    """A measurement could not be taken (a build missing, a command failing): no table."""


@dataclass(slots=True)
class Samples:
    """Every run's value of every figure, per build."""

    values: dict[tuple[str, Build], list[float]] = field(default_factory=dict)
    failures: list[str] = field(default_factory=list)  # commands that exited with an error

    def add(self, key: str, build: Build, value: float) -> None:
        self.values.setdefault((key, build), []).append(value)

    def of(self, key: str, build: Build) -> list[float]:
        return self.values.get((key, build), [])


@dataclass(frozen=True, slots=True)
class MachineInfo:
    cpu: str
    cores: int  # the CPUs this process may run on
    python: str
    vc: str  # ``vc --version`` of the compiled build

    def describe(self) -> str:
        return f"{self.cpu}, {self.cores} cores, Python {self.python}; {self.vc}"


def cpu_model(cpuinfo: str) -> str:
    """The ``model name`` of /proc/cpuinfo (the first; x86), else its ``Hardware`` or ``Processor`` (ARM)."""
    found: dict[str, str] = {}
    for line in cpuinfo.splitlines():
        name, _, value = line.partition(":")
        found.setdefault(name.strip().lower(), value.strip())
    for name in ("model name", "hardware", "processor", "cpu model"):
        if found.get(name) and not found[name].isdigit():
            return found[name]
    return platform.processor() or platform.machine() or "unknown CPU"


def machine_info(vc_version: str) -> MachineInfo:
    try:
        with open("/proc/cpuinfo", encoding="utf-8") as file:
            cpu = cpu_model(file.read())
    except OSError:
        cpu = cpu_model("")
    return MachineInfo(cpu, len(os.sched_getaffinity(0)), platform.python_version(), vc_version)


def vc_command(*arguments: str) -> list[str]:
    return [sys.executable, "-m", "vc.cli.main", *arguments]


def compiled_version() -> str:
    """``vc --version`` without VC_PURE; ComparisonError when that is not the compiled build."""
    done = subprocess.run(vc_command("--version"), env=Build.COMPILED.environment(), capture_output=True,
                          text=True, check=False)
    version = done.stdout.strip()
    if done.returncode != 0 or "compiled" not in version:
        raise ComparisonError(f"the compiled build does not run here ({version or done.stderr.strip()});"
                              " pip install -e . compiles it (a C compiler, the Python headers and mypyc)")
    return version


def bench_figures(build: Build, seconds: float) -> dict[str, float]:
    """``vc bench`` in ``build``: the figures of its JSON line."""
    done = subprocess.run(vc_command("bench", "--seconds", f"{seconds:g}"), env=build.environment(),
                          capture_output=True, text=True, check=False)
    lines = done.stdout.strip().splitlines()
    if done.returncode != 0 or not lines:
        raise ComparisonError(f"vc bench ({build}) exited with {done.returncode}: {done.stderr.strip()}")
    figures = json.loads(lines[-1])
    if figures.get("build") != str(build):
        raise ComparisonError(f"vc bench was asked for the {build} build and ran the {figures.get('build')} one")
    return {figure.key: float(figures[figure.key]) for figure in BENCH_FIGURES}


def run_wall_time(build: Build, path: str, jobs: int) -> tuple[float, int]:
    """``vc run PATH -j N`` in ``build``: wall seconds and exit code (1: a scenario failed)."""
    began = time.perf_counter()
    done = subprocess.run(vc_command("run", path, "-j", str(jobs)), env=build.environment(),
                          stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, check=False)
    return time.perf_counter() - began, done.returncode


def measure(runs: int, seconds: float, scenarios: str | None,
            say: Callable[[str], None] = lambda text: None) -> Samples:
    """``runs`` rounds of every measurement in both builds, the first build swapping every round."""
    samples = Samples()
    for round_number in range(runs):
        order = (Build.PURE, Build.COMPILED) if round_number % 2 == 0 else (Build.COMPILED, Build.PURE)
        for build in order:
            for key, value in bench_figures(build, seconds).items():
                samples.add(key, build, value)
            say(f"round {round_number + 1}/{runs}, {build}: vc bench {samples.of('us_per_cycle', build)[-1]:.1f}"
                f" / {samples.of('heavy_us_per_cycle', build)[-1]:.1f} us per IPO cycle")
        if scenarios is None:
            continue
        for jobs in JOBS:
            for build in order:
                wall, code = run_wall_time(build, scenarios, jobs)
                samples.add(run_figure(jobs, scenarios).key, build, wall)
                if code != 0:
                    samples.failures.append(f"vc run {scenarios} -j {jobs} ({build}) exited with {code}")
                say(f"round {round_number + 1}/{runs}, {build}: vc run -j {jobs} {wall:.1f} s")
    return samples


def figures_of(scenarios: str | None) -> list[Figure]:
    return [*BENCH_FIGURES, *([run_figure(jobs, scenarios) for jobs in JOBS] if scenarios is not None else [])]


def _cell(values: Sequence[float]) -> str:
    """``15.2 (14.8-16.0)``: the median and the range of the runs."""
    if not values:
        return "-"
    median = statistics.median(values)
    return f"{median:.1f}" if len(values) == 1 else f"{median:.1f} ({min(values):.1f}-{max(values):.1f})"


def speedup(figure: Figure, samples: Samples) -> float | None:
    """How many times the compiled build is faster than the pure one, from the medians."""
    pure, compiled = samples.of(figure.key, Build.PURE), samples.of(figure.key, Build.COMPILED)
    if not pure or not compiled:
        return None
    ratio = statistics.median(compiled) / statistics.median(pure)
    return ratio if figure.higher_is_better else 1 / ratio


def comparison_table(figures: Sequence[Figure], samples: Samples) -> str:
    """Markdown: a row per figure, the median (range) of each build and the speed-up."""
    lines = ["| measurement | pure | compiled | compiled faster by |", "|---|---:|---:|---:|"]
    for figure in figures:
        ratio = speedup(figure, samples)
        faster = "-" if ratio is None else f"{ratio:.2f}x"
        lines.append(f"| {figure.label} | {_cell(samples.of(figure.key, Build.PURE))}"
                     f" | {_cell(samples.of(figure.key, Build.COMPILED))} | {faster} |")
    return "\n".join(lines)


def medians(figures: Sequence[Figure], samples: Samples) -> dict[str, float]:
    """The JSON line: ``pure_<key>`` and ``compiled_<key>``, medians over the runs."""
    return {f"{build}_{figure.key}": round(statistics.median(samples.of(figure.key, build)), 2)
            for figure in figures for build in Build if samples.of(figure.key, build)}


def _load() -> str:
    one, five, fifteen = os.getloadavg()
    return f"{one:.2f} {five:.2f} {fifteen:.2f}"


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="compare_builds.py", description=__doc__.split("\n", 1)[0])
    parser.add_argument("--runs", type=int, default=DEFAULT_RUNS, help=f"rounds (default {DEFAULT_RUNS}, at least 1)")
    parser.add_argument("--seconds", type=float, default=DEFAULT_BENCH_SECONDS,
                        help=f"vc bench --seconds: simulated seconds per workload (default {DEFAULT_BENCH_SECONDS:g})")
    parser.add_argument("--scenarios", default=DEFAULT_SCENARIOS, metavar="PATH",
                        help=f"what vc run runs (default {DEFAULT_SCENARIOS})")
    parser.add_argument("--no-scenarios", action="store_true", help="vc bench only")
    arguments = parser.parse_args(argv)
    if arguments.runs < 1 or not arguments.seconds > 0:
        parser.error("--runs is at least 1 and --seconds more than 0")
    scenarios = None if arguments.no_scenarios else arguments.scenarios
    load_before = _load()
    try:
        info = machine_info(compiled_version())
        samples = measure(arguments.runs, arguments.seconds, scenarios, say=lambda text: print(text, flush=True))
    except ComparisonError as error:
        print(f"compare_builds: {error}", file=sys.stderr)
        return EXIT_PROBLEMS
    figures = figures_of(scenarios)
    print(f"machine: {info.describe()}")
    print(f"{arguments.runs} rounds, vc bench --seconds {arguments.seconds:g}; load average before"
          f" {load_before}, after {_load()}; median (min-max) of the rounds")
    print(comparison_table(figures, samples))
    for failure in samples.failures:
        print(f"failed: {failure}")
    result: Mapping[str, object] = {"cpu": info.cpu, "cores": info.cores, "python": info.python,
                                    "runs": arguments.runs, **medians(figures, samples)}
    print(json.dumps(result))
    return EXIT_FAILED if samples.failures else 0
