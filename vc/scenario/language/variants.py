"""``vary:``: one scenario as a matrix of variants, and campaign files that run scenarios over one.

A scenario file may declare a matrix; so may a campaign file, which names scenario files and
runs each of them over its matrix (it replaces their own ``vary:``)::

    vary:                             a product: every combination; the first key changes slowest
      KEY: [VALUE, ...]
      cases:                          values that go together: one entry per combination
        - {KEY: VALUE, KEY: VALUE}
    vary: [{KEY: VALUE, ...}, ...]    an explicit list of variants, each naming the same keys

    KEY
      INSTANCE.MD<number>[<index>]    machine data of an axis, channel or NC: X1.MD34050, X1.MD34100[0],
      INSTANCE.<MD name>              X1.REFP_SET_POS (as under machine_data:, checked the same way)
      INSTANCE.plant.KEY[.KEY]        plant and simulation of an axis (X1.plant.ref_cam, SP1.plant.gearbox.engaged,
      INSTANCE.sim.KEY                X1.sim.start_position) or the NC's drive line-up (NC.dc_link.precharge_time)
      NC.dc_link.KEY
      plc_parameters.NAME             a parameter of the PLC program (plc_parameters.referencing_order)
      machine | plc | timeout         the scenario's own entry: another machine file, PLC program or time limit
      fault                           a fault step's mapping ({axis: X1, kind: zero_marks_missing}) or none ...
      fault.at_step                   ... inserted before this step (1 = before the first; default: after the last)
      NAME                            a plain name (no dots): a value for ${NAME} in the scenario's texts

    campaign file:
      campaign: TEXT                  required: the campaign's name
      [description: TEXT]
      scenarios: [PATH, ...]          required: scenario files, relative to the campaign file
      vary: MATRIX                    required

Every text of a scenario may hold ``${...}`` placeholders of the varied values
(:mod:`vc.scenario.language.placeholders`); each variant is checked as a scenario of its own, before
anything runs.  A problem every variant of a scenario has is reported once; one that only
some variants have names the first of them.

A run holds at most ``MAX_RUN_VARIANTS`` variants (``vc run --max-variants N`` raises it),
counted from the sizes of the matrices before a single variant is built or a campaign's
scenario file is read.  Checking shares what variants have in common: the variants that differ
only in machine data share the check of their document, and each distinct machine is loaded
once (:class:`_Expansion`).

A variant's id is the scenario's name with the varied values in brackets,
``JOG-REF of X1[X1.MD34050=1,X1.plant.ref_cam=[250,260]]``, stable as long as the matrix is:
reports, trace files and golden files use it.
"""

from __future__ import annotations

import itertools
import math
import os
import re
from collections.abc import Callable, Iterator, Mapping, Sequence
from dataclasses import dataclass, replace
from typing import Any

from vc.input_limits import MAX_RUN_VARIANTS
from vc.located_yaml import LocatedList, LocatedMap, Mark, Problem, Problems
from vc.scenario.language.model import Scenario, Variant
from vc.scenario.language.placeholders import PlaceholderError, fill, has_placeholder, placeholder_names, shown

VARY = "vary"
CASES = "cases"
CAMPAIGN = "campaign"
CAMPAIGN_KEYS = (CAMPAIGN, "description", "scenarios", VARY)
ENTRIES = ("machine", "plc", "timeout")  # the scenario's own top-level entries a matrix may vary
FAULT = "fault"
FAULT_AT_STEP = "fault.at_step"
PLC_PARAMETERS = "plc_parameters"
MACHINE_DATA = "machine_data"
OVERRIDE_BLOCKS = ("plant", "sim", "dc_link")  # nested blocks of an instance's overrides
MAX_FAILED_VARIANTS = 1_000  # variants with problems after which a check stops (the file is broken)
_NO_CEILING = 1 << 62  # a worker building one variant the client counted
_VARIABLE = re.compile(r"^[A-Za-z_][A-Za-z0-9_]*$")
_NO_FAULT = (None, False, "none")

