"""The coverage report: figures per data block, per state machine, for the alarms and the plant I/O,
what was never exercised (with meaning and source), the terminal summary, JSON, thresholds.

Coverage points (what a figure counts):

* a bool signal of a DB instance: seen 0, seen 1, rising edge, falling edge (4 points); a bits,
  byte, word, double word or real signal: took two or more values (1 point; the report shows the
  number of distinct values and the lowest and highest); signals that do not apply to their
  instance are left out (``vc.coverage.collector.NOT_APPLICABLE``), and so are the signals the
  NC does not model (the catalogue's ``not_modelled``, ``vc map``'s ``modelled: no``): no
  scenario can exercise them, so they are listed apart with the reason, not as gaps;
* a state machine (``vc.coverage.state_machines``): each declared state entered, each declared
  transition taken (transitions seen that are not declared are listed, not counted);
* an alarm the NC can raise (``vc.core.alarms.ALARM_TEXTS``): raised, cleared (2 points; the
  report says by what it was cleared: reset, cancel, its cause gone, power-on, e-stop acknowledged);
* a plant I/O point: a bool rises and falls (toggled, 2 points), a byte took two or more values.

A figure's percentage is covered points over points.  Names for thresholds: ``signals``,
``functions``, ``alarms``, ``plant``, a data block kind ``DB10`` / ``DB11`` / ``DB19`` / ``DB21`` /
``DB31`` / ``DB100`` / ``DB2``, a state machine (``gear_change``) or a group of them by prefix
(``referencing``, ``esr``).
"""

from __future__ import annotations

import re
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from functools import cache
from pathlib import Path
from typing import Any

import vc
from interfaces.plant_io import plant_function
from interfaces.signals import FIRST_DB, PLACEHOLDER, InstanceKind
from vc.coverage.collector import NOT_APPLICABLE
from vc.coverage.data import FALLS, RISES, CoverageData, FunctionCoverage, MachineCoverage, ValueRecord
from vc.coverage.names import definitions, kind_of_db
from vc.coverage.state_machines import STATE_MACHINES, StateMachine
from vc.simulation.published import ALARM_TEXTS

CATEGORIES = ("signals", "functions", "alarms", "plant")
DB_KINDS = ("DB2", "DB10", "DB11", "DB19", "DB21", "DB31", "DB100")
_ROOT = Path(vc.__file__).resolve().parent.parent  # where the sources lie (the repository, or site-packages)


@dataclass(slots=True)
class Figure:
    name: str
    title: str
    covered: int = 0
    total: int = 0

    def add(self, covered: int, total: int) -> None:
        self.covered += covered
        self.total += total

    @property
    def percent(self) -> float:
        return 100.0 * self.covered / self.total if self.total else 100.0

    def to_json(self) -> dict[str, Any]:
        return {"name": self.name, "title": self.title, "covered": self.covered, "total": self.total,
                "percent": round(self.percent, 1)}


@dataclass(frozen=True, slots=True)
class Gap:
    """Something never exercised: ``item`` of ``group`` lacks ``missing``."""

    category: str  # one of CATEGORIES
    group: str  # the function it belongs to: "turn_mill X1 (DB31) spindle", a state machine's title ...
    item: str  # a signal, a state, a transition, an alarm, a plant point
    address: str
    missing: str
    meaning: str
    source: str

    def to_json(self) -> dict[str, str]:
        return {"category": self.category, "group": self.group, "item": self.item, "address": self.address,
                "missing": self.missing, "meaning": self.meaning, "source": self.source}


@dataclass(slots=True)
class FunctionFigures:
    machine: StateMachine
    states: Figure
    transitions: Figure
    instances: int
    other_transitions: list[tuple[str, str, int]]  # seen, not declared

    @property
    def figure(self) -> Figure:
        figure = Figure(self.machine.name, self.machine.title)
        figure.add(self.states.covered + self.transitions.covered, self.states.total + self.transitions.total)
        return figure


