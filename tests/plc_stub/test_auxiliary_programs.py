"""The PLC programs of the auxiliary functions (coolant, turret, tool_change): how they build on
each other and the turret's choice of direction; the scenarios under
scenarios/auxiliary_functions/ run them against the NC and the plant."""

from __future__ import annotations

import pytest

from plc_stub.programs import REGISTRY
from plc_stub.programs.auxiliary import AuxiliaryMachine
from plc_stub.programs.coolant import Coolant
from plc_stub.programs.spindle import Spindle
from plc_stub.programs.tool_change import ToolChange
from plc_stub.programs.turret import Turret, shorter_way_clockwise


@pytest.mark.parametrize(("station", "target", "clockwise"), [
    (1, 5, True),  # 4 either way: clockwise
    (5, 2, False), (1, 8, False), (8, 1, True), (7, 2, True), (2, 7, False), (3, 3, True)])
def test_turret_turns_the_shorter_way(station: int, target: int, clockwise: bool) -> None:
    assert shorter_way_clockwise(station, target, 8) is clockwise


def test_programs_build_on_spindle_and_coolant() -> None:
    assert REGISTRY["coolant"] is Coolant and REGISTRY["turret"] is Turret and REGISTRY["tool_change"] is ToolChange
    for program in (Coolant, Turret, ToolChange):
        assert issubclass(program, AuxiliaryMachine) and issubclass(program, Spindle)
    assert issubclass(Turret, Coolant) and issubclass(ToolChange, Coolant)