# read(path, problems) -> the document, or None (its problems reported)
ReadDocument = Callable[[str, Problems], LocatedMap | None]
# check(scenario path, document, problems) -> the checked scenario, or None (its problems reported)
CheckDocument = Callable[[str, LocatedMap, Problems], Scenario | None]
# rebuild(scenario path, document, checked, problems) -> ``checked`` with the machine of ``document``
# (whose other parts are those of the document ``checked`` came from); None when that machine has
# problems (reported) or another shape (nothing reported: check the document in full).  With
# ``checked`` None it only loads the machine and reports its problems.
RebuildVariant = Callable[[str, LocatedMap, Scenario | None, Problems], Scenario | None]


@dataclass(frozen=True, slots=True)
class _Setting:
    """One varied key with one of its values, and where both are written."""

    key: str
    key_mark: Mark
    value: Any
    value_mark: Mark


Combination = tuple[_Setting, ...]


# ---------------------------------------------------------------------------------- public


@dataclass(slots=True)
class VariantCeiling:
    """How many variants one run may hold (``vc run --max-variants N``), counted from the sizes of
    the matrices before any variant is built: a campaign of 1,000 files x 100,000 variants is
    refused at once, not after days of checking."""

    limit: int = MAX_RUN_VARIANTS
    counted: int = 0

    def admit(self, count: int, mark: Mark, problems: Problems, what: str) -> bool:
        """Count the ``count`` variants of ``what``; False (reported at ``mark``) when the run passes
        the ceiling."""
        before = self.counted
        self.counted += count
        if self.counted <= self.limit:
            return True
        run = f" ({self.counted:,} with the files before it)" if before else ""
        problems.add(mark, f"{what} gives {count:,} variants{run}; a run holds at most {self.limit:,} (vc run"
                           " --max-variants N raises the ceiling)")
        return False


def check_file(path: str, read: ReadDocument, check: CheckDocument, problems: Problems,
               only: int | None = None, *, rebuild: RebuildVariant | None = None,
               ceiling: VariantCeiling | None = None) -> list[Scenario]:
    """The scenarios of one file: itself, each variant of its matrix, or each variant of each
    scenario of a campaign.  ``only``: just the variant at that position of the file's matrix
    (no ceiling applies).  ``rebuild`` lets variants that differ only in their machine share the
    check of their document; ``ceiling`` counts the variants of the whole run."""
    document = read(path, problems)
    if document is None:
        return []
    ceiling = ceiling if only is None and ceiling is not None else VariantCeiling(_NO_CEILING)
    if CAMPAIGN in document:
        return _check_campaign(path, document, read, _Checks(check, rebuild, ceiling), problems, only)
    if VARY not in document:
        if only is not None:
            problems.add(document.mark, f"variant {only} asked for, but the file has no vary:")
            return []
        scenario = check(path, document, problems)
        return [scenario] if scenario is not None else []
    matrix = read_matrix(document[VARY], document.mark_of(VARY), problems)
    if matrix is None or not ceiling.admit(matrix.count, document.mark_of(VARY), problems, "this matrix"):
        return []
    return _Expansion(path, "", matrix, _Checks(check, rebuild, ceiling), problems).run([(path, document)], only)


def is_campaign(document: object) -> bool:
    return isinstance(document, LocatedMap) and CAMPAIGN in document


@dataclass(frozen=True, slots=True)
class Matrix:
    """The dimensions of a ``vary:`` matrix; its variants are their product, built one at a time."""

    dimensions: tuple[tuple[Combination, ...], ...]

    @property
    def count(self) -> int:
        """The number of variants, from the sizes alone."""
        return math.prod(len(dimension) for dimension in self.dimensions)

    def combinations(self) -> Iterator[Combination]:
        """Every combination in order (the first dimension changes slowest)."""
        for parts in itertools.product(*self.dimensions):
            yield tuple(setting for part in parts for setting in part)

    def combination(self, index: int) -> Combination:
        """The combination at position ``index`` (0 <= index < count), without the ones before it."""
        parts: list[Combination] = []
        for dimension in reversed(self.dimensions):
            index, position = divmod(index, len(dimension))
            parts.append(dimension[position])
        return tuple(setting for part in reversed(parts) for setting in part)

    def first(self) -> Combination:
        return self.combination(0)


