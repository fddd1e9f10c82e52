"""Scenario files -> checked :class:`~vc.scenario.model.Scenario` objects.

Every problem of a file is collected with ``file:line:column`` and one
:class:`~vc.located_yaml.SourceError` reports them all: unknown keys and step kinds (with
"did you mean"), missing entries, unknown PLC programs, problems of the machine file
(reported at the machine file's own lines; machine data overrides at the scenario's lines),
unknown signals, bad durations, expressions, expected values, values outside a signal's
range, and writes that the signal's owner would undo.  :func:`load_scenarios` checks every
file of a run before any of them runs.

A check that cannot fail is refused like any other mistake, since it would pass falsely: an
expected value that every value of the quantity meets (``"<= 1"`` on a bool, a tolerance
covering a byte's range; :meth:`~vc.scenario.values.ExpectedValue.judgement`), an
``expect_timing`` whose ``max`` is as long as the run can be or whose only bound is
``min: 0``, a condition that reads nothing and so never changes.  Numbers and times stay
within :mod:`vc.input_limits`.
"""

from __future__ import annotations

import difflib
import os
from collections.abc import Callable, Collection, Iterable, Mapping, Sequence
from dataclasses import replace
from typing import Any

from interfaces.image import Value, value_range
from interfaces.plant_io import Owner
from interfaces.plc import PlcEnvironment, PlcFactory
from interfaces.signals import (
    HMI_INSTANCE,
    Catalog,
    Direction,
    ExpandedCatalog,
    InterfaceLayout,
    SignalType,
    UnknownSignalError,
    expand,
)
from vc.config.loader import load_machine
from vc.config.machine_data import MdType
from vc.config.machine_files import looks_like_a_path, unknown_machine
from vc.config.machine_files import machine_file as packaged_machine_file
from vc.config.md_dictionary import BY_NUMBER
from vc.config.model import MachineConfig, machine_ipo_cycle_us
from vc.core.alarms import ALARM_TEXTS
from vc.core.axis.handwheel import HANDWHEELS
from vc.input_limits import MAX_MAGNITUDE
from vc.located_yaml import LocatedList, LocatedMap, Mark, Problem, Problems, SourceError, load_file, read_source
from vc.scenario.durations import Duration, DurationError, format_seconds, parse_duration
from vc.scenario.expressions import AlarmCall, Expression, ExpressionError, Name, parse_expression, walk
from vc.scenario.model import (
    EXTERNAL_PLCS,
    LINK_CAN,
    NO_PLC,
    AcknowledgeAlarms,
    ClearFaults,
    EdgeKind,
    Event,
    ExpectAlarm,
    ExpectCondition,
    ExpectOrder,
    ExpectTiming,
    ExpectValues,
    Hold,
    InjectFault,
    InjectLinkFault,
    Invariant,
    LoadMda,
    MoveByHand,
    PowerCycle,
    Press,
    Release,
    Scenario,
    SelectProgram,
    SetValues,
    Step,
    TurnHandwheels,
    Wait,
    WaitUntil,
    external_plc,
)
from vc.scenario.quantities import NameResolver, Quantity, QuantityKind
from vc.scenario.values import ExpectedValue, ExpectedValueError, parse_expected
from vc.scenario.variants import check_file
from vc.simulation.observables import FAULTS, LINK_AREA, LINK_DIRECTIONS, LINK_FAULTS, MACHINE_FAULTS, MAINS

TOP_KEYS = ("name", "description", "machine", "plc", "link", "machine_data", "plc_parameters", "timeout",
            "invariants", "steps")
REQUIRED_TOP_KEYS = ("name", "machine", "plc", "steps")
STEP_KINDS = ("press", "hold", "release", "set", "force", "pulse", "mda", "program", "wait", "expect",
              "expect_alarm", "expect_no_alarm", "expect_order", "expect_timing", "power_cycle", "fault",
              "clear_faults", "move_by_hand", "link_fault", "turn",
              "acknowledge")
STEP_EXAMPLES = {
    "press": "press: MCP.jog", "hold": "hold: MCP.plus.X1", "release": "release: MCP.plus.X1",
    "set": "set: {MCP.feedOverride: 50}", "force": "force: {X1.basic.out.enableCtrl: 0}",
    "pulse": "pulse: {signal: CHAN1.basic.out.ncStart, for: 20ms}", "mda": 'mda: "G1 X100 F2000"',
    "program": "program: {name: PART1, file: programs/part1.mpf}", "wait": "wait: 500ms",
    "expect": 'expect: {X1.position: "100 +- 0.001"}', "expect_alarm": "expect_alarm: 10621",
    "expect_no_alarm": "expect_no_alarm: all", "expect_order": "expect_order: [MCP.jog rises, MCP.jog falls]",
    "expect_timing": "expect_timing: {from: MCP.jog rises, to: MCP.jog falls, max: 1s}",
    "power_cycle": "power_cycle: 2s", "fault": "fault: {axis: X1, kind: zero_marks_missing}",
    "clear_faults": "clear_faults: X1", "move_by_hand": "move_by_hand: {axis: X1, velocity: 600}",
    "link_fault": "link_fault: {kind: loss, for: 300ms}", "turn": "turn: {handwheel1: 20, for: 200ms}",
    "acknowledge": "acknowledge: alarms",
}
LINKS = (LINK_CAN,)
LINK_FAULT_KEYS = ("kind", "for", "direction", "frames", "by", "every")
DEFAULT_POWER_OFF = Duration(1_000_000)
DEFAULT_TIMEOUT = Duration(300_000_000)
DEFAULT_PRESS = Duration(100_000)
SCENARIO_SUFFIXES = (".yaml", ".yml")
SKIPPED_DIRECTORY = "machines"

# load_machine(path, overrides, overrides_file) -> MachineConfig, raising SourceError
MachineLoader = Callable[[str, LocatedMap | None, str], MachineConfig]


def default_machine_loader(path: str, overrides: LocatedMap | None, overrides_file: str) -> MachineConfig:
    return load_machine(path, overrides, overrides_file)


def default_catalog() -> Catalog:
    from interfaces.catalog import load_catalog

    return load_catalog()


# ---------------------------------------------------------------------------------- public


Programs = Collection[str] | Mapping[str, PlcFactory]


def load_scenario(path: str, known_programs: Programs, *, catalog: Catalog | None = None,
                  machine_loader: MachineLoader | None = None, variant: int | None = None) -> Scenario:
    """Load and check one scenario file (``variant``: only that variant of its matrix); raises
    :class:`SourceError` with every problem."""
    return load_scenarios([path], known_programs, catalog=catalog, machine_loader=machine_loader,
                          variant=variant)[0]


