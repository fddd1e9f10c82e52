"""The NC's state machines as it publishes them: declared once beside each State enum, read through one view.

Each state machine of the NC declares, in the module that runs it and beside its State enum, one
:class:`StateMachine`: its name, a title, what an instance is (an axis, a spindle, a channel, the
mode group), its states with their meanings, its transitions with what triggers them (as the
module's diagram draws them, next to the code that makes them), and how the state of an instance is
read from the part that keeps it::

    CHANNEL_STATES = StateMachine(
        __name__, "channel", "Channel state (DB21.DBX35.5-35.7)", Instance.CHANNEL,
        states(*ChannelState),
        transitions(("RESET", "ACTIVE", "NC start"), ...),
        read=lambda run: run.state)

A state machine whose procedure differs by configuration declares one :class:`StateMachine` per
variant (each with the states and transitions its variant can take, counted apart by the coverage)
and a :class:`Variants` that says which variant an instance is in now (referencing, one per
measuring system).

The NCK publishes every instance through one :class:`StateView` (``Nck.state_view()``, built from
the table in ``vc/core/nck/state_view.py``): the state machine, the instance and the state, as
names, as LinuxCNC publishes ``joint.N.home-state`` for the tools that read it.  The view reads a
state when an observer asks (the coverage after each IPO cycle, an operator panel, the FMU's
outputs), never within the NC's cycle, and hands out names, not the parts that keep the states.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator, Sequence
from dataclasses import dataclass
from enum import Enum
from typing import Any, Generic, TypeVar

P = TypeVar("P")  # the part of the NC that keeps the state of one instance

StateValue = Enum | str  # what a reader returns: a member of the State enum, or the name of the state


class Instance(Enum):
    """What one instance of a state machine is."""

    MODE_GROUP = "mode group"
    CHANNEL = "channel"
    SPINDLE = "spindle"
    AXIS = "axis"


@dataclass(frozen=True, slots=True)
class StateInfo:
    name: str  # as the reader returns it: the enum member's name, or the declared name
    meaning: str
    enum: str = ""  # the State enum the state is a member of ("": a state declared by its name)


@dataclass(frozen=True, slots=True)
class Transition:
    before: str
    after: str
    trigger: str  # what takes the state machine from ``before`` to ``after``


def states(*items: Enum | tuple[str, str]) -> tuple[StateInfo, ...]:
    """The states of a state machine: members of its enum (the value says what the state means) or
    ``(name, meaning)`` for a state that has no member (no gear change running: ``("NONE", ...)``)."""
    return tuple(StateInfo(item.name, str(item.value), type(item).__name__) if isinstance(item, Enum)
                 else StateInfo(*item) for item in items)


def transitions(*items: tuple[str, str, str]) -> tuple[Transition, ...]:
    """The transitions of a state machine: ``(before, after, trigger)``."""
    return tuple(Transition(*item) for item in items)


class StateMachine(Generic[P]):
    """One state machine of the NC (see the module docstring); its fields are not changed after the
    declaration.  (A plain class: a generic dataclass does not compile with mypyc.)"""

    def __init__(self, module: str, name: str, title: str, instance: Instance, states: tuple[StateInfo, ...],
                 transitions: tuple[Transition, ...], *, read: Callable[[P], StateValue]):
        self.module = module  # the module that declares and runs it: ``__name__``
        self.name = name  # "gear_change", "referencing.distance_coded": what the coverage and its thresholds name
        self.title = title
        self.instance = instance
        self.states = states
        self.transitions = transitions
        self.read = read  # the state of one instance, from the part that keeps it

    def __repr__(self) -> str:
        return f"StateMachine({self.name!r})"

    @property
    def path(self) -> str:
        """The declaring module as a path relative to the repository: vc/core/spindle/gear_change.py."""
        return self.module.replace(".", "/") + ".py"

    def state(self, name: str) -> StateInfo | None:
        for state in self.states:
            if state.name == name:
                return state
        return None


class Variants(Generic[P]):
    """A state machine that runs differently by configuration: a :class:`StateMachine` per variant
    (all read alike) and which of them an instance is in now."""

    def __init__(self, name: str, machines: tuple[StateMachine[P], ...], variant: Callable[[P], StateMachine[P]]):
        self.name = name  # the name the variants share before the dot: "referencing"
        self.machines = machines
        self.variant = variant

    def __repr__(self) -> str:
        return f"Variants({self.name!r})"


@dataclass(frozen=True, slots=True)
class StateReading:
    """The state of one instance of a state machine, as names."""

    machine: str  # "referencing.incremental_cam"
    instance: str  # "X1", "CHAN1", "MODEGROUP"
    state: str  # "P2_ZERO_MARK"


class InstanceState:
    """One instance of a published state machine: its names and its state now, read-only."""

    __slots__ = ("_last", "_last_name", "_machine", "_read", "instance", "name")

    def __init__(self, name: str, instance: str, read: Callable[[], StateValue],
                 machine: Callable[[], StateMachine[Any]]):
        self.name = name  # the declared name: "referencing" for every variant, else the machine's
        self.instance = instance
        self._read = read
        self._machine = machine
        self._last: StateValue = ""
        self._last_name = ""

    def machine(self) -> StateMachine[Any]:
        """The state machine the instance is in now (for :class:`Variants`, the variant in force)."""
        return self._machine()

    def state(self) -> str:
        """The name of the state now (the same string object while the state stands)."""
        value = self._read()
        if value is not self._last:
            self._last = value
            self._last_name = value if isinstance(value, str) else value.name
        return self._last_name

    def reading(self) -> StateReading:
        return StateReading(self._machine().name, self.instance, self.state())


def publish(declaration: StateMachine[P] | Variants[P], instance: str, part: P) -> InstanceState:
    """The instance ``instance`` of ``declaration`` whose state ``part`` keeps."""
    if isinstance(declaration, Variants):
        read = declaration.machines[0].read
        variant = declaration.variant
        return InstanceState(declaration.name, instance, lambda: read(part), lambda: variant(part))
    machine = declaration
    read_one = machine.read
    return InstanceState(machine.name, instance, lambda: read_one(part), lambda: machine)


def machines_of(declaration: StateMachine[Any] | Variants[Any]) -> tuple[StateMachine[Any], ...]:
    return declaration.machines if isinstance(declaration, Variants) else (declaration,)


class StateView:
    """Every instance of every state machine the NCK publishes (see the module docstring)."""

    __slots__ = ("instances",)

    def __init__(self, instances: Sequence[InstanceState]):
        self.instances: tuple[InstanceState, ...] = tuple(instances)

    def __iter__(self) -> Iterator[StateReading]:
        for instance in self.instances:
            yield instance.reading()

    def readings(self) -> list[StateReading]:
        return list(self)

    def state(self, name: str, instance: str) -> str | None:
        """The state of ``instance`` of the state machine declared as ``name`` ("gear_change", "referencing");
        None when the NCK has no such instance."""
        for each in self.instances:
            if each.name == name and each.instance == instance:
                return each.state()
        return None