def read_matrix(value: Any, mark: Mark, problems: Problems) -> Matrix | None:
    """The matrix of a ``vary:`` value; None (reported) when it is not one.  Nothing is multiplied out."""
    before = len(problems.items)
    if isinstance(value, LocatedList):
        dimensions = [_cases(value, mark, problems, "vary")]
    elif isinstance(value, LocatedMap) and value:
        dimensions = []
        for key, item, item_mark in value.located_items():
            if key == CASES:
                dimensions.append(_cases(item, item_mark, problems, CASES))
            else:
                dimensions.append(_values(key, value.mark_of_key(key), item, item_mark, problems))
    else:
        problems.add(mark, "vary takes a mapping of keys to lists of values (a product), e.g."
                           " {X1.MD34050: [0, 1]}, or a list of variants, e.g. [{X1.MD34050: 0}, {X1.MD34050: 1}]")
        return None
    if len(problems.items) > before:
        return None
    keys: dict[str, Mark] = {}
    for setting in (setting for dimension in dimensions for setting in dimension[0]):
        if setting.key in keys:
            problems.add(setting.key_mark, f"'{setting.key}' is varied twice (first at line {keys[setting.key].line})")
        keys[setting.key] = setting.key_mark
    if FAULT_AT_STEP in keys and FAULT not in keys:
        problems.add(keys[FAULT_AT_STEP], "fault.at_step places a varied fault: vary fault too, e.g."
                                          " fault: [{axis: X1, kind: zero_marks_missing}]")
    for dimension in dimensions:
        _check_distinct(dimension, problems)
    if len(problems.items) > before:
        return None
    return Matrix(tuple(tuple(dimension) for dimension in dimensions))


def _check_distinct(dimension: list[Combination], problems: Problems) -> None:
    """Two equal entries of one dimension would give every variant twice (ids must be unique)."""
    seen: dict[str, Combination] = {}
    for combination in dimension:
        arguments = arguments_of(combination)
        if arguments in seen:
            problems.add(combination[0].value_mark, f"{arguments} appears twice in the matrix (first at line"
                                                    f" {seen[arguments][0].value_mark.line}): every variant would"
                                                    " run twice")
            continue
        seen[arguments] = combination


def arguments_of(combination: Combination) -> str:
    """The bracket of a variant id: ``X1.MD34050=1,X1.plant.ref_cam=[250,260]``."""
    return ",".join(f"{setting.key}={compact(setting.value)}" for setting in combination)


def compact(value: Any) -> str:
    """A value as an id shows it: as in a scenario text, without spaces after separators."""
    return shown(value).replace(", ", ",").replace(": ", ":")


# ---------------------------------------------------------------------------------- the matrix


def _values(key: str, key_mark: Mark, value: Any, mark: Mark, problems: Problems) -> list[Combination]:
    if not _key_is_sound(key, key_mark, problems):
        return []
    if not isinstance(value, LocatedList) or not value:
        problems.add(mark, f"{key}: give the values to vary over as a list, e.g. {key}: [0, 1]")
        return []
    return [(_setting(key, key_mark, item, item_mark, problems),) for _, item, item_mark in value.located_items()]


def _cases(value: Any, mark: Mark, problems: Problems, where: str) -> list[Combination]:
    """A list of mappings naming the same keys: the values of each mapping go together."""
    if not isinstance(value, LocatedList) or not value:
        problems.add(mark, f"{where} takes a list of mappings, one per variant, e.g. [{{X1.MD34050: 0, side: -1}},"
                           " {X1.MD34050: 1, side: 1}]")
        return []
    combinations: list[Combination] = []
    first: tuple[str, ...] = ()
    for position, item, item_mark in value.located_items():
        if not isinstance(item, LocatedMap) or not item:
            problems.add(item_mark, f"an entry of {where} is a mapping of keys to values, e.g. {{X1.MD34050: 0}}")
            continue
        if position == 0:
            first = tuple(item)
        elif set(item) != set(first):
            problems.add(item_mark, f"every entry of {where} names the same keys ({', '.join(first)});"
                                    f" this one names {', '.join(item)}")
            continue
        combinations.append(tuple(
            _setting(key, item.mark_of_key(key), item[key], item.mark_of(key), problems)
            for key in first if _key_is_sound(key, item.mark_of_key(key), problems)))
    return combinations


