"""One FMU instance as FMI sees it, over the unit of ``fmu/unit.py``, for both FMU variants.

The self-contained FMU's worker (``fmu/worker.py``) and the lean FMU's pythonfmu slave
(``fmu/slave.py``) are front ends on this class: how a batch of values is checked, what becomes
an error that the host is told about and what ends the instance is decided here once.

* A value reference of another type than the call's (``fmi2GetReal`` of a Boolean) ends the
  instance: the host's model description is not this FMU's.
* A value the unit refuses (a byte set to 300, an output set) is logged as an error and not
  taken; the instance goes on.
* A step the unit refuses (not a whole number of IPO cycles, a jump in time) is logged as an
  error and answered *discard*: the NC stays where it stood.
* A machine that does not load, or parameters that do not fit it, end the instance.

Every error is written to the process's standard error as well, with the instance's name: a
host that has logging off still shows why.
"""

from __future__ import annotations

import json
import sys
from collections.abc import Callable, Sequence
from enum import IntEnum
from pathlib import Path
from typing import Any

from fmu.unit import Kind, NcUnit, UnitError
from interfaces.errors import VcError

MANIFEST = "vc_fmu.json"


class Status(IntEnum):
    """The FMI status, numbered as fmi2Status and fmi3Status are."""

    OK = 0
    WARNING = 1
    DISCARD = 2
    ERROR = 3
    FATAL = 4


class FmuError(VcError):
    """Why the FMU cannot work (an export that fails, an instance that ends); the plain message."""

    def __repr__(self) -> str:
        return str(self)


Log = Callable[[Status, str], None]


class NcInstance:
    """The unit of the FMU whose resources are at ``resources``; errors go to ``log``."""

    def __init__(self, resources: Path, name: str, log: Log):
        self.name = name
        self._log = log
        try:
            self.manifest: dict[str, Any] = json.loads((resources / MANIFEST).read_text(encoding="utf-8"))
            self.machine_path = str(resources / self.manifest["machine"])
            self.unit = NcUnit(self.machine_path)
        except UnitError as error:
            raise self.fatal(str(error)) from None
        except (OSError, ValueError, KeyError) as error:
            raise self.fatal(f"the FMU's resources are damaged ({error!r})") from None
        self.time_reference = len(self.unit.variables)  # FMI 3.0's independent variable (model_description.py)
        self._of_kind = {kind: frozenset(index for index, variable in enumerate(self.unit.variables)
                                         if variable.kind is kind) for kind in Kind}

    # ------------------------------------------------------------------ errors
    def error(self, message: str) -> None:
        """An error the instance survives: to the host's logger and to standard error."""
        self._log(Status.ERROR, message)
        print(f"{self.name}: {message}", file=sys.stderr, flush=True)

    def fatal(self, message: str) -> FmuError:
        """The exception that ends the instance; its message is for the host's logger (fmi*Fatal)."""
        print(f"{self.name}: {message}", file=sys.stderr, flush=True)
        return FmuError(f"{self.name}: {message}")

    # ------------------------------------------------------------------ life cycle
    def setup(self, start_time: float) -> None:
        self.unit.setup(start_time)

    def exit_initialization(self) -> None:
        try:
            self.unit.initialize()
        except UnitError as error:
            raise self.fatal(str(error)) from None

    def step(self, current_time: float, step_size: float) -> Status:
        try:
            self.unit.step(current_time, step_size)
        except UnitError as error:
            self.error(str(error))
            return Status.DISCARD
        return Status.OK

    def reset(self) -> None:
        """Back to the state after instantiation: the machine file's power-on, no input set."""
        self.unit = NcUnit(self.machine_path)

    # ------------------------------------------------------------------ values, in batches
    def values(self, kind: Kind, references: Sequence[int]) -> list[Any]:
        wrong = set(references) - self._of_kind[kind]  # one check per batch: hosts ask for hundreds at once
        if kind is Kind.REAL:
            wrong.discard(self.time_reference)
        if wrong:
            raise self.fatal(f"value reference {min(wrong)} is not a {kind.value} variable of this FMU")
        get = self.unit.get
        if self.time_reference in references:
            return [self.unit.time if reference == self.time_reference else get(reference) for reference in references]
        return [get(reference) for reference in references]

    def take(self, kind: Kind, references: Sequence[int], values: Sequence[Any]) -> None:
        variables = self._of_kind[kind]
        for reference, value in zip(references, values, strict=True):
            if reference not in variables:
                self.error(f"value reference {reference} is not a {kind.value} variable of this FMU; not set")
                continue
            try:
                self.unit.set(reference, value)
            except UnitError as error:
                self.error(str(error))
