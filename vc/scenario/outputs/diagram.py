"""Timing diagrams drawn with matplotlib from a :class:`~vc.scenario.outputs.timing.TimingDiagram`.

One figure per scenario: a lane per signal, stacked over one time axis as in the manual's
diagrams.  A bool is a 0/1 trace with its high phases filled; a byte or word a bus whose values
are written in; axis quantities and other numbers a line with their scale.  Dotted lines mark
where each step began (numbers along the top), a red line the failing step and the moment of the
failure, an orange dashed line with its number where an alarm was raised; an ``expect_timing``
window is shaded green on its lane, a ``wait``'s time limit lightly.

The figures are built on :class:`matplotlib.figure.Figure` with the Agg canvas, without pyplot,
so drawing needs no display and no global state; only :func:`show` (``vc run --plot``) uses
pyplot for a window.  matplotlib comes with the ``report`` extra.
"""

from __future__ import annotations

import textwrap
from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

from interfaces.errors import VcError
from vc.escaping import image_text
from vc.scenario.outputs.timing import ANALOG, BUS, DIGITAL, Lane, TimingDiagram

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

WIDTH_IN = 12.0
HEIGHT_IN = {DIGITAL: 0.34, BUS: 0.42, ANALOG: 1.05}
HEADER_IN = 0.95  # title, step numbers
FOOTER_IN = 0.55  # time axis
DPI = 100
FORMATS = ("png", "svg")
_HIGH = "#1f5fa8"
_FAIL = "#c0392b"
_WINDOW = "#2e8b57"
_ALARM = "#d35400"


class DiagramError(VcError):
    """matplotlib is missing."""


MISSING = "timing diagrams need matplotlib: pip install 'vc-harness[report]'"


def require_matplotlib() -> None:
    """Raise :class:`DiagramError` unless matplotlib can be imported: a run that is to draw diagrams
    checks this before it starts, not after every scenario has run."""
    try:
        import matplotlib  # noqa: F401
    except ImportError:
        raise DiagramError(MISSING) from None


def figure_size(diagram: TimingDiagram) -> tuple[float, float]:
    lanes = sum(HEIGHT_IN[lane.kind] for lane in diagram.lanes) or HEIGHT_IN[DIGITAL]
    return WIDTH_IN, HEADER_IN + lanes + FOOTER_IN + (0.25 if diagram.failure else 0.0)


def save(diagram: TimingDiagram, path: str | Path) -> tuple[int, int]:
    """Write the diagram as PNG or SVG (by the file's suffix); its size in pixels (at 100 dpi)."""
    try:
        from matplotlib.backends.backend_agg import FigureCanvasAgg
        from matplotlib.figure import Figure
    except ImportError:
        raise DiagramError(MISSING) from None
    width, height = figure_size(diagram)
    figure = Figure(figsize=(width, height), dpi=DPI)
    FigureCanvasAgg(figure)
    draw(diagram, figure)
    target = Path(path)
    target.parent.mkdir(parents=True, exist_ok=True)
    suffix = target.suffix.lstrip(".").lower()
    figure.savefig(target, format=suffix if suffix in FORMATS else "png", dpi=DPI,
                   metadata={"Software": "vc-harness"} if suffix == "png" else {"Date": None})
    return round(width * DPI), round(height * DPI)


def show(diagram: TimingDiagram) -> None:
    """The diagram in a window (pyplot with the platform's interactive backend)."""
    try:
        import matplotlib.pyplot as pyplot
    except ImportError:
        raise DiagramError(MISSING) from None
    figure = pyplot.figure(figsize=figure_size(diagram))
    draw(diagram, figure)
    pyplot.show()


def draw(diagram: TimingDiagram, figure: Figure) -> None:
    """Draw ``diagram`` into an empty ``figure``.  Every text is drawn as written: a ``$`` in a
    scenario's name or a message is no mathtext (``$x^{$`` would make matplotlib's parser raise)."""
    from matplotlib import rc_context

    with rc_context({"text.parse_math": False}):
        _draw(diagram, figure)


