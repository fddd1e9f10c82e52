"""Faults of the bus between the NC and the PLC, as a scenario injects them (``link_fault`` step).

Three kinds, each for a window of NC cycles (``for:``), on the frames of one direction or both,
optionally only those of some areas (``DB31``, ``Q``, ``I`` ..., ``link`` = the link frames):

* ``loss``: the frames are lost (``every: n``: only every n-th of them);
* ``delay``: the frames arrive ``delay`` later; nothing overtakes a delayed frame, so the frames
  behind it wait as well until the queue has drained;
* ``bus_off``: the harness's CAN controller is bus-off: it sends nothing and receives nothing.

:class:`FaultyWire` is one direction of the bus under such faults: frames go in when they are
sent (or received), and come out when they are due, in their order.  Time is the NC cycle.
"""

from __future__ import annotations

from collections import deque
from collections.abc import Iterable, Iterator, Sequence
from dataclasses import dataclass
from enum import StrEnum
from typing import Generic, Protocol, TypeVar, runtime_checkable

from interfaces.signals import Direction
from vc.observables import LINK_AREA as LINK_AREA  # the link frames among a fault's areas


class LinkFaultKind(StrEnum):
    """The kinds of ``LINK_FAULTS`` in vc/observables.py."""

    LOSS = "loss"
    DELAY = "delay"
    BUS_OFF = "bus_off"


@dataclass(frozen=True, slots=True)
class LinkFault:
    kind: LinkFaultKind
    start: int  # first NC cycle
    end: int  # first NC cycle without the fault
    directions: frozenset[Direction]  # NC_TO_PLC, PLC_TO_NC or both
    areas: frozenset[str] = frozenset()  # empty: every frame
    delay: int = 0  # IPO cycles (delay)
    every: int = 1  # loss: every n-th matching frame is lost

    def applies(self, direction: Direction, area: str, cycle: int) -> bool:
        if not self.start <= cycle < self.end:
            return False
        if self.kind is LinkFaultKind.BUS_OFF:
            return True
        return direction in self.directions and (not self.areas or area in self.areas)


@runtime_checkable
class FaultInjectable(Protocol):
    """A PLC link that takes faults of its bus (the CAN link)."""

    def inject_fault(self, fault: LinkFault) -> None: ...


Item = TypeVar("Item")


class FaultyWire(Generic[Item]):
    """One direction of the bus: items pass, are lost or wait (module docstring)."""

    def __init__(self, direction: Direction):
        self.direction = direction
        self.lost = 0
        self.delayed = 0
        self._queue: deque[tuple[int, Item]] = deque()  # (due cycle, item), in order
        self._matched: dict[LinkFault, int] = {}  # frames a loss fault has seen (for every)

    def put(self, item: Item, area: str, cycle: int, faults: Sequence[LinkFault]) -> None:
        due = cycle
        for fault in faults:
            if not fault.applies(self.direction, area, cycle):
                continue
            if fault.kind is LinkFaultKind.DELAY:
                due = max(due, cycle + fault.delay)
                continue
            seen = self._matched.get(fault, 0) + 1
            self._matched[fault] = seen
            if fault.kind is LinkFaultKind.BUS_OFF or seen % fault.every == 0:
                self.lost += 1
                return
        if self._queue:
            due = max(due, self._queue[-1][0])
        if due > cycle:
            self.delayed += 1
        self._queue.append((due, item))

    def take(self, cycle: int) -> Iterator[Item]:
        """The items due by ``cycle``, in their order."""
        queue = self._queue
        while queue and queue[0][0] <= cycle:
            yield queue.popleft()[1]

    @property
    def waiting(self) -> int:
        return len(self._queue)


def active(faults: Iterable[LinkFault], cycle: int) -> list[LinkFault]:
    """The faults that have not ended by ``cycle``."""
    return [fault for fault in faults if fault.end > cycle]
