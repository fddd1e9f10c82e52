"""Reports of a scenario run: console lines (rich), a lazy progress bar, JUnit XML, problem lists.

Console: one line per scenario (PASS/FAIL/ERROR, name, file, simulated and wall time); for a
failure the failing step with ``file:line``, the message and a small table of the recent
history of the signals involved.  The progress bar appears only once the run has lasted one
second of wall time, so quick runs print nothing but their result lines.  Text from files and
from the simulation (names, paths, messages) is printed as :class:`~rich.text.Text`, never as
markup: rich would read ``[dim]`` in a name as a style and ``:100:`` in ``file:100:12`` as an
emoji; and through :func:`vc.escaping.terminal`, so that no control character of a name reaches
the terminal (``\x1b[2K\x1b[1G`` would repaint a FAIL line as PASS).

JUnit XML (stdlib ElementTree): one ``testsuite`` per run, one ``testcase`` per scenario with
``classname`` = the scenario file, ``<failure>`` for a failed scenario and ``<error>`` for a
scenario the harness could not run; every text through :func:`vc.escaping.junit` (XML 1.0 has no
control characters, not even as references).
"""

from __future__ import annotations

import time as wallclock
import xml.etree.ElementTree as ElementTree
from collections.abc import Callable, Sequence
from pathlib import Path

from rich.console import Console
from rich.padding import Padding
from rich.progress import BarColumn, Progress, TaskID, TextColumn, TimeElapsedColumn
from rich.table import Table
from rich.text import Text

from vc.escaping import junit, terminal
from vc.located_yaml import SourceError
from vc.scenario.language.durations import format_seconds
from vc.scenario.language.model import Scenario
from vc.scenario.language.values import format_value
from vc.scenario.run.runner import Failure, ScenarioResult

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
            table.add_row(Text(terminal(trail.name) if first else ""), Text(trail.address if first else ""),
                          f"{seconds:.3f} s", format_value(value, trail.unit))
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
            shown = ", ".join(f"{seconds:.3f} s = {format_value(value, trail.unit)}"
                              for seconds, value in trail.entries)
            address = f" [{trail.address}]" if trail.address and trail.address != trail.name else ""
            lines.append(f"  {trail.name}{address}: {shown or 'not recorded'}")
    return "\n".join(lines)


class ConsoleReport:
    """Prints results as they come; shows a progress bar once a run lasts longer than a second."""

    def __init__(self, console: Console | None = None, delay_s: float = PROGRESS_DELAY_S,
                 clock: Callable[[], float] = wallclock.perf_counter):
        self.console = console or Console(emoji=False, markup=False, highlight=False)
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
            # only on a terminal: into a file or a pipe the bar's transient line would leave a blank
            # line at its end, and a report of the same run would depend on how long it took
            if not self.console.is_terminal or self.clock() - self.began < self.delay_s:
                return
            self.progress = Progress(TextColumn("{task.description}", markup=False), BarColumn(),
                                     TextColumn("{task.completed}/{task.total}"), TimeElapsedColumn(),
                                     console=self.console, transient=True)
            self.progress.start()
            self.task = self.progress.add_task("", total=self.total)
        assert self.task is not None
        text = terminal(self.current) + (f" ({detail})" if detail else "")
        self.progress.update(self.task, completed=self.done, total=self.total, description=text)

    def close(self) -> None:
        if self.progress is not None:
            self.progress.stop()
            self.progress = None

    # printing

    def say(self, *parts: str | tuple[str, str]) -> None:
        """One line of plain text: ``(text, style)`` parts are styled, nothing is read as markup, and no
        control character (a line break neither) of a name or a message gets through."""
        self.console.print(Text.assemble(*(terminal(part) if isinstance(part, str) else (terminal(part[0]), part[1])
                                           for part in parts)), soft_wrap=True)

    def print_result(self, result: ScenarioResult) -> None:
        status = result.status
        self.say((f"{status:5}", _STYLE[status]), " ", result.scenario.name,
                 (f"  {result.scenario.path}  {_times(result)}", "dim"))
        if result.error:
            first, *rest = result.error.rstrip().splitlines() or [""]
            self.say("      ", ("the simulation failed:", "magenta"), " ", first)
            for line in rest:  # a traceback: each of its lines a line of the report
                self.say("      " + line)
            return
        failure = result.failure
        if failure is None:
            return
        self.say(("      " + failure_location(result), "bold"))
        self.say("      " + failure.message)
        table = history_table(failure)
        if table is not None:
            self.say((f"      history before the failure at {failure.time_s:.3f} s:", "dim"))
            self.console.print(Padding(table, (0, 0, 0, 6), expand=False))

    def print_summary(self, results: Sequence[ScenarioResult]) -> None:
        passed = sum(result.passed for result in results)
        errors = sum(bool(result.error) for result in results)
        failed = len(results) - passed - errors
        simulated = sum(result.simulated_s for result in results)
        wall = self.clock() - self.began
        style = "green" if passed == len(results) else "red"
        self.say((f"{passed} passed, {failed} failed, {errors} errors", style),
                 f" of {len(results)} scenarios ({format_seconds(simulated)} simulated, {wall:.2f} s wall)")

    def print_problems(self, error: SourceError) -> None:
        for problem in error.problems:
            self.say(str(problem))
        files = len({problem.mark.file for problem in error.problems})
        count = len(error.problems)
        plural = "s" if count != 1 else ""
        files_plural = "s" if files != 1 else ""
        self.say((f"{count} problem{plural} in {files} file{files_plural}; nothing ran.", "bold red"))


