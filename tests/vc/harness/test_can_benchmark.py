"""``vc bench --link can``, run very briefly: structure and plausibility of the figures (no speed
targets: one short run on a shared machine says nothing; bench/README.md records the figures)."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from vc.cli.main import main

ROOT = Path(__file__).resolve().parents[3]
TURN_MILL = str(ROOT / "scenarios" / "machines" / "turn_mill.yaml")
BUSES = ("virtual", "udp_multicast")


def test_the_command_prints_both_measurements_of_both_buses_and_the_figures_in_json(
        capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["bench", "--link", "can", "--machine", TURN_MILL, "--seconds", "0.5", "--frames", "600"]) == 0
    lines = capsys.readouterr().out.strip().splitlines()
    figures = json.loads(lines[-1])
    assert set(figures) == {f"{bus}_{name}" for bus in BUSES for name in (
        "frames_per_s", "lockstep_us_per_cycle", "added_us_per_cycle", "lockstep_frames_per_s",
        "lockstep_realtime_factor")}
    for bus in BUSES:
        assert figures[f"{bus}_frames_per_s"] > 0
        assert figures[f"{bus}_lockstep_us_per_cycle"] > 0 and figures[f"{bus}_lockstep_realtime_factor"] > 0
        # 16 + 1 frames out and 13 + 1 in every PLC period of 5 IPO cycles: 31 / 5 per cycle
        assert 5.5 < figures[f"{bus}_lockstep_frames_per_s"] / 1e6 * figures[f"{bus}_lockstep_us_per_cycle"] < 7.5
    text = "\n".join(lines[:-1])
    assert "throughput" in text and "lockstep" in text and "frames/s" in text and "us per IPO cycle" in text
