"""What a coverage file may name: the catalogue's signals per kind of data block, the plant I/O
functions, the declared state machines and their states, the alarms this NC raises.

``vc coverage report`` merges files of many runs; a name none of these knows (a signal that
is not in the catalogue, a state a state machine does not declare, an alarm the NC never
raises) would be merged and counted silently, so :class:`CoverageNames` lets the reader refuse
it with the file and the key.  :func:`kind_of_db` tells the kind of a data block instance by
its number, for the reader and the report alike.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cache

from interfaces.catalog import load_catalog
from interfaces.plant_io import plant_function
from interfaces.signals import FIRST_DB, PLACEHOLDER, InstanceKind, SignalDef, SignalType
from vc.coverage.state_machines import STATE_MACHINES
from vc.simulation.published import ALARM_TEXTS, PLC_USER_ALARMS

_LAST_DB = {InstanceKind.CHANNEL: FIRST_DB[InstanceKind.AXIS] - 1, InstanceKind.AXIS: FIRST_DB[InstanceKind.ALARMS] - 1}


def kind_of_db(db: int) -> InstanceKind | None:
    """The kind of the data block instance ``db`` (DB21..DB30 channels, DB31..DB99 axes), or None."""
    for kind, first in FIRST_DB.items():
        if first <= db <= _LAST_DB.get(kind, first):
            return kind
    return None


@cache
def definitions() -> dict[tuple[InstanceKind, str], SignalDef]:
    """Catalogue entries by kind and symbol without the instance: (AXIS, "basic.in.enc1Synchronized")."""
    result = {}
    for section in load_catalog().sections:
        placeholder = PLACEHOLDER[section.kind]
        for definition in section.signals:
            result[(section.kind, definition.symbol[len(placeholder) + 1:])] = definition
    return result


@dataclass(frozen=True, slots=True)
class CoverageNames:
    """The names of this harness (module docstring); each check returns a problem, or ""."""

    states: dict[str, frozenset[str]]  # state machine -> its declared states
    alarms: frozenset[int]
    types: frozenset[str]

    @classmethod
    def of_this_harness(cls) -> CoverageNames:
        return cls({machine.name: frozenset(state.name for state in machine.states) for machine in STATE_MACHINES},
                   frozenset(ALARM_TEXTS) | frozenset(PLC_USER_ALARMS), frozenset(item.value for item in SignalType))

    def instance(self, name: str, db: int) -> str:
        if kind_of_db(db) is None:
            return (f"DB{db} of '{name}' is no data block of the interface (DB2, DB10, DB11, DB19, DB21..30,"
                    " DB31..99, DB100)")
        return ""

    def signal(self, symbol: str, instances: dict[str, int]) -> str:
        instance, _, rest = symbol.partition(".")
        db = instances.get(instance)
        if db is None:
            return f"'{symbol}': its instance '{instance}' is not one of the file's instances"
        kind = kind_of_db(db)
        if kind is None or (kind, rest) not in definitions():
            return f"'{symbol}' is no signal of the catalogue for DB{db}"
        return ""

    def plant_point(self, name: str) -> str:
        return "" if plant_function(name) is not None else f"'{name}' is no plant I/O point of the harness"

    def type(self, name: str, kind: object) -> str:
        if isinstance(kind, str) and kind in self.types:
            return ""
        return f"the type of '{name}' must be one of {', '.join(sorted(self.types))}, not {str(kind)[:40]!r}"

    def state_machine(self, name: str) -> str:
        return "" if name in self.states else (f"'{name}' is no state machine of the harness (known:"
                                               f" {', '.join(self.states)})")

    def state(self, machine: str, state: str) -> str:
        declared = self.states.get(machine, frozenset())
        if state in declared:
            return ""
        return f"'{state}' is no state of {machine} (its states: {', '.join(sorted(declared))})"

    def alarm(self, number: int) -> str:
        if number in self.alarms:
            return ""
        return (f"alarm {number} is no alarm of this NC (vc/core/alarms.py) and no PLC user alarm"
                f" ({PLC_USER_ALARMS.start} .. {PLC_USER_ALARMS.stop - 1})")