def _setting(key: str, key_mark: Mark, value: Any, value_mark: Mark, problems: Problems) -> _Setting:
    if key == FAULT and value not in _NO_FAULT and not isinstance(value, LocatedMap):
        problems.add(value_mark, "a varied fault is a fault step's mapping, e.g. {axis: X1, kind: zero_marks_missing},"
                                 " or none")
    if key == FAULT_AT_STEP and (isinstance(value, bool) or not isinstance(value, int) or value < 1):
        problems.add(value_mark, f"fault.at_step is a step number from 1, not {shown(value)}")
    if any(has_placeholder(text) for text in _texts(value)):
        problems.add(value_mark, "a varied value is written out; ${...} belongs into the scenario's texts")
    return _Setting(key, key_mark, value, value_mark)


def _texts(value: Any) -> list[Any]:
    if isinstance(value, LocatedMap):
        return [text for item in value.values() for text in _texts(item)]
    if isinstance(value, LocatedList):
        return [text for item in value for text in _texts(item)]
    return [value]


def _key_is_sound(key: str, mark: Mark, problems: Problems) -> bool:
    head, dot, rest = key.partition(".")
    if key in (*ENTRIES, FAULT, FAULT_AT_STEP) or (not dot and _VARIABLE.match(key)):
        return True
    if dot and head and rest and ".." not in key and not key.endswith(".") and head != FAULT:
        return True
    problems.add(mark, f"'{key}' is no key a matrix varies: INSTANCE.MDnnnn (X1.MD34050), INSTANCE.plant.KEY,"
                       " INSTANCE.sim.KEY, plc_parameters.NAME, machine, plc, timeout, fault, fault.at_step, or a"
                       " plain name for ${NAME}")
    return False


# ---------------------------------------------------------------------------------- campaign


def _check_campaign(path: str, document: LocatedMap, read: ReadDocument, checks: _Checks, problems: Problems,
                    only: int | None) -> list[Scenario]:
    before = len(problems.items)
    for key in document:
        if key not in CAMPAIGN_KEYS:
            problems.add(document.mark_of_key(key),
                         f"unknown key '{key}' in a campaign (known: {', '.join(CAMPAIGN_KEYS)})")
    for key in (CAMPAIGN, "scenarios", VARY):
        if key not in document:
            problems.add(document.mark, f"a campaign needs '{key}'")
    name = document.get(CAMPAIGN)
    if CAMPAIGN in document and (not isinstance(name, str) or not name.strip()):
        problems.add(document.mark_of(CAMPAIGN), "campaign is the campaign's name, a text")
    listed = document.get("scenarios")
    if "scenarios" in document and (not isinstance(listed, LocatedList) or not listed
                                    or not all(isinstance(item, str) and item.strip() for item in listed)):
        problems.add(document.mark_of("scenarios"), "scenarios is a list of scenario files, relative to the campaign"
                                                    " file, e.g. [../scenarios/referencing/edges.yaml]")
    if len(problems.items) > before or not isinstance(listed, LocatedList):
        return []
    matrix = read_matrix(document[VARY], document.mark_of(VARY), problems)
    if matrix is None:
        return []
    # counted before a single scenario file is read
    files = f"{len(listed):,} scenario file{'s' if len(listed) != 1 else ''}"
    if not checks.ceiling.admit(matrix.count * len(listed), document.mark_of(VARY), problems,
                                f"this campaign (a matrix of {matrix.count:,} over {files})"):
        return []
    scenarios: list[tuple[str, LocatedMap]] = []
    stems: dict[str, Mark] = {}
    directory = os.path.dirname(path)
    for _, item, item_mark in listed.located_items():
        location = os.path.normpath(os.path.join(directory, item.strip()))
        if not os.path.isfile(location):
            shown_as = "" if os.path.normpath(item.strip()) == location else f" (looked for {location})"
            problems.add(item_mark, f"scenario file '{item}' not found{shown_as}")
            continue
        stem = _stem(location)
        if stem in stems:
            problems.add(item_mark, f"'{item}' has the name {stem} of the file at line {stems[stem].line}: the"
                                    " variants' ids would be the same")
            continue
        stems[stem] = item_mark
        scenario_document = read(location, problems)
        if scenario_document is None:
            continue
        if is_campaign(scenario_document):
            problems.add(item_mark, f"'{item}' is a campaign itself; a campaign names scenario files")
            continue
        scenarios.append((location, scenario_document))
    if len(problems.items) > before:
        return []
    return _Expansion(path, str(name).strip(), matrix, checks, problems).run(scenarios, only)


