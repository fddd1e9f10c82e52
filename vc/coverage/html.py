"""The coverage report as one HTML page: no scripts, no links to fetch, readable offline.

The page shows the figures (per data block kind and instance, per state machine, alarms, plant
I/O) and then everything never exercised, grouped by category and function (a DB instance's
signal group, a state machine, an alarm range, a plant function), each with its address, what
is missing, its meaning and its source (the catalogue's seed line, the module line of a state);
then, apart, the catalogue signals the NC does not model, with why.
Groups fold (``<details>``) so that a long list stays navigable.
"""

from __future__ import annotations

from html import escape

from vc.coverage.report import CATEGORIES, Figure, Gap, Report

_STYLE = """
body { font-family: system-ui, sans-serif; margin: 2em; color: #222; }
h1 { font-size: 1.5em; } h2 { font-size: 1.2em; margin-top: 1.5em; }
table { border-collapse: collapse; margin: 0.5em 0; }
th, td { padding: 0.2em 0.6em; text-align: left; vertical-align: top; border-bottom: 1px solid #ddd; }
td.number { text-align: right; font-variant-numeric: tabular-nums; }
.bar { display: inline-block; height: 0.8em; background: #4a8; }
.barbox { display: inline-block; width: 10em; background: #eee; }
details { margin: 0.3em 0; } summary { cursor: pointer; font-weight: 600; }
code { font-size: 0.95em; } .dim { color: #777; }
"""

_CATEGORY_TITLES = {"signals": "Interface signals", "functions": "State machines", "alarms": "Alarms",
                    "plant": "Plant I/O"}


def _figure_row(figure: Figure, title: str | None = None, extra: str = "") -> str:
    percent = figure.percent
    return (f"<tr><td>{escape(title or figure.title)}</td><td class=number>{figure.covered}</td>"
            f"<td class=number>{figure.total}</td><td class=number>{percent:.1f} %</td>"
            f"<td><span class=barbox><span class=bar style=\"width:{percent:.0f}%\"></span></span></td>"
            f"<td class=dim>{escape(extra)}</td></tr>")


def _table(rows: list[str]) -> str:
    head = "<tr><th></th><th>covered</th><th>points</th><th></th><th></th><th></th></tr>"
    return f"<table>{head}{''.join(rows)}</table>"


def _gap_rows(gaps: list[Gap]) -> str:
    rows = "".join(
        f"<tr><td><code>{escape(gap.item)}</code></td><td><code>{escape(gap.address)}</code></td>"
        f"<td>{escape(gap.missing)}</td><td>{escape(gap.meaning)}</td><td class=dim>{escape(gap.source)}</td></tr>"
        for gap in gaps)
    head = "<tr><th>item</th><th>address</th><th>never</th><th>meaning</th><th>source</th></tr>"
    return f"<table>{head}{rows}</table>"


def _grouped(gaps: list[Gap]) -> str:
    """The gaps by group, each group folded."""
    groups: dict[str, list[Gap]] = {}
    for gap in gaps:
        groups.setdefault(gap.group, []).append(gap)
    return "".join(f"<details><summary>{escape(group)} ({len(items)})</summary>{_gap_rows(items)}</details>"
                   for group, items in groups.items())


def report_html(report: Report, title: str = "Interface coverage") -> str:
    parts = [f"<!DOCTYPE html><html lang=en><head><meta charset=utf-8><title>{escape(title)}</title>"
             f"<style>{_STYLE}</style></head><body>",
             f"<h1>{escape(title)}</h1>",
             f"<p>{report.scenarios} scenario runs, {report.cycles} IPO cycles. Total:"
             f" <b>{report.total.percent:.1f} %</b> ({report.total.covered} of {report.total.total} points).</p>",
             "<h2>Figures</h2>",
             _table([_figure_row(report.categories[name], _CATEGORY_TITLES[name]) for name in CATEGORIES]),
             "<h2>Signals per data block</h2>",
             _table([*(_figure_row(figure) for figure in report.db_kinds if figure.total),
                     _figure_row(report.catalogue)]),
             "<details><summary>per DB instance</summary>",
             _table([_figure_row(figure) for figure in report.instances]), "</details>",
             "<h2>State machines</h2>",
             _table([_figure_row(function.figure, f"{function.machine.title} ({function.machine.name})",
                                 f"states {function.states.covered}/{function.states.total}, transitions"
                                 f" {function.transitions.covered}/{function.transitions.total},"
                                 f" {function.instances} instances")
                     for function in report.functions]),
             "<h2>Alarms</h2>",
             _table([_figure_row(report.alarm_raised), _figure_row(report.alarm_cleared)]),
             "<h2>Plant I/O</h2>",
             _table([_figure_row(figure, f"{figure.name}: {figure.title}") for figure in report.plant]),
             "<h2>Never exercised</h2>"]
    for category in CATEGORIES:
        gaps = [gap for gap in report.gaps if gap.category == category]
        parts.append(f"<h3>{_CATEGORY_TITLES[category]} ({len(gaps)})</h3>{_grouped(gaps)}")
    parts.append(f"<h3>Catalogue entries no instance exercised fully ({len(report.catalogue_gaps)})</h3>"
                 "<p class=dim>Each catalogue signal over all its DB instances on all machines: what none of them"
                 f" showed.</p>{_grouped(report.catalogue_gaps)}")
    parts.append(f"<h2>Not modelled by the NC ({len(report.not_modelled)})</h2>"
                 "<p class=dim>Catalogue signals the simulated NC neither reads nor writes (<code>vc map</code>,"
                 " column <code>modelled</code>): no scenario can exercise them, so they are no gap of the scenarios"
                 f" and are counted nowhere. The column <i>never</i> says why.</p>{_grouped(report.not_modelled)}")
    others = [function for function in report.functions if function.other_transitions]
    if others:
        parts.append("<h2>Transitions seen that no state machine declares</h2><p class=dim>States are sampled at"
                     " the end of each IPO cycle: two transitions within one cycle show as one.</p><table>")
        for function in others:
            for before, after, count in function.other_transitions:
                parts.append(f"<tr><td>{escape(function.machine.name)}</td><td><code>{escape(before)} -&gt;"
                             f" {escape(after)}</code></td><td class=number>{count}</td></tr>")
        parts.append("</table>")
    parts.append("</body></html>\n")
    return "".join(parts)
