"""A campaign at scale: ``python bench/campaign.py [--campaign FILE] [--modes j1,j2,local2,cli2]``.

Runs a campaign (default ``campaigns/referencing_matrix.yaml``, 1,000 variants) four ways, as
``vc run`` would, and prints per way the wall time, variants per second, the overhead per task
and the efficiency against the serial run, then what limits a bigger cluster and a projection
for 10 and 100 machines:

* ``j1``: ``vc run -j 1``, in this process;
* ``j2``: ``vc run -j 2``, two worker processes;
* ``local2``: ``vc run --cluster local:2``, a Dask LocalCluster of two worker processes (its start
  counted in the wall time, and shown on its own);
* ``cli2``: ``vc run --cluster ADDRESS`` on ``dask scheduler`` and two ``dask worker --nthreads 1``
  processes started here with Dask's CLI on 127.0.0.1 (started before the clock runs).

Figures:

* run time: the sum of the variants' own run times (the simulation), per way;
* overhead per task = (workers x wall - run time) / variants: what a variant costs beyond its
  simulation (loading its variant, the task's transport, the client's handling, idle workers);
* efficiency = serial wall / (workers x wall);
* the limits of a bigger cluster, measured on the CLI cluster: the scheduler's throughput for tasks
  that do nothing (``--null-tasks``), the client's time per outcome, and, with ``--trace-sample N``
  variants sent back with their recordings, the bytes per variant and the client's time to write
  its CSV, VCD and GTKWave file (``--cluster-files send`` with ``--trace-dir``).

Every way's JUnit file is compared with the serial run's (times aside).  The last line holds all
figures as one JSON object.  The machine these figures come from has 2 cores and is shared: the
absolute figures vary from run to run; compare the ways of one run with each other.
"""

from __future__ import annotations

import argparse
import json
import os
import re
import subprocess
import sys
import tempfile
import time
from collections.abc import Iterator, Sequence
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from interfaces.links.inprocess import plc_programs
from vc.harness.targets import simulation_for
from vc.scenario.distribution.cluster import ClusterSettings, run_on_cluster
from vc.scenario.distribution.parallel import RunSettings, run_parallel
from vc.scenario.language.loader import load_scenarios
from vc.scenario.language.model import Scenario
from vc.scenario.outputs.report import write_junit
from vc.scenario.run.runner import ScenarioResult, run_scenarios
from vc_build import status as build_status

DEFAULT_CAMPAIGN = "campaigns/referencing_matrix.yaml"
MODES = ("j1", "j2", "local2", "cli2")
WORKERS = {"j1": 1, "j2": 2, "local2": 2, "cli2": 2}
TIMES = re.compile(r'time="[0-9.]+"')


@dataclass
class Figures:
    mode: str
    workers: int
    wall_s: float
    run_s: float  # the variants' own run times, summed
    passed: int
    variants: int
    start_s: float = 0.0  # to start (local:N) or reach the cluster and hand over the tasks, part of wall_s
    client_s: float = 0.0  # the client's time handling outcomes
    task_s: float = 0.0  # the tasks' time on the workers, summed
    junit_same: bool = True

    @property
    def rate(self) -> float:
        return self.variants / self.wall_s

    @property
    def overhead_ms(self) -> float:
        return (self.workers * self.wall_s - self.run_s) / self.variants * 1000

    def efficiency(self, serial_wall_s: float) -> float:
        return serial_wall_s / (self.workers * self.wall_s)


class _Forget:
    """An observer that lets each recording go once reported (1,000 recordings would fill the memory)."""

    def scenario_started(self, scenario: Scenario, position: int, total: int) -> None:
        pass

    def scenario_progress(self, scenario: Scenario, simulated_s: float) -> None:
        pass

    def scenario_finished(self, result: ScenarioResult) -> None:
        result.recorder = None


def _junit(results: Sequence[ScenarioResult], path: Path) -> str:
    write_junit(results, path)
    return TIMES.sub('time="T"', path.read_text(encoding="utf-8"))


def _say(text: str) -> None:
    print(text, flush=True)