@dataclass(slots=True)
class Report:
    scenarios: int
    cycles: int
    categories: dict[str, Figure]
    total: Figure
    instances: list[Figure]  # per machine and DB instance
    db_kinds: list[Figure]  # per data block kind over all machines
    functions: list[FunctionFigures]
    alarm_raised: Figure
    alarm_cleared: Figure
    plant: list[Figure]  # per plant function over all machines
    gaps: list[Gap] = field(default_factory=list)
    # per catalogue entry over every instance of every machine (not counted in the total): which
    # entries no instance exercised fully
    catalogue: Figure = field(default_factory=lambda: Figure("catalogue", "catalogue entries, over all instances"))
    catalogue_gaps: list[Gap] = field(default_factory=list)
    # catalogue entries the NC does not model (not counted): one per entry, "missing" says why
    not_modelled: list[Gap] = field(default_factory=list)

    def named(self) -> dict[str, Figure]:
        """Every figure a threshold can name (state machine groups by their prefix)."""
        figures = dict(self.categories)
        figures.update((figure.name, figure) for figure in self.db_kinds)
        groups: dict[str, Figure] = {}
        for function in self.functions:
            figure = function.figure
            figures[figure.name] = figure
            if "." in figure.name:
                prefix = figure.name.split(".")[0]
                group = groups.setdefault(prefix, Figure(prefix, f"{prefix} (all variants)"))
                group.add(figure.covered, figure.total)
        for name, group in groups.items():
            figures.setdefault(name, group)
        return figures

    def to_json(self) -> dict[str, Any]:
        return {
            "scenarios": self.scenarios,
            "cycles": self.cycles,
            "total": self.total.to_json(),
            "categories": {name: figure.to_json() for name, figure in self.categories.items()},
            "data_blocks": [figure.to_json() for figure in self.db_kinds],
            "instances": [figure.to_json() for figure in self.instances],
            "functions": [{**function.figure.to_json(), "instances": function.instances,
                           "states": function.states.to_json(), "transitions": function.transitions.to_json(),
                           "other_transitions": [[a, b, n] for a, b, n in function.other_transitions]}
                          for function in self.functions],
            "alarms": {"raised": self.alarm_raised.to_json(), "cleared": self.alarm_cleared.to_json()},
            "plant": [figure.to_json() for figure in self.plant],
            "gaps": [gap.to_json() for gap in self.gaps],
            "catalogue": self.catalogue.to_json(),
            "catalogue_gaps": [gap.to_json() for gap in self.catalogue_gaps],
            "not_modelled": [gap.to_json() for gap in self.not_modelled],
        }


# ---------------------------------------------------------------------------------- building


def build_report(data: CoverageData) -> Report:
    categories = {name: Figure(name, title) for name, title in (
        ("signals", "interface signals"), ("functions", "state machines"), ("alarms", "alarms"),
        ("plant", "plant I/O"))}
    report = Report(data.scenarios, data.cycles, categories, Figure("total", "all points"), [],
                    [Figure(kind, f"{kind} {_KIND_TITLES[kind]}") for kind in DB_KINDS], [],
                    Figure("alarms.raised", "alarms raised"), Figure("alarms.cleared", "alarms cleared"), [])
    entries: dict[tuple[InstanceKind, str], tuple[ValueRecord, str]] = {}
    for name, machine in sorted(data.machines.items()):
        _signals(report, name, machine, entries)
    _catalogue(report, entries)
    plant: dict[str, Figure] = {}
    for name, machine in sorted(data.machines.items()):
        _plant(report, name, machine, plant)
    report.plant = sorted(plant.values(), key=lambda figure: figure.name)
    for state_machine in STATE_MACHINES:
        report.functions.append(_function(report, state_machine, data.functions.get(state_machine.name)))
    _alarms(report, data)
    for figure in report.categories.values():
        report.total.add(figure.covered, figure.total)
    return report


_KIND_TITLES = {"DB2": "PLC user alarms",
                "DB10": "NCK", "DB11": "mode group", "DB19": "operator panel", "DB21": "channels", "DB31": "axes",
                "DB100": "alarm list"}


