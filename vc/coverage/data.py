"""What the interface coverage counts: a plain object that merges, and its JSON file.

:class:`CoverageData` holds what runs exercised, never what they could have exercised beyond
the machines they used (the report compares it with the declared state machines and alarms):

* per machine (by name), every catalogued signal of every DB instance and every plant I/O point
  with the values it took (:class:`ValueRecord`: distinct values up to ``MAX_DISTINCT``, lowest and
  highest, rising and falling edges); the signals that do not apply to an instance (the spindle
  signals of a linear axis) are listed as such;
* per state machine (``vc.coverage.state_machines``), the states entered and the transitions
  taken, with the instances (``turn_mill/X1``) that showed them;
* per alarm number, how often it was raised and how often it was cleared, by what.

:meth:`CoverageData.merge` adds another run's data (counts add, value sets unite), so the data of
scenario runs in several processes, or of several ``vc run`` calls, add up to one report.
``save`` / ``load`` write and read the JSON file of ``vc run --coverage FILE``; a file that is not
such a file is reported as problems with their location (``SourceError``).  The file is read
within the limits of :mod:`vc.bounded_json` (nesting, digits, finite numbers), and with the
names of this harness (:class:`~vc.coverage.names.CoverageNames`) a signal, plant point, state
machine, state or alarm the harness does not know is refused with the file and the key instead
of being merged.
"""

from __future__ import annotations

import json
import math
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

from vc.bounded_json import JsonProblem, loads
from vc.located_yaml import Mark, Problem, SourceError, load_text

if TYPE_CHECKING:
    from vc.coverage.names import CoverageNames

FORMAT = "vc-coverage"
VERSION = 1
MAX_DISTINCT = 64  # distinct values kept per signal; beyond, only the count "more" and lowest / highest
MAX_PROBLEMS = 100  # problems shown of one file (a file that is no coverage file has thousands)
MAX_VALUE = 1e300  # a value a signal took: finite (a REAL reaches 3.4e38; a double beyond it is no signal's)

RISES = 1  # ValueRecord.edges: 0 -> not 0 seen
FALLS = 2  # not 0 -> 0 seen


@dataclass(slots=True)
class ValueRecord:
    """The values one signal or plant I/O point took."""

    values: set[float] = field(default_factory=set)  # distinct values, at most MAX_DISTINCT
    more: bool = False  # it took more distinct values than those kept
    low: float = math.inf
    high: float = -math.inf
    edges: int = 0  # RISES | FALLS

    def saw(self, value: float) -> None:
        if value not in self.values:
            if len(self.values) < MAX_DISTINCT:
                self.values.add(value)
            else:
                self.more = True
        self.low = min(self.low, value)
        self.high = max(self.high, value)

    def changed(self, old: float, new: float) -> None:
        self.saw(new)
        if not old and new:
            self.edges |= RISES
        elif old and not new:
            self.edges |= FALLS

    @property
    def distinct(self) -> int:
        """Distinct values seen (a lower bound when ``more``)."""
        return len(self.values) + (1 if self.more else 0)

    def merge(self, other: ValueRecord) -> None:
        for value in sorted(other.values):
            self.saw(value)
        self.more = self.more or other.more
        self.low = min(self.low, other.low)
        self.high = max(self.high, other.high)
        self.edges |= other.edges

    def to_json(self) -> dict[str, Any]:
        result: dict[str, Any] = {"values": sorted(self.values)}
        if self.values or self.more:
            result.update(low=self.low, high=self.high)
        if self.more:
            result["more"] = True
        if self.edges:
            result["edges"] = self.edges
        return result


@dataclass(slots=True)
class MachineCoverage:
    """The signals and plant I/O of one machine (every instance, every point, exercised or not)."""

    source: str = ""  # the machine file
    instances: dict[str, int] = field(default_factory=dict)  # DB instance name -> its data block number
    signals: dict[str, ValueRecord] = field(default_factory=dict)  # symbol -> values
    types: dict[str, str] = field(default_factory=dict)  # symbol or point -> "bool" or the value type
    plant: dict[str, ValueRecord] = field(default_factory=dict)  # plant I/O function name -> values
    not_applicable: set[str] = field(default_factory=set)  # symbols without meaning on their instance

    def merge(self, other: MachineCoverage) -> None:
        self.source = self.source or other.source
        self.instances.update(other.instances)
        self.types.update(other.types)
        self.not_applicable |= other.not_applicable
        for mine, theirs in ((self.signals, other.signals), (self.plant, other.plant)):
            for name, record in theirs.items():
                mine.setdefault(name, ValueRecord()).merge(record)


