"""The interface description the harness sends its PLC, over Modbus registers or CAN frames."""

from __future__ import annotations

import dataclasses

import pytest

from interfaces.codec_can import CanSettings
from interfaces.link_description import DescriptionError, LinkDescription, PlcSetupError

DESCRIPTION = LinkDescription("turn_mill", ("CHAN1",), ("X1", "SP1"), {"I0.0": "MCP.auto"}, 2000, 5, "spindle",
                              {"esr_time": 0.3}, 323, 132)


def test_the_description_comes_back_as_it_was_sent() -> None:
    assert LinkDescription.from_json(DESCRIPTION.to_json()) == DESCRIPTION
    over_can = dataclasses.replace(DESCRIPTION, can=CanSettings(link_id=0x300, fd=False), can_timeout_us=120_000)
    received = LinkDescription.from_json(over_can.to_json())
    assert (received.can, received.can_timeout_us) == (CanSettings(link_id=0x300, fd=False), 120_000)


@pytest.mark.parametrize("text", [b"", b"{", b'{"format": 99}', b'{"format": 1}', b"\xff"])
def test_a_plc_refuses_what_it_cannot_read_with_its_setup_error(text: bytes) -> None:
    with pytest.raises(DescriptionError):
        LinkDescription.from_json(text)
    with pytest.raises(PlcSetupError):
        LinkDescription.for_plc(text)
