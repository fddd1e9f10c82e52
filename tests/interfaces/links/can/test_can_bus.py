"""The python-can adapter: bus names, a node hears only what it listens to (on UDP multicast not its
own frames), errors become LinkError; the controller's state from python-can and SocketCAN's error
frames (with a stand-in interface); error frames on the wire of UDP multicast count receive errors
and never make the node bus-off; datagrams that are no frames are dropped; SocketCAN where the
kernel has it (skipped otherwise)."""

from __future__ import annotations

import socket
import time
from collections.abc import Callable

import can
import pytest

from interfaces.links.can.bus import (
    CAN_ERR_BUSOFF,
    CAN_ERR_CNT,
    CAN_ERR_CRTL,
    CAN_ERR_CRTL_TX_PASSIVE,
    CAN_ERR_RESTARTED,
    BusSpec,
    CanBus,
    ControllerState,
    private_udp_bus,
    private_virtual_bus,
    socketcan_available,
)
from interfaces.links.can.codec import Frame
from interfaces.links.errors import LinkError

TIMEOUT_S = 2.0


def test_bus_names_with_their_defaults_and_back_to_text() -> None:
    assert BusSpec.parse("udp_multicast") == BusSpec("udp_multicast", "239.74.163.2", 43113)
    assert BusSpec.parse("udp_multicast:239.1.2.3:5000") == BusSpec("udp_multicast", "239.1.2.3", 5000)
    assert BusSpec.parse("virtual") == BusSpec("virtual", "vc")
    assert BusSpec.parse("socketcan") == BusSpec("socketcan", "can0")
    assert BusSpec.parse("socketcan:vcan0") == BusSpec("socketcan", "vcan0")
    for text in ("udp_multicast:239.1.2.3:5000", "virtual:bench", "socketcan:can1"):
        assert str(BusSpec.parse(text)) == text


@pytest.mark.parametrize(("text", "message"), [
    ("can0", "'can0': the bus is one of virtual, udp_multicast, socketcan (e.g. udp_multicast, socketcan:can0,"
             " virtual)"),
    ("udp_multicast:10.0.0.1:5000", "'udp_multicast:10.0.0.1:5000': 10.0.0.1 is not a multicast group (224.0.0.0 .."
                                    " 239.255.255.255)"),
    ("udp_multicast:239.1.2.3:0", "'udp_multicast:239.1.2.3:0': udp_multicast takes GROUP:PORT, e.g."
                                  " udp_multicast:239.74.163.2:43113"),
])
def test_a_bad_bus_name_says_what_is_accepted(text: str, message: str) -> None:
    with pytest.raises(LinkError) as caught:
        BusSpec.parse(text)
    assert str(caught.value) == message


def test_a_bus_that_cannot_be_opened_is_a_link_error() -> None:
    with pytest.raises(LinkError, match=r"^cannot open the CAN bus socketcan:nosuchcan0: "):
        CanBus(BusSpec("socketcan", "nosuchcan0"))


def _exchange(spec: BusSpec) -> None:
    nc, plc = CanBus(spec, listen=(0x101, 0x400)), CanBus(spec, listen=(0x100, 0x200))
    try:
        nc.send(Frame(0x200, bytes(range(48))))
        nc.send(Frame(0x300, b"\x01"))  # nobody listens
        nc.send(Frame(0x100, bytes(8), fd=False))
        assert plc.receive(TIMEOUT_S) == Frame(0x200, bytes(range(48)), True)
        assert plc.receive(TIMEOUT_S) == Frame(0x100, bytes(8), False)
        assert plc.receive(0) is None
        plc.send(Frame(0x400, b"\xaa" * 12))
        assert nc.receive(TIMEOUT_S) == Frame(0x400, b"\xaa" * 12, True)  # after its own three frames, if echoed
        assert nc.receive(0) is None
        assert (nc.sent, nc.received, plc.sent, plc.received) == (3, 1, 1, 2)
    finally:
        nc.close()
        plc.close()


def test_two_nodes_on_a_virtual_bus() -> None:
    _exchange(private_virtual_bus())


def test_two_nodes_on_udp_multicast_drop_their_own_frames() -> None:
    spec = private_udp_bus()
    assert spec.kind == "udp_multicast" and spec.channel.startswith("239.74.")
    _exchange(spec)


def test_the_own_frames_of_udp_multicast_are_counted_as_dropped() -> None:
    node = CanBus(private_udp_bus(), listen=(0x101,))
    try:
        node.send(Frame(0x100, bytes(8)))
        assert node.receive(0.2) is None
        assert node.dropped == 1
    finally:
        node.close()


@pytest.mark.skipif(not socketcan_available("vcan0"), reason="this kernel has no SocketCAN / no vcan0 interface")
def test_two_nodes_on_socketcan_vcan0() -> None:
    _exchange(BusSpec("socketcan", "vcan0"))


