"""A missing optional extra is a problem at its option or line before anything runs (exit 2): matplotlib for
``--report`` and ``--plot``, awlsim for ``plc: awlsim:FILE``.  Each test runs ``vc run`` in a Python of its own
in which the package cannot be imported (a finder in front of ``sys.meta_path`` refuses it), as on a machine
where the extra was never installed."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

from vc.scenario.command import EXIT_PROBLEMS

ROOT = Path(__file__).resolve().parents[3]
PLAIN = "scenarios/foundation/jog_traverse.yaml"
WITHOUT = """
import sys

class Uninstalled:
    def find_spec(self, name, path=None, target=None):
        if name.partition(".")[0] in sys.argv[1].split(","):
            raise ModuleNotFoundError(f"No module named {name!r}", name=name)
        return None

sys.meta_path.insert(0, Uninstalled())
from vc.cli.main import main
sys.exit(main(sys.argv[2:]))
"""


def _vc_run_without(package: str, *arguments: str) -> tuple[int, str]:
    done = subprocess.run([sys.executable, "-c", WITHOUT, package, "run", *arguments], cwd=ROOT, capture_output=True,
                          text=True, timeout=120)
    return done.returncode, done.stdout + done.stderr


def test_report_without_matplotlib_is_a_problem_before_the_run(tmp_path: Path) -> None:
    code, output = _vc_run_without("matplotlib", PLAIN, "--report", str(tmp_path / "report"))
    assert code == EXIT_PROBLEMS, output
    assert output.strip() == "vc run --report: timing diagrams need matplotlib: pip install 'vc-harness[report]'"
    assert not (tmp_path / "report").exists()


def test_plot_without_matplotlib_is_a_problem_before_the_run(tmp_path: Path) -> None:
    code, output = _vc_run_without("matplotlib", "--plot", PLAIN, "--plot-to", str(tmp_path / "d.png"))
    assert code == EXIT_PROBLEMS, output
    assert output.strip() == "vc run --plot: timing diagrams need matplotlib: pip install 'vc-harness[report]'"


def test_an_awlsim_plc_without_awlsim_is_a_problem_at_its_line(tmp_path: Path) -> None:
    (tmp_path / "p.awl").write_text("")
    scenario = tmp_path / "s.yaml"
    scenario.write_text(f"name: s\nmachine: {ROOT / 'scenarios/machines/turn_mill.yaml'}\nplc: awlsim:p.awl\n"
                        "steps:\n  - wait: 10ms\n")
    code, output = _vc_run_without("awlsim", str(scenario))
    assert code == EXIT_PROBLEMS, output
    assert output.splitlines() == [
        f"{scenario}:3:6: plc: awlsim: runs the program in awlsim, which is not installed here:"
        " pip install 'vc-harness[awlsim]'",
        "1 problem in 1 file; nothing ran."]
