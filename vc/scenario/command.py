"""``vc run PATH... [-j N | --cluster ADDRESS] [--junit FILE] [--trace-dir DIR] [--report DIR]`` and
``vc run --plot SCENARIO`` as functions the CLI calls.

Exit codes: 0 every scenario passed, 1 a scenario failed (or the harness could not run it),
2 a file has problems and nothing ran (or the cluster cannot be used), 130 the user stopped the
run (Ctrl-C): the JUnit file and the HTML report are still written, with the scenarios that
finished and the others marked as not run.
"""

from __future__ import annotations

import os
import re
import sys
import time as wallclock
from collections.abc import Callable, Collection, Sequence
from pathlib import Path

from rich.console import Console

from interfaces.signals import Catalog
from vc.input_limits import MAX_RUN_VARIANTS
from vc.located_yaml import SourceError
from vc.scenario.distribution.cluster import ClusterError, ClusterSettings, run_on_cluster
from vc.scenario.distribution.parallel import RunSettings, jobs_for, process_context, run_parallel
from vc.scenario.distribution.tasks import SEND_DIAGRAM, SEND_NOTHING
from vc.scenario.language.loader import MachineLoader, Programs, load_scenarios
from vc.scenario.language.model import Scenario
from vc.scenario.language.selection import Selection
from vc.scenario.language.target import ScenarioTarget
from vc.scenario.outputs.golden import GoldenCheck
from vc.scenario.outputs.report import ConsoleReport, write_junit
from vc.scenario.run.runner import RunInterrupted, RunObserver, ScenarioResult, file_stem, run_one, run_scenarios

EXIT_PASSED = 0
EXIT_FAILED = 1
EXIT_PROBLEMS = 2
EXIT_INTERRUPTED = 130  # as a shell reports a command ended by SIGINT


class _Observers:
    """Tells every observer; then lets the result's recording go (a campaign of thousands of
    variants would otherwise keep every recording until the end)."""

    def __init__(self, *observers: RunObserver):
        self.observers = observers

    def scenario_started(self, scenario: Scenario, position: int, total: int) -> None:
        for observer in self.observers:
            observer.scenario_started(scenario, position, total)

    def scenario_progress(self, scenario: Scenario, simulated_s: float) -> None:
        for observer in self.observers:
            observer.scenario_progress(scenario, simulated_s)

    def scenario_finished(self, result: ScenarioResult) -> None:
        for observer in self.observers:
            observer.scenario_finished(result)
        result.recorder = None


def run_command(paths: Sequence[str], make_target: Callable[[Scenario], ScenarioTarget],
                known_programs: Programs, *, junit: str | Path | None = None,
                trace_dir: str | Path | None = None, console: Console | None = None,
                catalog: Catalog | None = None, machine_loader: MachineLoader | None = None,
                golden: str | Path | None = None, update_golden: bool = False, jobs: int | None = 1,
                build: str = "", cluster: ClusterSettings | None = None,
                report_dir: str | Path | None = None, default_plc: str | None = None,
                max_variants: int = MAX_RUN_VARIANTS, selection: Selection | None = None) -> int:
    """Check every scenario of ``paths``, run them if all are sound, report; return the exit code.

    With ``golden`` each passed scenario is compared with its golden trace in that directory
    (``update_golden`` writes the traces instead).  ``jobs`` worker processes run the scenarios
    (None: one per core; 1: in this process); ``cluster`` runs them on a Dask cluster instead
    (:mod:`vc.scenario.distribution.cluster`).  A run with its own ``catalog`` or ``machine_loader``, or with a
    scenario of an external PLC, stays in this process.  ``report_dir`` gets the HTML report with timing diagrams.
    ``build`` names the build that runs (printed first); ``default_plc`` and ``max_variants``: see
    :func:`load_scenarios`; ``selection`` (``-k``, ``--shard``) keeps part of the scenarios.
    """
    report = ConsoleReport(console)
    began = wallclock.perf_counter()

    def say(text: str) -> None:  # plain text: a path or a message is never read as markup or emoji
        report.say(text)

    if report_dir is not None and not _can_draw(say, "--report"):
        return EXIT_PROBLEMS
    try:
        scenarios = load_scenarios(paths, known_programs, catalog=catalog, machine_loader=machine_loader,
                                   default_plc=default_plc, max_variants=max_variants)
    except SourceError as error:
        report.print_problems(error)
        return EXIT_PROBLEMS
    if not scenarios:
        report.say("no scenario files found in " + ", ".join(paths))
        return EXIT_PROBLEMS
    if selection is not None:
        found = len(scenarios)
        scenarios = selection.apply(scenarios)
        say(f"{selection.describe()}: {len(scenarios)} of {found} scenarios")
        if not scenarios:
            say(f"vc run: {selection.describe()} selects none of the {found} scenarios")
            return EXIT_PROBLEMS
    check = GoldenCheck(Path(golden), update_golden) if golden is not None else None
    if check is not None and (shared := check.shared(scenarios)):
        for sentence in shared:
            say(f"vc run --golden: {sentence}")
        return EXIT_PROBLEMS
    if cluster is not None:
        try:
            cluster.check()
        except ClusterError as error:
            say(f"vc run: {error}")
            return EXIT_PROBLEMS
    if catalog is not None or machine_loader is not None:
        jobs, cluster = 1, None
    if any(scenario.external_plc is not None for scenario in scenarios):
        jobs, cluster = 1, None  # each external PLC process belongs to the process that starts and ends it
    html = None
    if report_dir is not None:
        from vc.scenario.outputs.html_report import HtmlReport

        html = HtmlReport(report_dir)
    observer = _Observers(report, html) if html is not None else _Observers(report)
    workers = jobs_for(jobs, scenarios)
    if build:
        across = f"{workers} worker processes" if workers > 1 else "in this process"
        if cluster is not None:
            across = f"on the Dask cluster {cluster.address}"
        say(f"{len(scenarios)} scenarios, {across}, {build}")
    settings = RunSettings(tuple(known_programs), make_target, None if trace_dir is None else str(trace_dir),
                           None if golden is None else str(golden), update_golden,
                           SEND_DIAGRAM if html is not None else SEND_NOTHING)
    notes: list[str] = []
    interrupted = False
    try:
        if cluster is not None:
            run = run_on_cluster(scenarios, settings, cluster, check=check, report=html is not None,
                                 observer=observer, say=say)
            results, notes = run.results, run.rerun_lines(scenarios)
        elif workers > 1:
            parallel = run_parallel(scenarios, settings, workers, observer=observer)
            results, notes = parallel.results, parallel.rerun_lines(scenarios)
        else:
            results = run_scenarios(scenarios, make_target, observer=observer, trace_dir=trace_dir, check=check,
                                    record_all=settings.records_all)
    except ClusterError as error:
        report.close()
        say(f"vc run: {error}")
        return EXIT_PROBLEMS
    except KeyboardInterrupt as interruption:  # what finished is still reported, marked as interrupted
        results = interruption.results if isinstance(interruption, RunInterrupted) else []
        interrupted = True
    finally:
        report.close()
    finished = {id(result.scenario) for result in results}
    not_run = [scenario for scenario in scenarios if id(scenario) not in finished]
    try:
        if interrupted:
            say(f"interrupted after {len(results)} of {len(scenarios)} scenarios")
        else:
            report.print_summary(results)
        for note in notes:
            say(f"re-run: {note}")
        if junit is not None:
            write_junit(results, junit, not_run=not_run)
        if html is not None:
            html.include(results)
            page = html.write(notes=notes, wall_s=wallclock.perf_counter() - began, build=build, jobs=workers,
                              mp_context=process_context(), not_run=len(not_run))
            say(f"report: {page}")
    except KeyboardInterrupt:  # pressed again while the reports are written
        return EXIT_INTERRUPTED
    if interrupted:
        return EXIT_INTERRUPTED
    return EXIT_PASSED if all(result.passed for result in results) else EXIT_FAILED


