"""A short version of the input parts of the robustness campaign (bench/robustness.py): a few
hostile recordings, expressions and oversized campaigns, each through ``vc replay`` or ``vc run``
in its own process.  None may end in a crash, a hang, a traceback, a false pass or a refusal
without its location (the full parts: bench/robustness.py --parts recordings,expressions,campaign_size)."""

from __future__ import annotations

import pytest

from vc.bench.robustness.campaign import CampaignSettings, Row, table
from vc.bench.robustness.campaign_size import run_campaign_size
from vc.bench.robustness.hostile_expressions import run_hostile_expressions
from vc.bench.robustness.hostile_recordings import run_hostile_recordings

SETTINGS = CampaignSettings()


def _clean(row: Row, inputs: int) -> None:
    assert (row.crashes, row.hangs, row.tracebacks, row.false_passes, row.violations) == (0, 0, 0, 0, 0), table([row])
    assert row.inputs == inputs


@pytest.mark.timeout(600)
def test_hostile_recordings() -> None:
    said: list[str] = []
    chosen = {"row nested 100,000 deep", "ipo_cycle_us of 5,000 digits", "NaN velocity", "an area of 10^12 bytes",
              "cycle 10^30", "newline in the machine's name", "a cut last line", "a cut gzip stream"}
    _clean(run_hostile_recordings(SETTINGS, said.append, only=chosen, bound_s=60), 2 * len(chosen))
    assert said[0].startswith("a sound recording of ")


@pytest.mark.timeout(600)
def test_hostile_expressions() -> None:
    chosen = {"3,000 unary minus", "a product of 250 numbers of 20 digits", "5,000 digits divided by 3",
              "2,000 and"}
    _clean(run_hostile_expressions(SETTINGS, lambda text: None, only=chosen, bound_s=60), 11)


@pytest.mark.timeout(600)
def test_campaign_size() -> None:
    row = run_campaign_size(SETTINGS, lambda text: None, only={"1,000 files x 100,000 variants",
                                                              "two files of 60,000 variants"},
                            bound_s=60, allowed=False)
    _clean(row, 2)