@dataclass(slots=True)
class FunctionCoverage:
    """The states one state machine entered and the transitions it took, over all its instances."""

    states: dict[str, int] = field(default_factory=dict)  # state -> times entered
    transitions: dict[tuple[str, str], int] = field(default_factory=dict)  # (from, to) -> times taken
    instances: set[str] = field(default_factory=set)  # "machine/instance" that ran this state machine

    def entered(self, state: str) -> None:
        self.states[state] = self.states.get(state, 0) + 1

    def took(self, before: str, after: str) -> None:
        key = (before, after)
        self.transitions[key] = self.transitions.get(key, 0) + 1
        self.entered(after)

    def merge(self, other: FunctionCoverage) -> None:
        for state, count in other.states.items():
            self.states[state] = self.states.get(state, 0) + count
        for key, count in other.transitions.items():
            self.transitions[key] = self.transitions.get(key, 0) + count
        self.instances |= other.instances


@dataclass(slots=True)
class AlarmCoverage:
    raised: int = 0
    cleared: dict[str, int] = field(default_factory=dict)  # how (reset, cancel, self, power_on ...) -> times

    def cleared_by(self, how: str) -> None:
        self.cleared[how] = self.cleared.get(how, 0) + 1

    def merge(self, other: AlarmCoverage) -> None:
        self.raised += other.raised
        for how, count in other.cleared.items():
            self.cleared[how] = self.cleared.get(how, 0) + count


@dataclass(slots=True)
class CoverageData:
    """Everything one or more runs exercised (see the module docstring)."""

    scenarios: int = 0  # scenario runs (power-ons of a scenario's machine) observed
    cycles: int = 0  # IPO cycles observed
    machines: dict[str, MachineCoverage] = field(default_factory=dict)
    functions: dict[str, FunctionCoverage] = field(default_factory=dict)
    alarms: dict[int, AlarmCoverage] = field(default_factory=dict)

    def function(self, name: str) -> FunctionCoverage:
        found = self.functions.get(name)
        if found is None:
            found = self.functions[name] = FunctionCoverage()
        return found

    def alarm(self, number: int) -> AlarmCoverage:
        found = self.alarms.get(number)
        if found is None:
            found = self.alarms[number] = AlarmCoverage()
        return found

    def merge(self, other: CoverageData) -> CoverageData:
        """Add ``other`` to this data (which is returned)."""
        self.scenarios += other.scenarios
        self.cycles += other.cycles
        for name, machine in other.machines.items():
            self.machines.setdefault(name, MachineCoverage()).merge(machine)
        for name, function in other.functions.items():
            self.function(name).merge(function)
        for number, alarm in other.alarms.items():
            self.alarm(number).merge(alarm)
        return self

    @classmethod
    def merged(cls, items: Iterable[CoverageData]) -> CoverageData:
        result = cls()
        for item in items:
            result.merge(item)
        return result

    # ------------------------------------------------------------------ JSON
    def to_json(self) -> dict[str, Any]:
        return {
            "format": FORMAT,
            "version": VERSION,
            "scenarios": self.scenarios,
            "cycles": self.cycles,
            "machines": {
                name: {
                    "source": machine.source,
                    "instances": dict(sorted(machine.instances.items())),
                    "types": dict(sorted(machine.types.items())),
                    "not_applicable": sorted(machine.not_applicable),
                    "signals": {symbol: record.to_json() for symbol, record in sorted(machine.signals.items())},
                    "plant": {point: record.to_json() for point, record in sorted(machine.plant.items())},
                }
                for name, machine in sorted(self.machines.items())
            },
            "functions": {
                name: {
                    "instances": sorted(function.instances),
                    "states": dict(sorted(function.states.items())),
                    "transitions": [[before, after, count]
                                    for (before, after), count in sorted(function.transitions.items())],
                }
                for name, function in sorted(self.functions.items())
            },
            "alarms": {str(number): {"raised": alarm.raised, "cleared": dict(sorted(alarm.cleared.items()))}
                       for number, alarm in sorted(self.alarms.items())},
        }

    def save(self, path: str) -> None:
        with open(path, "w", encoding="utf-8") as handle:
            json.dump(self.to_json(), handle, indent=1)
            handle.write("\n")

    @classmethod
    def load(cls, path: str, names: CoverageNames | None = None) -> CoverageData:
        """Read a coverage file; raises :class:`SourceError` with every problem and its location.
        With ``names`` every name in it must be one of them."""
        try:
            with open(path, encoding="utf-8") as handle:
                text = handle.read()
        except OSError as error:
            raise SourceError([Problem(Mark(path, 1, 1), f"cannot read the file: {error.strerror}")]) from None
        except UnicodeDecodeError as error:
            raise SourceError([Problem(Mark(path, 1, 1), f"the file is not UTF-8 text ({error.reason})")]) from None
        try:
            document = loads(text)
        except JsonProblem as error:
            raise SourceError([Problem(Mark(path, error.line, error.column),
                                       f"not a coverage file of vc run --coverage ({error.message})")]) from None
        reader = _Reader(names)
        data = reader.document(document)
        if reader.problems:
            located, _ = load_text(text, path)  # once for all problems: JSON is YAML, its composer marks each node
            shown = reader.problems[:MAX_PROBLEMS]
            problems = [Problem(locate(located, path, where), message) for where, message in shown]
            if len(reader.problems) > len(shown):
                problems.append(Problem(Mark(path, 1, 1), f"and {len(reader.problems) - len(shown):,} more problems"))
            raise SourceError(problems)
        return data


