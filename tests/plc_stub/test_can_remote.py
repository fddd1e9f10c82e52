"""``python -m plc_stub --can``: what it says and how it ends when there is nothing to run for.
(The PLC on the bus with a harness: tests/vc/harness/test_can_link.py.)"""

from __future__ import annotations

import pytest

from interfaces.links.can_bus import private_udp_bus
from plc_stub.__main__ import main
from plc_stub.can_remote import run_on_can


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
    assert run_on_can("fieldbus", None, None, 1.0, said.append) == 1
    assert said == ["'fieldbus': the bus is one of virtual, udp_multicast, socketcan (e.g. udp_multicast,"
                    " socketcan:can0, virtual)"]


def test_without_a_harness_on_the_bus_it_gives_up_after_the_time_out() -> None:
    said: list[str] = []
    bus = private_udp_bus()
    assert run_on_can(str(bus), None, None, 0.3, said.append) == 1
    assert said == [f"listening on the CAN bus {bus}, link frames from 0x100",
                    f"no harness heard on {bus} for 0.3 s"]
