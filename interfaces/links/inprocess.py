"""The in-process link: lockstep and zero copy, and the registry of built-in PLC programs.

Programs register under the ``vc_harness.plc_programs`` entry point: each entry point
names a mapping ``{program name: PlcFactory}`` (the built-in soft PLC ``plc_stub``
provides one).  Reading the installed distributions' metadata is why the registry lives
among the links, the only place in ``interfaces`` that touches the outside world.
"""

from __future__ import annotations

from collections.abc import Mapping
from functools import lru_cache
from importlib.metadata import entry_points

from interfaces.errors import VcError
from interfaces.plc import PlcEnvironment, PlcFactory, SoftPlc

ENTRY_POINT_GROUP = "vc_harness.plc_programs"


class UnknownPlcProgram(VcError, LookupError):
    pass


@lru_cache(maxsize=1)
def plc_programs() -> dict[str, PlcFactory]:
    """Every PLC program installed, by name."""
    programs: dict[str, PlcFactory] = {}
    for entry in entry_points(group=ENTRY_POINT_GROUP):
        registry = entry.load()
        if isinstance(registry, Mapping):
            programs.update(registry)
    return programs


def plc_program(name: str) -> PlcFactory:
    programs = plc_programs()
    try:
        return programs[name]
    except KeyError:
        known = ", ".join(sorted(programs)) or "none installed"
        raise UnknownPlcProgram(f"no PLC program '{name}' (known: {known})") from None


class InProcessConnector:
    """The built-in programs, run in the harness's own process in lockstep."""

    def connect(self, environment: PlcEnvironment, program: str) -> SoftPlc:
        return plc_program(program)(environment)
