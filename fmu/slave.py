"""The lean FMU's slave: the instance of ``fmu/instance.py`` behind pythonfmu's FMI 2.0 facade.

``vc fmu export --python host`` builds the FMU from this file: pythonfmu's binary imports it in
the host's Python and instantiates :class:`VcNcSlave` with the FMU's ``resources`` folder, which
holds the machine file, the manifest (``vc_fmu.json``) and this project's code under a name of
its own (see ``fmu/export.py``).  This is the one module that imports pythonfmu.

Variable attributes, as ``fmpy validate`` wants them: Booleans and Integers are ``discrete``;
every output is ``initial="exact"`` with its power-on value as start value (pythonfmu writes
no InitialUnknowns); parameters are ``fixed``.  The value reference of a variable is its index
in the unit's list.

Errors (see ``fmu/instance.py``): pythonfmu turns an exception into ``fmi2Fatal``, so only what
ends the instance is raised; a refused step is answered ``fmi2Discard``.  pythonfmu passes
messages to the host's logger only while the host has logging on (``loggingOn`` /
``fmi2SetDebugLogging``); every error also goes to the process's standard error.
"""

from __future__ import annotations

from collections.abc import Sequence
from functools import partial
from pathlib import Path
from typing import Any

from pythonfmu import Boolean, Fmi2Causality, Fmi2Initial, Fmi2Slave, Fmi2Variability, Integer, Real
from pythonfmu.default_experiment import DefaultExperiment
from pythonfmu.enums import Fmi2Status

from fmu.instance import FmuError, NcInstance, Status
from fmu.unit import Causality, Kind, Variability, Variable

DEFAULT_STOP_TIME_S = 10.0
_VARIABLE_CLASSES = {Kind.BOOLEAN: Boolean, Kind.INTEGER: Integer, Kind.REAL: Real}
_CAUSALITIES = {Causality.INPUT: Fmi2Causality.input, Causality.OUTPUT: Fmi2Causality.output,
                Causality.PARAMETER: Fmi2Causality.parameter}
_VARIABILITIES = {Variability.DISCRETE: Fmi2Variability.discrete, Variability.CONTINUOUS: Fmi2Variability.continuous,
                  Variability.FIXED: Fmi2Variability.fixed}


class VcNcSlave(Fmi2Slave):
    author = "VC harness"

    def __init__(self, **kwargs: Any):
        super().__init__(**kwargs)
        try:
            self.instance = NcInstance(Path(self.resources), self.instance_name, self._log_status)
        except FmuError as error:
            raise FmuError(_format_safe(str(error))) from None
        self.unit = self.instance.unit
        manifest = self.instance.manifest
        self.modelName = manifest["model"]
        self.description = (f"{manifest['name']}: SINUMERIK-style NC and machine plant; the PLC connects"
                            " through the NC/PLC interface signals")
        self.default_experiment = DefaultExperiment(0.0, DEFAULT_STOP_TIME_S, self.unit.plc_cycle_s)
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
        self.instance.setup(start_time)

    def exit_initialization_mode(self) -> None:
        try:
            self.instance.exit_initialization()
        except FmuError as error:
            raise FmuError(_format_safe(str(error))) from None

    def do_step(self, current_time: float, step_size: float) -> bool:
        return self.instance.step(current_time, step_size) is Status.OK

    def _log_status(self, status: Status, message: str) -> None:
        self.log(_format_safe(message), Fmi2Status(int(status)))

    # ------------------------------------------------------------------ values, in batches
    def _values(self, kind: Kind, references: Sequence[int]) -> list[Any]:
        try:
            return self.instance.values(kind, references)
        except FmuError as error:
            raise FmuError(_format_safe(str(error))) from None

    def get_boolean(self, vrs: list[int]) -> list[bool]:
        return self._values(Kind.BOOLEAN, vrs)

    def get_integer(self, vrs: list[int]) -> list[int]:
        return self._values(Kind.INTEGER, vrs)

    def get_real(self, vrs: list[int]) -> list[float]:
        return self._values(Kind.REAL, vrs)

    def set_boolean(self, vrs: list[int], values: list[bool]) -> None:
        self.instance.take(Kind.BOOLEAN, vrs, values)

    def set_integer(self, vrs: list[int], values: list[int]) -> None:
        self.instance.take(Kind.INTEGER, vrs, values)

    def set_real(self, vrs: list[int], values: list[float]) -> None:
        self.instance.take(Kind.REAL, vrs, values)


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
