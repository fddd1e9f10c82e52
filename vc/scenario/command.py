"""``vc run PATH... [--junit FILE] [--trace-dir DIR]`` as one function the CLI calls.

Exit codes: 0 every scenario passed, 1 a scenario failed (or the harness could not run it),
2 a file has problems and nothing ran.
"""

from __future__ import annotations

from collections.abc import Callable, Collection, Sequence
from pathlib import Path

from rich.console import Console

from interfaces.signals import Catalog
from vc.located_yaml import SourceError
from vc.scenario.golden import GoldenCheck
from vc.scenario.loader import MachineLoader, load_scenarios
from vc.scenario.model import Scenario
from vc.scenario.report import ConsoleReport, write_junit
from vc.scenario.runner import run_scenarios
from vc.scenario.target import ScenarioTarget

EXIT_PASSED = 0
EXIT_FAILED = 1
EXIT_PROBLEMS = 2


def run_command(paths: Sequence[str], make_target: Callable[[Scenario], ScenarioTarget],
                known_programs: Collection[str], *, junit: str | Path | None = None,
                trace_dir: str | Path | None = None, console: Console | None = None,
                catalog: Catalog | None = None, machine_loader: MachineLoader | None = None,
                golden: str | Path | None = None, update_golden: bool = False,
                default_plc: str | None = None) -> int:
    """Check every scenario of ``paths``, run them if all are sound, report; return the exit code.

    With ``golden`` each passed scenario is compared with its golden trace in that directory
    (``update_golden`` writes the traces instead); ``default_plc``: see :func:`load_scenarios`.
    """
    report = ConsoleReport(console)
    try:
        scenarios = load_scenarios(paths, known_programs, catalog=catalog, machine_loader=machine_loader,
                                   default_plc=default_plc)
    except SourceError as error:
        report.print_problems(error)
        return EXIT_PROBLEMS
    if not scenarios:
        report.console.print("no scenario files found in " + ", ".join(paths), highlight=False)
        return EXIT_PROBLEMS
    try:
        check = GoldenCheck(Path(golden), update_golden) if golden is not None else None
        results = run_scenarios(scenarios, make_target, observer=report, trace_dir=trace_dir, check=check)
    finally:
        report.close()
    report.print_summary(results)
    if junit is not None:
        write_junit(results, junit)
    return EXIT_PASSED if all(result.passed for result in results) else EXIT_FAILED
