"""``vc run PATH... [-j N] [--junit FILE] [--trace-dir DIR]`` as one function the CLI calls.

Exit codes: 0 every scenario passed, 1 a scenario failed (or the harness could not run it),
2 a file has problems and nothing ran, 130 the user stopped the run (Ctrl-C).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from pathlib import Path

from rich.console import Console

from interfaces.signals import Catalog
from vc.located_yaml import SourceError
from vc.scenario.golden import GoldenCheck
from vc.scenario.loader import MachineLoader, Programs, load_scenarios
from vc.scenario.model import Scenario
from vc.scenario.parallel import RunSettings, jobs_for, run_parallel
from vc.scenario.report import ConsoleReport, write_junit
from vc.scenario.runner import run_scenarios
from vc.scenario.target import ScenarioTarget

EXIT_PASSED = 0
EXIT_FAILED = 1
EXIT_PROBLEMS = 2
EXIT_INTERRUPTED = 130  # as a shell reports a command ended by SIGINT


def run_command(paths: Sequence[str], make_target: Callable[[Scenario], ScenarioTarget],
                known_programs: Programs, *, junit: str | Path | None = None,
                trace_dir: str | Path | None = None, console: Console | None = None,
                catalog: Catalog | None = None, machine_loader: MachineLoader | None = None,
                golden: str | Path | None = None, update_golden: bool = False, jobs: int | None = 1,
                build: str = "") -> int:
    """Check every scenario of ``paths``, run them if all are sound, report; return the exit code.

    With ``golden`` each passed scenario is compared with its golden trace in that directory
    (``update_golden`` writes the traces instead).  ``jobs`` worker processes run the files
    (None: one per core; 1: in this process); a run with its own ``catalog`` or
    ``machine_loader``, or with a scenario of an external PLC, stays in this process.  ``build``
    names the build that runs (printed first).
    """
    report = ConsoleReport(console)
    try:
        scenarios = load_scenarios(paths, known_programs, catalog=catalog, machine_loader=machine_loader)
    except SourceError as error:
        report.print_problems(error)
        return EXIT_PROBLEMS
    if not scenarios:
        report.say("no scenario files found in " + ", ".join(paths))
        return EXIT_PROBLEMS
    if catalog is not None or machine_loader is not None:
        jobs = 1
    if any(scenario.external_plc is not None for scenario in scenarios):
        jobs = 1  # each external PLC process belongs to the process that starts and ends it
    workers = jobs_for(jobs, scenarios)
    if build:
        across = f"{workers} worker processes" if workers > 1 else "in this process"
        report.console.print(f"{len(scenarios)} scenarios, {across}, {build}", highlight=False, soft_wrap=True)
    try:
        if workers > 1:
            settings = RunSettings(tuple(known_programs), make_target, None if trace_dir is None else str(trace_dir),
                                   None if golden is None else str(golden), update_golden)
            results = run_parallel(scenarios, settings, workers, observer=report)
        else:
            check = GoldenCheck(Path(golden), update_golden) if golden is not None else None
            results = run_scenarios(scenarios, make_target, observer=report, trace_dir=trace_dir, check=check)
    except KeyboardInterrupt:
        report.close()
        report.console.print(f"interrupted after {report.done} of {len(scenarios)} scenarios", highlight=False)
        return EXIT_INTERRUPTED
    finally:
        report.close()
    report.print_summary(results)
    if junit is not None:
        write_junit(results, junit)
    return EXIT_PASSED if all(result.passed for result in results) else EXIT_FAILED
