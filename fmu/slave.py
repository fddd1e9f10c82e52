"""The FMU's slave: the co-simulation unit of ``fmu/unit.py`` behind pythonfmu's FMI 2.0 facade.

``vc fmu export`` builds the FMU from this file: pythonfmu's binary imports it in the host's
Python and instantiates :class:`VcNcSlave` with the FMU's ``resources`` folder, which holds
the machine file, the manifest (``vc_fmu.json``) and this project's code under a name of its
own (see ``fmu/export.py``).  This is the one module that imports pythonfmu.

Variable attributes, as ``fmpy validate`` wants them: Booleans and Integers are ``discrete``;
every output is ``initial="exact"`` with its power-on value as start value (pythonfmu writes
no InitialUnknowns); parameters are ``fixed``.  The value reference of a variable is its index
in the unit's list.

Errors: pythonfmu turns an exception into ``fmi2Fatal``; so a step the unit refuses is
logged with status ``fmi2Error`` and answered ``fmi2Discard`` (the instance stays usable),
a value the unit refuses is logged and not taken, and only a machine that does not load (or
parameters that do not fit it) ends the instance with ``fmi2Fatal`` and the reason as message.
pythonfmu passes messages to the host's logger only while the host has logging on
(``loggingOn`` / ``fmi2SetDebugLogging``); so that a host with logging off still shows why,
every error is also written to the process's standard error.
"""

from __future__ import annotations

import json
import sys
from collections.abc import Sequence
from functools import partial
from pathlib import Path
from typing import Any

from pythonfmu import Boolean, Fmi2Causality, Fmi2Initial, Fmi2Slave, Fmi2Variability, Integer, Real
from pythonfmu.default_experiment import DefaultExperiment
from pythonfmu.enums import Fmi2Status

from fmu.unit import Causality, Kind, NcUnit, UnitError, Variability, Variable

MANIFEST = "vc_fmu.json"
DEFAULT_STOP_TIME_S = 10.0
_VARIABLE_CLASSES = {Kind.BOOLEAN: Boolean, Kind.INTEGER: Integer, Kind.REAL: Real}
_CAUSALITIES = {Causality.INPUT: Fmi2Causality.input, Causality.OUTPUT: Fmi2Causality.output,
                Causality.PARAMETER: Fmi2Causality.parameter}
_VARIABILITIES = {Variability.DISCRETE: Fmi2Variability.discrete, Variability.CONTINUOUS: Fmi2Variability.continuous,
                  Variability.FIXED: Fmi2Variability.fixed}


class FmuError(Exception):
    """Why the FMU cannot work; pythonfmu logs the representation, so it is the plain message."""

    def __repr__(self) -> str:
        return str(self)


