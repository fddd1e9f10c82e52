"""Faults of the bus, frame by frame: lost (all or every n-th), delayed in order, bus-off."""

from __future__ import annotations

from interfaces.signals import Direction
from vc.harness.link_faults import FaultyWire, LinkFault, LinkFaultKind, active
from vc.observables import LINK_FAULTS

BOTH = frozenset((Direction.NC_TO_PLC, Direction.PLC_TO_NC))


def fault(kind: LinkFaultKind, start: int = 10, end: int = 20, *, areas: frozenset[str] = frozenset(),
          directions: frozenset[Direction] = BOTH, delay: int = 0, every: int = 1) -> LinkFault:
    return LinkFault(kind, start, end, directions, areas, delay, every)


def test_the_kinds_are_the_scenario_vocabulary() -> None:
    assert tuple(kind.value for kind in LinkFaultKind) == LINK_FAULTS


def test_without_faults_frames_pass_at_once_in_order() -> None:
    wire: FaultyWire[str] = FaultyWire(Direction.PLC_TO_NC)
    for name in "abc":
        wire.put(name, "DB31", 5, [])
    assert list(wire.take(5)) == ["a", "b", "c"] and wire.waiting == 0


def test_loss_in_its_window_direction_and_areas_only() -> None:
    wire: FaultyWire[str] = FaultyWire(Direction.PLC_TO_NC)
    faults = [fault(LinkFaultKind.LOSS, areas=frozenset({"DB31"}), directions=frozenset({Direction.PLC_TO_NC}))]
    wire.put("before", "DB31", 9, faults)
    wire.put("lost", "DB31", 10, faults)
    wire.put("other area", "DB32", 10, faults)
    wire.put("after", "DB31", 20, faults)
    assert list(wire.take(20)) == ["before", "other area", "after"] and wire.lost == 1
    other_way: FaultyWire[str] = FaultyWire(Direction.NC_TO_PLC)
    other_way.put("passes", "DB31", 15, faults)
    assert list(other_way.take(15)) == ["passes"]


def test_every_third_frame_is_lost() -> None:
    wire: FaultyWire[int] = FaultyWire(Direction.PLC_TO_NC)
    faults = [fault(LinkFaultKind.LOSS, 0, 100, every=3)]
    for number in range(1, 10):
        wire.put(number, "DB31", 1, faults)
    assert list(wire.take(1)) == [1, 2, 4, 5, 7, 8]


def test_a_delay_keeps_the_order_and_holds_the_frames_behind() -> None:
    wire: FaultyWire[str] = FaultyWire(Direction.PLC_TO_NC)
    faults = [fault(LinkFaultKind.DELAY, 10, 12, delay=5)]
    wire.put("late", "DB31", 11, faults)  # due at 16
    wire.put("behind", "DB31", 12, faults)  # the fault is over, but it may not overtake
    assert list(wire.take(15)) == []
    assert list(wire.take(16)) == ["late", "behind"]
    assert wire.delayed == 2


def test_bus_off_loses_everything_whatever_the_areas() -> None:
    wire: FaultyWire[str] = FaultyWire(Direction.NC_TO_PLC)
    faults = [fault(LinkFaultKind.BUS_OFF, areas=frozenset({"DB31"}), directions=frozenset({Direction.PLC_TO_NC}))]
    wire.put("x", "link", 10, faults)
    wire.put("y", "Q", 19, faults)
    assert list(wire.take(30)) == [] and wire.lost == 2


def test_ended_faults_are_dropped() -> None:
    faults = [fault(LinkFaultKind.LOSS, 0, 5), fault(LinkFaultKind.DELAY, 0, 50, delay=1)]
    assert active(faults, 10) == faults[1:]