def _stem(path: str) -> str:
    return os.path.splitext(os.path.basename(path))[0]


# ---------------------------------------------------------------------------------- expansion


@dataclass(frozen=True, slots=True)
class _Checks:
    check: CheckDocument
    rebuild: RebuildVariant | None
    ceiling: VariantCeiling


@dataclass(slots=True)
class _Document:
    """A scenario document filled for one combination of the settings that are not machine data:
    checked once, shared by every variant that differs from it only in its machine."""

    filled: LocatedMap  # placeholders filled, settings applied (but machine data)
    problems: list[Problem]  # of the filling, and of the check where they are not about its machine
    known: bool = False  # a variant of it was checked in full
    checked: Scenario | None = None  # the check of a variant of it that passed


class _Expansion:
    """The variants of one matrix over one or more scenario documents.

    A variant is a document filled with its values, its settings applied, and checked as a
    scenario.  Variants that differ only in machine data (``X1.MD34040``, ``X1.plant.ref_cam``,
    ...) share their document: it is filled and checked once, and each of them gets its own
    machine through ``rebuild`` (each distinct machine loaded and checked once), as long as that
    machine has the shape of the checked one (all the check of the steps reads of a machine);
    otherwise the variant is checked in full.  A matrix of 100,000 variants over a few documents
    costs a few checks and its distinct machines, not 100,000 checks.
    """

    def __init__(self, origin: str, campaign: str, matrix: Matrix, checks: _Checks, problems: Problems):
        self.origin = origin
        self.campaign = campaign
        self.matrix = matrix
        self.checks = checks
        self.problems = problems
        self.variables_used: set[str] = set()
        # a problem -> the labels of the variants that have it, per scenario
        self.found: dict[Problem, dict[int, list[str]]] = {}
        self.documents: dict[tuple[int, object], _Document] = {}
        self.read_by_placeholders: dict[int, set[str]] = {}  # per scenario: the names its placeholders read
        self.sharing: dict[int, bool] = {}  # per scenario: whether its variants share documents

    def run(self, scenarios: Sequence[tuple[str, LocatedMap]], only: int | None) -> list[Scenario]:
        per_scenario = self.matrix.count
        total = per_scenario * len(scenarios)
        if only is not None and not 0 <= only < total:
            self.problems.add(Mark(self.origin, 1, 1), f"variant {only} asked for; the matrix has {total}")
            return []
        checked: list[Scenario] = []
        tried = failed = 0
        for index, scenario_number, number, combination in self.positions(len(scenarios), only):
            if failed == MAX_FAILED_VARIANTS:
                self.problems.add(self.matrix_mark(), f"checking stopped after {failed:,} variants with problems"
                                                      f" ({tried:,} of {total:,} checked)")
                break
            path, document = scenarios[scenario_number]
            arguments = arguments_of(combination)
            scenario = self.variant(path, document, combination, scenario_number, f"{_stem(path)}[{arguments}]")
            tried += 1
            if scenario is None:
                failed += 1
                continue
            variant = Variant(self.origin, index, arguments,
                              tuple((setting.key, compact(setting.value)) for setting in combination),
                              self.campaign, number == 0)
            checked.append(replace(scenario, name=f"{scenario.name}[{arguments}]", variant=variant,
                                   sources=tuple(dict.fromkeys((self.origin, *scenario.sources)))))
        self.report(1 if only is not None else per_scenario)
        if only is None:
            self.check_variables_used(scenarios)
        return checked

    def positions(self, scenarios: int, only: int | None) -> Iterator[tuple[int, int, int, Combination]]:
        """(position in the file's matrix, scenario number, position in the scenario's matrix, combination)."""
        per_scenario = self.matrix.count
        if only is not None:
            scenario_number, number = divmod(only, per_scenario)
            yield only, scenario_number, number, self.matrix.combination(number)
            return
        for scenario_number in range(scenarios):
            for number, combination in enumerate(self.matrix.combinations()):
                yield scenario_number * per_scenario + number, scenario_number, number, combination

    def matrix_mark(self) -> Mark:
        first = self.matrix.first()
        return first[0].key_mark if first else Mark(self.origin, 1, 1)

    def variant(self, path: str, document: LocatedMap, combination: Combination, scenario_number: int,
                label: str) -> Scenario | None:
        settings = self.rebased(path, combination)
        machine_only = self.machine_only(scenario_number, document)
        if not self.shares(scenario_number, machine_only):  # every variant a document of its own: nothing to keep
            shared = self.fill(document, settings, machine_only)
        else:
            key = (scenario_number, _plain([(setting.key, setting.value) for setting in settings
                                            if not machine_only(setting.key)]))
            shared = self.documents.get(key) or self.documents.setdefault(
                key, self.fill(document, settings, machine_only))
        found = Problems()
        variant_document = _copy_top(shared.filled)
        _apply(variant_document, tuple(setting for setting in settings if machine_only(setting.key)), found)
        scenario = self.shared_check(path, variant_document, shared, found)
        if scenario is None and not found:  # not checked yet, or another shape of machine: the whole check
            scenario = self.whole_check(path, variant_document, shared, found)
        for problem in found.items:
            self.found.setdefault(problem, {}).setdefault(scenario_number, []).append(label)
        return scenario if not found else None

    def machine_only(self, scenario_number: int, document: LocatedMap) -> Callable[[str], bool]:
        """Whether a varied key changes only the machine of ``document``: machine data that no
        placeholder of its texts reads (``${X1.MD32020 * override}`` makes X1.MD32020 a part
        of the document's texts too)."""
        read = self.read_by_placeholders.get(scenario_number)
        if read is None:
            read = self.read_by_placeholders[scenario_number] = _placeholder_names(document)
        return lambda key: _is_machine_setting(key) and key not in read and key.partition("[")[0] not in read

    def shares(self, scenario_number: int, machine_only: Callable[[str], bool]) -> bool:
        """Whether some dimension of the matrix changes only the machine, so that variants share documents."""
        shares = self.sharing.get(scenario_number)
        if shares is None:
            shares = self.sharing[scenario_number] = any(
                all(machine_only(setting.key) for setting in dimension[0]) for dimension in self.matrix.dimensions)
        return shares

    def fill(self, document: LocatedMap, settings: Combination, machine_only: Callable[[str], bool]) -> _Document:
        """The document with its placeholders filled and the settings that are not only machine data applied."""
        problems = Problems()
        values = {setting.key: setting.value for setting in settings}
        filled = _fill(document, values, problems, self.variables_used)
        assert isinstance(filled, LocatedMap)
        _apply(filled, tuple(setting for setting in settings if not machine_only(setting.key)), problems)
        return _Document(filled, list(problems.items))

    def shared_check(self, path: str, document: LocatedMap, shared: _Document, found: Problems) -> Scenario | None:
        """A variant of a document checked before: its machine, and the document's problems; None
        without problems when it needs the whole check."""
        rebuild = self.checks.rebuild
        if rebuild is None or not shared.known:
            return None
        found.extend(shared.problems)
        return rebuild(path, document, None if shared.problems else shared.checked, found)

    def whole_check(self, path: str, document: LocatedMap, shared: _Document, found: Problems) -> Scenario | None:
        """Check the variant as a scenario; a text whose placeholder failed is reported once."""
        found.extend(shared.problems)
        unfilled = {problem.mark for problem in found.items}
        checked = Problems()
        scenario = self.checks.check(path, document, checked)
        found.extend([problem for problem in checked.items if problem.mark not in unfilled])
        shared.known = True
        if scenario is not None and not found:
            shared.checked = scenario
        elif self.checks.rebuild is not None:
            # what is not about this variant's machine holds for every variant of the document
            of_machine = Problems()
            self.checks.rebuild(path, document, None, of_machine)
            about_machine = set(of_machine.items)
            shared.problems = [problem for problem in found.items if problem not in about_machine]
        return scenario

    def rebased(self, path: str, combination: Combination) -> Combination:
        """A campaign's machine files are written relative to the campaign file; the scenario
        document wants them relative to the scenario file."""
        if path == self.origin:
            return combination
        return tuple(replace(setting, value=_rebase(setting.value, self.origin, path))
                     if setting.key == "machine" and isinstance(setting.value, str) else setting
                     for setting in combination)

    def report(self, variants_per_scenario: int) -> None:
        """A problem every variant of a scenario has is reported as it is; one that only some have
        names the first of them."""
        for problem, by_scenario in self.found.items():
            everywhere = all(len(labels) == variants_per_scenario for labels in by_scenario.values())
            if everywhere:
                self.problems.add(problem.mark, problem.message)
                continue
            labels = [label for _, found in sorted(by_scenario.items()) for label in found]
            more = f" and {len(labels) - 1} more" if len(labels) > 1 else ""
            self.problems.add(problem.mark, f"{problem.message} (in variant {labels[0]}{more})")

    def check_variables_used(self, scenarios: Sequence[tuple[str, LocatedMap]]) -> None:
        if not scenarios:
            return
        for setting in self.matrix.first():
            key = setting.key
            if _VARIABLE.match(key) and key not in (*ENTRIES, FAULT) and key not in self.variables_used:
                self.problems.add(setting.key_mark, f"'{key}' is varied, but no text of the scenario uses ${{{key}}}:"
                                                    " every variant would be the same")


