"""A checked scenario: names resolved, durations parsed, expressions compiled to trees.

Everything here is built by :mod:`vc.scenario.language.loader` and read by :mod:`vc.scenario.run.runner`;
nothing in it touches a simulation.
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass, field
from enum import Enum

from interfaces.image import Value
from interfaces.signals import ExpandedCatalog
from vc.config.model import MachineConfig
from vc.located_yaml import Mark
from vc.scenario.language.durations import Duration
from vc.scenario.language.expressions import Expression
from vc.scenario.language.quantities import Quantity
from vc.scenario.language.values import ExpectedValue

NO_PLC = "none"
LINK_CAN = "can"  # ``link: can``: the PLC program sits behind the CAN link
# ``plc: awlsim:PROGRAM.awl``: a PLC of its own process, started with the program and run over a
# lockstep Modbus TCP link (docs/scenarios.md); the kinds and the command each starts are the harness's.
# Each kind with the package that process needs and the extra that installs it, checked when the
# scenario loads (a missing one is a problem at its plc: line, not a traceback once the run started).
EXTERNAL_PLCS = {"awlsim": ("awlsim", "awlsim")}  # kind -> (package imported, vc-harness extra)


def external_plc(plc: str) -> tuple[str, str] | None:
    """``(kind, program file)`` of ``plc: KIND:FILE``, or None for a built-in program (or none)."""
    kind, separator, program = plc.partition(":")
    return (kind, program) if separator and kind in EXTERNAL_PLCS else None


class EdgeKind(Enum):
    RISES = "rises"  # 0 -> not 0
    FALLS = "falls"  # not 0 -> 0
    CHANGES = "changes"  # any change of the value
    WHEN = "when"  # the cycle a condition becomes true


@dataclass(frozen=True, slots=True)
class Event:
    text: str  # as written: "X1.basic.in.enc1Synchronized rises", "when X1.position > 5"
    kind: EdgeKind
    quantity: Quantity | None = None  # for rises / falls / changes
    condition: Expression | None = None  # for when

    @property
    def quantities(self) -> tuple[Quantity, ...]:
        if self.condition is not None:
            return self.condition.names
        return (self.quantity,) if self.quantity is not None else ()

    def __str__(self) -> str:
        return self.text


@dataclass(frozen=True, slots=True)
class Step:
    """Common part of every step: its 1-based position and where it is written."""

    index: int
    kind: str
    mark: Mark

    @property
    def quantities(self) -> tuple[Quantity, ...]:
        """The names this step reads or writes (their history goes into a failure report)."""
        return ()

    @property
    def label(self) -> str:
        return f"step {self.index} ({self.kind})"


@dataclass(frozen=True, slots=True)
class Press(Step):
    """``press`` / ``pulse``: set the keys to 1, let ``duration`` pass, set them to 0."""

    keys: tuple[Quantity, ...]
    duration: Duration

    @property
    def quantities(self) -> tuple[Quantity, ...]:
        return self.keys


@dataclass(frozen=True, slots=True)
class Hold(Step):
    keys: tuple[Quantity, ...]

    @property
    def quantities(self) -> tuple[Quantity, ...]:
        return self.keys


@dataclass(frozen=True, slots=True)
class Release(Step):
    """End the forces on these names; names that are not forced are keys let go (set to 0)."""

    names: tuple[Quantity, ...]

    @property
    def quantities(self) -> tuple[Quantity, ...]:
        return self.names


@dataclass(frozen=True, slots=True)
class SetValues(Step):
    """``set`` (once, as the owner would) or ``force`` (held against the owner until released)."""

    values: tuple[tuple[Quantity, Value], ...]
    forced: bool

    @property
    def quantities(self) -> tuple[Quantity, ...]:
        return tuple(quantity for quantity, _ in self.values)


@dataclass(frozen=True, slots=True)
class LoadMda(Step):
    channel: str
    text: str


@dataclass(frozen=True, slots=True)
class SelectProgram(Step):
    channel: str
    name: str
    text: str


@dataclass(frozen=True, slots=True)
class Wait(Step):
    duration: Duration


@dataclass(frozen=True, slots=True)
class WaitUntil(Step):
    condition: Expression
    timeout: Duration | None  # None: until the scenario's own timeout

    @property
    def quantities(self) -> tuple[Quantity, ...]:
        return self.condition.names


@dataclass(frozen=True, slots=True)
class ExpectValues(Step):
    checks: tuple[tuple[Quantity, ExpectedValue], ...]

    @property
    def quantities(self) -> tuple[Quantity, ...]:
        return tuple(quantity for quantity, _ in self.checks)


@dataclass(frozen=True, slots=True)
class ExpectCondition(Step):
    condition: Expression

    @property
    def quantities(self) -> tuple[Quantity, ...]:
        return self.condition.names


@dataclass(frozen=True, slots=True)
class ExpectAlarm(Step):
    """``expect_alarm`` (present) or ``expect_no_alarm`` (absent); number 0 = any alarm."""

    number: int
    place: str  # axis or channel; "" = anywhere
    present: bool
    text: str = ""  # a part of the alarm text it must show (its block, spindle ...); "" = any


@dataclass(frozen=True, slots=True)
class ExpectOrder(Step):
    events: tuple[Event, ...]

    @property
    def quantities(self) -> tuple[Quantity, ...]:
        return _unique(quantity for event in self.events for quantity in event.quantities)


@dataclass(frozen=True, slots=True)
class ExpectTiming(Step):
    start: Event
    end: Event
    minimum: Duration | None
    maximum: Duration | None

    @property
    def quantities(self) -> tuple[Quantity, ...]:
        return _unique((*self.start.quantities, *self.end.quantities))


@dataclass(frozen=True, slots=True)
class PowerCycle(Step):
    """Switch the machine off and on again after ``off``: the NC keeps its memory, the PLC restarts."""

    off: Duration


@dataclass(frozen=True, slots=True)
class InjectFault(Step):
    """A fault of the simulated machine on one axis (``FAULTS`` in vc/simulation/observables.py)."""

    axis: str
    fault: str
    start: float  # reference_marks_missing: the range without marks
    end: float
    amount: float  # encoder_slip: by how much the measuring system miscounts
    encoder: int  # measuring system 1 or 2


@dataclass(frozen=True, slots=True)
class InjectLinkFault(Step):
    """A fault of the CAN bus between NC and PLC for ``duration`` (``LINK_FAULTS`` in vc/simulation/observables.py)."""

    fault: str  # loss, delay, bus_off
    duration: Duration
    directions: tuple[str, ...]  # nc_to_plc, plc_to_nc
    areas: tuple[str, ...]  # area keys (DB31, Q ..) and "link"; empty: every frame
    delay: Duration  # delay: how much later the frames arrive
    every: int  # loss: every n-th frame


@dataclass(frozen=True, slots=True)
class ClearFaults(Step):
    axis: str


@dataclass(frozen=True, slots=True)
class AcknowledgeAlarms(Step):
    """The operator's alarm acknowledge (cancel) key on the HMI: the alarms cleared with it go."""


