"""The isolation part: the real-time NC and its PLC beside CPU-heavy processes, without and with
what ``--cpu`` and ``--fifo`` give (:mod:`interfaces.links.scheduling`).

``vc serve --realtime`` with the built-in PLC, while one busy process per CPU of this host
computes for the part's seconds (ordinary processes, on any CPU), three times:

1. as they start by default;
2. pinned: the server to the last CPU, the PLC to the first (``--cpu``), the busy ones anywhere;
3. pinned and with ``SCHED_FIFO`` (``--fifo 50`` for the server, ``--fifo 40`` for the PLC), where
   permitted.

The row's figures are the third run's, the notes give all three: overruns, the share of real time
the NC kept, alarm 2000 (the PLC's sign of life standing longer than MD10100).  Rule violation:
alarm 2000 in the third run while both processes got SCHED_FIFO (then nothing ordinary can hold
the PLC back).
"""

from __future__ import annotations

import os
import sys
import time as wallclock
from dataclasses import dataclass

from vc.bench.robustness.campaign import CampaignSettings, Row, Say
from vc.bench.robustness.processes import Child, FinalPacing, ServedNc, final_pacing

BUSY = "while True: pass"
SERVER_FIFO, PLC_FIFO = "50", "40"


@dataclass(frozen=True, slots=True)
class _Run:
    name: str
    pacing: FinalPacing | None
    alarm_2000: bool
    scheduling: str  # what the server said it got
    plc_scheduling: str
    crashes: int
    tracebacks: int

    def __str__(self) -> str:
        if self.pacing is None:
            return f"{self.name}: no statistics"
        pacing = self.pacing
        return (f"{self.name}: {pacing.overruns} overruns in {pacing.cycles} cycles"
                f" ({100 * pacing.overruns / max(1, pacing.cycles):.1f} %), NC at {pacing.share_pct:.1f} % of real"
                f" time, alarm 2000 {'raised' if self.alarm_2000 else 'not raised'}")


def _run(name: str, seconds: float, serve: list[str], plc: list[str]) -> _Run:
    with ServedNc(["--realtime", "--stats", "60", *serve], plc_options=plc) as served:
        wallclock.sleep(1.0)  # the PLC's first scans
        busy = [Child("busy", ["-c", BUSY]) for _ in os.sched_getaffinity(0)]
        try:
            wallclock.sleep(seconds)
        finally:
            for child in busy:
                child.stop()
        crashes = served.crashes()
    assert served.plc is not None
    scheduling = next((line.removeprefix("scheduling: ") for line in served.serve.lines
                       if line.startswith("scheduling: ")), "")
    plc_scheduling = next((line.removeprefix("plc_stub: scheduling: ") for line in served.plc.errors
                           if line.startswith("plc_stub: scheduling: ")), "")
    alarm = any(line.split("alarm ")[1].startswith("2000") for line in served.serve.lines if "  alarm " in line)
    return _Run(name, final_pacing(served.serve), alarm, scheduling, plc_scheduling, crashes, served.tracebacks())


def run_isolation(settings: CampaignSettings, say: Say) -> Row:
    """The part's row (module docstring)."""
    seconds = settings.flood_seconds
    cpus = sorted(os.sched_getaffinity(0))
    server_cpu, plc_cpu = str(cpus[-1]), str(cpus[0])
    runs = []
    for name, serve, plc in (
            ("default", [], []),
            ("--cpu", ["--cpu", server_cpu], ["--cpu", plc_cpu]),
            ("--cpu --fifo", ["--cpu", server_cpu, "--fifo", SERVER_FIFO], ["--cpu", plc_cpu, "--fifo", PLC_FIFO])):
        runs.append(_run(name, seconds, serve, plc))
        say(f"  isolation: {runs[-1]}")
    isolated = runs[-1]
    fifo = "SCHED_FIFO" in isolated.scheduling and "SCHED_FIFO" in isolated.plc_scheduling \
        and "not permitted" not in isolated.scheduling + isolated.plc_scheduling
    pacing = isolated.pacing
    return Row(f"Isolation ({len(cpus)} busy processes beside vc serve --realtime and plc_stub, {seconds:g} s each:"
               " default, --cpu, --cpu --fifo)",
               inputs=sum(run.pacing.cycles for run in runs if run.pacing), crashes=sum(run.crashes for run in runs),
               tracebacks=sum(run.tracebacks for run in runs), violations=int(fifo and isolated.alarm_2000),
               overruns=str(pacing) if pacing else "-",
               notes="; ".join(str(run) for run in runs) + f"; server {isolated.scheduling}, PLC"
                     f" {isolated.plc_scheduling}{'' if fifo else ' (SCHED_FIFO not granted here: no rule applies)'};"
                     f" Python {sys.version.split()[0]}")
