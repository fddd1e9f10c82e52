"""Golden traces: a scenario's recorded behaviour, kept as a regression baseline.

``vc run --golden DIR`` compares each run with ``DIR/<scenario path>.json`` and fails a
scenario whose behaviour changed; ``--update-golden`` writes the baselines anew.

The name of a golden trace does not depend on how the scenario's path is spelt (from which
directory, relative or absolute): it is the scenario file's path below its *scenario root*, the
nearest directory above the file that holds a file named ``.vc-scenario-root`` (the project marks
``scenarios/``, ``examples/`` and ``campaigns/``), or, without one, the file's own directory.
``scenarios/referencing/x.yaml`` gives ``DIR/referencing/x.json`` from anywhere; a golden trace
never lies outside ``DIR``.

Compared by meaning, not byte by byte:

* every digital signal (bool, bits, byte, word of the interface and the plant I/O) must go
  through the same sequence of values; each change may move by up to one PLC scan in time,
  so an unrelated change of timing inside a scan does not count;
* the alarms raised, in order;
* per axis, the end position and the smallest and largest position reached, within 1 um;
* likewise for the quantities of ``GOLDEN_QUANTITIES`` a scenario names (the relation error of a
  coupled spindle: that it stayed within its tolerance is part of the behaviour).

A signal that changes in one trace but not in the other is a difference too.
"""

from __future__ import annotations

import json
import os
from collections.abc import Collection, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from vc.scenario.language.model import Scenario
from vc.scenario.language.quantities import QuantityKind
from vc.scenario.run.runner import Failure, ScenarioResult, file_stem
from vc.scenario.run.trace import Recording, is_alarm_number

POSITION_TOLERANCE = 1e-3  # mm or degrees
GOLDEN_QUANTITIES = ("couplingRelationError",)  # axis quantities kept when a scenario names them
FORMAT_VERSION = 1


@dataclass(frozen=True, slots=True)
class GoldenSummary:
    digital: dict[str, list[tuple[float, int]]]  # name -> [(time s, value), ...]
    alarms: list[int]
    positions: dict[str, tuple[float, float, float]]  # axis -> (end, lowest, highest)
    # "SP3.couplingRelationError" -> (end, lowest, highest); only written when there are any
    quantities: dict[str, tuple[float, float, float]] = field(default_factory=dict)

    def to_json(self) -> dict[str, Any]:
        document: dict[str, Any] = {
            "format": FORMAT_VERSION,
            "alarms": self.alarms,
            "positions": {axis: list(values) for axis, values in sorted(self.positions.items())},
        }
        if self.quantities:
            document["quantities"] = {name: list(values) for name, values in sorted(self.quantities.items())}
        document["digital"] = {name: [[round(t, 6), v] for t, v in changes]
                               for name, changes in sorted(self.digital.items())}
        return document

    @classmethod
    def from_json(cls, document: dict[str, Any]) -> GoldenSummary:
        return cls(
            digital={name: [(float(t), int(v)) for t, v in changes] for name, changes in document["digital"].items()},
            alarms=[int(number) for number in document["alarms"]],
            positions={axis: (float(a), float(b), float(c)) for axis, (a, b, c) in document["positions"].items()},
            quantities={name: (float(a), float(b), float(c))
                        for name, (a, b, c) in document.get("quantities", {}).items()},
        )


def summarize(recorder: Recording, alarm_numbers: Sequence[int], named: Collection[str] = ()) -> GoldenSummary:
    """What a golden trace keeps of a run; ``named``: the names the scenario itself uses."""
    digital: dict[str, list[tuple[float, int]]] = {}
    positions: dict[str, tuple[float, float, float]] = {}
    quantities: dict[str, tuple[float, float, float]] = {}
    for history in recorder.histories:
        quantity = history.quantity
        if quantity.kind is QuantityKind.AXIS:
            if len(history) and quantity.name.endswith(".position"):
                values = list(history.values)
                positions[quantity.name.rsplit(".", 1)[0]] = (values[-1], min(values), max(values))
            elif len(history) and quantity.quantity in GOLDEN_QUANTITIES:
                values = list(history.values)
                quantities[quantity.name] = (values[-1], min(values), max(values))
            continue
        if not quantity.is_integer or len(history) < 2:
            continue  # a signal that never changed says nothing about behaviour
        if is_alarm_number(quantity) and quantity.name not in named:
            continue  # compared as the alarms raised, in order
        digital[quantity.name] = [(recorder.time_of(cycle), int(value)) for cycle, value in history.entries()]
    return GoldenSummary(digital, list(alarm_numbers), positions, quantities)