@dataclass(frozen=True, slots=True)
class MoveByHand(Step):
    """The slide is moved from outside at ``velocity`` (mm/min or rev/min; 0 = stops)."""

    axis: str
    velocity: float


@dataclass(frozen=True, slots=True)
class TurnHandwheels(Step):
    """``turn``: the operator turns handwheels by detents (sign = direction), evenly over ``duration``."""

    detents: tuple[tuple[int, int], ...]  # (handwheel number, detents)
    duration: Duration


@dataclass(frozen=True, slots=True)
class Variant:
    """One combination of a ``vary:`` matrix (:mod:`vc.scenario.language.variants`)."""

    origin: str  # the file that declares the matrix: the scenario file itself, or a campaign file
    index: int  # the position in the origin's matrix, from 0 (counting on over a campaign's scenarios)
    arguments: str  # what the id shows in brackets: "X1.MD34050=1,X1.plant.ref_cam=[250,260]"
    values: tuple[tuple[str, str], ...]  # (varied key, value as shown), in the matrix's order
    campaign: str = ""  # the campaign's name when a campaign file declares the matrix
    first: bool = False  # the first variant of its scenario in the matrix

    @property
    def keys(self) -> tuple[str, ...]:
        return tuple(key for key, _ in self.values)


@dataclass(frozen=True, slots=True)
class Invariant:
    condition: Expression
    mark: Mark


@dataclass(slots=True)
class Scenario:
    name: str
    description: str
    path: str  # the scenario file as given
    machine_file: str  # the machine file, relative to the working directory like ``path``, or a packaged machine's name
    machine: MachineConfig
    catalog: ExpandedCatalog
    plc: str  # a built-in PLC program, "none" (the steps act as the PLC) or KIND:FILE (an external PLC)
    timeout: Duration
    invariants: tuple[Invariant, ...]
    steps: tuple[Step, ...]
    mark: Mark = field(default_factory=lambda: Mark("", 1, 1))
    link: str | None = None  # LINK_CAN: the PLC program behind the CAN link; None: wherever the run puts it
    variant: Variant | None = None  # the combination of a vary: matrix this scenario is (its name ends in [...])
    sources: tuple[str, ...] = ()  # every file its check read: the scenario, a campaign, machine and program files

    @property
    def plc_program(self) -> str | None:
        return None if self.plc == NO_PLC else self.plc

    @property
    def external_plc(self) -> tuple[str, str] | None:
        """``(kind, program file)`` when the PLC is an external one (``plc: awlsim:FILE``)."""
        return external_plc(self.plc)

    @property
    def events(self) -> tuple[Event, ...]:
        """Every event named by an expect_order or expect_timing step."""
        found: list[Event] = []
        for step in self.steps:
            if isinstance(step, ExpectOrder):
                found.extend(step.events)
            elif isinstance(step, ExpectTiming):
                found.extend((step.start, step.end))
        return tuple(found)

    @property
    def quantities(self) -> tuple[Quantity, ...]:
        """Every name the scenario reads or writes."""
        names = [q for invariant in self.invariants for q in invariant.condition.names]
        names += [q for step in self.steps for q in step.quantities]
        return _unique(names)


def _unique(quantities: Iterable[Quantity]) -> tuple[Quantity, ...]:
    seen: dict[str, Quantity] = {}
    for quantity in quantities:
        seen.setdefault(quantity.name, quantity)
    return tuple(seen.values())