def load_scenarios(paths: Sequence[str], known_programs: Programs, *, catalog: Catalog | None = None,
                   machine_loader: MachineLoader | None = None, variant: int | None = None,
                   default_plc: str | None = None) -> list[Scenario]:
    """Load every scenario of ``paths`` (files, or directories searched recursively for ``*.yaml``
    outside directories named ``machines``), each variant of a ``vary:`` matrix and of a campaign
    file a scenario of its own (:mod:`vc.scenario.variants`).  Raises one :class:`SourceError`
    for all files.  ``variant``: only the variant at that position of each file's matrix.

    ``known_programs`` names the PLC programs a scenario may run; given as the registry
    (name -> factory), each scenario's program is also started once on its machine, to check
    its parameters (the machine file's ``plc:`` section and ``plc_parameters``) before anything runs.
    ``default_plc``: the program of a scenario without ``plc:`` (``vc serve``, where the PLC is on
    the link and ``plc:`` only names what a PLC that follows the harness runs); None: ``plc:`` is
    required."""
    files, problems = scenario_files(paths)
    machines = _Machines(machine_loader or default_machine_loader)
    collected = Problems()
    collected.extend(problems)
    scenarios: list[Scenario] = []

    def check(path: str, document: LocatedMap, found: Problems) -> Scenario | None:
        return _ScenarioChecker(path, known_programs, catalog, machines, found, default_plc).check(document)

    for file in files:
        scenarios += check_file(file, _read_scenario, check, collected, only=variant)
    if collected:
        raise SourceError(sorted(set(collected.items)))
    return scenarios


def _read_scenario(path: str, problems: Problems) -> LocatedMap | None:
    document, parse_problems = load_file(path)
    problems.extend(parse_problems)
    if document is None:
        return None
    if not isinstance(document, LocatedMap):
        problems.add(Mark(path, 1, 1),
                     "a scenario is a mapping with name, machine, plc and steps (see docs/scenarios.md)")
        return None
    return document


def scenario_files(paths: Iterable[str]) -> tuple[list[str], list[Problem]]:
    """The scenario files named by ``paths``, in a stable order, and the paths that do not exist."""
    files: list[str] = []
    problems: list[Problem] = []
    for path in paths:
        if os.path.isdir(path):
            found = []
            for directory, subdirectories, names in os.walk(path):
                subdirectories[:] = sorted(d for d in subdirectories if d != SKIPPED_DIRECTORY)
                found += [os.path.join(directory, n) for n in names if n.endswith(SCENARIO_SUFFIXES)]
            files += sorted(found)
        elif os.path.exists(path):  # a file; reading it reports what else it may be (a device, a FIFO)
            files.append(path)
        else:
            problems.append(Problem(Mark(path, 1, 1), "no such scenario file or directory"))
    unique = list(dict.fromkeys(os.path.normpath(f) if os.path.isabs(f) else f for f in files))
    return unique, problems


# ---------------------------------------------------------------------------------- machine


class _Machines:
    """Loads each machine file once per run, and once per distinct set of overrides of a scenario
    file (the variants of a matrix share them); expands the catalogue once per interface layout."""

    def __init__(self, loader: MachineLoader):
        self.loader = loader
        self._loaded: dict[tuple[str, str, object], MachineConfig | SourceError] = {}
        self._expanded: dict[tuple[int, InterfaceLayout], ExpandedCatalog] = {}

    def load(self, path: str, overrides: LocatedMap | None, overrides_file: str) -> MachineConfig:
        # the overrides' problems carry the scenario file's marks: kept per scenario file
        key = machine_key(path, overrides, overrides_file)
        if key not in self._loaded:
            try:
                self._loaded[key] = self.loader(path, overrides or None, overrides_file)
            except SourceError as error:
                self._loaded[key] = error
        result = self._loaded[key]
        if isinstance(result, SourceError):
            raise result
        return result

    def expanded(self, catalog: Catalog, layout: InterfaceLayout) -> ExpandedCatalog:
        key = (id(catalog), layout)
        if key not in self._expanded:
            self._expanded[key] = expand(catalog, layout)
        return self._expanded[key]


def machine_key(path: str, overrides: LocatedMap | None, overrides_file: str) -> tuple[str, str, object]:
    """What decides the machine a load gives: the file, and the overrides with the scenario file
    whose marks their problems carry."""
    return os.path.abspath(path), overrides_file if overrides else "", _plain(overrides) if overrides else None


def _plain(value: object) -> object:
    """A hashable copy of a YAML value."""
    if isinstance(value, dict):
        return tuple((key, _plain(item)) for key, item in value.items())
    if isinstance(value, list):
        return tuple(_plain(item) for item in value)
    return (type(value).__name__, value)


# ---------------------------------------------------------------------------------- checker


def _suggest(word: str, choices: Sequence[str]) -> str:
    close = difflib.get_close_matches(word, choices, n=1, cutoff=0.6)
    return f"; did you mean {close[0]}?" if close else ""


def _looked_for(written: str, location: str) -> str:
    return "" if os.path.normpath(written) == location else f" (looked for {location})"


def _brief(text: str) -> str:
    """A text of the file as a message quotes it: whole if short, else its start and its length."""
    return text if len(text) <= 200 else f"{text[:160]}... ({len(text):,} characters)"


def _kind_of_value(value: object) -> str:
    if isinstance(value, LocatedMap):
        return "a mapping"
    if isinstance(value, LocatedList):
        return "a list"
    if isinstance(value, bool):
        return "true/false"
    if value is None:
        return "empty"
    return f"'{_brief(str(value))}'"