NOT_RUN = "not run: the run was interrupted (Ctrl-C) before this scenario finished"


def write_junit(results: Sequence[ScenarioResult], path: str | Path, suite_name: str = "vc run",
                not_run: Sequence[Scenario] = ()) -> None:
    """JUnit XML: a testsuite for the run, a testcase per scenario (classname = scenario file).
    ``not_run``: the scenarios of an interrupted run that did not finish, each a skipped testcase;
    the suite then carries the property ``interrupted``."""
    failures = sum(1 for result in results if not result.passed and not result.error)
    errors = sum(1 for result in results if result.error)
    wall = sum(result.wall_s for result in results)
    tests = str(len(results) + len(not_run))
    suites = ElementTree.Element("testsuites", name=suite_name, tests=tests,
                                 failures=str(failures), errors=str(errors), time=f"{wall:.3f}")
    suite = ElementTree.SubElement(suites, "testsuite", name=suite_name, tests=tests,
                                   failures=str(failures), errors=str(errors), skipped=str(len(not_run)),
                                   time=f"{wall:.3f}")
    if not_run:
        properties = ElementTree.SubElement(suite, "properties")
        ElementTree.SubElement(properties, "property", name="interrupted",
                               value=f"the run was interrupted (Ctrl-C) after {len(results)} of"
                                     f" {len(results) + len(not_run)} scenarios")
    for result in results:
        case = ElementTree.SubElement(suite, "testcase", classname=junit(result.scenario.path),
                                      name=junit(result.scenario.name), time=f"{result.wall_s:.3f}")
        if result.error:
            last_line = result.error.strip().splitlines()[-1] if result.error.strip() else "error"
            element = ElementTree.SubElement(case, "error", message=junit(last_line), type="harness")
            element.text = junit(result.error)
        elif result.failure is not None:
            failure = result.failure
            element = ElementTree.SubElement(case, "failure", type=failure.kind,
                                             message=junit(f"{failure_location(result)}: {failure.message}"))
            element.text = junit(failure_text(result))
        out = [f"simulated {format_seconds(result.simulated_s)} ({result.cycles} IPO cycles)"]
        out += [f"trace: {file}" for file in result.trace_files]
        ElementTree.SubElement(case, "system-out").text = junit("\n".join(out))
    for scenario in not_run:
        case = ElementTree.SubElement(suite, "testcase", classname=junit(scenario.path), name=junit(scenario.name),
                                      time="0.000")
        ElementTree.SubElement(case, "skipped", message=NOT_RUN)
    tree = ElementTree.ElementTree(suites)
    ElementTree.indent(tree)
    Path(path).parent.mkdir(parents=True, exist_ok=True)
    tree.write(path, encoding="utf-8", xml_declaration=True)