def _is_machine_setting(key: str) -> bool:
    """A key whose value goes under ``machine_data:`` (machine data, plant, simulation, DC link)."""
    head, dot, _ = key.partition(".")
    return bool(dot) and key not in (*ENTRIES, FAULT, FAULT_AT_STEP) and head != PLC_PARAMETERS


def _plain(value: Any) -> object:
    """A hashable copy of a value of a matrix (lists and mappings as tuples)."""
    if isinstance(value, Mapping):
        return ("map", tuple((key, _plain(item)) for key, item in value.items()))
    if isinstance(value, (list, tuple)):
        return ("list", tuple(_plain(item) for item in value))
    return (type(value).__name__, value)


def _placeholder_names(document: LocatedMap) -> set[str]:
    """Every name a placeholder of the document's texts reads (``vary:`` left out)."""
    names: set[str] = set()
    for key, value in document.items():
        if key != VARY:
            for text in _texts(value):
                if has_placeholder(text):
                    names |= placeholder_names(text)
    return names


def _copy_top(document: LocatedMap) -> LocatedMap:
    """A copy of the top level of a document (its blocks shared: ``_apply`` copies what it changes)."""
    copy = _empty_map(document.mark)
    copy.update(document)
    copy.key_marks.update(document.key_marks)
    copy.value_marks.update(document.value_marks)
    return copy


