"""``vc run --report DIR``: one HTML page of a run, readable offline, with a timing diagram per scenario.

``DIR/index.html`` needs no server and nothing from the network: the style is in the page, the
diagrams are PNG (or SVG) files beside it in ``DIR/diagrams/``, where CI systems can attach them.
The page shows, in this order:

* the summary: passed, failed, errors, simulated and wall time, and what the run noted (a
  cluster's re-runs);
* every failing scenario and variant, with where and why, linking to its diagram;
* per matrix (a scenario's ``vary:`` or a campaign): each varied value with how many of its
  variants passed, and the matrix itself, one row per variant with the varied values as columns
  and its outcome, the failing ones linking to their diagrams;
* the diagrams (:mod:`vc.scenario.outputs.diagram`): failures first, then every scenario in run order;
  of a matrix only its first variant and its failures (a campaign of a thousand variants would
  otherwise draw a thousand).

:class:`HtmlReport` is a run observer: it keeps what the page needs of each result as it is
reported (the diagram's data, not the recording) and draws and writes everything at the end.
"""

from __future__ import annotations

import datetime
import os
import urllib.parse
from collections.abc import Sequence
from concurrent.futures import ProcessPoolExecutor
from dataclasses import dataclass, field
from multiprocessing.context import BaseContext
from pathlib import Path

from vc.escaping import html_text
from vc.scenario.language.durations import format_seconds
from vc.scenario.language.model import Scenario, Variant
from vc.scenario.outputs.report import failure_location, failure_text
from vc.scenario.outputs.timing import TimingDiagram, timing_diagram
from vc.scenario.run.runner import ScenarioResult, trace_names

PAGE = "index.html"
DIAGRAMS = "diagrams"
MAX_FAILURE_DIAGRAMS = 200  # of failing variants of matrices; every failing plain scenario gets one
_STATUS_CLASS = {"PASS": "pass", "FAIL": "fail", "ERROR": "error"}
_STYLE = """
body{font:14px/1.45 system-ui,-apple-system,Segoe UI,Roboto,sans-serif;margin:24px;color:#222;max-width:1500px}
h1{font-size:22px;margin:0 0 4px}h2{font-size:18px;margin:28px 0 8px;border-bottom:1px solid #ddd}
h3{font-size:15px;margin:18px 0 6px}table{border-collapse:collapse;margin:6px 0 12px}
th,td{border:1px solid #ddd;padding:3px 8px;text-align:left;vertical-align:top}th{background:#f4f4f4}
td.num{text-align:right}.pass{color:#1e7d32}.fail{color:#c0392b;font-weight:600}
.error{color:#8e24aa;font-weight:600}tr.fail td,tr.error td{background:#fdf0ef}
pre{background:#f8f8f8;padding:8px;overflow-x:auto;font-size:12px;white-space:pre-wrap}
.muted{color:#777}section{margin:18px 0 30px}img{max-width:100%;height:auto;border:1px solid #eee}
.summary td{font-size:15px}code{font-size:12px}
"""


@dataclass(slots=True)
class _Entry:
    position: int
    scenario: Scenario
    status: str
    where: str
    why: str  # the failure's message, or the last line of a harness error
    text: str
    simulated_s: float
    wall_s: float
    trace_files: list[str]
    diagram: TimingDiagram | None = None
    image: str = ""  # relative to the page, once drawn
    size: tuple[int, int] = (0, 0)
    drawing_error: str = ""  # why the diagram could not be drawn

    @property
    def anchor(self) -> str:
        return f"s{self.position + 1}"


@dataclass(slots=True)
class _Matrix:
    origin: str
    path: str
    title: str
    keys: list[str]
    entries: list[_Entry] = field(default_factory=list)