class _ScenarioChecker:
    def __init__(self, path: str, known_programs: Programs, catalog: Catalog | None,
                 machines: _Machines, problems: Problems, default_plc: str | None = None):
        self.path = path
        self.default_plc = default_plc
        self.directory = os.path.dirname(path)
        self.known_programs = known_programs
        self.catalog = catalog
        self.machines = machines
        self.problems = problems
        self.machine: MachineConfig | None = None
        self.resolver: NameResolver | None = None
        self.plc = NO_PLC
        self.link: str | None = None
        self.forced: set[str] = set()
        self.timeout = DEFAULT_TIMEOUT
        self.sources = [path]  # the files this scenario reads: what travels with it to another machine

    def add(self, mark: Mark, message: str) -> None:
        self.problems.add(mark, message)

    # -- top level -------------------------------------------------------------------------

    def check(self, document: LocatedMap) -> Scenario | None:
        problems_before = len(self.problems.items)
        required = REQUIRED_TOP_KEYS if self.default_plc is None else tuple(
            key for key in REQUIRED_TOP_KEYS if key != "plc")
        self.check_keys(document, TOP_KEYS, required, "the scenario")
        name = self.text(document, "name")
        description = self.text(document, "description") if "description" in document else ""
        self.plc = self.check_plc(document)
        self.link = self.check_link(document)
        machine_file = self.load_machine(document)
        if "timeout" in document:
            self.timeout = self.duration(document["timeout"], document.mark_of("timeout"), positive=True) \
                or self.timeout
        invariants = self.invariants(document)
        steps = self.steps(document)
        self.check_timing_bounds(steps)
        if len(self.problems.items) > problems_before or self.machine is None or self.resolver is None:
            return None
        return Scenario(
            name=name, description=description, path=self.path, machine_file=machine_file,
            machine=self.machine, catalog=self.resolver.catalog, plc=self.plc, timeout=self.timeout,
            invariants=tuple(invariants), steps=tuple(steps), mark=document.mark, link=self.link,
            sources=tuple(dict.fromkeys(self.sources)),
        )

    def check_keys(self, mapping: LocatedMap, allowed: Sequence[str], required: Sequence[str],
                   where: str) -> bool:
        """Report unknown and missing keys; True if all required keys are there."""
        for key in mapping:
            if key not in allowed:
                hint = _suggest(key, allowed) or f" (known: {', '.join(allowed)})"
                self.add(mapping.mark_of_key(key), f"unknown key '{key}' in {where}{hint}")
        missing = [key for key in required if key not in mapping]
        for key in missing:
            self.add(mapping.mark, f"{where} needs '{key}'")
        return not missing

    def text(self, mapping: LocatedMap, key: str) -> str:
        value = mapping.get(key)
        if key in mapping and (not isinstance(value, str) or not value.strip()):
            self.add(mapping.mark_of(key), f"{key} must be a text, not {_kind_of_value(value)}")
            return ""
        return str(value or "").strip()

    def check_plc(self, document: LocatedMap) -> str:
        if "plc" not in document:
            return self.default_plc or NO_PLC
        value = document["plc"]
        mark = document.mark_of("plc")
        if value is False:  # YAML reads "plc: no" or "plc: off" as false
            return NO_PLC
        if not isinstance(value, str):
            self.add(mark, f"plc must name a PLC program or be none, not {_kind_of_value(value)}")
            return NO_PLC
        if value == NO_PLC or value in self.known_programs:
            return value
        kind, separator, program = value.partition(":")
        if separator and kind in EXTERNAL_PLCS:
            return self.external_program(kind, program.strip(), mark)
        known = sorted(self.known_programs)
        hint = _suggest(value, known)
        self.add(mark, f"unknown PLC program '{value}'{hint} (known: {', '.join([*known, NO_PLC])})")
        return NO_PLC

    def external_program(self, kind: str, program: str, mark: Mark) -> str:
        """``plc: awlsim:FILE``: the program file, relative to the scenario like the machine file."""
        if not program:
            self.add(mark, f"plc: {kind}: needs the program file, e.g. {kind}:../../examples/awlsim/turn_mill.awl")
            return NO_PLC
        path = os.path.normpath(os.path.join(self.directory, program))
        if not os.path.isfile(path):
            self.add(mark, f"no {kind} program '{program}' (looked for {path})")
            return NO_PLC
        return f"{kind}:{path}"

    def check_link(self, document: LocatedMap) -> str | None:
        if "link" not in document:
            return None
        value, mark = document["link"], document.mark_of("link")
        if value not in LINKS:
            hint = _suggest(str(value), LINKS)
            self.add(mark, f"link must be {' or '.join(LINKS)} (the PLC behind that link), not"
                     f" {_kind_of_value(value)}{hint}")
            return None
        if self.plc == NO_PLC:
            self.add(mark, f"link: {value} needs a PLC program behind it, and plc is none")
            return None
        if external_plc(self.plc) is not None:
            self.add(mark, f"link: {value} is for the built-in programs; {self.plc.partition(':')[0]} runs over its"
                           " own lockstep Modbus link")
            return None
        return str(value)

    def load_machine(self, document: LocatedMap) -> str:
        value = document.get("machine")
        if "machine" not in document:
            return ""
        mark = document.mark_of("machine")
        if not isinstance(value, str) or not value.strip():
            self.add(mark, f"machine must be the path of a machine file or the name of a packaged machine,"
                           f" not {_kind_of_value(value)}")
            return ""
        reference = value.strip()
        overrides = document.get("machine_data")
        if overrides is not None and not isinstance(overrides, LocatedMap):
            self.add(document.mark_of("machine_data"),
                     "machine_data is a mapping {axis, channel or NC: {MD number or name: value}}")
            overrides = None
        if looks_like_a_path(reference):
            machine_file = os.path.normpath(os.path.join(self.directory, reference))
            if not os.path.isfile(machine_file):
                what = "is not a regular file (a directory, device or FIFO)" if os.path.exists(machine_file) \
                    else "not found"
                self.add(mark, f"machine file '{value}' {what}{_looked_for(value, machine_file)}")
                return machine_file
            self.sources.append(machine_file)
        else:  # the name of a packaged machine (turn_mill)
            machine_file = reference
            packaged = packaged_machine_file(reference)
            if packaged is None:
                self.add(mark, unknown_machine(reference))
                return machine_file
            self.sources.append(packaged)
        try:
            self.machine = self.machines.load(machine_file, overrides or None, self.path)
        except SourceError as error:
            self.problems.extend(error.problems)
            if not overrides:
                return machine_file
            # The overrides are wrong; the machine itself may be sound, and its names let the
            # rest of the file be checked.
            try:
                self.machine = self.machines.load(machine_file, None, self.path)
            except SourceError:
                return machine_file
        parameters = document.get("plc_parameters")
        if parameters is not None:
            if isinstance(parameters, LocatedMap):
                # parameters of the PLC program over the machine file's plc: section (the program checks them)
                self.machine = replace(self.machine, plc_parameters={**self.machine.plc_parameters, **parameters})
            else:
                self.add(document.mark_of("plc_parameters"), "plc_parameters is a mapping of the PLC program's"
                         " parameters, e.g. {referencing_order: [[Z1], [X1]]}")
        catalog = self.catalog if self.catalog is not None else default_catalog()
        machine = self.machine
        self.resolver = NameResolver(self.machines.expanded(catalog, machine.layout), machine.plant_io,
                                     (axis.name for axis in machine.axes),
                                     (channel.name for channel in machine.channels), link=self.link == LINK_CAN,
                                     dc_link=machine.dc_link is not None)
        self.check_plc_parameters(document)
        return machine_file

    def check_plc_parameters(self, document: LocatedMap) -> None:
        """Start the PLC program once on this machine: it checks its parameters when it starts,
        and a refusal then would end the run with a traceback instead of a located problem."""
        factory = self.known_programs.get(self.plc) if isinstance(self.known_programs, Mapping) else None
        if factory is None or self.machine is None or self.resolver is None:
            return
        machine = self.machine
        ipo_cycle_us = machine_ipo_cycle_us(machine)
        environment = PlcEnvironment(self.resolver.catalog, machine.plant_io,
                                     machine.plc_cycle_ipo * ipo_cycle_us / 1_000_000, machine.plc_parameters,
                                     machine.name, ipo_cycle_us, machine.plc_cycle_ipo)
        try:
            factory(environment)
        except Exception as error:  # the program's own check (ValueError), or a parameter it trips over
            key = "plc_parameters" if "plc_parameters" in document else "plc"
            detail = str(error) if isinstance(error, ValueError) else f"{type(error).__name__}: {error}"
            for line in detail.splitlines() or [type(error).__name__]:
                self.add(document.mark_of(key), f"the PLC program {self.plc} refuses its parameters (the machine"
                         f" file's plc: section and plc_parameters): {line}")

    def invariants(self, document: LocatedMap) -> list[Invariant]:
        value = document.get("invariants")
        if value is None:
            return []
        items = value if isinstance(value, LocatedList) else None
        if items is None:
            if isinstance(value, str):
                expression = self.expression(value, document.mark_of("invariants"))
                return [Invariant(expression, document.mark_of("invariants"))] if expression else []
            self.add(document.mark_of("invariants"), "invariants is a list of conditions in quotes")
            return []
        result = []
        for _, item, mark in items.located_items():
            expression = self.expression(item, mark)
            if expression is not None:
                result.append(Invariant(expression, mark))
        return result

    def steps(self, document: LocatedMap) -> list[Step]:
        value = document.get("steps")
        if "steps" not in document:
            return []
        if not isinstance(value, LocatedList) or not value:
            self.add(document.mark_of("steps"), "steps is a list of steps, each starting with '- '"
                     " (e.g. '- wait: 2s')")
            return []
        steps: list[Step] = []
        for index, item, mark in value.located_items():
            step = self.step(index + 1, item, mark)
            if step is not None:
                steps.append(step)
        return steps

    # -- steps -----------------------------------------------------------------------------

    def step(self, index: int, item: Any, mark: Mark) -> Step | None:
        if isinstance(item, str) and item in STEP_KINDS:
            self.add(mark, f"'{item}' needs a colon and what to do, e.g. '- {STEP_EXAMPLES[item]}'")
            return None
        if not isinstance(item, LocatedMap) or not item:
            shown = _kind_of_value(item)
            hint = _suggest(item, STEP_KINDS) if isinstance(item, str) else ""
            self.add(mark, f"a step is written 'kind: what' (e.g. '- wait: 2s'), not {shown}{hint}")
            return None
        if len(item) > 1:
            kinds = " and ".join(f"'{key}'" for key in item)
            self.add(item.mark, f"one step per '-': this one has {kinds}"
                     " (options of a step go into a mapping, e.g. press: {key: MCP.jog, for: 300ms})")
            return None
        kind = next(iter(item))
        value = item[kind]
        value_mark = item.mark_of(kind)
        if kind not in STEP_KINDS:
            hint = _suggest(kind, STEP_KINDS) or f" (steps: {', '.join(STEP_KINDS)})"
            self.add(item.mark_of_key(kind), f"unknown step '{kind}'{hint}")
            return None
        handler: Callable[[int, Mark, Any, Mark], Step | None] = getattr(self, f"step_{kind}")
        return handler(index, item.mark, value, value_mark)

    def step_press(self, index: int, mark: Mark, value: Any, value_mark: Mark) -> Step | None:
        return self.press(index, mark, value, value_mark, "press", "key")

    def step_pulse(self, index: int, mark: Mark, value: Any, value_mark: Mark) -> Step | None:
        return self.press(index, mark, value, value_mark, "pulse", "signal")

    def press(self, index: int, mark: Mark, value: Any, value_mark: Mark, kind: str,
              name_key: str) -> Step | None:
        duration = DEFAULT_PRESS
        names_value, names_mark = value, value_mark
        if isinstance(value, LocatedMap):
            if not self.check_keys(value, (name_key, "for"), (name_key,), kind):
                return None
            names_value, names_mark = value[name_key], value.mark_of(name_key)
            if "for" in value:
                parsed = self.duration(value["for"], value.mark_of("for"), positive=True)
                if parsed is None:
                    return None
                duration = parsed
        keys = self.writable_keys(names_value, names_mark, kind)
        return Press(index, kind, mark, keys, duration) if keys is not None else None

    def step_hold(self, index: int, mark: Mark, value: Any, value_mark: Mark) -> Step | None:
        keys = self.writable_keys(value, value_mark, "hold")
        return Hold(index, "hold", mark, keys) if keys is not None else None

    def step_release(self, index: int, mark: Mark, value: Any, value_mark: Mark) -> Step | None:
        names = self.name_list(value, value_mark, "release")
        if names is None:
            return None
        result: list[Quantity] = []
        for name, name_mark in names:
            quantity = self.resolve(name, name_mark)
            if quantity is None:
                continue
            if quantity.name in self.forced:
                self.forced.discard(quantity.name)
            elif self.key_refusal(quantity, "release"):
                self.add(name_mark, f"cannot release {quantity.label}: no step before this one forces it"
                         " (release ends a force, or lets go of a key)")
                continue
            result.append(quantity)
        return Release(index, "release", mark, tuple(result)) if len(result) == len(names) else None

    def step_set(self, index: int, mark: Mark, value: Any, value_mark: Mark) -> Step | None:
        return self.set_values(index, mark, value, value_mark, forced=False)

    def step_force(self, index: int, mark: Mark, value: Any, value_mark: Mark) -> Step | None:
        return self.set_values(index, mark, value, value_mark, forced=True)

    def set_values(self, index: int, mark: Mark, value: Any, value_mark: Mark, forced: bool) -> Step | None:
        kind = "force" if forced else "set"
        if not isinstance(value, LocatedMap) or not value:
            self.add(value_mark, f"{kind} takes a mapping of names and values,"
                     f" e.g. {kind}: {{MCP.feedOverride: 50}}")
            return None
        values: list[tuple[Quantity, Value]] = []
        for name, item, item_mark in value.located_items():
            name_mark = value.mark_of_key(name)
            quantity = self.resolve(name, name_mark)
            if quantity is None:
                continue
            if not forced and not self.check_writable(quantity, name_mark, kind):
                continue
            if forced and not self.check_signal(quantity, name_mark, kind):
                continue
            checked = self.signal_value(quantity, item, item_mark)
            if checked is not None:
                values.append((quantity, checked))
                if forced:
                    self.forced.add(quantity.name)
        if len(values) != len(value):
            return None
        return SetValues(index, kind, mark, tuple(values), forced)

    def step_mda(self, index: int, mark: Mark, value: Any, value_mark: Mark) -> Step | None:
        channel = self.first_channel()
        text = value
        text_mark = value_mark
        if isinstance(value, LocatedMap):
            if not self.check_keys(value, ("channel", "text"), ("text",), "mda"):
                return None
            channel = self.channel(value, channel)
            text, text_mark = value["text"], value.mark_of("text")
        if not isinstance(text, str) or not text.strip():
            self.add(text_mark, f"mda takes the block(s) to run as a text, not {_kind_of_value(text)}")
            return None
        return LoadMda(index, "mda", mark, channel, text) if channel is not None else None

    def step_program(self, index: int, mark: Mark, value: Any, value_mark: Mark) -> Step | None:
        if not isinstance(value, LocatedMap):
            self.add(value_mark, "program takes a mapping: {name: PART1, text: ...}"
                     " or {name: PART1, file: ...}")
            return None
        if not self.check_keys(value, ("name", "text", "file", "channel"), ("name",), "program"):
            return None
        name = self.text(value, "name")
        channel = self.channel(value, self.first_channel())
        if ("text" in value) == ("file" in value):
            self.add(value.mark, "program needs either 'text' (the program itself) or 'file' (where it is)")
            return None
        if "text" in value:
            text = self.text(value, "text")
        else:
            file = self.text(value, "file")
            if not file:
                return None
            location = os.path.normpath(os.path.join(self.directory, file))
            self.sources.append(location)
            read, problems = read_source(location, f"program file '{file}'")
            if read is None:  # reported at the scenario's line, with where in the program file
                where = problems[0].mark
                inside = f" at line {where.line}, column {where.column}" if (where.line, where.column) != (1, 1) else ""
                self.add(value.mark_of("file"), f"{problems[0].message}{inside}{_looked_for(file, location)}")
                return None
            text = read
        if not name or not text or channel is None:
            return None
        return SelectProgram(index, "program", mark, channel, name, text)

    def step_power_cycle(self, index: int, mark: Mark, value: Any, value_mark: Mark) -> Step | None:
        off = DEFAULT_POWER_OFF
        if isinstance(value, LocatedMap):
            if not self.check_keys(value, ("off",), ("off",), "power_cycle"):
                return None
            value, value_mark = value["off"], value.mark_of("off")
        if value is not None:
            parsed = self.duration(value, value_mark, positive=True)
            if parsed is None:
                return None
            off = parsed
        return PowerCycle(index, "power_cycle", mark, off)

    def step_fault(self, index: int, mark: Mark, value: Any, value_mark: Mark) -> Step | None:
        if not isinstance(value, LocatedMap):
            self.add(value_mark, f"fault takes a mapping, e.g. {STEP_EXAMPLES['fault']}")
            return None
        kind = value.get("kind")
        machine_fault = kind in MACHINE_FAULTS
        if not self.check_keys(value, ("kind",) if machine_fault else ("axis", "kind", "from", "to", "by", "encoder"),
                               ("kind",) if machine_fault else ("axis", "kind"), "fault"):
            return None
        if machine_fault and self.machine is not None and self.machine.dc_link is None:
            self.add(value.mark_of("kind"), f"a {kind} fault needs the machine's DC link: this machine has no"
                                            " dc_link: section (only Drives.ready would fall)")
            return None
        if machine_fault:
            return InjectFault(index, "fault", mark, "", str(kind), 0.0, 0.0, 0.0, 1)
        axis = self.machine_axis(value["axis"], value.mark_of("axis"))
        if kind not in FAULTS:
            hint = _suggest(str(kind), FAULTS) or f" (faults: {', '.join(FAULTS)})"
            self.add(value.mark_of("kind"), f"unknown fault '{kind}'{hint}")
            return None
        needed = {"reference_marks_missing": ("from", "to"), "encoder_slip": ("by",), "load_disturbance": ("by",),
                  "workpiece_clamp": ("by",)}.get(kind, ())
        numbers: dict[str, float] = {}
        for key in ("from", "to", "by", "encoder"):
            if key in value:
                if key not in (*needed, "encoder"):
                    self.add(value.mark_of_key(key), f"a {kind} fault takes no '{key}'")
                    return None
                number = self.number(value[key], value.mark_of(key), key)
                if number is None:
                    return None
                numbers[key] = float(number)
        missing = [key for key in needed if key not in numbers]
        if missing:
            self.add(value.mark, f"a {kind} fault needs {' and '.join(missing)}")
            return None
        if kind == "reference_marks_missing" and numbers["from"] == numbers["to"]:
            self.add(value.mark_of("to"), "from and to are the same position: no reference mark would be missing")
            return None
        encoder = int(numbers.get("encoder", 1))
        if encoder not in (1, 2):
            self.add(value.mark_of("encoder"), "encoder is the measuring system 1 or 2")
            return None
        if axis is None:
            return None
        return InjectFault(index, "fault", mark, axis, str(kind), numbers.get("from", 0.0), numbers.get("to", 0.0),
                           numbers.get("by", 0.0), encoder)

    def step_clear_faults(self, index: int, mark: Mark, value: Any, value_mark: Mark) -> Step | None:
        if value == MAINS:
            return ClearFaults(index, "clear_faults", mark, MAINS)
        axis = self.machine_axis(value, value_mark)
        return ClearFaults(index, "clear_faults", mark, axis) if axis is not None else None

    def step_acknowledge(self, index: int, mark: Mark, value: Any, value_mark: Mark) -> Step | None:
        if value != "alarms":
            self.add(value_mark, f"acknowledge takes 'alarms' (the alarm cancel key): {STEP_EXAMPLES['acknowledge']}")
            return None
        return AcknowledgeAlarms(index, "acknowledge", mark)

    def step_move_by_hand(self, index: int, mark: Mark, value: Any, value_mark: Mark) -> Step | None:
        if not isinstance(value, LocatedMap):
            self.add(value_mark, f"move_by_hand takes a mapping, e.g. {STEP_EXAMPLES['move_by_hand']}")
            return None
        if not self.check_keys(value, ("axis", "velocity"), ("axis", "velocity"), "move_by_hand"):
            return None
        axis = self.machine_axis(value["axis"], value.mark_of("axis"))
        velocity = self.number(value["velocity"], value.mark_of("velocity"), "velocity (mm/min or rev/min)")
        if velocity is None:
            return None
        return MoveByHand(index, "move_by_hand", mark, axis, float(velocity)) if axis is not None else None

    def step_turn(self, index: int, mark: Mark, value: Any, value_mark: Mark) -> Step | None:
        """``turn: {handwheel1: 20, handwheel2: -5, for: 200ms}``: detents per handwheel, turned together."""
        if not isinstance(value, LocatedMap):
            self.add(value_mark, f"turn takes a mapping, e.g. {STEP_EXAMPLES['turn']}")
            return None
        wheels = tuple(f"handwheel{number}" for number in range(1, HANDWHEELS + 1))
        if not self.check_keys(value, (*wheels, "for"), (), "turn"):
            return None
        detents = []
        for number, key in enumerate(wheels, start=1):
            if key not in value:
                continue
            count = value[key]
            if isinstance(count, bool) or not isinstance(count, int) or not abs(count) <= MAX_MAGNITUDE:
                self.add(value.mark_of(key), f"{key} takes a whole number of detents, not {_kind_of_value(count)}")
                return None
            detents.append((number, count))
        if not detents:
            self.add(value_mark, f"turn names no handwheel, e.g. {STEP_EXAMPLES['turn']}")
            return None
        duration = DEFAULT_PRESS
        if "for" in value:
            parsed = self.duration(value["for"], value.mark_of("for"), positive=True)
            if parsed is None:
                return None
            duration = parsed
        return TurnHandwheels(index, "turn", mark, tuple(detents), duration)

    def step_link_fault(self, index: int, mark: Mark, value: Any, value_mark: Mark) -> Step | None:
        if not isinstance(value, LocatedMap):
            self.add(value_mark, f"link_fault takes a mapping, e.g. {STEP_EXAMPLES['link_fault']}")
            return None
        if self.link != LINK_CAN:
            self.add(mark, f"a link fault acts on the CAN bus: the scenario needs 'link: {LINK_CAN}' and a PLC"
                     " program behind it")
        if not self.check_keys(value, LINK_FAULT_KEYS, ("kind", "for"), "link_fault"):
            return None
        kind = value["kind"]
        if kind not in LINK_FAULTS:
            hint = _suggest(str(kind), LINK_FAULTS) or f" (link faults: {', '.join(LINK_FAULTS)})"
            self.add(value.mark_of("kind"), f"unknown link fault '{kind}'{hint}")
            return None
        takes = {"loss": ("direction", "frames", "every"), "delay": ("direction", "frames", "by"),
                 "bus_off": ()}[kind]
        for key in value:
            if key in LINK_FAULT_KEYS[2:] and key not in takes:
                self.add(value.mark_of_key(key), f"a {kind} link fault takes no '{key}'"
                         + (" (bus-off stops every frame both ways)" if kind == "bus_off" else ""))
        if kind == "delay" and "by" not in value:
            self.add(value.mark, "a delay link fault needs 'by' (how much later the frames arrive, e.g. 50ms)")
        duration = self.duration(value["for"], value.mark_of("for"), positive=True)
        delay = self.duration(value["by"], value.mark_of("by"), positive=True) if "by" in value else Duration(0)
        directions: tuple[str, ...] = LINK_DIRECTIONS
        if "direction" in value:
            direction = value["direction"]
            if direction in LINK_DIRECTIONS:
                directions = (str(direction),)
            elif direction != "both":
                hint = _suggest(str(direction), [*LINK_DIRECTIONS, "both"])
                self.add(value.mark_of("direction"), f"direction is {', '.join(LINK_DIRECTIONS)} or both, not"
                         f" {_kind_of_value(direction)}{hint}")
        every = value.get("every", 1)
        if isinstance(every, bool) or not isinstance(every, int) or every < 1:
            self.add(value.mark_of("every"), f"every is a whole number from 1 (1 = every frame), not"
                     f" {_kind_of_value(every)}")
            every = 1
        areas = self.link_frames(value["frames"], value.mark_of("frames")) if "frames" in value else ()
        if duration is None or delay is None or areas is None:
            return None
        return InjectLinkFault(index, "link_fault", mark, str(kind), duration, directions, areas, delay, every)

    def link_frames(self, value: Any, mark: Mark) -> tuple[str, ...] | None:
        """The areas whose frames a link fault hits: instance names (X1, CHAN1, NC, MODEGROUP, HMI), data
        blocks (DB31), the plant areas I and Q, or link (the link frames)."""
        if self.machine is None:
            return None
        names = self.name_list(value, mark, "frames")
        if names is None:
            return None
        layout = self.machine.layout
        instances = {"NC": "DB10", "MODEGROUP": "DB11", "HMI": "DB19",
                     **{name: f"DB{layout.channel_db(name)}" for name in layout.channels},
                     **{name: f"DB{layout.axis_db(name)}" for name in layout.axes}}
        known = {*instances.values(), "I", "Q", LINK_AREA}
        areas = []
        for name, name_mark in names:
            area = instances.get(name, name)
            if area not in known:
                choices = [*instances, *sorted(known)]
                hint = _suggest(name, choices) or f" (e.g. {', '.join(choices[:4])}, I, Q, {LINK_AREA})"
                self.add(name_mark, f"'{name}' names no frames of this machine{hint}")
                return None
            areas.append(area)
        return tuple(dict.fromkeys(areas))

    def machine_axis(self, value: Any, mark: Mark) -> str | None:
        """A machine axis of the scenario's machine, or None (reported)."""
        if self.machine is None:
            return None
        names = [axis.name for axis in self.machine.axes]
        if not isinstance(value, str) or value not in names:
            hint = _suggest(str(value), names) or f" (axes: {', '.join(names)})"
            self.add(mark, f"'{value}' is not a machine axis of this machine{hint}")
            return None
        return value

    def step_wait(self, index: int, mark: Mark, value: Any, value_mark: Mark) -> Step | None:
        if not isinstance(value, LocatedMap):
            duration = self.duration(value, value_mark)
            return Wait(index, "wait", mark, duration) if duration is not None else None
        if not self.check_keys(value, ("until", "timeout"), ("until",), "wait"):
            return None
        condition = self.expression(value["until"], value.mark_of("until"))
        timeout = None
        if "timeout" in value:
            timeout = self.duration(value["timeout"], value.mark_of("timeout"), positive=True)
            if timeout is None:
                return None
        return WaitUntil(index, "wait", mark, condition, timeout) if condition is not None else None

    def step_expect(self, index: int, mark: Mark, value: Any, value_mark: Mark) -> Step | None:
        if isinstance(value, str):
            condition = self.expression(value, value_mark)
            return ExpectCondition(index, "expect", mark, condition) if condition is not None else None
        if not isinstance(value, LocatedMap) or not value:
            self.add(value_mark, "expect takes a condition in quotes or a mapping of names and expected"
                     ' values, e.g. expect: {X1.position: "100 +- 0.001"}')
            return None
        checks: list[tuple[Quantity, ExpectedValue]] = []
        for name, item, item_mark in value.located_items():
            quantity = self.resolve(name, value.mark_of_key(name))
            try:
                expected = parse_expected(item)
            except ExpectedValueError as error:
                self.add(item_mark, str(error))
                continue
            if quantity is None:
                continue
            if self.expected_in_range(quantity, expected, item_mark):
                checks.append((quantity, expected))
        if len(checks) != len(value):
            return None
        return ExpectValues(index, "expect", mark, tuple(checks))

    def step_expect_alarm(self, index: int, mark: Mark, value: Any, value_mark: Mark) -> Step | None:
        return self.alarm_step(index, mark, value, value_mark, present=True)

    def step_expect_no_alarm(self, index: int, mark: Mark, value: Any, value_mark: Mark) -> Step | None:
        return self.alarm_step(index, mark, value, value_mark, present=False)

    def alarm_step(self, index: int, mark: Mark, value: Any, value_mark: Mark, present: bool) -> Step | None:
        kind = "expect_alarm" if present else "expect_no_alarm"
        place, text = "", ""
        number_value, number_mark = value, value_mark
        if isinstance(value, LocatedMap):
            if not self.check_keys(value, ("number", "axis", "channel", "text"), ("number",), kind):
                return None
            if "axis" in value and "channel" in value:
                self.add(value.mark, f"{kind} takes 'axis' or 'channel', not both")
                return None
            for key in ("axis", "channel"):
                if key in value:
                    place = self.place(value[key], value.mark_of(key), key) or ""
                    if not place:
                        return None
            number_value, number_mark = value["number"], value.mark_of("number")
            text = value.get("text", "")
            if not isinstance(text, str):
                self.add(value.mark_of("text"), f"{kind}: text takes a part of the alarm text, e.g. 'block N20'")
                return None
        if not present and number_value == "all" and not place:
            return ExpectAlarm(index, kind, mark, 0, "", present)
        if isinstance(number_value, bool) or not isinstance(number_value, int):
            also = " or all" if not present else ""
            hint = " (all is for expect_no_alarm)" if number_value == "all" else ""
            self.add(number_mark,
                     f"{kind} takes an alarm number{also}, not {_kind_of_value(number_value)}{hint}")
            return None
        if number_value not in ALARM_TEXTS:
            known = ", ".join(str(number) for number in sorted(ALARM_TEXTS))
            self.add(number_mark, f"alarm {number_value} is not an alarm of the simulated control"
                     f" (known: {known})")
            return None
        return ExpectAlarm(index, kind, mark, number_value, place, present, text)

    def step_expect_order(self, index: int, mark: Mark, value: Any, value_mark: Mark) -> Step | None:
        if not isinstance(value, LocatedList) or len(value) < 2:
            self.add(value_mark, "expect_order takes a list of two or more events, e.g."
                     " [X1.basic.out.refPointApproachCam rises, X1.basic.in.enc1Synchronized rises]")
            return None
        events = [self.event(item, item_mark) for _, item, item_mark in value.located_items()]
        checked = [event for event in events if event is not None]
        if len(checked) != len(events):
            return None
        return ExpectOrder(index, "expect_order", mark, tuple(checked))

    def step_expect_timing(self, index: int, mark: Mark, value: Any, value_mark: Mark) -> Step | None:
        if not isinstance(value, LocatedMap):
            self.add(value_mark, "expect_timing takes a mapping"
                     " {from: EVENT, to: EVENT, min: TIME, max: TIME}")
            return None
        if not self.check_keys(value, ("from", "to", "min", "max"), ("from", "to"), "expect_timing"):
            return None
        start = self.event(value["from"], value.mark_of("from"))
        end = self.event(value["to"], value.mark_of("to"))
        minimum = self.duration(value["min"], value.mark_of("min")) if "min" in value else None
        maximum = self.duration(value["max"], value.mark_of("max")) if "max" in value else None
        if "min" not in value and "max" not in value:
            self.add(value.mark, "expect_timing needs 'min', 'max' or both")
            return None
        if minimum is not None and maximum is not None and minimum > maximum:
            self.add(value.mark_of("max"), f"max ({maximum}) is shorter than min ({minimum})")
            return None
        if minimum is not None and minimum.microseconds == 0 and "max" not in value:
            self.add(value.mark_of("min"), "min: 0 s alone holds for every interval, so the check cannot fail"
                     " (give a max, or a min above 0)")
            return None
        if start is None or end is None or (("min" in value) != (minimum is not None)) \
                or (("max" in value) != (maximum is not None)):
            return None
        return ExpectTiming(index, "expect_timing", mark, start, end, minimum, maximum)

    def check_timing_bounds(self, steps: Sequence[Step]) -> None:
        """An ``expect_timing`` max as long as the run can be cannot fail: no interval of the run is
        longer than its timeout plus the time the machine is switched off in power cycles."""
        longest = self.timeout.microseconds + sum(step.off.microseconds for step in steps
                                                  if isinstance(step, PowerCycle))
        for step in steps:
            if isinstance(step, ExpectTiming) and step.maximum is not None and step.maximum.microseconds >= longest:
                self.add(step.mark, f"expect_timing: max ({step.maximum}) is as long as the whole run can be"
                         f" ({format_seconds(longest / 1e6)}: the timeout and the power cycles), so the check"
                         " cannot fail")

    # -- pieces ----------------------------------------------------------------------------

    def resolve(self, name: object, mark: Mark) -> Quantity | None:
        if not isinstance(name, str) or not name.strip():
            self.add(mark, f"expected a signal name, not {_kind_of_value(name)}")
            return None
        if self.resolver is None:
            return None
        try:
            return self.resolver.resolve(name)
        except UnknownSignalError as error:
            self.add(mark, error.message)
            return None

    def name_list(self, value: Any, mark: Mark, kind: str) -> list[tuple[str, Mark]] | None:
        if isinstance(value, str):
            return [(value, mark)]
        if isinstance(value, LocatedList) and value and all(isinstance(item, str) for item in value):
            return [(item, item_mark) for _, item, item_mark in value.located_items()]
        self.add(mark, f"{kind} takes a name or a list of names, not {_kind_of_value(value)}")
        return None

    def writable_keys(self, value: Any, mark: Mark, kind: str) -> tuple[Quantity, ...] | None:
        names = self.name_list(value, mark, kind)
        if names is None:
            return None
        keys = []
        for name, name_mark in names:
            quantity = self.resolve(name, name_mark)
            if quantity is not None and self.check_key(quantity, name_mark, kind):
                keys.append(quantity)
        return tuple(keys) if len(keys) == len(names) else None

    def check_key(self, quantity: Quantity, mark: Mark, kind: str) -> bool:
        """A key for press/hold/release/pulse: a bool the scenario may write."""
        refusal = self.key_refusal(quantity, kind)
        if refusal:
            self.add(mark, refusal)
        return not refusal

    def check_writable(self, quantity: Quantity, mark: Mark, kind: str) -> bool:
        """Whether the scenario may write ``quantity`` once (as its owner would)."""
        refusal = self.write_refusal(quantity, kind)
        if refusal:
            self.add(mark, refusal)
        return not refusal

    def check_signal(self, quantity: Quantity, mark: Mark, kind: str) -> bool:
        refusal = self.signal_refusal(quantity, kind)
        if refusal:
            self.add(mark, refusal)
        return not refusal

    def signal_refusal(self, quantity: Quantity, kind: str) -> str:
        if quantity.kind is QuantityKind.SIGNAL:
            return ""
        what = {QuantityKind.AXIS: "the simulated axis", QuantityKind.MACHINE_DATUM: "the control's machine data",
                QuantityKind.LINK: "the CAN link"}.get(quantity.kind, "the simulation")
        return f"cannot {kind} {quantity.label}: it is a quantity of {what}, not a signal"

    def write_refusal(self, quantity: Quantity, kind: str) -> str:
        refusal = self.signal_refusal(quantity, kind)
        if refusal:
            return refusal
        assert quantity.ref is not None
        direction = quantity.ref.direction
        owner = ""
        if direction is Direction.NC_TO_PLC and not _operator_panel_key(quantity):
            owner = "it is written by the NC"
        elif direction in (Direction.PLC_TO_NC, Direction.PLC_TO_PLANT) and self.plc != NO_PLC:
            owner = f"it is written by the PLC program {self.plc}"
        elif direction is Direction.PLANT_TO_PLC and not self.is_operator_input(quantity):
            owner = "it is driven by the simulated machine"
        return f"cannot {kind} {quantity.label}: {owner}; use force to override it" if owner else ""

    def key_refusal(self, quantity: Quantity, kind: str) -> str:
        refusal = self.write_refusal(quantity, kind)
        if refusal:
            return refusal
        assert quantity.ref is not None
        if quantity.ref.type is not SignalType.BOOL:
            return (f"{kind} works on keys and bool signals; {quantity.label} is a"
                    f" {quantity.ref.type.value} (use set)")
        return ""

    def is_operator_input(self, quantity: Quantity) -> bool:
        """Plant inputs an operator works: the panel keys and switches, the emergency-stop button."""
        assert quantity.ref is not None
        if self.machine is None:
            return False
        address = quantity.ref.address
        for point in self.machine.plant_io.points:
            inside = point.address.area == address.area and \
                point.address.byte <= address.byte < point.address.byte + point.address.size
            if point.address == address or (address.is_bit and not point.address.is_bit and inside):
                return point.owner is Owner.OPERATOR
        return False

    def signal_value(self, quantity: Quantity, value: Any, mark: Mark) -> Value | None:
        assert quantity.ref is not None
        ref = quantity.ref
        if isinstance(value, bool):
            value = int(value)
        if not isinstance(value, (int, float)):
            self.add(mark, f"the value for {quantity.label} must be a number (or true/false),"
                     f" not {_kind_of_value(value)}")
            return None
        if ref.type is SignalType.REAL:
            if not abs(value) <= MAX_MAGNITUDE:
                self.add(mark, f"{quantity.label} is a real; {value:g} is beyond {MAX_MAGNITUDE:g}, the largest"
                         " number a scenario may write")
                return None
            return float(value)
        if isinstance(value, float):
            if not value.is_integer():
                self.add(mark, f"{quantity.label} is a {ref.type.value}; {value} is not a whole number")
                return None
            value = int(value)
        low, high = value_range(ref.type, ref.bits)
        number = int(value)
        if not low <= number <= high:
            self.add(mark, f"{quantity.label} is a {ref.type.value};"
                     f" {number} is outside {int(low)}..{int(high)}")
            return None
        return number

    def expected_in_range(self, quantity: Quantity, expected: ExpectedValue, mark: Mark) -> bool:
        """Whether ``expected`` can both pass and fail for the values ``quantity`` can take."""
        low, high, whole, kind = _value_range(quantity)
        judgement = expected.judgement(low, high, whole)
        if not judgement:
            return True
        span = f"{int(low)}..{int(high)}" if whole else f"{low:g}..{high:g}"
        if judgement == "never" and expected.exact is not None:
            self.add(mark, f"{quantity.label} is a {kind} ({span}); it can never be {expected.exact}")
        elif judgement == "never":
            self.add(mark, f"{quantity.label} is a {kind} ({span}); it is never {_relation(expected)}")
        else:
            self.add(mark, f"{quantity.label} is a {kind} ({span}); it is always {_relation(expected)},"
                     " so the check cannot fail")
        return False

    def number(self, value: Any, mark: Mark, what: str) -> float | None:
        """A number the scenario hands to the simulation: finite and at most MAX_MAGNITUDE."""
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            self.add(mark, f"{what} must be a number, not {_kind_of_value(value)}")
            return None
        if not abs(value) <= MAX_MAGNITUDE:
            self.add(mark, f"{what}: {value:g} is beyond {MAX_MAGNITUDE:g}, the largest number a scenario may write")
            return None
        return float(value)

    def duration(self, value: Any, mark: Mark, positive: bool = False) -> Duration | None:
        try:
            duration = parse_duration(value)
        except DurationError as error:
            self.add(mark, str(error))
            return None
        if positive and duration.microseconds == 0:
            self.add(mark, "the time must be longer than 0 s")
            return None
        return duration

    def expression(self, value: Any, mark: Mark, offset: int = 0, shown: str = "") -> Expression | None:
        if not isinstance(value, str):
            self.add(mark, f"a condition is a text in quotes (e.g. \"X1.position > 5\"),"
                     f" not {_kind_of_value(value)}")
            return None
        try:
            expression = parse_expression(value, self.resolver)
        except ExpressionError as error:
            where = f" at column {error.column + offset}" if error.column is not None else ""
            self.add(mark, f'in "{_brief(shown or value)}": {error.message}{where}')
            return None
        if not any(isinstance(node, Name | AlarmCall) for node in walk(expression.root)):
            self.add(mark, f'"{_brief(shown or value)}" reads no signal, quantity, time or alarm: it never changes,'
                     " so as a check it always holds or never does")
            return None
        return expression

    def event(self, value: Any, mark: Mark) -> Event | None:
        usage = "write 'NAME rises', 'NAME falls', 'NAME changes' or 'when CONDITION'"
        if not isinstance(value, str):
            self.add(mark, f"an event is a text ({usage}), not {_kind_of_value(value)}")
            return None
        text = value.strip()
        head, _, rest = text.partition(" ")
        if head.lower() == "when":
            condition_text = rest.lstrip()
            offset = len(value.rstrip()) - len(condition_text)
            condition = self.expression(condition_text, mark, offset=offset, shown=value)
            return Event(text, EdgeKind.WHEN, condition=condition) if condition is not None else None
        name, _, edge = text.rpartition(" ")
        kinds = {kind.value: kind for kind in EdgeKind if kind is not EdgeKind.WHEN}
        if edge.lower() not in kinds or not name.strip():
            self.add(mark, f"'{text}' is not an event ({usage})")
            return None
        quantity = self.resolve(name.strip(), mark)
        if quantity is None:
            return None
        return Event(text, kinds[edge.lower()], quantity=quantity)

    def first_channel(self) -> str | None:
        if self.machine is None:
            return None
        return self.machine.channels[0].name if self.machine.channels else None

    def channel(self, mapping: LocatedMap, default: str | None) -> str | None:
        if "channel" not in mapping:
            return default
        return self.place(mapping["channel"], mapping.mark_of("channel"), "channel")

    def place(self, value: Any, mark: Mark, key: str) -> str | None:
        if not isinstance(value, str):
            self.add(mark, f"{key} must be a name, not {_kind_of_value(value)}")
            return None
        if self.machine is None:
            return None
        names = [axis.name for axis in self.machine.axes] if key == "axis" else \
            [channel.name for channel in self.machine.channels]
        if value not in names:
            plural = "axes" if key == "axis" else "channels"
            self.add(mark, f"this machine has no {key} '{value}'{_suggest(value, names)}"
                     f" ({plural}: {', '.join(names)})")
            return None
        return value