@contextmanager
def dask_cli_cluster(directory: Path, workers: int) -> Iterator[str]:
    """``dask scheduler`` and ``dask worker`` processes on 127.0.0.1 (ephemeral ports); the address."""
    from distributed import Client

    dask = Path(sys.executable).parent / "dask"
    scheduler_file = directory / "scheduler.json"
    processes = [subprocess.Popen([str(dask), "scheduler", "--host", "127.0.0.1", "--port", "0", "--no-dashboard",
                                   "--dashboard-address", "127.0.0.1:0", "--scheduler-file", str(scheduler_file)],
                                  stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)]
    try:
        deadline = time.monotonic() + 120
        while not (scheduler_file.exists() and scheduler_file.stat().st_size):
            if time.monotonic() > deadline:
                raise RuntimeError("dask scheduler did not start within 120 s")
            time.sleep(0.1)
        address = json.loads(scheduler_file.read_text())["address"]
        for number in range(workers):
            processes.append(subprocess.Popen(
                [str(dask), "worker", address, "--nthreads", "1", "--no-dashboard", "--dashboard-address",
                 "127.0.0.1:0", "--host", "127.0.0.1", "--name", f"w{number + 1}"],
                stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL))
        with Client(address, timeout="30s") as client:
            client.wait_for_workers(workers, timeout=120)
        yield address
    finally:
        for process in processes:
            process.terminate()
        for process in processes:
            try:
                process.wait(timeout=30)
            except subprocess.TimeoutExpired:
                process.kill()


def _null(position: int) -> int:
    return position


def null_task_rate(address: str, count: int) -> float:
    """Tasks per second the cluster completes for tasks that do nothing: the scheduler's and
    client's bound on any campaign."""
    from distributed import Client, as_completed

    with Client(address, timeout="30s") as client:
        client.submit(_null, -1).result()  # warm: the function is known on the workers
        began = time.perf_counter()
        futures = [client.submit(_null, position, pure=False) for position in range(count)]
        for _ in as_completed(futures):
            pass
        return count / (time.perf_counter() - began)


def run_mode(mode: str, scenarios: Sequence[Scenario], directory: Path, address: str | None) -> tuple[Figures, str]:
    settings = RunSettings(tuple(plc_programs()), simulation_for)
    workers = WORKERS[mode]
    began = time.perf_counter()
    start_s = client_s = task_s = 0.0
    if mode == "j1":
        results = run_scenarios(scenarios, simulation_for, observer=_Forget())
    elif mode == "j2":
        results = run_parallel(scenarios, settings, workers, observer=_Forget()).results
    else:
        cluster = ClusterSettings(f"local:{workers}" if mode.startswith("local") else str(address))
        run = run_on_cluster(scenarios, settings, cluster)
        results = run.results
        start_s, client_s, task_s = run.submit_s, run.client_s, sum(run.task_s)
    wall = time.perf_counter() - began
    junit = _junit(results, directory / f"{mode}.xml")
    figures = Figures(mode, workers, wall, sum(result.wall_s for result in results),
                      sum(result.passed for result in results), len(results), start_s, client_s, task_s)
    return figures, junit


def trace_sample(address: str, scenarios: Sequence[Scenario], directory: Path) -> dict[str, float]:
    """Variants sent back with their recordings; the client writes their traces."""
    settings = RunSettings(tuple(plc_programs()), simulation_for, trace_dir=str(directory / "traces"))
    run = run_on_cluster(scenarios, settings, ClusterSettings(address))
    count = len(scenarios)
    sizes = [file.stat().st_size for file in (directory / "traces").iterdir()]
    return {"variants": count, "received_kb_per_variant": run.received_bytes / count / 1024,
            "client_ms_per_variant": run.client_s / count * 1000,
            "trace_files_kb_per_variant": sum(sizes) / count / 1024}