class HtmlReport:
    """Collects what the page shows while the run reports; :meth:`write` draws and writes it."""

    def __init__(self, directory: str | Path, image_format: str = "png"):
        self.directory = Path(directory)
        self.image_format = image_format
        self.entries: list[_Entry] = []
        self.failure_diagrams = 0

    # RunObserver

    def scenario_started(self, scenario: Scenario, position: int, total: int) -> None:
        pass

    def scenario_progress(self, scenario: Scenario, simulated_s: float) -> None:
        pass

    def scenario_finished(self, result: ScenarioResult) -> None:
        variant = result.scenario.variant
        wanted = variant is None or variant.first
        if not wanted and not result.passed and self.failure_diagrams < MAX_FAILURE_DIAGRAMS:
            wanted = True
            self.failure_diagrams += 1
        where = failure_location(result) if result.failure is not None else ""
        why = result.failure.message if result.failure is not None else ""
        if result.error:
            why = result.error.strip().splitlines()[-1] if result.error.strip() else "error"
        self.entries.append(_Entry(len(self.entries), result.scenario, result.status, where, why, failure_text(result),
                                   result.simulated_s, result.wall_s, list(result.trace_files),
                                   timing_diagram(result) if wanted else None))

    def include(self, results: Sequence[ScenarioResult]) -> None:
        """Take the results it was not told about (a run interrupted while it reported one)."""
        seen = {id(entry.scenario) for entry in self.entries}
        for result in results:
            if id(result.scenario) not in seen:
                self.scenario_finished(result)

    # writing

    def write(self, *, title: str = "vc run", notes: Sequence[str] = (), wall_s: float | None = None,
              build: str = "", jobs: int = 1, mp_context: BaseContext | None = None, not_run: int = 0) -> Path:
        """Draw the diagrams, write the page; the page's path.  ``jobs`` processes draw, started as
        ``mp_context`` says (the caller's way of starting processes; Python's default if None).
        ``not_run``: the scenarios of an interrupted run that did not finish (the page says so first)."""
        self.directory.mkdir(parents=True, exist_ok=True)
        self._draw(jobs, mp_context)
        if not_run:
            total = len(self.entries) + not_run
            notes = [f"The run was interrupted (Ctrl-C) after {len(self.entries)} of {total} scenarios: the other"
                     f" {not_run} did not finish and are not on this page.", *notes]
        page = self.directory / PAGE
        page.write_text(self._page(title, notes, wall_s, build, not_run), encoding="utf-8")
        return page

    def _draw(self, jobs: int, mp_context: BaseContext | None) -> None:
        drawn = [entry for entry in self.entries if entry.diagram is not None]
        names = trace_names([entry.scenario for entry in drawn])
        targets = [self.directory / DIAGRAMS / f"{name}.{self.image_format}" for name in names]
        jobs = max(1, min(jobs, len(drawn) // 4))
        if jobs > 1:
            with ProcessPoolExecutor(max_workers=jobs, mp_context=mp_context) as pool:
                sizes = list(pool.map(_save, [entry.diagram for entry in drawn], targets))
        else:
            sizes = [_save(entry.diagram, target) for entry, target in zip(drawn, targets, strict=True)]
        for entry, target, (size, error) in zip(drawn, targets, sizes, strict=True):
            if error:
                entry.drawing_error = error
                continue
            entry.image = f"{DIAGRAMS}/{urllib.parse.quote(target.name)}"
            entry.size = size

    # -- the page --------------------------------------------------------------------------

    def _page(self, title: str, notes: Sequence[str], wall_s: float | None, build: str, not_run: int) -> str:
        entries = self.entries
        passed = sum(entry.status == "PASS" for entry in entries)
        errors = sum(entry.status == "ERROR" for entry in entries)
        failed = len(entries) - passed - errors
        headline = f"{failed + errors} of {len(entries)} failed" if failed + errors else f"all {len(entries)} passed"
        if not_run:
            headline = f"interrupted, {headline} of those that finished"
        generated = datetime.datetime.now(datetime.UTC).strftime("%Y-%m-%d %H:%M UTC")
        out = ["<!DOCTYPE html>", '<html lang="en"><head><meta charset="utf-8">',
               f"<title>{_e(title)}: {_e(headline)}</title>", f"<style>{_STYLE}</style></head><body>",
               f"<h1>{_e(title)}: {_e(headline)}</h1>",
               f'<p class="muted">{_e(generated)}{" &middot; " + _e(build) if build else ""}</p>']
        simulated = sum(entry.simulated_s for entry in entries)
        rows = [("passed", f'<span class="pass">{passed}</span>'), ("failed", _count(failed, "fail")),
                ("errors", _count(errors, "error")), ("scenarios and variants", str(len(entries))),
                ("simulated", _e(format_seconds(simulated)))]
        if wall_s is not None:
            rows.append(("wall time", f"{wall_s:.1f} s"))
        out.append('<table class="summary">' + "".join(f"<tr><th>{label}</th><td>{value}</td></tr>"
                                                       for label, value in rows) + "</table>")
        if notes:
            out.append("<h2>Notes</h2><ul>" + "".join(f"<li>{_e(note)}</li>" for note in notes) + "</ul>")
        out += self._failing()
        out += self._matrices()
        out += self._diagrams()
        out += self._all()
        out.append("</body></html>")
        return "\n".join(out) + "\n"

    def _failing(self) -> list[str]:
        failing = [entry for entry in self.entries if entry.status != "PASS"]
        if not failing:
            return []
        out = ["<h2>Failing</h2>", "<table><tr><th>outcome</th><th>scenario</th><th>where</th><th>why</th></tr>"]
        for entry in failing:
            out.append(f'<tr class="{_STATUS_CLASS[entry.status]}"><td>{_status(entry.status)}</td>'
                       f"<td>{self._link(entry, entry.scenario.name)}</td><td><code>{_e(entry.where)}</code></td>"
                       f"<td>{_e(entry.why)}</td></tr>")
        out.append("</table>")
        return out

    def _matrices(self) -> list[str]:
        matrices = _matrices_of(self.entries)
        if not matrices:
            return []
        out = ["<h2>Matrices</h2>"]
        for matrix in matrices:
            failing = sum(entry.status != "PASS" for entry in matrix.entries)
            out.append(f"<h3>{_e(matrix.title)}</h3>")
            over = f" over the matrix of <code>{_e(matrix.origin)}</code>" if matrix.origin != matrix.path else ""
            out.append(f'<p class="muted"><code>{_e(matrix.path)}</code>{over}: {len(matrix.entries)} variants,'
                       f" {_count(failing, 'fail')} failed</p>")
            out += _by_value(matrix)
            out.append("<table><tr><th>#</th>" + "".join(f"<th>{_e(key)}</th>" for key in matrix.keys)
                       + "<th>outcome</th><th>simulated</th></tr>")
            for entry in matrix.entries:
                variant = entry.scenario.variant
                assert variant is not None
                values = dict(variant.values)
                outcome = self._link(entry, entry.status) if entry.diagram is not None else _status(entry.status)
                out.append(f'<tr class="{_STATUS_CLASS[entry.status]}"><td class="num">{variant.index + 1}</td>'
                           + "".join(f"<td>{_e(values.get(key, ''))}</td>" for key in matrix.keys)
                           + f'<td class="{_STATUS_CLASS[entry.status]}">{outcome}</td>'
                           f'<td class="num">{_e(format_seconds(entry.simulated_s))}</td></tr>')
            out.append("</table>")
        return out

    def _diagrams(self) -> list[str]:
        drawn = [entry for entry in self.entries if entry.diagram is not None]
        ordered = [entry for entry in drawn if entry.status != "PASS"] + \
                  [entry for entry in drawn if entry.status == "PASS"]
        if not ordered:
            return []
        out = ["<h2>Timing diagrams</h2>",
               '<p class="muted">Digital lanes: the keys pressed and the signals the scenario expects, waits for'
               " and orders; analog lanes: axis quantities. Dotted lines: where the numbered steps began; red: the"
               " failing step and the failure; green: an expected window (expect_timing), lightly: the time a"
               " wait may take.</p>"]
        for entry in ordered:
            out.append(f'<section id="{entry.anchor}"><h3>{_status(entry.status)} {_e(entry.scenario.name)}</h3>')
            out.append(f'<p class="muted"><code>{_e(entry.scenario.path)}</code> &middot;'
                       f" {_e(format_seconds(entry.simulated_s))} simulated, {entry.wall_s:.2f} s wall</p>")
            if entry.status != "PASS" and entry.text:
                out.append(f"<pre>{_e(entry.text)}</pre>")
            if entry.image:
                width, height = entry.size
                out.append(f'<p><img src="{_e(entry.image)}" width="{width}" height="{height}"'
                           f' alt="timing diagram of {_e(entry.scenario.name)}"></p>')
            elif entry.drawing_error:
                out.append(f'<p class="fail">the timing diagram could not be drawn: {_e(entry.drawing_error)}</p>')
            traces = [os.path.relpath(file, self.directory) for file in entry.trace_files]
            if traces:
                out.append('<p class="muted">traces: ' + " &middot; ".join(
                    f'<a href="{_e(urllib.parse.quote(Path(trace).as_posix()))}">{_e(Path(trace).name)}</a>'
                    for trace in traces) + "</p>")
            out.append("</section>")
        return out

    def _all(self) -> list[str]:
        plain = [entry for entry in self.entries if entry.scenario.variant is None]
        if not plain:
            return []
        out = ["<h2>All scenarios</h2>",
               "<table><tr><th>outcome</th><th>scenario</th><th>file</th><th>simulated</th><th>wall</th></tr>"]
        for entry in plain:
            out.append(f'<tr class="{_STATUS_CLASS[entry.status]}"><td>{_status(entry.status)}</td>'
                       f"<td>{self._link(entry, entry.scenario.name)}</td>"
                       f"<td><code>{_e(entry.scenario.path)}</code></td>"
                       f'<td class="num">{_e(format_seconds(entry.simulated_s))}</td>'
                       f'<td class="num">{entry.wall_s:.2f} s</td></tr>')
        out.append("</table>")
        return out

    @staticmethod
    def _link(entry: _Entry, text: str) -> str:
        return f'<a href="#{entry.anchor}">{_e(text)}</a>' if entry.diagram is not None else _e(text)


def _save(diagram: TimingDiagram | None, target: Path) -> tuple[tuple[int, int], str]:
    """The diagram drawn to ``target``: its size, and "" or why it could not be drawn (the page is
    written whatever a diagram holds)."""
    from vc.scenario.outputs.diagram import save

    assert diagram is not None
    try:
        return save(diagram, target), ""
    except Exception as error:  # matplotlib's, on whatever text or values a scenario brought along
        return (0, 0), f"{type(error).__name__}: {error}"


def _matrices_of(entries: Sequence[_Entry]) -> list[_Matrix]:
    matrices: dict[tuple[str, str], _Matrix] = {}
    for entry in entries:
        variant: Variant | None = entry.scenario.variant
        if variant is None:
            continue
        key = (variant.origin, entry.scenario.path)
        if key not in matrices:
            base = entry.scenario.name[:-len(variant.arguments) - 2]
            title = f"{variant.campaign}: {base}" if variant.campaign else base
            matrices[key] = _Matrix(variant.origin, entry.scenario.path, title, list(variant.keys))
        matrices[key].entries.append(entry)
    return list(matrices.values())


def _by_value(matrix: _Matrix) -> list[str]:
    """Per varied key and value: how many of its variants passed (where a failure comes from)."""
    out = ['<table><tr><th>varied</th><th>value</th><th>passed</th><th>failed</th></tr>']
    for key in matrix.keys:
        counts: dict[str, list[int]] = {}
        for entry in matrix.entries:
            assert entry.scenario.variant is not None
            value = dict(entry.scenario.variant.values).get(key, "")
            tally = counts.setdefault(value, [0, 0])
            tally[0 if entry.status == "PASS" else 1] += 1
        for number, (value, (good, bad)) in enumerate(counts.items()):
            out.append(f"<tr><td>{_e(key) if number == 0 else ''}</td><td>{_e(value)}</td>"
                       f'<td class="num">{good}</td><td class="num">{_count(bad, "fail")}</td></tr>')
    out.append("</table>")
    return out


def _status(status: str) -> str:
    return f'<span class="{_STATUS_CLASS[status]}">{status}</span>'


def _count(count: int, css: str) -> str:
    return f'<span class="{css}">{count}</span>' if count else "0"


def _e(text: str) -> str:
    return html_text(text)