Path = tuple[str | int, ...]  # where in the document: keys and list indices


def locate(document: Any, file: str, where: Path) -> Mark:
    """The mark of the value at ``where`` in the located ``document`` (its enclosing value if it is missing)."""
    mark = Mark(file, 1, 1)
    node = document
    for key in where:
        marks = getattr(node, "value_marks", None)
        if isinstance(key, str) and isinstance(node, dict) and key in node:
            mark = marks.get(key, mark) if marks else mark
            node = node[key]
        elif isinstance(key, int) and isinstance(node, list) and 0 <= key < len(node):
            item_marks = getattr(node, "item_marks", [])
            mark = item_marks[key] if key < len(item_marks) else mark
            node = node[key]
        else:
            break
    return mark


class _Reader:
    """Builds :class:`CoverageData` from a parsed document, collecting ``(where, message)`` problems."""

    def __init__(self, names: CoverageNames | None = None) -> None:
        self.problems: list[tuple[Path, str]] = []
        self.names = names

    def problem(self, where: Path, message: str) -> None:
        self.problems.append((where, message))

    def known(self, where: Path, problem: str) -> bool:
        """False (reported at ``where``) when a check of the names found a problem."""
        if problem:
            self.problem(where, problem)
        return not problem

    def mapping(self, value: Any, where: Path, what: str) -> Mapping[str, Any]:
        if isinstance(value, dict):
            return value
        self.problem(where, f"{_shown(where)} must be {what}")
        return {}

    def count(self, value: Any, where: Path) -> int:
        if isinstance(value, int) and not isinstance(value, bool) and value >= 0:
            return value
        self.problem(where, f"{_shown(where)} must be a whole number >= 0, not {json.dumps(value)}")
        return 0

    def number(self, value: Any, where: Path) -> float:
        if isinstance(value, (int, float)) and not isinstance(value, bool) and abs(value) <= MAX_VALUE:
            return float(value)
        self.problem(where, f"{_shown(where)} must be a number (at most {MAX_VALUE:g}), not {json.dumps(value)[:40]}")
        return 0.0

    def names_list(self, value: Any, where: Path) -> set[str]:
        if isinstance(value, list) and all(isinstance(item, str) for item in value):
            return set(value)
        self.problem(where, f"{_shown(where)} must be a list of names")
        return set()

    def document(self, document: Any) -> CoverageData:
        top = self.mapping(document, (), "a JSON object")
        data = CoverageData()
        if top.get("format") != FORMAT:
            self.problem(("format",) if "format" in top else (), f"not a coverage file of vc run --coverage"
                         f" (\"format\" must be \"{FORMAT}\")")
            return data
        if top.get("version") != VERSION:
            self.problem(("version",), f"coverage file version {json.dumps(top.get('version'))}: this vc reads"
                                       f" version {VERSION}")
            return data
        known = {"format", "version", "scenarios", "cycles", "machines", "functions", "alarms"}
        for key in sorted(set(top) - known):
            self.problem((key,), f"unknown key '{key}' (known: {', '.join(sorted(known))})")
        data.scenarios = self.count(top.get("scenarios", 0), ("scenarios",))
        data.cycles = self.count(top.get("cycles", 0), ("cycles",))
        for name, machine in self.mapping(top.get("machines", {}), ("machines",), "an object").items():
            data.machines[name] = self.machine(machine, ("machines", name))
        for name, function in self.mapping(top.get("functions", {}), ("functions",), "an object").items():
            data.functions[name] = self.function(function, ("functions", name))
        for number, alarm in self.mapping(top.get("alarms", {}), ("alarms",), "an object").items():
            where: Path = ("alarms", number)
            if not number.isdigit() or len(number) > 9:
                self.problem(where, f"alarm '{number[:20]}' is not an alarm number")
                continue
            if self.names is not None and not self.known(where, self.names.alarm(int(number))):
                continue
            entry = self.mapping(alarm, where, "an object {raised, cleared}")
            record = AlarmCoverage(self.count(entry.get("raised", 0), (*where, "raised")))
            for how, count in self.mapping(entry.get("cleared", {}), (*where, "cleared"), "an object").items():
                record.cleared[how] = self.count(count, (*where, "cleared", how))
            data.alarms[int(number)] = record
        return data

    def machine(self, value: Any, where: Path) -> MachineCoverage:
        entry = self.mapping(value, where, "an object {source, instances, types, not_applicable, signals, plant}")
        source = entry.get("source", "")
        if not isinstance(source, str):
            self.problem((*where, "source"), f"{_shown((*where, 'source'))} must be the machine file, a text")
        machine = MachineCoverage(source=str(source))
        names = self.names
        refused: set[str] = set()  # instances refused: their signals are not reported once more
        for name, db in self.mapping(entry.get("instances", {}), (*where, "instances"), "an object").items():
            problems = len(self.problems)
            number = self.count(db, (*where, "instances", name))
            if len(self.problems) == problems and (
                    names is None or self.known((*where, "instances", name), names.instance(name, number))):
                machine.instances[name] = number
            else:
                refused.add(name)
        for name, kind in self.mapping(entry.get("types", {}), (*where, "types"), "an object").items():
            if names is None or self.known((*where, "types", name), names.type(name, kind)):
                machine.types[name] = str(kind)
        machine.not_applicable = self.names_list(entry.get("not_applicable", []), (*where, "not_applicable"))
        for name, record in self.mapping(entry.get("signals", {}), (*where, "signals"), "an object").items():
            if name.partition(".")[0] in refused:
                continue
            if names is None or self.known((*where, "signals", name), names.signal(name, machine.instances)):
                machine.signals[name] = self.record(record, (*where, "signals", name))
        for name, record in self.mapping(entry.get("plant", {}), (*where, "plant"), "an object").items():
            if names is None or self.known((*where, "plant", name), names.plant_point(name)):
                machine.plant[name] = self.record(record, (*where, "plant", name))
        return machine

    def record(self, value: Any, where: Path) -> ValueRecord:
        entry = self.mapping(value, where, "an object {values, low, high, more, edges}")
        values = entry.get("values", [])
        record = ValueRecord()
        if not isinstance(values, list) or len(values) > MAX_DISTINCT:
            self.problem((*where, "values"), f"{_shown((*where, 'values'))} must be a list of at most {MAX_DISTINCT}"
                                             " numbers")
            values = []
        for index, item in enumerate(values):
            record.values.add(self.number(item, (*where, "values", index)))
        if "low" in entry or "high" in entry:
            record.low = self.number(entry.get("low"), (*where, "low"))
            record.high = self.number(entry.get("high"), (*where, "high"))
        elif record.values:
            record.low, record.high = min(record.values), max(record.values)
        record.more = entry.get("more", False) is True
        edges = self.count(entry.get("edges", 0), (*where, "edges"))
        if edges > RISES | FALLS:
            self.problem((*where, "edges"), f"{_shown((*where, 'edges'))} must be 0..3 (1 rises, 2 falls)")
        record.edges = edges & (RISES | FALLS)
        return record

    def function(self, value: Any, where: Path) -> FunctionCoverage:
        entry = self.mapping(value, where, "an object {instances, states, transitions}")
        function = FunctionCoverage(instances=self.names_list(entry.get("instances", []), (*where, "instances")))
        machine = str(where[-1])
        states_known = self.names is None or self.known(where, self.names.state_machine(machine))
        for state, count in self.mapping(entry.get("states", {}), (*where, "states"), "an object").items():
            if not states_known or self.names is None or self.known((*where, "states", state),
                                                                    self.names.state(machine, state)):
                function.states[state] = self.count(count, (*where, "states", state))
        transitions = entry.get("transitions", [])
        if not isinstance(transitions, list):
            self.problem((*where, "transitions"), f"{_shown((*where, 'transitions'))} must be a list")
            transitions = []
        for index, item in enumerate(transitions):
            place = (*where, "transitions", index)
            if not (isinstance(item, list) and len(item) == 3 and isinstance(item[0], str)
                    and isinstance(item[1], str)):
                self.problem(place, f"{_shown(place)} must be [from state, to state, count]")
                continue
            if states_known and self.names is not None and not (
                    self.known((*place, 0), self.names.state(machine, item[0]))
                    and self.known((*place, 1), self.names.state(machine, item[1]))):
                continue
            function.transitions[(item[0], item[1])] = self.count(item[2], (*place, 2))
        return function


def _shown(where: Path) -> str:
    return ".".join(str(key) for key in where) or "the document"