def compare(golden: GoldenSummary, actual: GoldenSummary, time_tolerance_s: float) -> list[str]:
    """The differences in meaning, each as one sentence; empty when the behaviour is the same."""
    differences: list[str] = []
    if golden.alarms != actual.alarms:
        differences.append(f"alarms raised: expected {golden.alarms}, got {actual.alarms}")
    for axis, (end, low, high) in sorted(golden.positions.items()):
        found = actual.positions.get(axis)
        if found is None:
            differences.append(f"{axis}: no positions recorded")
            continue
        for label, expected, value in (("end position", end, found[0]), ("lowest position", low, found[1]),
                                       ("highest position", high, found[2])):
            if abs(expected - value) > POSITION_TOLERANCE:
                differences.append(f"{axis} {label}: expected {expected:.4f}, got {value:.4f}")
    for name in sorted(set(golden.quantities) | set(actual.quantities)):
        expected_range, found_range = golden.quantities.get(name), actual.quantities.get(name)
        if expected_range is None or found_range is None:
            differences.append(f"{name} is {'no longer' if found_range is None else 'now'} recorded")
            continue
        for label, expected, value in zip(("end", "lowest", "highest"), expected_range, found_range, strict=True):
            if abs(expected - value) > POSITION_TOLERANCE:
                differences.append(f"{name} {label}: expected {expected:.4f}, got {value:.4f}")
    for name in sorted(set(golden.digital) | set(actual.digital)):
        expected_changes = golden.digital.get(name)
        found_changes = actual.digital.get(name)
        if expected_changes is None:
            differences.append(f"{name} now changes ({_values(found_changes)}) but did not in the golden trace")
        elif found_changes is None:
            differences.append(f"{name} no longer changes (golden: {_values(expected_changes)})")
        else:
            differences.extend(_compare_changes(name, expected_changes, found_changes, time_tolerance_s))
    return differences


def _compare_changes(name: str, expected: list[tuple[float, int]], found: list[tuple[float, int]],
                     tolerance: float) -> list[str]:
    if [value for _, value in expected] != [value for _, value in found]:
        return [f"{name} went through {_values(found)}, golden {_values(expected)}"]
    for (expected_time, value), (found_time, _) in zip(expected, found, strict=True):
        if abs(expected_time - found_time) > tolerance + 1e-9:
            return [f"{name} became {value} at {found_time:.3f} s, golden {expected_time:.3f} s"
                    f" (tolerance {tolerance * 1000:.0f} ms)"]
    return []


def _values(changes: list[tuple[float, int]] | None) -> str:
    shown = [str(value) for _, value in (changes or [])]
    return " -> ".join(shown[:12]) + (" ..." if len(shown) > 12 else "")


ROOT_MARKER = ".vc-scenario-root"  # marks the directory golden traces are named from (module docstring)


def _root_of(directory: str) -> str:
    for candidate in (directory, *(str(parent) for parent in Path(directory).parents)):
        if os.path.isfile(os.path.join(candidate, ROOT_MARKER)):
            return candidate
    return directory


def scenario_root(scenario_path: str) -> Path:
    """The scenario file's scenario root: the nearest directory above it holding :data:`ROOT_MARKER`,
    else its own directory."""
    return Path(_root_of(os.path.dirname(os.path.abspath(scenario_path))))