def _value_range(quantity: Quantity) -> tuple[float, float, bool, str]:
    """The values ``quantity`` can take: lowest, highest, whether only whole numbers, what it is."""
    if quantity.ref is not None:
        low, high = value_range(quantity.ref.type, quantity.ref.bits)
        return low, high, quantity.ref.type is not SignalType.REAL, quantity.ref.type.value
    if quantity.kind is QuantityKind.MACHINE_DATUM:
        md = BY_NUMBER[int(quantity.quantity)]
        if md.type is MdType.BOOL:
            return 0, 1, True, "machine datum of true/false"
        if md.type in (MdType.INT, MdType.FLOAT) and md.minimum is not None and md.maximum is not None:
            whole = md.type is MdType.INT
            return md.minimum, md.maximum, whole, f"machine datum of {'whole ' if whole else ''}numbers"
    return -MAX_MAGNITUDE, MAX_MAGNITUDE, False, "number"


def _relation(expected: ExpectedValue) -> str:
    shown = str(expected)
    return shown if shown[0] in "<>!=" else f"= {shown}"


def _operator_panel_key(quantity: Quantity) -> bool:
    """A request of the operator panel to the PLC (DB19 OP -> PLC, e.g. the MCS/WCS softkey
    HMI.basic.in.mcsWcsSwitched): the operator works it, as the panel's keys."""
    signal = quantity.ref.signal if quantity.ref is not None else None
    return signal is not None and signal.instance == HMI_INSTANCE
