"""``vc bench --link can``, run very briefly: structure and plausibility of the figures (no speed
targets: one short run on a shared machine says nothing; bench/README.md records the figures)."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from vc.bench.can_link import burst_of
from vc.cli.main import main
from vc.config.loader import load_machine

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
        # 20 + 1 frames out and 14 + 1 in every PLC period of 5 IPO cycles: 36 / 5 per cycle
        assert 6.0 < figures[f"{bus}_lockstep_frames_per_s"] / 1e6 * figures[f"{bus}_lockstep_us_per_cycle"] < 8.5
    text = "\n".join(lines[:-1])
    assert "throughput" in text and "lockstep" in text and "frames/s" in text and "us per IPO cycle" in text


def test_the_burst_is_the_machines_frame_table(tmp_path: Path) -> None:
    burst = burst_of(load_machine(TURN_MILL))
    assert [can_id for can_id, _ in burst.data] == list(range(0x200, 0x214))
    assert (burst.end, burst.answer) == (0x100, 0x101)
    assert burst.data[0] == (0x200, 12) and burst.data[-1] == (0x213, 12)  # IB0..9, DB10.DBB110..117 (docs/can.md)
    moved = tmp_path / "moved.yaml"
    moved.write_text(Path(TURN_MILL).read_text(encoding="utf-8") + "can: {ids: {link: 0x80, nc_to_plc: 0x300}}\n",
                     encoding="utf-8")
    burst = burst_of(load_machine(str(moved)))
    assert [can_id for can_id, _ in burst.data] == list(range(0x300, 0x314))
    assert (burst.end, burst.answer) == (0x80, 0x81)
    assert [len(frame.data) for frame in burst.frames()][:2] == [12, 5]
