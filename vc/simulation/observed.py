"""A simulation with observers: told after every IPO cycle and after every action of the operator.

:class:`ObservedSimulation` is a :class:`~vc.scenario.language.target.ScenarioTarget` over a
:class:`~vc.simulation.lockstep.Simulation`.  It steps the simulation one IPO cycle at a time and
after each one calls every :class:`SimulationObserver`; every action of the operator (a scenario
step that writes, forces, releases, loads a program, switches the machine off and on ...) goes to
the simulation and then, as an :class:`OperatorAction`, to the observers.  The interface
coverage (``vc run --coverage``) and the session recording (``vc serve --record``) are such
observers.  Nobody pays for them unless they are asked for: a plain run steps the
:class:`Simulation` itself, with no hook in its cycle.

An :class:`OperatorAction` is plain data (its arguments are JSON values: a signal by its name),
so that a recording can store it and :func:`perform` can do it again on another simulation.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Protocol

from interfaces.image import Value
from interfaces.signals import SignalRef, UnknownSignalError
from vc.core.alarms import Alarm
from vc.simulation.lockstep import Simulation

# The kinds of operator actions and the names of their arguments, in order.
ACTION_ARGUMENTS: dict[str, tuple[str, ...]] = {
    "write": ("signal", "value"),
    "force": ("signal", "value"),
    "release": ("signal",),
    "mda": ("channel", "text"),
    "program": ("channel", "name", "text"),
    "power_cycle": ("off_seconds",),
    "fault": ("axis", "kind", "start", "end", "amount", "encoder"),
    "link_fault": ("kind", "duration_us", "directions", "areas", "delay_us", "every"),
    "clear_faults": ("axis",),
    "acknowledge": (),
    "move_by_hand": ("axis", "velocity"),
    "handwheel": ("number", "detents", "cycles"),
}

ActionArgument = str | int | float | list[str]


@dataclass(frozen=True, slots=True)
class OperatorAction:
    """What the operator (a scenario step) did between two IPO cycles; ``arguments`` in the order of
    ``ACTION_ARGUMENTS[kind]``."""

    kind: str
    arguments: tuple[ActionArgument, ...] = ()

    def argument(self, name: str) -> ActionArgument:
        return self.arguments[ACTION_ARGUMENTS[self.kind].index(name)]


class SimulationObserver(Protocol):
    def attached(self, simulation: Simulation) -> None:
        """The observation begins (after the power-on, before the first cycle)."""

    def cycle_done(self, simulation: Simulation) -> None:
        """An IPO cycle (NC, plant, and the PLC when its scan was due) has completed."""

    def acted(self, simulation: Simulation, action: OperatorAction) -> None:
        """The operator did ``action``; it has taken effect (a power cycle: the machine is on again)."""


def resolve(simulation: Simulation, name: str) -> SignalRef:
    """An interface signal (symbol or address) or a plant I/O point (function or address) by name."""
    try:
        return simulation.catalog.resolve(name)
    except UnknownSignalError:
        return simulation.plant_io.resolve(name)


def perform(simulation: Simulation, action: OperatorAction) -> None:
    """Do ``action`` on ``simulation`` as the operator did it.  Raises KeyError or ValueError for an
    action the simulation cannot take (an unknown signal, axis or fault)."""
    kind, arguments = action.kind, action.arguments
    if kind in ("write", "force"):
        name, value = arguments
        ref = resolve(simulation, str(name))
        number = value if isinstance(value, (int, float)) else float(str(value))
        (simulation.write if kind == "write" else simulation.force)(ref, number)
    elif kind == "release":
        simulation.release(resolve(simulation, str(arguments[0])))
    elif kind == "mda":
        simulation.load_mda(str(arguments[0]), str(arguments[1]))
    elif kind == "program":
        simulation.select_program(str(arguments[0]), str(arguments[1]), str(arguments[2]))
    elif kind == "power_cycle":
        simulation.power_cycle(_number(arguments[0]))
    elif kind == "fault":
        axis, fault, start, end, amount, encoder = arguments
        simulation.inject_fault(str(axis), str(fault), _number(start), _number(end), _number(amount),
                                int(_number(encoder)))
    elif kind == "link_fault":
        fault, duration_us, directions, areas, delay_us, every = arguments
        simulation.inject_link_fault(str(fault), int(_number(duration_us)), _names(directions), _names(areas),
                                     int(_number(delay_us)), int(_number(every)))
    elif kind == "clear_faults":
        simulation.clear_faults(str(arguments[0]))
    elif kind == "acknowledge":
        simulation.acknowledge_alarms()
    elif kind == "move_by_hand":
        simulation.move_by_hand(str(arguments[0]), _number(arguments[1]))
    elif kind == "handwheel":
        number, detents, cycles = (int(_number(item)) for item in arguments)
        simulation.turn_handwheel(number, detents, cycles)
    else:
        raise ValueError(f"unknown operator action '{kind}'")


def _number(value: ActionArgument) -> float:
    if isinstance(value, (int, float)):
        return float(value)
    raise ValueError(f"{value!r} is not a number")


def _names(value: ActionArgument) -> list[str]:
    if isinstance(value, list):
        return [str(item) for item in value]
    raise ValueError(f"{value!r} is not a list of names")


class ObservedSimulation:
    """A :class:`~vc.scenario.language.target.ScenarioTarget` that tells its observers about every cycle and
    every action of the operator (see the module docstring)."""

    def __init__(self, simulation: Simulation, observers: Sequence[SimulationObserver]):
        self.simulation = simulation
        self.observers = tuple(observers)
        self.machine = simulation.machine
        self.catalog = simulation.catalog
        self.plant_io = simulation.plant_io
        for observer in self.observers:
            observer.attached(simulation)

    def _acted(self, kind: str, *arguments: ActionArgument) -> None:
        action = OperatorAction(kind, arguments)
        for observer in self.observers:
            observer.acted(self.simulation, action)

    # ------------------------------------------------------------------ time
    @property
    def cycle(self) -> int:
        return self.simulation.cycle

    @property
    def ipo_cycle_us(self) -> int:
        return self.simulation.ipo_cycle_us

    def step(self, cycles: int = 1) -> None:
        simulation, observers = self.simulation, self.observers
        for _ in range(cycles):
            simulation.step(1)
            for observer in observers:
                observer.cycle_done(simulation)

    # ------------------------------------------------------------------ reads
    def read(self, ref: SignalRef) -> Value:
        return self.simulation.read(ref)

    def image_areas(self) -> Mapping[str, bytearray]:
        """The trace recorder's fast path (``vc.scenario.run.trace.ImageSource``)."""
        return self.simulation.image_areas()

    def axis_quantity(self, axis: str, quantity: str) -> float:
        return self.simulation.axis_quantity(axis, quantity)

    def link_quantity(self, name: str) -> float:
        return self.simulation.link_quantity(name)

    def alarms(self) -> Sequence[Alarm]:
        return self.simulation.alarms()

    def alarm_history(self) -> Sequence[Alarm]:
        return self.simulation.alarm_history()

    def machine_datum(self, instance: str, number: int, index: int | None = None) -> float:
        return self.simulation.machine_datum(instance, number, index)

    # ------------------------------------------------------------------ the operator's actions
    def write(self, ref: SignalRef, value: Value) -> None:
        self.simulation.write(ref, value)
        self._acted("write", ref.name, value)

    def force(self, ref: SignalRef, value: Value) -> None:
        self.simulation.force(ref, value)
        self._acted("force", ref.name, value)

    def release(self, ref: SignalRef) -> None:
        self.simulation.release(ref)
        self._acted("release", ref.name)

    def load_mda(self, channel: str, text: str) -> None:
        self.simulation.load_mda(channel, text)
        self._acted("mda", channel, text)

    def select_program(self, channel: str, name: str, text: str) -> None:
        self.simulation.select_program(channel, name, text)
        self._acted("program", channel, name, text)

    def power_cycle(self, off_seconds: float = 1.0) -> None:
        self.simulation.power_cycle(off_seconds)
        self.catalog = self.simulation.catalog
        self._acted("power_cycle", off_seconds)

    def inject_fault(self, axis: str, kind: str, start: float = 0.0, end: float = 0.0, amount: float = 0.0,
                     encoder: int = 1) -> None:
        self.simulation.inject_fault(axis, kind, start, end, amount, encoder)
        self._acted("fault", axis, kind, start, end, amount, encoder)

    def inject_link_fault(self, kind: str, duration_us: int, directions: Sequence[str] = ("nc_to_plc", "plc_to_nc"),
                          areas: Sequence[str] = (), delay_us: int = 0, every: int = 1) -> None:
        self.simulation.inject_link_fault(kind, duration_us, directions, areas, delay_us, every)
        self._acted("link_fault", kind, duration_us, list(directions), list(areas), delay_us, every)

    def clear_faults(self, axis: str) -> None:
        self.simulation.clear_faults(axis)
        self._acted("clear_faults", axis)

    def acknowledge_alarms(self) -> None:
        self.simulation.acknowledge_alarms()
        self._acted("acknowledge")

    def move_by_hand(self, axis: str, velocity: float) -> None:
        self.simulation.move_by_hand(axis, velocity)
        self._acted("move_by_hand", axis, velocity)

    def turn_handwheel(self, number: int, detents: int, cycles: int) -> None:
        self.simulation.turn_handwheel(number, detents, cycles)
        self._acted("handwheel", number, detents, cycles)
