"""Faults of the bus between the NC and the PLC, as a scenario injects them (``link_fault`` step).

Three kinds, each for a window of NC cycles (``for:``), on the frames of one direction or both,
optionally only those of some areas (``DB31``, ``Q``, ``I`` ..., ``link`` = the link frames):

* ``loss``: the frames are lost (``every: n``: only every n-th of them);
* ``delay``: the frames arrive ``delay`` later; nothing overtakes a delayed frame, so the frames
  behind it wait as well until the queue has drained;
* ``bus_off``: a disturbance of the bus (a short, a node with the wrong bit rate) drives the
  NC's CAN controller bus-off (:class:`CanController`): while it lasts no frame gets through
  either way, and every frame the controller tries to send counts its transmit error counter up.

:class:`FaultyWire` is one direction of the bus under loss and delay: frames go in when they are
sent (or received), and come out when they are due, in their order.  Time is the NC cycle.
"""

from __future__ import annotations

from collections import deque
from collections.abc import Iterable, Iterator, Sequence
from dataclasses import dataclass
from enum import StrEnum
from typing import Generic, Protocol, TypeVar, runtime_checkable

from interfaces.links.can.codec import ControllerState
from interfaces.signals import Direction
from vc.simulation.observables import LINK_AREA as LINK_AREA  # the link frames among a fault's areas


class LinkFaultKind(StrEnum):
    """The kinds of ``LINK_FAULTS`` in vc/simulation/observables.py."""

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
        """Whether this loss or delay hits a frame of ``area`` sent in ``direction`` in ``cycle``."""
        if not self.start <= cycle < self.end or self.kind is LinkFaultKind.BUS_OFF:
            return False
        return direction in self.directions and (not self.areas or area in self.areas)


def disturbed(faults: Iterable[LinkFault], cycle: int) -> bool:
    """Whether a disturbance (``bus_off``) holds the bus in ``cycle``."""
    return any(fault.kind is LinkFaultKind.BUS_OFF and fault.start <= cycle < fault.end for fault in faults)


@runtime_checkable
class FaultInjectable(Protocol):
    """A PLC link that takes faults of its bus and shows its counters (the CAN link): a capability
    beside the links' contract (vc/harness/links/), which the Modbus and S7 link do not have."""

    def inject_fault(self, fault: LinkFault) -> None: ...

    def quantity(self, name: str) -> float:
        """One of ``LINK_QUANTITIES`` in vc/simulation/observables.py."""


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
        if self.loses(area, cycle, faults):
            return
        due = cycle
        for fault in faults:
            if fault.kind is LinkFaultKind.DELAY and fault.applies(self.direction, area, cycle):
                due = max(due, cycle + fault.delay)
        if self._queue:
            due = max(due, self._queue[-1][0])
        if due > cycle:
            self.delayed += 1
        self._queue.append((due, item))

    def loses(self, area: str, cycle: int, faults: Sequence[LinkFault]) -> bool:
        """Whether a loss fault takes the frame of ``area`` sent now (counted as lost)."""
        for fault in faults:
            if fault.kind is LinkFaultKind.LOSS and fault.applies(self.direction, area, cycle):
                seen = self._matched.get(fault, 0) + 1
                self._matched[fault] = seen
                if seen % fault.every == 0:
                    self.lost += 1
                    return True
        return False

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


# ISO 11898-1 fault confinement: a failed transmission counts the transmit error counter up by 8,
# a successful one down by 1; at 128 the controller is error passive, beyond 255 bus-off.
TRANSMIT_ERROR_STEP = 8
ERROR_PASSIVE_LIMIT = 128
BUS_OFF_LIMIT = 255
RECOVERY_BITS = 128 * 11  # a controller leaves bus-off after 128 times 11 recessive bits
NOMINAL_BITRATE = 500_000  # [INF] bit/s of the arbitration phase (docs/can.md: bus load)


@dataclass(slots=True)
class CanController:
    """The NC's CAN controller under disturbances of the bus: error counter, state, restarts.

    Each frame is sent once (SocketCAN's one-shot mode; a controller that retransmits on its own
    would fail 32 times on one frame within milliseconds [INF]).  While the bus is disturbed every
    transmission fails: after 32 of them the counter passes 255
    and the controller is bus-off, so a short disturbance keeps it off the bus far longer than
    it lasts.  ``restart_cycles`` after it went bus-off the controller restarts (``can.restart``;
    0: never by itself) and takes part again, counter at 0, once it has seen
    ``recovery_cycles`` of undisturbed bus (128 x 11 recessive bits, which a disturbed bus does
    not give).  Time is the NC cycle."""

    restart_cycles: int
    recovery_cycles: int
    state: ControllerState = ControllerState.ERROR_ACTIVE
    transmit_errors: int = 0
    bus_offs: int = 0  # times the controller went bus-off
    _restart_at: int = -1  # the cycle the restart is due (bus-off), -1: none
    _quiet_since: int = -1  # first cycle of undisturbed bus after the restart, -1: not yet

    @classmethod
    def for_cycle(cls, restart_cycles: int, ipo_cycle_us: int) -> CanController:
        return cls(restart_cycles, -(-RECOVERY_BITS * 1_000_000 // (NOMINAL_BITRATE * ipo_cycle_us)))

    def transmit(self, cycle: int, disturbed: bool) -> bool:
        """One frame to send in ``cycle``: True when it gets on the bus."""
        if self.state is ControllerState.BUS_OFF:
            return False
        if not disturbed:
            self.transmit_errors = max(0, self.transmit_errors - 1)
            if self.transmit_errors < ERROR_PASSIVE_LIMIT:
                self.state = ControllerState.ERROR_ACTIVE
            return True
        self.transmit_errors += TRANSMIT_ERROR_STEP
        if self.transmit_errors > BUS_OFF_LIMIT:
            self.state = ControllerState.BUS_OFF
            self.bus_offs += 1
            self._restart_at = cycle + self.restart_cycles if self.restart_cycles else -1
            self._quiet_since = -1
        elif self.transmit_errors >= ERROR_PASSIVE_LIMIT:
            self.state = ControllerState.ERROR_PASSIVE
        return False

    def receives(self, disturbed: bool) -> bool:
        """Whether a frame of the other node gets through to the NC now."""
        return self.state is not ControllerState.BUS_OFF and not disturbed

    def tick(self, cycle: int, disturbed: bool) -> None:
        """Every NC cycle: the restart after bus-off and the recovery that follows it."""
        if self.state is not ControllerState.BUS_OFF or self._restart_at < 0 or cycle < self._restart_at:
            return
        if disturbed:
            self._quiet_since = -1
            return
        if self._quiet_since < 0:
            self._quiet_since = cycle
        if cycle - self._quiet_since >= self.recovery_cycles:
            self.state, self.transmit_errors, self._restart_at = ControllerState.ERROR_ACTIVE, 0, -1