def golden_path(golden_dir: str | Path, scenario_path: str) -> Path:
    """``DIR/<scenario file below its scenario root>.json`` (scenarios/a/b.yaml -> DIR/a/b.json)."""
    absolute = Path(os.path.abspath(scenario_path))
    return Path(golden_dir) / absolute.relative_to(scenario_root(scenario_path)).with_suffix(".json")


def golden_file(golden_dir: str | Path, scenario: Scenario) -> Path:
    """Where a scenario's golden trace lies: :func:`golden_path`; a variant's beside it under its
    id (``DIR/a/b[X1.MD34050=1].json``), a campaign's variants in a directory named after the
    campaign file (campaigns/matrix.yaml: ``DIR/matrix/b[...].json``)."""
    variant = scenario.variant
    if variant is None:
        return golden_path(golden_dir, scenario.path)
    name = f"{file_stem(scenario)}.json"
    if variant.origin == scenario.path:
        return golden_path(golden_dir, scenario.path).with_name(name)
    return golden_path(golden_dir, variant.origin).with_suffix("") / name


def load(path: Path) -> GoldenSummary | None:
    if not path.exists():
        return None
    with path.open(encoding="utf-8") as handle:
        return GoldenSummary.from_json(json.load(handle))


def store(summary: GoldenSummary, path: Path) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    with path.open("w", encoding="utf-8") as handle:
        json.dump(summary.to_json(), handle, indent=0, separators=(",", ":"))
        handle.write("\n")


@dataclass(frozen=True, slots=True)
class GoldenCheck:
    """Compare each passed scenario with its golden trace, or (``update``) write it anew."""

    directory: Path
    update: bool = False

    def __call__(self, result: ScenarioResult) -> None:
        recorder = result.recorder
        if not result.passed or recorder is None:
            return
        scenario = result.scenario
        summary = summarize(recorder, recorder.alarm_numbers(), {quantity.name for quantity in scenario.quantities})
        path = golden_file(self.directory, scenario)
        if not _inside(path, self.directory):  # cannot be by construction; the check keeps it so
            self._fail(result, f"the golden trace {path} would lie outside {self.directory}")
            return
        if self.update:
            store(summary, path)
            return
        golden = load(path)
        if golden is None:
            root = scenario_root(scenario.variant.origin if scenario.variant is not None else scenario.path)
            self._fail(result, f"no golden trace {path} (named by the scenario's path below its scenario root {root});"
                               f" write it with vc run ... --golden {self.directory} --update-golden")
            return
        machine = scenario.machine
        tolerance = machine.plc_cycle_ipo * recorder.ipo_cycle_us / 1e6
        differences = compare(golden, summary, tolerance)
        if differences:
            shown = "; ".join(differences[:6]) + (f"; and {len(differences) - 6} more" if len(differences) > 6 else "")
            self._fail(result, f"the behaviour differs from the golden trace {path}: {shown}")

    def shared(self, scenarios: Sequence[Scenario]) -> list[str]:
        """A sentence for each golden trace two different scenarios of a run would share (files of
        one name in different directories without a scenario root above them)."""
        first: dict[Path, Scenario] = {}
        found = []
        for scenario in scenarios:
            path = golden_file(self.directory, scenario)
            other = first.setdefault(path, scenario)
            if other is not scenario and _identity(other) != _identity(scenario):
                found.append(f"{other.path} and {scenario.path} would share the golden trace {path}: put a file"
                             f" {ROOT_MARKER} into the directory that holds their tree (docs/scenarios.md)")
        return found

    @staticmethod
    def _fail(result: ScenarioResult, message: str) -> None:
        result.passed = False
        result.failure = Failure("golden", None, result.scenario.mark, message, result.cycles, result.simulated_s)


def _identity(scenario: Scenario) -> tuple[str, str, int | None]:
    variant = scenario.variant
    return (os.path.abspath(scenario.path), os.path.abspath(variant.origin) if variant is not None else "",
            variant.index if variant is not None else None)


def _inside(path: Path, directory: Path) -> bool:
    return os.path.commonpath([os.path.abspath(path), os.path.abspath(directory)]) == os.path.abspath(directory)
