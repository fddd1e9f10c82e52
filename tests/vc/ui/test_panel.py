"""The panel and the force rules come from the machine file (vc/ui/panel.py)."""

from __future__ import annotations

import pytest

from interfaces.signals import UnknownSignalError
from vc.config.loader import load_machine
from vc.config.machine_files import machine_file
from vc.ui.panel import ControlKind, Rules, lamps, panel_controls


@pytest.fixture(scope="module")
def turn_mill():  # type: ignore[no-untyped-def]
    path = machine_file("turn_mill")
    assert path is not None
    return load_machine(path)


def test_the_panel_has_exactly_the_operator_points_of_the_machine_file(turn_mill) -> None:  # type: ignore[no-untyped-def]
    controls = {control.name: control for control in panel_controls(turn_mill.plant_io)}
    operator = {point.name for point in turn_mill.plant_io.points if point.owner.value == "operator"}
    assert set(controls) == operator
    assert controls["MCP.jog"].kind is ControlKind.KEY and controls["MCP.jog"].group == "modes"
    assert controls["MCP.plus.X1"].label == "X1 +"
    assert controls["EStop.chainOk"].kind is ControlKind.SWITCH
    assert controls["MCP.feedOverride"].kind is ControlKind.KNOB and controls["MCP.feedOverride"].maximum == 200
    assert "X1.refCam" not in controls  # a sensor is the plant's: forced in the watch table, never pressed
    assert "Lamp.ncStart" in lamps(turn_mill.plant_io)


def test_keys_only_of_the_panel_and_in_range(turn_mill) -> None:  # type: ignore[no-untyped-def]
    rules = Rules(turn_mill.plant_io, ())
    assert rules.key_refusal("MCP.jog", 1) is None
    assert "no key or switch" in str(rules.key_refusal("X1.refCam", 1))
    assert "no key or switch" in str(rules.key_refusal("DB21.DBX7.1", 1))
    assert "out of range" in str(rules.key_refusal("MCP.jog", 2))
    assert "out of range" in str(rules.key_refusal("MCP.feedOverride", 201))
    assert rules.key_refusal("MCP.feedOverride", 120) is None
    assert "finite" in str(rules.key_refusal("MCP.feedOverride", float("nan")))


def test_force_rules(turn_mill) -> None:  # type: ignore[no-untyped-def]
    cam = turn_mill.plant_io.resolve("X1.refCam")
    open_rules, writer_rules = Rules(turn_mill.plant_io, ()), Rules(turn_mill.plant_io, ("127.0.0.1",))
    assert open_rules.force_refusal(cam, 1, "127.0.0.1") is None
    assert "out of range" in str(open_rules.force_refusal(cam, 3, "127.0.0.1"))
    lamp = turn_mill.plant_io.resolve("Lamp.ncStart")
    assert "not forced" in str(open_rules.force_refusal(lamp, 1, "127.0.0.1"))
    with pytest.raises(UnknownSignalError):
        turn_mill.plant_io.resolve("X9.refCam")
    assert writer_rules.writers.admits("127.0.0.1") and not writer_rules.writers.admits("10.0.0.1")
