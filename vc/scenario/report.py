"""Reports of a scenario run: console lines (rich), a lazy progress bar, JUnit XML, problem lists.

Console: one line per scenario (PASS/FAIL/ERROR, name, file, simulated and wall time); for a
failure the failing step with ``file:line``, the message and a small table of the recent
history of the signals involved.  The progress bar appears only once the run has lasted one
second of wall time, so quick runs print nothing but their result lines.

JUnit XML (stdlib ElementTree): one ``testsuite`` per run, one ``testcase`` per scenario with
``classname`` = the scenario file, ``<failure>`` for a failed scenario and ``<error>`` for a
scenario the harness could not run.
"""

from __future__ import annotations

import time as wallclock
import xml.etree.ElementTree as ElementTree
from collections.abc import Callable, Sequence
from pathlib import Path

from rich.console import Console
from rich.markup import escape
from rich.padding import Padding
from rich.progress import BarColumn, Progress, TaskID, TextColumn, TimeElapsedColumn
from rich.table import Table

from vc.located_yaml import SourceError
from vc.scenario.durations import format_seconds
from vc.scenario.model import Scenario
from vc.scenario.runner import Failure, ScenarioResult
from vc.scenario.values import format_value

PROGRESS_DELAY_S = 1.0
_STYLE = {"PASS": "bold green", "FAIL": "bold red", "ERROR": "bold magenta"}


def _times(result: ScenarioResult) -> str:
    return f"{format_seconds(result.simulated_s)} simulated, {result.wall_s:.2f} s wall"


def failure_location(result: ScenarioResult) -> str:
    return result.failure.where if result.failure is not None else result.scenario.path


def history_table(failure: Failure) -> Table | None:
    if not failure.history:
        return None
    table = Table(box=None, pad_edge=False, show_edge=False, header_style="bold")
    table.add_column("signal")
    table.add_column("address", style="dim")
    table.add_column("time", justify="right")
    table.add_column("value", justify="right")
    for trail in failure.history:
        for position, (seconds, value) in enumerate(trail.entries):
            first = position == 0
            table.add_row(escape(trail.name) if first else "", trail.address if first else "",
                          f"{seconds:.3f} s", format_value(value))
    return table


def failure_text(result: ScenarioResult) -> str:
    """The failure as plain text (for JUnit and logs)."""
    if result.error:
        return result.error
    failure = result.failure
    if failure is None:
        return ""
    lines = [f"{failure_location(result)}: {failure.message}"]
    if failure.history:
        lines.append(f"history before the failure at {failure.time_s:.3f} s:")
        for trail in failure.history:
            shown = ", ".join(f"{seconds:.3f} s = {format_value(value)}" for seconds, value in trail.entries)
            address = f" [{trail.address}]" if trail.address and trail.address != trail.name else ""
            lines.append(f"  {trail.name}{address}: {shown or 'not recorded'}")
    return "\n".join(lines)


