"""Scenario files -> checked :class:`~vc.scenario.language.model.Scenario` objects.

Every problem of a file is collected with ``file:line:column`` and one
:class:`~vc.located_yaml.SourceError` reports them all: unknown keys and step kinds (with
"did you mean"), missing entries, unknown PLC programs, problems of the machine file
(reported at the machine file's own lines; machine data overrides at the scenario's lines),
unknown signals, bad durations, expressions, expected values, values outside a signal's
range, and writes that the signal's owner would undo.  :func:`load_scenarios` checks every
file of a run before any of them runs.

A check that cannot fail is refused like any other mistake, since it would pass falsely: an
expected value that every value of the quantity meets (``"<= 1"`` on a bool, a tolerance
covering a byte's range; :meth:`~vc.scenario.language.values.ExpectedValue.judgement`), an
``expect_timing`` whose ``max`` is as long as the run can be or whose only bound is
``min: 0``, a condition that reads nothing and so never changes.  Numbers and times stay
within :mod:`vc.input_limits`.

This module checks a file as a whole: its top keys, machine, PLC, link, timeout and invariants,
and the variants of a ``vary:`` matrix (:mod:`vc.scenario.language.variants`).  Each item of ``steps:`` is
checked by its kind's checker in the table of step kinds, :mod:`vc.scenario.language.steps.table`.
"""

from __future__ import annotations

import importlib.util
import os
from collections.abc import Callable, Collection, Iterable, Mapping, Sequence
from dataclasses import replace

from interfaces.links import in_process_links
from interfaces.plc import PlcEnvironment, PlcFactory
from interfaces.signals import Catalog, ExpandedCatalog, InterfaceLayout, expand
from vc.config.loader import load_machine
from vc.config.machine_files import looks_like_a_path, unknown_machine
from vc.config.machine_files import machine_file as packaged_machine_file
from vc.config.model import MachineConfig, machine_ipo_cycle_us
from vc.input_limits import MAX_RUN_VARIANTS
from vc.located_yaml import LocatedList, LocatedMap, Mark, Problem, Problems, SourceError, load_file
from vc.scenario.language.durations import Duration
from vc.scenario.language.model import EXTERNAL_PLCS, LINK_CAN, NO_PLC, Invariant, Scenario, Step, external_plc
from vc.scenario.language.quantities import NameResolver
from vc.scenario.language.steps.common import StepChecker, kind_of_value, looked_for, suggest
from vc.scenario.language.steps.expectations import check_timing_bounds
from vc.scenario.language.steps.table import check_step
from vc.scenario.language.variants import VariantCeiling, check_file

TOP_KEYS = ("name", "description", "machine", "plc", "link", "machine_data", "plc_parameters", "timeout",
            "invariants", "steps")
REQUIRED_TOP_KEYS = ("name", "machine", "plc", "steps")
LINKS = in_process_links()  # a scenario's link: NAME (interfaces/links/__init__.py)
DEFAULT_TIMEOUT = Duration(300_000_000)
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
                   default_plc: str | None = None, max_variants: int = MAX_RUN_VARIANTS) -> list[Scenario]:
    """Load every scenario of ``paths`` (files, or directories searched recursively for ``*.yaml``
    outside directories named ``machines``), each variant of a ``vary:`` matrix and of a campaign
    file a scenario of its own (:mod:`vc.scenario.language.variants`).  Raises one :class:`SourceError`
    for all files.  ``variant``: only the variant at that position of each file's matrix.

    ``known_programs`` names the PLC programs a scenario may run; given as the registry
    (name -> factory), each scenario's program is also started once on its machine, to check
    its parameters (the machine file's ``plc:`` section and ``plc_parameters``) before anything runs.
    ``default_plc``: the program of a scenario without ``plc:`` (``vc serve``, where the PLC is on
    the link and ``plc:`` only names what a PLC that follows the harness runs); None: ``plc:`` is
    required.  ``max_variants``: the most variants the matrices of all files may give together
    (counted before any is built)."""
    files, problems = scenario_files(paths)
    machines = _Machines(machine_loader or default_machine_loader)
    collected = Problems()
    collected.extend(problems)
    scenarios: list[Scenario] = []

    def check(path: str, document: LocatedMap, found: Problems) -> Scenario | None:
        return _ScenarioChecker(path, known_programs, catalog, machines, found, default_plc).check(document)

    def rebuild(path: str, document: LocatedMap, checked: Scenario | None, found: Problems) -> Scenario | None:
        checker = _ScenarioChecker(path, known_programs, catalog, machines, found, default_plc)
        checker.machine_of(document)
        if checker.machine is None or checked is None or found:
            return None
        if machine_shape(checker.machine) != machine_shape(checked.machine):
            return None
        return replace(checked, machine=checker.machine)

    ceiling = VariantCeiling(max_variants)
    for file in files:
        scenarios += check_file(file, _read_scenario, check, collected, only=variant, rebuild=rebuild,
                                ceiling=ceiling)
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


