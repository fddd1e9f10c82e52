"""Faults of the bus, frame by frame: lost (all or every n-th), delayed in order; a disturbance that
drives the NC's CAN controller bus-off, its error counter and its restart."""

from __future__ import annotations

from interfaces.links.can.codec import ControllerState
from interfaces.signals import Direction
from vc.simulation.link_faults import CanController, FaultyWire, LinkFault, LinkFaultKind, active, disturbed
from vc.simulation.observables import LINK_FAULTS

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


def test_a_disturbance_is_no_loss_of_the_wire_but_holds_the_bus_both_ways_in_its_window() -> None:
    """bus_off acts through the controller (below), whatever its areas and directions."""
    wire: FaultyWire[str] = FaultyWire(Direction.NC_TO_PLC)
    faults = [fault(LinkFaultKind.BUS_OFF, areas=frozenset({"DB31"}), directions=frozenset({Direction.PLC_TO_NC}))]
    wire.put("x", "link", 10, faults)
    assert list(wire.take(10)) == ["x"] and wire.lost == 0
    assert [disturbed(faults, cycle) for cycle in (9, 10, 19, 20)] == [False, True, True, False]


def test_the_controller_goes_bus_off_after_32_failed_frames_and_restarts_on_a_quiet_bus() -> None:
    controller = CanController.for_cycle(restart_cycles=50, ipo_cycle_us=2000)
    assert controller.recovery_cycles == 2  # 128 x 11 bits at 500 kbit/s = 2.8 ms
    states = []
    for _ in range(32):
        assert not controller.transmit(10, disturbed=True)
        states.append(controller.state)
    assert states[14] is ControllerState.ERROR_ACTIVE and states[15] is ControllerState.ERROR_PASSIVE  # 128
    assert states[30] is ControllerState.ERROR_PASSIVE and states[31] is ControllerState.BUS_OFF  # 256 > 255
    assert (controller.transmit_errors, controller.bus_offs) == (256, 1)
    assert not controller.receives(disturbed=False)
    for cycle in range(11, 67):
        controller.tick(cycle, disturbed=cycle < 65)  # restart due at 60, the bus is quiet from 65
        assert controller.state is ControllerState.BUS_OFF, cycle
        assert not controller.transmit(cycle, disturbed=False)
    controller.tick(67, disturbed=False)  # 65 and 66 quiet: two cycles of recessive bits
    assert controller.state is ControllerState.ERROR_ACTIVE and controller.transmit_errors == 0
    assert controller.transmit(70, disturbed=False) and controller.receives(disturbed=False)


def test_the_error_counter_counts_down_on_success_and_without_restart_bus_off_stays() -> None:
    controller = CanController.for_cycle(restart_cycles=0, ipo_cycle_us=2000)
    for _ in range(16):
        controller.transmit(0, disturbed=True)
    assert controller.state is ControllerState.ERROR_PASSIVE and controller.transmit_errors == 128
    assert controller.transmit(1, disturbed=False)
    assert controller.state is ControllerState.ERROR_ACTIVE and controller.transmit_errors == 127
    for _ in range(20):
        controller.transmit(2, disturbed=True)
    for cycle in range(3, 10_000, 100):
        controller.tick(cycle, disturbed=False)
    assert controller.state is ControllerState.BUS_OFF


def test_ended_faults_are_dropped() -> None:
    faults = [fault(LinkFaultKind.LOSS, 0, 5), fault(LinkFaultKind.DELAY, 0, 50, delay=1)]
    assert active(faults, 10) == faults[1:]