class _Interface(can.BusABC):
    """A stand-in for a SocketCAN interface: hands out the messages given, refuses sends when told,
    and reports a state as python-can's interfaces do."""

    def __init__(self, messages: list[can.Message], state: can.BusState = can.BusState.ACTIVE):
        super().__init__(channel="fake")
        self.messages = messages
        self.reported = state
        self.sent: list[can.Message] = []

    @property
    def state(self) -> can.BusState:
        return self.reported

    def send(self, msg: can.Message, timeout: float | None = None) -> None:
        self.sent.append(msg)

    def _recv_internal(self, timeout: float | None) -> tuple[can.Message | None, bool]:
        return (self.messages.pop(0) if self.messages else None), False


def _error_frame(error_class: int, data: bytes = bytes(8)) -> can.Message:
    return can.Message(arbitration_id=error_class, data=data, is_error_frame=True, is_extended_id=False)


def test_socketcan_error_frames_give_the_controller_state_and_its_counters() -> None:
    interface = _Interface([])
    bus = CanBus(BusSpec("socketcan", "can0"), listen={0x101}, opened=interface)
    assert bus.state is ControllerState.ERROR_ACTIVE
    interface.messages = [_error_frame(CAN_ERR_CRTL | CAN_ERR_CNT,
                                       bytes([0, CAN_ERR_CRTL_TX_PASSIVE, 0, 0, 0, 0, 131, 7]))]
    assert bus.receive(0) is None
    assert (bus.state, bus.transmit_errors, bus.receive_errors) == (ControllerState.ERROR_PASSIVE, 131, 7)
    interface.messages = [_error_frame(CAN_ERR_BUSOFF)]
    assert bus.receive(0) is None and bus.bus_off
    interface.messages = [_error_frame(CAN_ERR_RESTARTED)]
    assert bus.receive(0) is None and bus.state is ControllerState.ERROR_ACTIVE
    assert (bus.transmit_errors, bus.receive_errors) == (0, 0)  # the restart clears the counters
    interface.messages = [_error_frame(CAN_ERR_BUSOFF), can.Message(arbitration_id=0x101, data=b"x",
                                                                    is_extended_id=False)]
    assert bus.receive(0) == Frame(0x101, b"x", False)
    assert bus.state is ControllerState.ERROR_ACTIVE  # a frame arrived: the controller is back
    assert bus.error_frames == 4


def test_the_state_python_can_reports_counts_too() -> None:
    interface = _Interface([], can.BusState.ERROR)
    bus = CanBus(BusSpec("socketcan", "can0"), opened=interface)
    assert bus.state is ControllerState.BUS_OFF
    interface.reported = can.BusState.PASSIVE
    assert bus.state is ControllerState.ERROR_PASSIVE


def _drain(node: CanBus, until: Callable[[], bool]) -> None:
    deadline = time.monotonic() + TIMEOUT_S
    while not until() and time.monotonic() < deadline:
        node.receive(0.05)


def test_a_datagram_that_is_no_frame_is_dropped_and_counted() -> None:
    spec = private_udp_bus()
    nc, plc = CanBus(spec, listen=(0x101,)), CanBus(spec, listen=(0x100,))
    try:
        with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as stranger:
            stranger.setsockopt(socket.IPPROTO_IP, socket.IP_MULTICAST_TTL, 0)  # stays on the host
            for garbage in (b"\x00", b"no frame at all", b"\x81\xa1x\x01", bytes(range(256))):
                stranger.sendto(garbage, (spec.channel, spec.port))
        plc.send(Frame(0x101, b"after the noise"))
        assert nc.receive(TIMEOUT_S) == Frame(0x101, b"after the noise", True)
        assert nc.foreign == 4
    finally:
        nc.close()
        plc.close()


def test_error_frames_on_the_wire_count_receive_errors_and_never_make_the_node_bus_off() -> None:
    spec = private_udp_bus()
    nc, disturbance = CanBus(spec, listen=(0x101,)), CanBus(spec, listen=())
    try:
        for _ in range(20):  # each one even says "bus-off": it is another node's, not this controller's
            disturbance.send_error_frame(CAN_ERR_BUSOFF | CAN_ERR_CRTL)
        _drain(nc, lambda: nc.error_frames == 20)
        assert (nc.error_frames, nc.receive_errors, nc.state) == (20, 20, ControllerState.ERROR_ACTIVE)
        for _ in range(110):
            disturbance.send_error_frame(CAN_ERR_BUSOFF)
        _drain(nc, lambda: nc.error_frames == 130)
        assert (nc.receive_errors, nc.state) == (130, ControllerState.ERROR_PASSIVE)
        disturbance.send(Frame(0x101, b"ok"))
        assert nc.receive(TIMEOUT_S) == Frame(0x101, b"ok", True)
        assert (nc.receive_errors, nc.state) == (127, ControllerState.ERROR_ACTIVE)  # ISO 11898-1: 119..127
    finally:
        nc.close()
        disturbance.close()