def _installed(package: str) -> bool:
    """Whether ``package`` can be imported here (found, not imported: it runs in the PLC's own process)."""
    try:
        return importlib.util.find_spec(package) is not None
    except (ImportError, ValueError):  # blocked, or a module in sys.modules without a spec
        return False


# ---------------------------------------------------------------------------------- machine


class _Machines:
    """Loads each machine file once per run, and once per distinct set of overrides of a scenario
    file (the variants of a matrix share them); expands the catalogue once per interface layout."""

    def __init__(self, loader: MachineLoader):
        self.loader = loader
        self._loaded: dict[tuple[str, str, object], MachineConfig | SourceError] = {}
        self._expanded: dict[tuple[int, InterfaceLayout], ExpandedCatalog] = {}
        self.plc_refusals: dict[tuple[object, ...], tuple[str, ...]] = {}  # (program, machine shape)

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


def machine_shape(machine: MachineConfig) -> tuple[object, ...]:
    """All the check of a scenario's PLC, invariants and steps reads of its machine: its layout,
    names, plant I/O, DC link, CAN settings, cycles and PLC parameters, not the values of its
    machine data.  Variants whose machines have one shape share the check of their document."""
    return (machine.name, machine.layout, tuple(axis.name for axis in machine.axes),
            tuple(channel.name for channel in machine.channels), machine.plant_io, machine.dc_link is None,
            machine.can, machine.plc_cycle_ipo, machine_ipo_cycle_us(machine), machine.plc_parameters)


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


