"""The state machines whose coverage is measured: every one the NC publishes, as the report shows it.

The NC declares each state machine once, beside its State enum (``vc.simulation.published``:
name, title, instances, states with meanings, transitions with triggers); ``vc.coverage.probes``
reads the states of a running NC through its state view, the report compares the two.  A state
machine is counted over all its instances (every axis, spindle or channel of every machine that
ran): a state is covered when any instance entered it.  Referencing is one state machine per
procedure (incremental with and without cam, distance-coded, absolute, follow-up).

The states are sampled at the end of every IPO cycle: a state entered and left within one cycle
is not seen, and its two transitions show as one (listed as "other transitions" in the report).
For the report each state names the text of its declaring module it is declared by (``anchor``:
the member of its enum, or the declared name), so that the report can point to the line.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from vc.simulation.published import STATE_MACHINES as PUBLISHED
from vc.simulation.published import StateInfo, Transition
from vc.simulation.published import StateMachine as Declared


@dataclass(frozen=True, slots=True)
class StateDef:
    name: str
    meaning: str
    anchor: str  # a text of the module that declares the state (for its line)


@dataclass(frozen=True, slots=True)
class StateMachine:
    """A published state machine as the report counts it."""

    name: str  # "referencing.distance_coded": what --fail-under-function names (a prefix names a group)
    title: str
    module: str  # the declaring source file, relative to the repository
    instances: str  # what one instance is: "axis", "spindle", "channel", "mode group"
    states: tuple[StateDef, ...]
    transitions: tuple[Transition, ...]

    @classmethod
    def of(cls, machine: Declared[Any]) -> StateMachine:
        return cls(machine.name, machine.title, machine.path, machine.instance.value,
                   tuple(StateDef(state.name, state.meaning, _anchor(state)) for state in machine.states),
                   machine.transitions)

    def state(self, name: str) -> StateDef | None:
        for state in self.states:
            if state.name == name:
                return state
        return None


def _anchor(state: StateInfo) -> str:
    """The member of the state's enum (``IDLE = "no stop reaction"``), or the declaration of a state
    without one (``("NONE", ``)."""
    return f'{state.name} = "{state.meaning}"' if state.enum else f'("{state.name}", '


STATE_MACHINES: tuple[StateMachine, ...] = tuple(StateMachine.of(machine) for machine in PUBLISHED)

BY_NAME: dict[str, StateMachine] = {machine.name: machine for machine in STATE_MACHINES}
