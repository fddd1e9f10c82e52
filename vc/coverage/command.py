"""``vc coverage report FILE... [--json OUT] [--html OUT] [--fail-under PCT] [--fail-under-function NAME=PCT]``.

Reads and merges the coverage files of ``vc run --coverage`` (several runs, or the parts of one),
prints the summary, writes the JSON and HTML reports, and checks the thresholds.  A name the
harness does not know (a signal, a plant point, a state machine or state, an alarm) is a problem
of its file at its key, not merged.  Exit codes:
0 every threshold met, 1 a figure falls short, 2 a file or an option has problems (each problem
``file:line:column: message``).
"""

from __future__ import annotations

import json
from collections.abc import Callable, Mapping, Sequence

from vc.coverage.data import CoverageData
from vc.coverage.html import report_html
from vc.coverage.names import CoverageNames
from vc.coverage.report import build_report, check_thresholds, summary_text
from vc.located_yaml import Problem, SourceError

EXIT_MET = 0
EXIT_SHORT = 1
EXIT_PROBLEMS = 2


def parse_function_threshold(text: str) -> tuple[str, float]:
    """``referencing=90`` -> ("referencing", 90.0); raises ValueError with what is expected."""
    name, separator, value = text.partition("=")
    try:
        percent = float(value)
    except ValueError:
        percent = -1.0
    if not separator or not name.strip() or not 0.0 <= percent <= 100.0:
        raise ValueError(f"--fail-under-function {text}: write NAME=PERCENT, e.g. gear_change=80")
    return name.strip(), percent


def coverage_report(paths: Sequence[str], *, json_path: str | None = None, html_path: str | None = None,
                    fail_under: float | None = None, fail_under_function: Mapping[str, float] | None = None,
                    say: Callable[[str], None] = print, complain: Callable[[str], None] = print) -> int:
    problems: list[Problem] = []
    data = CoverageData()
    names = CoverageNames.of_this_harness()
    for path in paths:
        try:
            data.merge(CoverageData.load(path, names))
        except SourceError as error:
            problems.extend(error.problems)
    if problems:
        raise SourceError(problems)
    report = build_report(data)
    say(summary_text(report).rstrip("\n"))
    try:
        short = check_thresholds(report, fail_under, fail_under_function or {})
    except KeyError as error:
        complain(f"vc coverage report: {error.args[0]}")
        return EXIT_PROBLEMS
    if json_path is not None:
        with open(json_path, "w", encoding="utf-8") as handle:
            json.dump(report.to_json(), handle, indent=1)
            handle.write("\n")
    if html_path is not None:
        with open(html_path, "w", encoding="utf-8") as handle:
            handle.write(report_html(report))
    for line in short:
        complain(f"FAIL {line}")
    return EXIT_SHORT if short else EXIT_MET