def _draw(diagram: TimingDiagram, figure: Figure) -> None:
    height = figure.get_size_inches()[1]
    lanes = diagram.lanes
    end = max(diagram.end_s, 1e-3)
    title = image_text(f"{diagram.status}  {diagram.title}")
    figure.suptitle("\n".join(textwrap.wrap(title, 130)[:2]), x=0.01, ha="left", fontsize=10,
                    color=_FAIL if diagram.status != "PASS" else "black", y=1 - 0.12 / height)
    if diagram.failure:
        figure.text(0.01, 1 - 0.42 / height, textwrap.shorten(image_text(diagram.failure), 210, placeholder=" ..."),
                    fontsize=7.5, color=_FAIL, ha="left", va="top")
    if not lanes:
        figure.text(0.5, 0.5, "the scenario names no recorded signal", ha="center", fontsize=9)
        return
    top = 1 - (HEADER_IN + (0.25 if diagram.failure else 0.0)) / height
    bottom = FOOTER_IN / height
    figure.subplots_adjust(left=0.25, right=0.985, top=top, bottom=bottom, hspace=0.0)
    ratios = [HEIGHT_IN[lane.kind] for lane in lanes]
    grid = figure.subplots(len(lanes), 1, sharex=True, squeeze=False, gridspec_kw={"height_ratios": ratios})
    axes: Sequence[Axes] = list(grid[:, 0])
    for ax, lane in zip(axes, lanes, strict=True):
        _draw_lane(ax, lane, end)
        ax.tick_params(axis="x", length=0)
    for window in diagram.windows:
        for ax, lane in zip(axes, lanes, strict=True):
            if lane.name == window.lane:
                ax.axvspan(window.start_s, max(window.end_s, window.start_s + end * 0.002), color=_WINDOW,
                           alpha=0.22 if window.strong else 0.08, linewidth=0)
                if window.strong:
                    ax.text(window.end_s, 0.5, f" {window.label}", transform=ax.get_xaxis_transform(), fontsize=6.5,
                            color=_WINDOW, va="center", ha="left", clip_on=True)
    _mark_steps(axes, diagram)
    _mark_alarms(axes, diagram)
    axes[-1].set_xlim(0, end)
    axes[-1].tick_params(axis="x", length=3)
    axes[-1].set_xlabel("time since the scenario started [s]", fontsize=8)
    axes[-1].tick_params(axis="x", labelsize=7.5)
    if diagram.left_out:
        figure.text(0.01, 0.01, f"{diagram.left_out} more named signals not drawn", fontsize=7, color="grey")


def _draw_lane(ax: Axes, lane: Lane, end: float) -> None:
    times = [*lane.times, end]
    values = [*lane.values, lane.values[-1] if lane.values else 0.0]
    ax.set_ylabel(lane.name + (f" [{lane.unit}]" if lane.unit else ""), rotation=0, ha="right", va="center",
                  fontsize=7.5, labelpad=6)
    for side in ("top", "right"):
        ax.spines[side].set_visible(False)
    if lane.kind == DIGITAL:
        levels = [1.0 if value else 0.0 for value in values]
        ax.step(times, levels, where="post", color=_HIGH, linewidth=1.2)
        ax.fill_between(times, levels, step="post", color=_HIGH, alpha=0.15, linewidth=0)
        ax.set_ylim(-0.25, 1.35)
        ax.set_yticks([])
    elif lane.kind == BUS:
        _draw_bus(ax, times, values, end)
    else:
        ax.step(times, values, where="post", color="#333333", linewidth=1.0)
        ax.tick_params(axis="y", labelsize=6.5)
        ax.yaxis.set_major_locator(_locator(3))
        low, high = min(values), max(values)
        margin = (high - low) * 0.12 or max(abs(high) * 0.1, 1.0)
        ax.set_ylim(low - margin, high + margin)
    ax.grid(axis="x", color="#dddddd", linewidth=0.5)