class VcNcSlave(Fmi2Slave):
    author = "VC harness"

    def __init__(self, **kwargs: Any):
        super().__init__(**kwargs)
        resources = Path(self.resources)
        try:
            manifest = json.loads((resources / MANIFEST).read_text(encoding="utf-8"))
            self.unit = NcUnit(str(resources / manifest["machine"]))
        except UnitError as error:
            raise self._fatal(str(error)) from None
        except (OSError, ValueError, KeyError) as error:
            raise self._fatal(f"the FMU's resources are damaged ({error!r})") from None
        self.modelName = manifest["model"]
        self.description = (f"{manifest['name']}: SINUMERIK-style NC and machine plant; the PLC connects"
                            " through the NC/PLC interface signals")
        self.default_experiment = DefaultExperiment(0.0, DEFAULT_STOP_TIME_S, self.unit.plc_cycle_s)
        self._of_kind = {kind: frozenset(index for index, variable in enumerate(self.unit.variables)
                                         if variable.kind is kind) for kind in Kind}
        for index, variable in enumerate(self.unit.variables):
            self.register_variable(self._fmi_variable(index, variable), nested=False)

    def _fmi_variable(self, index: int, variable: Variable) -> Any:
        settable = variable.causality is not Causality.OUTPUT
        return _VARIABLE_CLASSES[variable.kind](
            variable.name,
            causality=_CAUSALITIES[variable.causality],
            variability=_VARIABILITIES[variable.variability],
            initial=None if variable.causality is Causality.INPUT else Fmi2Initial.exact,
            description=variable.description,
            getter=partial(self.unit.get, index),
            setter=partial(self.unit.set, index) if settable else None,
        )

    # ------------------------------------------------------------------ life cycle
    def setup_experiment(self, start_time: float, stop_time: float | None = None,
                         tolerance: float | None = None) -> None:
        self.unit.setup(start_time)

    def exit_initialization_mode(self) -> None:
        try:
            self.unit.initialize()
        except UnitError as error:
            raise self._fatal(str(error)) from None

    def do_step(self, current_time: float, step_size: float) -> bool:
        try:
            self.unit.step(current_time, step_size)
        except UnitError as error:
            self._error(str(error))
            return False
        return True

    # ------------------------------------------------------------------ errors
    def _error(self, message: str) -> None:
        self.log(_format_safe(message), Fmi2Status.error)
        print(f"{self.instance_name}: {message}", file=sys.stderr, flush=True)

    def _fatal(self, message: str) -> FmuError:
        """The exception that ends the instance; pythonfmu logs its message with fmi2Fatal."""
        print(f"{self.instance_name}: {message}", file=sys.stderr, flush=True)
        return FmuError(_format_safe(f"{self.instance_name}: {message}"))

    # ------------------------------------------------------------------ values, in batches
    def _values(self, kind: Kind, references: Sequence[int]) -> list[Any]:
        wrong = set(references) - self._of_kind[kind]  # one check per batch: hosts ask for hundreds at once
        if wrong:
            raise self._fatal(f"value reference {min(wrong)} is not a {kind.value} variable of this FMU")
        get = self.unit.get
        return [get(reference) for reference in references]

    def _take(self, kind: Kind, references: Sequence[int], values: Sequence[Any]) -> None:
        variables = self._of_kind[kind]
        for reference, value in zip(references, values, strict=True):
            if reference not in variables:
                self._error(f"value reference {reference} is not a {kind.value} variable of this FMU; not set")
                continue
            try:
                self.unit.set(reference, value)
            except UnitError as error:
                self._error(str(error))

    def get_boolean(self, vrs: list[int]) -> list[bool]:
        return self._values(Kind.BOOLEAN, vrs)

    def get_integer(self, vrs: list[int]) -> list[int]:
        return self._values(Kind.INTEGER, vrs)

    def get_real(self, vrs: list[int]) -> list[float]:
        return self._values(Kind.REAL, vrs)

    def set_boolean(self, vrs: list[int], values: list[bool]) -> None:
        self._take(Kind.BOOLEAN, vrs, values)

    def set_integer(self, vrs: list[int], values: list[int]) -> None:
        self._take(Kind.INTEGER, vrs, values)

    def set_real(self, vrs: list[int], values: list[float]) -> None:
        self._take(Kind.REAL, vrs, values)


def _format_safe(message: str) -> str:
    """The FMI logger takes its message as a printf format (FMI 2.0, 2.1.5) and pythonfmu passes
    ours without arguments: a ``%`` of the text (an override in %) must not start a conversion."""
    return message.replace("%", "%%")


def build_fmu(script: Path, project_files: Sequence[Path], destination: Path) -> Path:
    """Build the FMU with pythonfmu from ``script`` (this module, as exported) and its resources."""
    from pythonfmu.builder import FmuBuilder

    try:
        built: Path = FmuBuilder.build_FMU(script, dest=destination, project_files=project_files,
                                           needsExecutionTool=False)
    except (ValueError, TypeError, AssertionError, OSError) as error:
        raise FmuError(f"pythonfmu could not build the FMU: {error}") from None
    return built
