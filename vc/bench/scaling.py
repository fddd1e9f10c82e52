"""``vc bench --scaling``: how the cost of an IPO cycle grows with what moves.

Each machine (by default the three packaged machines) runs each load of
vc/bench/workloads.py (idle, two axes, everything) on a fresh simulation, all with
the PLC program ``spindle`` so that the rows of a machine differ in the motion alone (the light
workload of ``vc bench`` runs ``basic_machine``: its figure differs a little from the two-axes
row here).  Each row is checked like a ``vc bench`` workload (what should move moved, nothing
else, no alarm).
"""

from __future__ import annotations

from collections.abc import Sequence

from vc.bench.lockstep import HEAVY_PLC, BenchmarkResult, run_benchmark
from vc.bench.workloads import Load

SCALING_MACHINES = (
    "mill_3axis",
    "turn_mill",
    "mill_5axis",
)
SCALING_PLC = HEAVY_PLC


def row_figures(result: BenchmarkResult) -> dict[str, object]:
    """One row for the JSON line: machine, load, axes and spindles moving and in all, the figures."""
    plan = result.plan
    return {"machine": result.machine, "load": str(plan.load), "moving": len(plan.moving), "axes": len(plan.axes),
            "us_per_cycle": round(result.us_per_cycle, 2), "realtime_factor": round(result.realtime_factor, 1)}


def run_scaling(machine_paths: Sequence[str] = SCALING_MACHINES,
                simulated_seconds: float = 10.0) -> list[BenchmarkResult]:
    """Every machine under every load, in this order; BenchmarkError if a load's motion failed."""
    return [run_benchmark(path, simulated_seconds, load, SCALING_PLC) for path in machine_paths for load in Load]


def scaling_table(rows: Sequence[BenchmarkResult]) -> str:
    """The rows as a Markdown table: machine, load, moving / axes, us per IPO cycle, real-time factor."""
    lines = ["| machine | load | moving / axes | us per IPO cycle | real-time factor |",
             "|---|---|---|---:|---:|"]
    lines += [f"| {row.machine} | {row.plan.load} | {len(row.plan.moving)} / {len(row.plan.axes)}"
              f" | {row.us_per_cycle:.1f} | {row.realtime_factor:.1f}x |" for row in rows]
    return "\n".join(lines)