def _draw_bus(ax: Axes, times: list[float], values: list[float], end: float) -> None:
    """A bus lane: one band per value, the value written in where there is room."""
    ax.set_ylim(0, 1)
    ax.set_yticks([])
    for index in range(len(times) - 1):
        start, stop = times[index], times[index + 1]
        if stop <= start:
            continue
        ax.plot([start, stop], [0.15, 0.15], color=_HIGH, linewidth=0.9)
        ax.plot([start, stop], [0.85, 0.85], color=_HIGH, linewidth=0.9)
        ax.plot([start, start], [0.15, 0.85], color=_HIGH, linewidth=0.9)
        if stop - start > end * 0.03:
            value = values[index]
            shown = str(int(value)) if float(value).is_integer() else f"{value:g}"
            ax.text((start + stop) / 2, 0.5, shown, ha="center", va="center", fontsize=6.5, clip_on=True)


def _mark_steps(axes: Sequence[Axes], diagram: TimingDiagram) -> None:
    """Dotted lines where steps began, their numbers over the first lane (steps of one instant
    together: "12-15"); the failing step and the failure in red."""
    groups: list[tuple[float, list[int], bool]] = []
    for step in diagram.steps:
        if groups and abs(groups[-1][0] - step.time_s) < 1e-9:
            groups[-1][1].append(step.index)
            groups[-1] = (groups[-1][0], groups[-1][1], groups[-1][2] or step.failed)
        else:
            groups.append((step.time_s, [step.index], step.failed))
    first = axes[0]
    plain = [time_s for time_s, _, failed in groups if not failed]
    failing = [time_s for time_s, _, failed in groups if failed]
    for ax in axes:  # one collection of lines per lane: hundreds of single lines draw slowly
        ax.vlines(plain, 0, 1, transform=ax.get_xaxis_transform(), colors="#999999", linestyles=":", linewidths=0.7)
        if failing:
            ax.vlines(failing, 0, 1, transform=ax.get_xaxis_transform(), colors=_FAIL, linestyles=":", linewidths=1.1)
    for time_s, numbers, failed in groups:
        color = _FAIL if failed else "#999999"
        label = str(numbers[0]) if len(numbers) == 1 else f"{numbers[0]}-{numbers[-1]}"
        first.text(time_s, 1.02, label, transform=first.get_xaxis_transform(), fontsize=6, rotation=90,
                   ha="center", va="bottom", color=color, fontweight="bold" if failed else "normal")
    first.text(0.0, 1.02, "step ", transform=first.get_xaxis_transform(), fontsize=6, ha="right",
               va="bottom", color="#999999")
    if diagram.failure_s is not None:
        for ax in axes:
            ax.axvline(diagram.failure_s, color=_FAIL, linewidth=1.3)
        axes[-1].text(diagram.failure_s, 0.0, " failure", transform=axes[-1].get_xaxis_transform(), color=_FAIL,
                      fontsize=7, va="bottom", ha="left")


def _mark_alarms(axes: Sequence[Axes], diagram: TimingDiagram) -> None:
    """A dashed line where each alarm was raised, its number at the top of the first lane."""
    if not diagram.alarms:
        return
    for ax in axes:
        ax.vlines([mark.time_s for mark in diagram.alarms], 0, 1, transform=ax.get_xaxis_transform(),
                  colors=_ALARM, linestyles="--", linewidths=1.0)
    first = axes[0]
    for mark in diagram.alarms:
        first.text(mark.time_s, 0.95, f" alarm {mark.number}", transform=first.get_xaxis_transform(), fontsize=6.5,
                   color=_ALARM, ha="left", va="top", fontweight="bold", clip_on=False)


def _locator(count: int) -> Any:
    from matplotlib.ticker import MaxNLocator

    return MaxNLocator(count)
