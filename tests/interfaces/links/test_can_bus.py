"""The python-can adapter: bus names, a node hears only what it listens to (on UDP multicast not its
own frames), errors become LinkError; SocketCAN where the kernel has it (skipped otherwise)."""

from __future__ import annotations

import pytest

from interfaces.codec_can import Frame
from interfaces.links.can_bus import BusSpec, CanBus, private_udp_bus, private_virtual_bus, socketcan_available
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