def signal_points(record: ValueRecord, kind: str) -> list[tuple[str, bool]]:
    """The coverage points of a signal: ``(what, covered)``."""
    if kind == "bool":
        return [("seen 0", 0 in record.values), ("seen 1", 1 in record.values),
                ("rises", bool(record.edges & RISES)), ("falls", bool(record.edges & FALLS))]
    return [("two or more values", record.distinct >= 2)]


def plant_points(record: ValueRecord, kind: str) -> list[tuple[str, bool]]:
    if kind == "bool":
        return [("rises", bool(record.edges & RISES)), ("falls", bool(record.edges & FALLS))]
    return [("two or more values", record.distinct >= 2)]


def _shown_values(record: ValueRecord) -> str:
    if not record.values:
        return "no value seen"
    more = "+" if record.more else ""
    plural = "" if record.distinct == 1 else "s"
    return f"{record.distinct}{more} distinct value{plural}, {record.low:g} .. {record.high:g}"


def _signals(report: Report, machine_name: str, machine: MachineCoverage,
             entries: dict[tuple[InstanceKind, str], tuple[ValueRecord, str]]) -> None:
    catalogue = definitions()
    instances: dict[str, Figure] = {}
    for instance, number in sorted(machine.instances.items(), key=lambda item: (item[1], item[0])):
        instances[instance] = Figure(f"{machine_name}/{instance}", f"{machine_name} DB{number} {instance}")
    kinds = {figure.name: figure for figure in report.db_kinds}
    for symbol, record in sorted(machine.signals.items()):
        if symbol in machine.not_applicable:
            continue
        instance, _, rest = symbol.partition(".")
        db = machine.instances.get(instance)
        kind = kind_of_db(db) if db is not None else None
        if db is None or kind is None:
            continue
        definition = catalogue.get((kind, rest))
        if definition is not None and not definition.modelled:
            _not_modelled(report, kind, rest, definition.not_modelled)
            continue
        signal_type = machine.types.get(symbol, "bool")
        merged, _ = entries.setdefault((kind, rest), (ValueRecord(), signal_type))
        merged.merge(record)
        points = signal_points(record, signal_type)
        covered = sum(1 for _, hit in points if hit)
        instances[instance].add(covered, len(points))
        kinds[f"DB{FIRST_DB[kind]}"].add(covered, len(points))
        report.categories["signals"].add(covered, len(points))
        missing = [what for what, hit in points if not hit]
        if missing:
            group = rest.rsplit(".", 1)[0]
            detail = "" if machine.types.get(symbol, "bool") == "bool" else f" ({_shown_values(record)})"
            report.gaps.append(Gap(
                "signals", f"{machine_name} {instance} (DB{db}) {group}", symbol,
                str(definition.address.in_db(db)) if definition else "", ", ".join(missing) + detail,
                definition.meaning if definition else "", definition.source if definition else ""))
    report.instances.extend(figure for figure in instances.values() if figure.total)


def _not_modelled(report: Report, kind: InstanceKind, rest: str, why: str) -> None:
    """A catalogue entry the NC does not model: listed once, with why, and counted nowhere."""
    symbol = f"{PLACEHOLDER[kind]}.{rest}"
    if any(gap.item == symbol for gap in report.not_modelled):
        return
    definition = definitions()[(kind, rest)]
    report.not_modelled.append(Gap("signals", f"DB{FIRST_DB[kind]} {rest.rsplit('.', 1)[0]}", symbol,
                                   str(definition.address), why, definition.meaning, definition.source))