def projection(serial: Figures, cluster: Figures, null_rate: float, machines: int, cores: int,
               variants: int) -> dict[str, Any]:
    """What ``machines`` machines of ``cores`` workers each would give.  Each worker spends on a
    variant what a worker of the measured cluster spent, its run and its overhead (workers x wall
    / variants, less the cluster's start); the client and the scheduler bound the rate by the
    outcomes per second they can take (the slower of the client's measured time per outcome and the
    scheduler's rate for tasks that do nothing)."""
    per_task_s = cluster.workers * (cluster.wall_s - cluster.start_s) / cluster.variants
    workers_rate = machines * cores / per_task_s
    client_rate = cluster.variants / cluster.client_s if cluster.client_s else null_rate
    bound = min(null_rate, client_rate)
    rate = min(workers_rate, bound)
    limit = "the workers" if workers_rate < bound else \
        ("the scheduler (tasks per second)" if null_rate < client_rate else "the client (outcomes per second)")
    limit += f" (workers {workers_rate:.0f}/s, scheduler and client {bound:.0f}/s)"
    return {"machines": machines, "workers": machines * cores, "variants_per_s": rate, "wall_s": variants / rate,
            "limited_by": limit, "speed_up": rate / serial.rate, "per_task_s": per_task_s,
            "workers_rate": workers_rate, "bound_rate": bound}


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n", 1)[0])
    parser.add_argument("--campaign", default=DEFAULT_CAMPAIGN)
    parser.add_argument("--modes", default=",".join(MODES), help=f"comma-separated, of {', '.join(MODES)}")
    parser.add_argument("--null-tasks", type=int, default=2000, help="tasks of the scheduler throughput measurement")
    parser.add_argument("--trace-sample", type=int, default=50, help="variants sent back with their traces")
    parser.add_argument("--cores-per-machine", type=int, default=2, help="workers per machine in the projection")
    arguments = parser.parse_args(argv)
    modes = [mode for mode in arguments.modes.split(",") if mode]
    unknown = set(modes) - set(MODES)
    if unknown or "j1" not in modes:
        parser.error(f"--modes: {', '.join(sorted(unknown)) or 'j1 is the reference and must be there'}")
    began = time.perf_counter()
    scenarios = load_scenarios([arguments.campaign], plc_programs().keys())
    check_s = time.perf_counter() - began
    _say(f"vc-harness {build_status().describe()}, Python {sys.version.split()[0]}, {os.cpu_count()} cores;"
         f" load average {os.getloadavg()[0]:.1f} at the start")
    _say(f"{arguments.campaign}: {len(scenarios)} variants checked in {check_s:.1f} s")
    figures: dict[str, Figures] = {}
    extra: dict[str, Any] = {}
    with tempfile.TemporaryDirectory(prefix="vc-bench-") as scratch:
        directory = Path(scratch)
        reference = ""
        with _maybe_cli(directory, "cli2" in modes) as address:
            for mode in modes:
                _say(f"-- {mode} ...")
                found, junit = run_mode(mode, scenarios, directory, address)
                if mode == "j1":
                    reference = junit
                found.junit_same = junit == reference
                figures[mode] = found
                _report(found, figures["j1"])
            if address is not None:
                extra["null_tasks_per_s"] = null_task_rate(address, arguments.null_tasks)
                _say(f"scheduler and client, {arguments.null_tasks} tasks that do nothing:"
                     f" {extra['null_tasks_per_s']:.0f} tasks/s")
                if arguments.trace_sample:
                    sample = trace_sample(address, scenarios[:arguments.trace_sample], directory)
                    extra["traces"] = sample
                    _say(f"with --trace-dir (send): {sample['received_kb_per_variant']:.0f} kB of recording back per"
                         f" variant, {sample['client_ms_per_variant']:.0f} ms of the client per variant (traces"
                         f" {sample['trace_files_kb_per_variant']:.0f} kB written)")
    serial = figures["j1"]
    cluster = figures.get("cli2") or figures.get("local2")
    projections = []
    if cluster is not None and "null_tasks_per_s" in extra:
        for machines in (10, 100):
            projected = projection(serial, cluster, extra["null_tasks_per_s"], machines,
                                   arguments.cores_per_machine, len(scenarios))
            projections.append(projected)
            _say(f"projection, {machines} machines x {arguments.cores_per_machine} workers:"
                 f" {projected['variants_per_s']:.0f} variants/s, {projected['wall_s']:.1f} s for"
                 f" {len(scenarios)} variants ({projected['speed_up']:.0f}x -j 1),"
                 f" limited by {projected['limited_by']}")
    summary = {"variants": len(scenarios), "check_s": round(check_s, 2),
               "modes": {mode: {"wall_s": round(f.wall_s, 2), "variants_per_s": round(f.rate, 2),
                                "overhead_ms_per_task": round(f.overhead_ms, 1),
                                "efficiency": round(f.efficiency(serial.wall_s), 3), "passed": f.passed,
                                "run_s": round(f.run_s, 2), "start_s": round(f.start_s, 2),
                                "client_ms_per_task": round(f.client_s / f.variants * 1000, 2),
                                "junit_same_as_j1": f.junit_same} for mode, f in figures.items()},
               **extra, "projections": projections}
    print(json.dumps(summary, default=_rounded))
    return 0 if all(f.junit_same and f.passed == f.variants for f in figures.values()) else 1


def _rounded(value: object) -> object:
    return round(value, 3) if isinstance(value, float) else str(value)


def _report(found: Figures, serial: Figures) -> None:
    start = f", of it {found.start_s:.1f} s to reach the cluster and hand over the tasks" if found.start_s else ""
    _say(f"{found.mode}: {found.passed}/{found.variants} passed, wall {found.wall_s:.1f} s{start},"
         f" {found.rate:.2f} variants/s, run time {found.run_s:.1f} s, overhead {found.overhead_ms:.0f} ms per task,"
         f" efficiency {found.efficiency(serial.wall_s):.2f} against -j 1, JUnit"
         f" {'equal to' if found.junit_same else 'DIFFERENT from'} -j 1's")


@contextmanager
def _maybe_cli(directory: Path, wanted: bool) -> Iterator[str | None]:
    if not wanted:
        yield None
        return
    with dask_cli_cluster(directory, 2) as address:
        yield address


if __name__ == "__main__":
    sys.exit(main())
