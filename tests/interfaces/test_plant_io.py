"""The plant I/O vocabulary of a spindle gearbox and chuck: actuators are PLC outputs, sensors plant
inputs; the guard door switch is the operator's."""

from __future__ import annotations

import pytest

from interfaces.plant_io import (
    GearboxPoint,
    PlantIoError,
    PlantIoMap,
    PointOwner,
    chuck_axis,
    chuck_close,
    chuck_closed,
    chuck_open,
    chuck_release,
    gear_engaged,
    gear_neutral,
    gear_shift,
    gearbox_point,
    plant_function,
)
from interfaces.signals import Direction


@pytest.mark.parametrize(("name", "direction", "owner"), [
    ("SP1.gearShift1", Direction.PLC_TO_PLANT, PointOwner.PLC),
    ("SP1.gearShift5", Direction.PLC_TO_PLANT, PointOwner.PLC),
    ("SP1.gearEngaged3", Direction.PLANT_TO_PLC, PointOwner.PLANT),
    ("SP1.gearNeutral", Direction.PLANT_TO_PLC, PointOwner.PLANT),
    ("SP1.chuckClose", Direction.PLC_TO_PLANT, PointOwner.PLC),
    ("SP1.chuckRelease", Direction.PLC_TO_PLANT, PointOwner.PLC),
    ("SP2.chuckClosed", Direction.PLANT_TO_PLC, PointOwner.PLANT),
    ("SP2.chuckOpen", Direction.PLANT_TO_PLC, PointOwner.PLANT),
    ("Door.closed", Direction.PLANT_TO_PLC, PointOwner.OPERATOR),
])
def test_gearbox_chuck_and_door_points_are_in_the_vocabulary(name: str, direction: Direction,
                                                             owner: PointOwner) -> None:
    function = plant_function(name)
    assert function is not None
    assert (function.direction, function.owner) == (direction, owner)


@pytest.mark.parametrize("name", ["SP1.gearShift0", "SP1.gearShift6", "SP1.gearEngaged", "SP1.gearNeutral1"])
def test_stages_outside_1_to_5_are_no_gearbox_points(name: str) -> None:
    assert plant_function(name) is None
    assert gearbox_point(name) is None


def test_gearbox_point_names_axis_kind_and_stage() -> None:
    assert gearbox_point(gear_shift("SP1", 2)) == GearboxPoint("SP1", "gearShift", 2)
    assert gearbox_point(gear_engaged("SP_2", 5)) == GearboxPoint("SP_2", "gearEngaged", 5)
    assert gearbox_point(gear_neutral("SP1")) == GearboxPoint("SP1", "gearNeutral", 0)
    assert gearbox_point("SP1.refCam") is None


def test_an_actuator_is_an_output_and_a_sensor_an_input() -> None:
    with pytest.raises(PlantIoError) as error:
        PlantIoMap.from_mapping({"I0.0": "SP1.gearShift1", "Q0.0": "SP1.gearEngaged1"}, ["SP1"])
    assert error.value.problems == [
        ("I0.0", "'SP1.gearShift1' is an output; wire it to Q, not I"),
        ("Q0.0", "'SP1.gearEngaged1' is an input; wire it to I, not Q"),
    ]


def test_chuck_point_names_its_spindle() -> None:
    names = [chuck_close("SP1"), chuck_release("SP1"), chuck_closed("SP_2"), chuck_open("SP_2")]
    assert names == ["SP1.chuckClose", "SP1.chuckRelease", "SP_2.chuckClosed", "SP_2.chuckOpen"]
    assert [chuck_axis(name) for name in names] == ["SP1", "SP1", "SP_2", "SP_2"]
    assert chuck_axis("SP1.chuckJaws") is None
    assert chuck_axis("Door.closed") is None
