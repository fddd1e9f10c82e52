"""The page's live scope, on the NC's side: the picked lanes sampled once per IPO cycle.

The lanes are interface signals and plant points (by symbol or address, as in the watch table) and
axis quantities (``X1.position``, ``X1.velocity``, ``X1.following_error``).  The scope is the
server's, shared by its pages (like a scope project of a PLC tool): the last page that picks sets
the lanes.  After every IPO cycle, and only while a page is open and lanes are picked, one sample
(the cycle and a value per lane) goes into a ring of at most ``seconds`` of cycles (bounded memory:
at most :data:`MAX_LANES` lanes, :data:`MAX_SECONDS` seconds) and into the samples not yet sent,
which the next snapshot takes.  The page draws the timing diagram, triggers and freezes; the VCD
is written from the ring by the project's trace writer (:func:`vc.scenario.run.trace.write_vcd`).
"""

from __future__ import annotations

import math
from collections import deque
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

from interfaces.signals import SignalType, UnknownSignalError
from vc.scenario.language.quantities import Quantity, axis_quantity, signal_quantity
from vc.scenario.run.trace import History, Recording
from vc.simulation.lockstep import Simulation
from vc.simulation.observed import resolve

MAX_LANES = 16
MAX_SECONDS = 60.0
PAGE_AXIS_QUANTITIES = {"position": "position", "velocity": "velocity", "following_error": "followingError"}


@dataclass(frozen=True, slots=True)
class Lane:
    name: str  # as picked
    quantity: Quantity
    digital: bool  # a bit: drawn as 0/1 steps; else a line
    read: Callable[[], float]


class Scope:
    """The lanes, their ring of samples and the samples not yet sent (see the module docstring)."""

    def __init__(self) -> None:
        self.lanes: tuple[Lane, ...] = ()
        self.samples: deque[tuple[int, tuple[float, ...]]] = deque(maxlen=1)
        self.unsent: deque[tuple[int, tuple[float, ...]]] = deque(maxlen=1)
        self.seconds = 0.0

    def pick(self, simulation: Simulation, names: list[str], seconds: float) -> str:
        """The lanes ``names`` (none: the scope stops sampling), the last ``seconds`` kept."""
        if len(names) > MAX_LANES:
            return f"refused: at most {MAX_LANES} lanes in the scope"
        if not (isinstance(seconds, (int, float)) and math.isfinite(seconds) and 0.1 <= seconds <= MAX_SECONDS):
            return f"refused: the scope keeps 0.1 .. {MAX_SECONDS:g} s"
        lanes, unknown = [], []
        for name in names:
            try:
                lanes.append(_lane(simulation, name))
            except (UnknownSignalError, KeyError, ValueError) as error:
                unknown.append(str(error.args[0]) if isinstance(error, KeyError) and error.args else str(error))
        if unknown:
            return "refused: " + "; ".join(unknown)
        cycles = max(1, round(seconds / simulation.ipo_cycle_s))
        self.lanes, self.seconds = tuple(lanes), float(seconds)
        self.samples = deque(maxlen=cycles)
        self.unsent = deque(maxlen=cycles)
        if not lanes:
            return "scope stopped"
        return f"scope: {len(lanes)} lanes, the last {seconds:g} s ({cycles} IPO cycles)"

    def sample(self, simulation: Simulation) -> None:
        """After an IPO cycle (the bridge calls it only while a page is open)."""
        if not self.lanes:
            return
        sample = (simulation.cycle, tuple(lane.read() for lane in self.lanes))
        self.samples.append(sample)
        self.unsent.append(sample)

    def take_unsent(self, simulation: Simulation) -> dict[str, Any] | None:
        """The samples since the last snapshot, for the pages (None: no lanes)."""
        if not self.lanes:
            return None
        unsent = [[cycle, *(_plain(value) for value in values)] for cycle, values in self.unsent]
        self.unsent.clear()
        return {"lanes": [{"name": lane.name, "digital": lane.digital} for lane in self.lanes],
                "ipo_s": simulation.ipo_cycle_s, "seconds": self.seconds, "samples": unsent}

    def recording(self, ipo_cycle_us: int) -> Recording:
        """The ring as a trace recording (a copy, taken in the NC thread): a history per lane with
        its changes only, for the trace writers."""
        histories = [History(lane.quantity) for lane in self.lanes]
        for cycle, values in self.samples:
            for history, value in zip(histories, values, strict=True):
                if not len(history) or history.last != value:
                    history.add(cycle, value)
        return Recording(ipo_cycle_us, histories)


def _lane(simulation: Simulation, name: str) -> Lane:
    axis, _, tail = name.rpartition(".")
    if tail in PAGE_AXIS_QUANTITIES and axis in {item.name for item in simulation.machine.axes}:
        quantity = axis_quantity(axis, PAGE_AXIS_QUANTITIES[tail])
        return Lane(name, quantity, False, lambda: simulation.axis_quantity(axis, quantity.quantity))
    ref = resolve(simulation, name)
    quantity = signal_quantity(ref)
    digital = ref.type is SignalType.BOOL
    return Lane(name, quantity, digital, lambda: float(simulation.read(ref)))


def _plain(value: float) -> float | int | None:
    if not math.isfinite(value):
        return None
    return int(value) if value == int(value) else round(value, 6)
