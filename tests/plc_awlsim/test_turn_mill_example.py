"""The shipped STL program in awlsim runs its scenario in lockstep: it passes, matches its golden trace,
and two runs give the same trace to the last bit; a broken program is reported with its line."""

from __future__ import annotations

import io
from pathlib import Path

import pytest
from rich.console import Console

pytest.importorskip("awlsim")

from interfaces.links.inprocess import plc_programs
from vc.harness.external_plc import ExternalPlcs
from vc.harness.targets import simulation_for
from vc.scenario.command import EXIT_FAILED, EXIT_PASSED, run_command

ROOT = Path(__file__).resolve().parents[2]
SCENARIO = "examples/awlsim/turn_mill_bringup.yaml"


def _run(paths: list[str], **options: object) -> tuple[int, str, int]:
    output = io.StringIO()
    with ExternalPlcs(first_scan_timeout_s=60) as external:
        code = run_command(paths, external.wrap(simulation_for), plc_programs().keys(),
                           console=Console(file=output, width=200), **options)  # type: ignore[arg-type]
        runs = external.runs
    return code, output.getvalue(), runs


@pytest.mark.timeout(600)
def test_the_example_passes_matches_its_golden_trace_and_repeats_bit_for_bit(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(ROOT)
    traces = []
    for run in ("first", "second"):
        code, output, runs = _run([SCENARIO], golden="tests/golden", trace_dir=str(tmp_path / run))
        assert code == EXIT_PASSED, output
        assert runs == 1  # its own awlsim process
        traces.append((tmp_path / run / "turn_mill_bringup.csv").read_bytes())
    assert traces[0] == traces[1]
    assert b"SP1.spindle.out.oscillEnable" in traces[0]


@pytest.mark.timeout(120)
def test_a_broken_program_fails_the_scenario_with_the_line_awlsim_found(tmp_path: Path) -> None:
    program = tmp_path / "broken.awl"
    program.write_text('ORGANIZATION_BLOCK OB 1\nBEGIN\n\tA\t"X1_enc1Synchronized"\n\tXYZ\tM 0.0\n'
                       'END_ORGANIZATION_BLOCK\n')
    scenario = tmp_path / "broken.yaml"
    scenario.write_text(f"name: broken\nmachine: {ROOT / 'scenarios/machines/turn_mill.yaml'}\n"
                        "plc: awlsim:broken.awl\nsteps:\n  - wait: 100ms\n")
    code, output, _ = _run([str(scenario)])
    assert code == EXIT_FAILED
    assert "cannot run" in output and "broken.awl" in output and "XYZ" in output, output