class ConsoleReport:
    """Prints results as they come; shows a progress bar once a run lasts longer than a second."""

    def __init__(self, console: Console | None = None, delay_s: float = PROGRESS_DELAY_S,
                 clock: Callable[[], float] = wallclock.perf_counter):
        self.console = console or Console()
        self.delay_s = delay_s
        self.clock = clock
        self.began = clock()
        self.total = 0
        self.done = 0
        self.current = ""
        self.progress: Progress | None = None
        self.task: TaskID | None = None

    # RunObserver

    def scenario_started(self, scenario: Scenario, position: int, total: int) -> None:
        self.total = total
        self.current = scenario.name
        self._tick("")

    def scenario_progress(self, scenario: Scenario, simulated_s: float) -> None:
        self._tick(f"{format_seconds(simulated_s)} simulated")

    def scenario_finished(self, result: ScenarioResult) -> None:
        self.done += 1
        self.print_result(result)
        self._tick("")

    def _tick(self, detail: str) -> None:
        if self.progress is None:
            if self.clock() - self.began < self.delay_s:
                return
            self.progress = Progress(TextColumn("{task.description}"), BarColumn(),
                                     TextColumn("{task.completed}/{task.total}"), TimeElapsedColumn(),
                                     console=self.console, transient=True)
            self.progress.start()
            self.task = self.progress.add_task("", total=self.total)
        assert self.task is not None
        text = escape(self.current) + (f" [dim]({detail})[/]" if detail else "")
        self.progress.update(self.task, completed=self.done, total=self.total, description=text)

    def close(self) -> None:
        if self.progress is not None:
            self.progress.stop()
            self.progress = None

    # printing

    def print_result(self, result: ScenarioResult) -> None:
        status = result.status
        self.console.print(
            f"[{_STYLE[status]}]{status:5}[/] {escape(result.scenario.name)}"
            f"  [dim]{escape(result.scenario.path)}  {_times(result)}[/]", highlight=False, soft_wrap=True)
        if result.error:
            self.console.print(f"      [magenta]the simulation failed:[/] {escape(result.error.rstrip())}",
                               highlight=False, soft_wrap=True)
            return
        failure = result.failure
        if failure is None:
            return
        self.console.print(f"      {escape(failure_location(result))}", style="bold", highlight=False,
                           soft_wrap=True)
        self.console.print(f"      {escape(failure.message)}", highlight=False, soft_wrap=True)
        table = history_table(failure)
        if table is not None:
            self.console.print(f"      [dim]history before the failure at {failure.time_s:.3f} s:[/]")
            self.console.print(Padding(table, (0, 0, 0, 6), expand=False))

    def print_summary(self, results: Sequence[ScenarioResult]) -> None:
        passed = sum(result.passed for result in results)
        errors = sum(bool(result.error) for result in results)
        failed = len(results) - passed - errors
        simulated = sum(result.simulated_s for result in results)
        wall = self.clock() - self.began
        style = "green" if passed == len(results) else "red"
        self.console.print(
            f"[{style}]{passed} passed, {failed} failed, {errors} errors[/] of {len(results)} scenarios"
            f" ({format_seconds(simulated)} simulated, {wall:.2f} s wall)", highlight=False, soft_wrap=True)

    def print_problems(self, error: SourceError) -> None:
        for problem in error.problems:
            self.console.print(escape(str(problem)), highlight=False, soft_wrap=True)
        files = len({problem.mark.file for problem in error.problems})
        count = len(error.problems)
        plural = "s" if count != 1 else ""
        files_plural = "s" if files != 1 else ""
        self.console.print(f"[bold red]{count} problem{plural} in {files} file{files_plural};"
                           " nothing ran.[/]", highlight=False, soft_wrap=True)


def write_junit(results: Sequence[ScenarioResult], path: str | Path, suite_name: str = "vc run") -> None:
    """JUnit XML: a testsuite for the run, a testcase per scenario (classname = scenario file)."""
    failures = sum(1 for result in results if not result.passed and not result.error)
    errors = sum(1 for result in results if result.error)
    wall = sum(result.wall_s for result in results)
    suites = ElementTree.Element("testsuites", name=suite_name, tests=str(len(results)),
                                 failures=str(failures), errors=str(errors), time=f"{wall:.3f}")
    suite = ElementTree.SubElement(suites, "testsuite", name=suite_name, tests=str(len(results)),
                                   failures=str(failures), errors=str(errors), skipped="0",
                                   time=f"{wall:.3f}")
    for result in results:
        case = ElementTree.SubElement(suite, "testcase", classname=result.scenario.path,
                                      name=result.scenario.name, time=f"{result.wall_s:.3f}")
        if result.error:
            last_line = result.error.strip().splitlines()[-1] if result.error.strip() else "error"
            element = ElementTree.SubElement(case, "error", message=last_line, type="harness")
            element.text = result.error
        elif result.failure is not None:
            failure = result.failure
            element = ElementTree.SubElement(case, "failure", type=failure.kind,
                                             message=f"{failure_location(result)}: {failure.message}")
            element.text = failure_text(result)
        out = [f"simulated {format_seconds(result.simulated_s)} ({result.cycles} IPO cycles)"]
        out += [f"trace: {file}" for file in result.trace_files]
        ElementTree.SubElement(case, "system-out").text = "\n".join(out)
    tree = ElementTree.ElementTree(suites)
    ElementTree.indent(tree)
    Path(path).parent.mkdir(parents=True, exist_ok=True)
    tree.write(path, encoding="utf-8", xml_declaration=True)