def _catalogue(report: Report, entries: dict[tuple[InstanceKind, str], tuple[ValueRecord, str]]) -> None:
    catalogue = definitions()
    for (kind, rest), (record, signal_type) in sorted(entries.items()):
        points = signal_points(record, signal_type)
        covered = sum(1 for _, hit in points if hit)
        report.catalogue.add(covered, len(points))
        missing = [what for what, hit in points if not hit]
        definition = catalogue.get((kind, rest))
        if missing and definition is not None:
            detail = "" if signal_type == "bool" else f" ({_shown_values(record)})"
            report.catalogue_gaps.append(Gap(
                "signals", f"DB{FIRST_DB[kind]} {rest.rsplit('.', 1)[0]}", f"{PLACEHOLDER[kind]}.{rest}",
                str(definition.address), ", ".join(missing) + detail, definition.meaning, definition.source))


def _plant(report: Report, machine_name: str, machine: MachineCoverage, groups: dict[str, Figure]) -> None:
    for name, record in sorted(machine.plant.items()):
        function = plant_function(name)
        meaning = function.meaning if function else ""
        group_name = _plant_group(name)
        group = groups.setdefault(group_name, Figure(group_name, meaning.split(":")[0]))
        points = plant_points(record, machine.types.get(name, "bool"))
        covered = sum(1 for _, hit in points if hit)
        group.add(covered, len(points))
        report.categories["plant"].add(covered, len(points))
        missing = [what for what, hit in points if not hit]
        if missing:
            report.gaps.append(Gap("plant", f"{machine_name} plant: {group_name}", name, "",
                                   ", ".join(missing), meaning, f"machine file {machine.source}"))


def _plant_group(name: str) -> str:
    """The kind of a plant point: ``refCam``, ``hwLimit``, ``gearEngaged``, ``MCP key`` ..."""
    head, _, tail = name.partition(".")
    if head == "MCP":
        return "MCP." + re.sub(r"\d+$", "", tail.split(".")[0])
    if head in ("EStop", "Drives", "Door", "Lamp"):
        return f"{head}.{tail}" if head != "Lamp" else "Lamp"
    return re.sub(r"(Minus|Plus|\d+)$", "", tail)


def _function(report: Report, machine: StateMachine, coverage: FunctionCoverage | None) -> FunctionFigures:
    coverage = coverage or FunctionCoverage()
    states = Figure(f"{machine.name}.states", "states")
    transitions = Figure(f"{machine.name}.transitions", "transitions")
    declared: set[tuple[str, str]] = set()
    lines = _anchor_lines(machine.module)
    for state in machine.states:
        entered = coverage.states.get(state.name, 0) > 0
        states.add(int(entered), 1)
        if not entered:
            report.gaps.append(Gap("functions", machine.title, state.name, "", "never entered", state.meaning,
                                   _where(machine.module, lines, state.anchor)))
    for transition in machine.transitions:
        key = (transition.before, transition.after)
        declared.add(key)
        taken = coverage.transitions.get(key, 0) > 0
        transitions.add(int(taken), 1)
        if not taken:
            before = machine.state(transition.before)
            report.gaps.append(Gap("functions", machine.title, f"{transition.before} -> {transition.after}", "",
                                   "never taken", transition.trigger,
                                   _where(machine.module, lines, before.anchor if before else "")))
    other = [(a, b, count) for (a, b), count in sorted(coverage.transitions.items()) if (a, b) not in declared]
    report.categories["functions"].add(states.covered + transitions.covered, states.total + transitions.total)
    return FunctionFigures(machine, states, transitions, len(coverage.instances), other)


def _alarms(report: Report, data: CoverageData) -> None:
    lines = _anchor_lines("vc/core/alarms.py")
    for number, definition in sorted(ALARM_TEXTS.items()):
        alarm = data.alarms.get(number)
        raised = alarm is not None and alarm.raised > 0
        cleared = alarm is not None and sum(alarm.cleared.values()) > 0
        report.alarm_raised.add(int(raised), 1)
        report.alarm_cleared.add(int(cleared), 1)
        report.categories["alarms"].add(int(raised) + int(cleared), 2)
        if not (raised and cleared):
            missing = "never raised" if not raised else "never cleared"
            where = _where("vc/core/alarms.py", lines, f"({number}, ") or _where("vc/core/alarms.py", lines,
                                                                                  f"({number},")
            report.gaps.append(Gap("alarms", _alarm_group(number), str(number), "", missing, definition.text,
                                   f"{definition.source}; {where}" if where else definition.source))


