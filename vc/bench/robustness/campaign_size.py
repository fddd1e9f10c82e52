"""The campaign part "campaign size": matrices and campaigns far beyond a run's ceiling, and an
allowed large one, through ``vc run`` in its own process (:mod:`.one_shot`).

:data:`OVERSIZED` are the files a run must refuse before anything is built: a campaign of 15 kB
naming 1,000 scenario files over a matrix of 100,000 variants (10^8; it was still being checked
after 120 s, some 5 CPU-days), a scenario of 10^12 variants, two files whose 60,000 variants each make 120,000
together, a campaign naming one file 1,000 times.  Each must end with exit 2 and the problem
at ``FILE:LINE:COLUMN`` within the bound.  Then an allowed campaign of 10,000 variants over
machine data and an override is checked with ``--max-variants`` at its size, and its checking
time per variant is the part's figure (``vc run`` with a scenario that fails its check at
once: the run stops after checking, nothing runs).
"""

from __future__ import annotations

import tempfile
import time as wallclock
from collections.abc import Callable, Collection
from dataclasses import dataclass
from pathlib import Path

from vc.bench.robustness.campaign import CampaignSettings, Row, Say
from vc.bench.robustness.one_shot import Outcome, run_vc, tally
from vc.bench.robustness.processes import ROOT

PART = "Campaign size (vc run)"
DEFAULT_BOUND_S = 120.0
SCENARIO = ROOT / "scenarios" / "referencing" / "incremental_either_edge_cam_moved.yaml"


def _values(count: int, start: int = 1) -> str:
    return "[" + ", ".join(str(value) for value in range(start, start + count)) + "]"


def _campaign(files: list[str], matrix: str) -> str:
    return f"campaign: size\nscenarios: [{', '.join(files)}]\nvary:\n{matrix}"


def _scenario(matrix: str) -> str:
    text = SCENARIO.read_text(encoding="utf-8").replace("machine: ../machines/", f"machine: {ROOT}/scenarios/machines/")
    head, _, rest = text.partition("vary:\n")
    body = rest[rest.index("invariants:"):]
    return f"{head}vary:\n{matrix}{body}"


@dataclass(frozen=True, slots=True)
class Oversized:
    name: str
    files: Callable[[Path], list[Path]]  # writes the files into the directory; the ones to run


def _thousand_files(directory: Path) -> list[Path]:
    campaign = directory / "thousand.yaml"
    listed = [f"scenario_{number}.yaml" for number in range(1000)]
    small = (f"name: small\nmachine: {ROOT}/scenarios/machines/turn_mill.yaml\nplc: basic_machine\nsteps:\n"
             '  - set: {MCP.feedOverride: "${override}"}\n  - wait: "${a}ms"\n  - wait: "${b}ms"\n')
    for name in listed:
        (directory / name).write_text(small, encoding="utf-8")
    campaign.write_text(_campaign(listed, f"  override: {_values(10)}\n  a: {_values(100)}\n  b: {_values(100)}\n"),
                        encoding="utf-8")
    return [campaign]


def _trillion(directory: Path) -> list[Path]:
    path = directory / "trillion.yaml"
    matrix = "".join(f"  k{number}: {_values(100)}\n" for number in range(6))
    path.write_text(_scenario(matrix), encoding="utf-8")
    return [path]


def _two_files(directory: Path) -> list[Path]:
    paths = [directory / "first.yaml", directory / "second.yaml"]
    for path in paths:
        path.write_text(_scenario("  cases:\n    - {X1.MD34050: 0, side: -1}\n    - {X1.MD34050: 1, side: 1}\n"
                                  f"  override: {_values(100)}\n  X1.MD34040: {_values(300, 100)}\n"
                                  "  X1.plant.ref_cam: [[280, 295]]\n"), encoding="utf-8")
    return paths


def _one_file_a_thousand_times(directory: Path) -> list[Path]:
    campaign = directory / "repeated.yaml"
    campaign.write_text(_campaign([str(SCENARIO)] * 1000, f"  override: {_values(100)}\n"
                                                          "  cases: [{X1.MD34050: 0, side: -1}]\n"), encoding="utf-8")
    return [campaign]


OVERSIZED: tuple[Oversized, ...] = (
    Oversized("1,000 files x 100,000 variants", _thousand_files),
    Oversized("a scenario of 10^12 variants", _trillion),
    Oversized("two files of 60,000 variants", _two_files),
    Oversized("one file named 1,000 times", _one_file_a_thousand_times),
)


def _allowed(directory: Path) -> tuple[Path, int]:
    """A campaign of 10,000 variants over machine data and an override (and its size)."""
    campaign = directory / "allowed.yaml"
    campaign.write_text(_campaign([str(SCENARIO)], "  cases:\n    - {X1.MD34050: 0, side: -1}\n"
                                                   "    - {X1.MD34050: 1, side: 1}\n"
                                                   f"  override: {_values(10, 20)}\n"
                                                   f"  X1.MD34040: {_values(50, 100)}\n"
                                                   "  X1.plant.ref_cam: [[280, 295], [250, 265]]\n"
                                                   "  X1.sim.start_position: [120, 130, 140, 150, 160]\n"),
                        encoding="utf-8")
    broken = directory / "broken.yaml"  # a problem of its own: the run stops after checking both
    broken.write_text("name: broken\nmachine: turn_mill\nplc: basic_machine\nsteps: [{wait: 1 fortnight}]\n",
                      encoding="utf-8")
    return campaign, 2 * 10 * 50 * 2 * 5


def run_campaign_size(settings: CampaignSettings, say: Say, *, only: Collection[str] | None = None,
                      bound_s: float = DEFAULT_BOUND_S, allowed: bool = True) -> Row:
    """Every oversized file (or those named in ``only``), then the allowed campaign's checking time."""
    outcomes: list[Outcome] = []
    false_passes = violations = 0
    notes = ""
    with tempfile.TemporaryDirectory(prefix="vc-campaign-size-") as directory:
        folder = Path(directory)
        for oversized in (item for item in OVERSIZED if only is None or item.name in only):
            paths = oversized.files(folder)
            outcome = run_vc(oversized.name, ["run", *map(str, paths), "-j", "1"], bound_s)
            outcomes.append(outcome)
            why = outcome.bad
            if not why and outcome.code != 2:
                false_passes += 1
                why = f"exit {outcome.code}: the run went on"
            elif not why and not any(f"{path}:" in outcome.output for path in paths):
                violations += 1
                why = "refused without FILE:LINE:COLUMN"
            if why:
                say(f"{oversized.name}: {why} ({outcome.seconds:.0f} s): {outcome.output.strip()[-300:]}")
        if allowed:
            campaign, count = _allowed(folder)
            began = wallclock.monotonic()
            outcome = run_vc("an allowed campaign of 10,000 variants", [
                "run", str(campaign), str(folder / "broken.yaml"), "--max-variants", str(count), "-j", "1"],
                bound_s * 10)
            seconds = wallclock.monotonic() - began
            outcomes.append(outcome)
            if outcome.bad or outcome.code != 2 or "broken.yaml:4" not in outcome.output \
                    or str(campaign) in outcome.output:
                violations += 1
                say(f"the allowed campaign: {outcome.bad or f'exit {outcome.code}'}: {outcome.output.strip()[-300:]}")
            notes = f"; {count:,} allowed variants checked in {seconds:.1f} s ({1000 * seconds / count:.2f} ms each)"
    return tally(PART, outcomes, false_passes=false_passes, violations=violations,
                 notes=f"{len(outcomes)} runs; false passes: an oversized run that went on{notes}")