def _rebase(written: str, origin: str, scenario: str) -> str:
    location = os.path.normpath(os.path.join(os.path.dirname(origin), written.strip()))
    return os.path.relpath(location, os.path.dirname(scenario) or os.curdir)


def _fill(value: Any, values: dict[str, Any], problems: Problems, used: set[str], mark: Mark | None = None) -> Any:
    """A copy of a document part with every ``${...}`` filled in (``vary:`` itself left out)."""
    if isinstance(value, LocatedMap):
        copy = _empty_map(value.mark)
        for key, item, item_mark in value.located_items():
            if key == VARY:
                continue
            copy[key] = _fill(item, values, problems, used, item_mark)
            copy.key_marks[key] = value.mark_of_key(key)
            copy.value_marks[key] = item_mark
        return copy
    if isinstance(value, LocatedList):
        items = _empty_list(value.mark)
        for _, item, item_mark in value.located_items():
            items.append(_fill(item, values, problems, used, item_mark))
            items.item_marks.append(item_mark)
        return items
    if has_placeholder(value):
        assert isinstance(value, str) and mark is not None
        try:
            return fill(value, values, used)
        except PlaceholderError as error:
            problems.add(mark, f"in \"{value}\": {error.message}")
    return value


def _apply(document: LocatedMap, combination: Combination, problems: Problems) -> None:
    """Write the matrix's keys into a (filled) scenario document."""
    fault: _Setting | None = None
    at_step: _Setting | None = None
    for setting in combination:
        key = setting.key
        head, _, rest = key.partition(".")
        if key == FAULT:
            fault = setting
        elif key == FAULT_AT_STEP:
            at_step = setting
        elif key in ENTRIES:
            _put(document, key, setting)
        elif head == PLC_PARAMETERS:
            _put(_block(document, PLC_PARAMETERS, setting), rest, setting)
        elif rest:
            block = _block(_block(document, MACHINE_DATA, setting), head, setting)
            path = rest.split(".") if rest.split(".")[0] in OVERRIDE_BLOCKS else [rest]
            for part in path[:-1]:
                block = _block(block, part, setting)
            _put(block, path[-1], setting)
    if fault is not None and fault.value not in _NO_FAULT:
        _insert_fault(document, fault, at_step, problems)


