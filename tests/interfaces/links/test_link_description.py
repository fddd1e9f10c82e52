"""The interface description the harness sends its PLC, over Modbus registers or CAN frames."""

from __future__ import annotations

import dataclasses

import pytest

from interfaces.links.can.codec import CanSettings
from interfaces.links.description import DescriptionError, LinkDescription, PlcSetupError

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


def test_the_description_says_where_the_alarm_block_is_and_what_its_codes_mean() -> None:
    from interfaces.catalog import load_catalog
    from interfaces.links.modbus.codec import RegisterMap, Table
    from interfaces.plant_io import PlantIoMap
    from interfaces.plc import PlcEnvironment
    from interfaces.signals import InterfaceLayout, expand

    catalog = expand(load_catalog(), InterfaceLayout(("CHAN1",), ("X1", "SP1")))
    plant_io = PlantIoMap.from_mapping({"I0.0": "MCP.auto"}, ("X1", "SP1"))
    register_map = RegisterMap.build(catalog, plant_io.area_sizes())
    described = LinkDescription.of(PlcEnvironment(catalog, plant_io, 0.01, {}, "m", 2000, 5), None, register_map)
    alarms = LinkDescription.from_json(described.to_json()).alarms
    location = register_map.location(catalog.resolve("ALARMS.list.in.count"))
    assert location is not None and location.table is Table.NC_TO_PLC
    assert (alarms["data_block"], alarms["input_register"], alarms["entries"]) == (100, location.register, 8)
    # the alarm block is the last range but the software cams (DB10.DBB110-117, four registers behind it)
    assert alarms["input_register"] + 34 + 4 == register_map.registers(Table.NC_TO_PLC)
    assert alarms["cleared_by"][4].startswith("emergency stop released, acknowledged with DB10.DBX56.2")
