"""``python -m plc_stub --can``: what it says and how it ends when there is nothing to run for, and
that noise on the bus does not end it.  (The PLC on the bus with a harness:
tests/vc/harness/links/test_can.py; under noise with a harness: tests/vc/bench/test_robustness.py.)"""

from __future__ import annotations

import socket
import threading

import pytest

from interfaces.links.can.bus import CAN_ERR_BUSOFF, CanBus, private_udp_bus
from interfaces.links.can.plc_end import run_plc
from interfaces.links.scan_loop import PlcProcessOptions
from plc_stub.__main__ import main
from plc_stub.programs import FACTORIES


def test_modbus_or_can_not_both(capsys: pytest.CaptureFixture[str]) -> None:
    with pytest.raises(SystemExit) as caught:
        main(["--modbus", "127.0.0.1:5020", "--can", "udp_multicast"])
    assert caught.value.code == 2
    assert "argument --can: not allowed with argument --modbus" in capsys.readouterr().err


def test_a_bad_link_identifier_is_refused(capsys: pytest.CaptureFixture[str]) -> None:
    with pytest.raises(SystemExit):
        main(["--can", "udp_multicast", "--can-link-id", "0x7FF"])
    assert "'0x7FF': the link frames need 0 .. 0x7FD" in capsys.readouterr().err


def test_a_bus_that_is_no_bus_ends_with_code_1() -> None:
    said: list[str] = []
    assert run_plc("fieldbus", FACTORIES, PlcProcessOptions(connect_timeout_s=1.0), said.append) == 1
    assert said == ["'fieldbus': the bus is one of virtual, udp_multicast, socketcan (e.g. udp_multicast,"
                    " socketcan:can0, virtual)"]


def test_without_a_harness_on_the_bus_it_gives_up_after_the_time_out() -> None:
    said: list[str] = []
    bus = private_udp_bus()
    assert run_plc(str(bus), FACTORIES, PlcProcessOptions(connect_timeout_s=0.3), said.append) == 1
    assert said == [f"listening on the CAN bus {bus}, link frames from 0x100",
                    f"no harness heard on {bus} for 0.3 s"]


def test_datagrams_that_are_no_frames_and_error_frames_do_not_end_it() -> None:
    """python-can raised on a datagram that was no frame of its own, and the PLC ended (code 1)."""
    said: list[str] = []
    bus = private_udp_bus()
    stop = threading.Event()
    codes: list[int] = []
    options = PlcProcessOptions(connect_timeout_s=30.0)
    plc = threading.Thread(target=lambda: codes.append(run_plc(str(bus), FACTORIES, options, said.append,
                                                               should_stop=stop.is_set)))
    plc.start()
    noise = CanBus(bus)
    try:
        with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as stranger:
            stranger.setsockopt(socket.IPPROTO_IP, socket.IP_MULTICAST_TTL, 0)
            for index in range(50):
                stranger.sendto(b"no frame %d" % index, (bus.channel, bus.port))
                noise.send_error_frame(CAN_ERR_BUSOFF)
        plc.join(1.0)
        assert plc.is_alive(), said  # still listening
    finally:
        stop.set()
        plc.join(10)
        noise.close()
    assert codes == [0]
    assert not any("bus lost" in line for line in said)