def _alarm_group(number: int) -> str:
    """Alarms by their number range, as the control's manuals group them."""
    if number < 10000:
        return "alarms: general and NCK"
    if number < 20000:
        return "alarms: channel"
    if number < 30000:
        return "alarms: axis and spindle"
    return "alarms: project and cycles"


@cache
def _anchor_lines(module: str) -> tuple[str, ...]:
    try:
        return tuple((_ROOT / module).read_text(encoding="utf-8").splitlines())
    except OSError:
        return ()


def _where(module: str, lines: Sequence[str], anchor: str) -> str:
    """``module:line`` of the first line holding ``anchor`` (just the module when it is not found)."""
    if anchor:
        for number, line in enumerate(lines, start=1):
            if anchor in line:
                return f"{module}:{number}"
    return module


# ---------------------------------------------------------------------------------- output


def summary_text(report: Report) -> str:
    """The terminal summary: per data block, per state machine, alarms, plant, total."""
    lines = [f"Interface coverage of {report.scenarios} scenario runs ({report.cycles} IPO cycles)", ""]

    def row(name: str, covered: int, total: int, extra: str = "") -> None:
        percent = 100.0 * covered / total if total else 100.0
        lines.append(f"  {name:<52} {covered:>6} / {total:<6} {percent:5.1f} %{extra}")

    lines.append("signals per data block (seen 0, seen 1, rises, falls; values: two or more)")
    for figure in report.db_kinds:
        if figure.total:
            row(figure.title, figure.covered, figure.total)
    row(report.catalogue.title, report.catalogue.covered, report.catalogue.total)
    lines.append("signals per DB instance")
    for figure in report.instances:
        row(figure.title, figure.covered, figure.total)
    lines.append("state machines (states entered + transitions taken)")
    for function in report.functions:
        figure = function.figure
        extra = (f"   states {function.states.covered}/{function.states.total},"
                 f" transitions {function.transitions.covered}/{function.transitions.total}")
        row(f"{figure.name}", figure.covered, figure.total, extra)
    lines.append("alarms (raised, cleared)")
    row("alarms", report.categories["alarms"].covered, report.categories["alarms"].total,
        f"   raised {report.alarm_raised.covered}/{report.alarm_raised.total},"
        f" cleared {report.alarm_cleared.covered}/{report.alarm_cleared.total}")
    lines.append("plant I/O (bool: rises and falls; bytes: two or more values)")
    for figure in report.plant:
        row(figure.name, figure.covered, figure.total)
    lines.append("")
    for figure in report.categories.values():
        row(figure.name, figure.covered, figure.total)
    row("total", report.total.covered, report.total.total)
    if report.not_modelled:
        lines.append("")
        lines.append(f"  {len(report.not_modelled)} catalogue signals the NC does not model are left out (not a gap"
                     " of the scenarios: vc map --format csv, column modelled)")
    return "\n".join(lines) + "\n"


def check_thresholds(report: Report, total: float | None, per_name: Mapping[str, float]) -> list[str]:
    """What falls short of the thresholds (empty: all met).  Raises KeyError for an unknown name."""
    named = report.named()
    unknown = sorted(set(per_name) - set(named))
    if unknown:
        raise KeyError(f"unknown coverage figure {', '.join(unknown)} (known: {', '.join(sorted(named))})")
    short = []
    if total is not None and report.total.percent < total:
        short.append(f"total coverage {report.total.percent:.1f} % is below {total:g} %")
    for name, threshold in sorted(per_name.items()):
        figure = named[name]
        if figure.percent < threshold:
            short.append(f"{name} coverage {figure.percent:.1f} % is below {threshold:g} %")
    return short


def not_applicable_rules() -> Iterable[str]:
    for kind, part, who in NOT_APPLICABLE:
        yield f"DB{FIRST_DB[kind]} {part.strip('.')}.* only on {who}"