_VARIANT = re.compile(r"^(?P<path>.+?)\[(?P<arguments>.*)\]$")


def plot_command(spec: str, make_target: Callable[[Scenario], ScenarioTarget], known_programs: Collection[str],
                 *, output: str | None = None, console: Console | None = None) -> int:
    """``vc run --plot SCENARIO``: run one scenario in this process and show its timing diagram
    (in a window; written to ``output``, or to ``<name>.png`` here when there is no display).

    ``SCENARIO`` is a scenario file (its first variant, if it has a matrix) or a variant of it,
    ``FILE[ARGUMENTS]`` with the bracket of the variant's id (``edges.yaml[X1.MD34050=1,...]``).
    """
    from vc.scenario.outputs.diagram import DiagramError, save, show
    from vc.scenario.outputs.timing import timing_diagram

    report = ConsoleReport(console)

    def say(text: str) -> None:
        report.say(text)

    if not _can_draw(say, "--plot"):
        return EXIT_PROBLEMS
    path, wanted = spec, None
    match = _VARIANT.match(spec)
    if match is not None and not os.path.isfile(spec):
        path, wanted = match.group("path"), match.group("arguments")
    try:
        scenarios = load_scenarios([path], known_programs)
    except SourceError as error:
        report.print_problems(error)
        return EXIT_PROBLEMS
    chosen = [s for s in scenarios if wanted is None or (s.variant is not None and s.variant.arguments == wanted)]
    if not chosen:
        known = "; ".join(s.variant.arguments for s in scenarios[:5] if s.variant is not None)
        say(f"--plot {spec}: no variant [{wanted}] in {path} (variants such as: {known})")
        return EXIT_PROBLEMS
    result = run_one(chosen[0], make_target)
    report.print_result(result)
    diagram = timing_diagram(result)
    if diagram is None:
        say("the scenario could not run: no diagram")
        return EXIT_FAILED
    try:
        if output is None and _has_display():
            show(diagram)
        else:
            target = Path(output or f"{file_stem(chosen[0])}.png")
            save(diagram, target)
            say(f"timing diagram: {target}")
    except DiagramError as error:
        say(f"vc run --plot: {error}")
        return EXIT_PROBLEMS
    return EXIT_PASSED if result.passed else EXIT_FAILED


def _can_draw(say: Callable[[str], None], option: str) -> bool:
    """Whether the diagrams of ``option`` can be drawn here; if not, says why (before anything runs)."""
    from vc.scenario.outputs.diagram import DiagramError, require_matplotlib

    try:
        require_matplotlib()
    except DiagramError as error:
        say(f"vc run {option}: {error}")
        return False
    return True


def _has_display() -> bool:
    if sys.platform in ("darwin", "win32"):
        return True
    return bool(os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY"))