def _insert_fault(document: LocatedMap, fault: _Setting, at_step: _Setting | None, problems: Problems) -> None:
    steps = document.get("steps")
    if not isinstance(steps, LocatedList):
        return  # the scenario's check reports the missing steps
    position = len(steps) + 1 if at_step is None else at_step.value
    if not 1 <= position <= len(steps) + 1:
        assert at_step is not None
        problems.add(at_step.value_mark, f"fault.at_step {position}: the scenario has steps 1 to {len(steps)}"
                                         f" ({len(steps) + 1} = after the last)")
        return
    step = _empty_map(fault.value_mark)
    step[FAULT] = fault.value
    step.key_marks[FAULT] = fault.key_mark
    step.value_marks[FAULT] = fault.value_mark
    steps.insert(position - 1, step)
    steps.item_marks.insert(position - 1, fault.value_mark)


def _block(parent: LocatedMap, key: str, setting: _Setting) -> LocatedMap:
    """``parent[key]`` as a mapping of its own (a copy; created at the setting's mark if missing)."""
    existing = parent.get(key)
    block = _empty_map(existing.mark if isinstance(existing, LocatedMap) else setting.key_mark)
    if isinstance(existing, LocatedMap):
        block.update(existing)
        block.key_marks.update(existing.key_marks)
        block.value_marks.update(existing.value_marks)
    parent[key] = block
    parent.key_marks.setdefault(key, setting.key_mark)
    parent.value_marks.setdefault(key, setting.key_mark)
    return block


def _put(mapping: LocatedMap, key: str, setting: _Setting) -> None:
    mapping.pop(key, None)  # the varied value replaces the written one, and comes last
    mapping[key] = setting.value
    mapping.key_marks[key] = setting.key_mark
    mapping.value_marks[key] = setting.value_mark


def _empty_map(mark: Mark) -> LocatedMap:
    mapping = LocatedMap()
    mapping.mark = mark
    mapping.key_marks = {}
    mapping.value_marks = {}
    return mapping


def _empty_list(mark: Mark) -> LocatedList:
    items = LocatedList()
    items.mark = mark
    items.item_marks = []
    return items