class _ScenarioChecker(StepChecker):
    """One scenario file: its top keys, machine, PLC and link; its invariants and steps (their
    kinds are checked by :mod:`vc.scenario.language.steps`)."""

    def __init__(self, path: str, known_programs: Programs, catalog: Catalog | None,
                 machines: _Machines, problems: Problems, default_plc: str | None = None):
        super().__init__(path, problems, DEFAULT_TIMEOUT)
        self.default_plc = default_plc
        self.known_programs = known_programs
        self.catalog = catalog
        self.machines = machines

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
        check_timing_bounds(self, steps)
        if len(self.problems.items) > problems_before or self.machine is None or self.resolver is None:
            return None
        return Scenario(
            name=name, description=description, path=self.path, machine_file=machine_file,
            machine=self.machine, catalog=self.resolver.catalog, plc=self.plc, timeout=self.timeout,
            invariants=tuple(invariants), steps=tuple(steps), mark=document.mark, link=self.link,
            sources=tuple(dict.fromkeys(self.sources)),
        )

    def check_plc(self, document: LocatedMap) -> str:
        if "plc" not in document:
            return self.default_plc or NO_PLC
        value = document["plc"]
        mark = document.mark_of("plc")
        if value is False:  # YAML reads "plc: no" or "plc: off" as false
            return NO_PLC
        if not isinstance(value, str):
            self.add(mark, f"plc must name a PLC program or be none, not {kind_of_value(value)}")
            return NO_PLC
        if value == NO_PLC or value in self.known_programs:
            return value
        kind, separator, program = value.partition(":")
        if separator and kind in EXTERNAL_PLCS:
            return self.external_program(kind, program.strip(), mark)
        known = sorted(self.known_programs)
        hint = suggest(value, known)
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
        package, extra = EXTERNAL_PLCS[kind]
        if not _installed(package):
            self.add(mark, f"plc: {kind}: runs the program in {package}, which is not installed here:"
                           f" pip install 'vc-harness[{extra}]'")
            return NO_PLC
        return f"{kind}:{path}"

    def check_link(self, document: LocatedMap) -> str | None:
        if "link" not in document:
            return None
        value, mark = document["link"], document.mark_of("link")
        if value not in LINKS:
            hint = suggest(str(value), LINKS)
            self.add(mark, f"link must be {' or '.join(LINKS)} (the PLC behind that link), not"
                     f" {kind_of_value(value)}{hint}")
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
        machine_file = self.machine_of(document)
        if self.machine is None:
            return machine_file
        catalog = self.catalog if self.catalog is not None else default_catalog()
        machine = self.machine
        self.resolver = NameResolver(self.machines.expanded(catalog, machine.layout), machine.plant_io,
                                     (axis.name for axis in machine.axes),
                                     (channel.name for channel in machine.channels), link=self.link == LINK_CAN,
                                     dc_link=machine.dc_link is not None)
        self.check_plc_parameters(document)
        return machine_file

    def machine_of(self, document: LocatedMap) -> str:
        """The machine file and the machine (``self.machine``) with the overrides and PLC parameters."""
        value = document.get("machine")
        if "machine" not in document:
            return ""
        mark = document.mark_of("machine")
        if not isinstance(value, str) or not value.strip():
            self.add(mark, f"machine must be the path of a machine file or the name of a packaged machine,"
                           f" not {kind_of_value(value)}")
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
                self.add(mark, f"machine file '{value}' {what}{looked_for(value, machine_file)}")
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
        return machine_file

    def check_plc_parameters(self, document: LocatedMap) -> None:
        """Start the PLC program once on this machine: it checks its parameters when it starts,
        and a refusal then would end the run with a traceback instead of a located problem."""
        factory = self.known_programs.get(self.plc) if isinstance(self.known_programs, Mapping) else None
        if factory is None or self.machine is None or self.resolver is None:
            return
        machine = self.machine
        # what the program is given is all of the machine's shape: once per program and shape in a run
        # (the variants of a matrix and the scenarios on one machine), not once per scenario
        shape = machine_shape(machine)
        key = (self.plc, shape[:-1], _plain(shape[-1]))  # the PLC parameters (last) as a hashable copy
        refusal = self.machines.plc_refusals.get(key)
        if refusal is None:
            refusal = self.machines.plc_refusals[key] = self.plc_refusal(factory)
        if refusal:
            place = "plc_parameters" if "plc_parameters" in document else "plc"
            for line in refusal:
                self.add(document.mark_of(place), f"the PLC program {self.plc} refuses its parameters (the machine"
                         f" file's plc: section and plc_parameters): {line}")

    def plc_refusal(self, factory: PlcFactory) -> tuple[str, ...]:
        """Why the PLC program refuses to start on this machine, line by line; () when it starts."""
        machine, resolver = self.machine, self.resolver
        assert machine is not None and resolver is not None
        ipo_cycle_us = machine_ipo_cycle_us(machine)
        environment = PlcEnvironment(resolver.catalog, machine.plant_io,
                                     machine.plc_cycle_ipo * ipo_cycle_us / 1_000_000, machine.plc_parameters,
                                     machine.name, ipo_cycle_us, machine.plc_cycle_ipo)
        try:
            factory(environment)
        except Exception as error:  # the program's own check (ValueError), or a parameter it trips over
            detail = str(error) if isinstance(error, ValueError) else f"{type(error).__name__}: {error}"
            return tuple(detail.splitlines() or [type(error).__name__])
        return ()

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
            step = check_step(self, index + 1, item, mark)
            if step is not None:
                steps.append(step)
        return steps
