"""The traverse keys in JOG (vc/core/axis/jog_keys.py): incremental JOG in jog and continuous mode,
continuous JOG in continuous mode, and what ends a motion; driven cycle by cycle on one axis.
Through the whole NC (DB31.DBX5.x / 65.x, MD11330, SD41010, MD31090): tests/vc/core/nck/test_jog_functions.py."""

from __future__ import annotations

import pytest
from core_rig import ABSOLUTE_X1, Rig, machine

from vc.core.axis.axis import MachineAxis
from vc.core.axis.jog import FREE_JOG
from vc.core.axis.jog_keys import CONTINUOUS_JOG, JogKeyState, JogSelection
from vc.core.axis.owner import Owner

INC_HELD = JogSelection(10.0)  # 10 mm, jog mode (MD11300 = 1)
INC_LATCHED = JogSelection(10.0, increment_held=False)  # continuous mode (MD11300 = 0)
CONTINUOUS_LATCHED = JogSelection(0.0, continuous_held=False)  # SD41050 = 0


def enabled_x1() -> MachineAxis:
    axis = Rig(machine(ABSOLUTE_X1)).axis("X1")
    axis.inputs.controller_enable = axis.inputs.pulse_enable = True
    return axis


def jog(axis: MachineAxis, cycles: int, selection: JogSelection, allowed: bool = True) -> None:
    for _ in range(cycles):
        axis.jog.cycle(axis, allowed, False, FREE_JOG, selection)


def test_jog_mode_the_held_key_travels_the_increment_exactly_then_waits_for_the_release() -> None:
    axis = enabled_x1()
    axis.inputs.key_plus = True
    jog(axis, 10, INC_HELD)
    assert axis.jog.keys.state is JogKeyState.INCREMENT and axis.owner is Owner.JOG
    jog(axis, 1000, INC_HELD)
    assert axis.setpoint == pytest.approx(160.0, abs=1e-9)
    assert axis.jog.keys.state is JogKeyState.AT_END and axis.owner is Owner.NONE
    jog(axis, 100, INC_HELD)
    assert axis.setpoint == pytest.approx(160.0, abs=1e-9)  # held on: no second increment
    axis.inputs.key_plus = False
    jog(axis, 1, INC_HELD)
    assert axis.jog.keys.state is JogKeyState.IDLE and not axis.jog.keys.busy
    axis.inputs.key_plus = True
    jog(axis, 1000, INC_HELD)
    assert axis.setpoint == pytest.approx(170.0, abs=1e-9)  # a new press: the next increment


def test_jog_mode_released_early_it_stops_keeps_the_rest_and_the_same_key_goes_on() -> None:
    axis = enabled_x1()
    axis.inputs.key_plus = True
    jog(axis, 20, INC_HELD)
    axis.inputs.key_plus = False
    jog(axis, 100, INC_HELD)
    stopped = axis.setpoint
    assert 150.0 < stopped < 160.0 and axis.command_velocity == 0.0
    assert axis.jog.keys.state is JogKeyState.INCREMENT_HELD
    assert axis.jog.keys.rest == pytest.approx(160.0 - stopped, abs=1e-9)
    axis.inputs.key_minus = True  # the other key does nothing until the increment is done
    jog(axis, 100, INC_HELD)
    assert axis.setpoint == stopped
    axis.inputs.key_minus = False
    axis.inputs.key_plus = True
    jog(axis, 1000, INC_HELD)
    assert axis.setpoint == pytest.approx(160.0, abs=1e-9)


def test_continuous_mode_a_press_travels_the_whole_increment_a_second_press_ends_it() -> None:
    axis = enabled_x1()
    axis.inputs.key_minus = True
    jog(axis, 2, INC_LATCHED)
    axis.inputs.key_minus = False
    jog(axis, 1000, INC_LATCHED)
    assert axis.setpoint == pytest.approx(140.0, abs=1e-9) and axis.owner is Owner.NONE
    axis.inputs.key_minus = True
    jog(axis, 20, INC_LATCHED)
    axis.inputs.key_minus = False
    jog(axis, 5, INC_LATCHED)
    axis.inputs.key_minus = True  # the same key again: the rest is dropped, the axis brakes
    jog(axis, 100, INC_LATCHED)
    assert 130.0 < axis.setpoint < 140.0 and axis.command_velocity == 0.0
    assert axis.jog.keys.state is JogKeyState.AT_END and axis.jog.keys.rest == 0.0


@pytest.mark.parametrize("end", ["reset_movement", "selection", "jog_left", "owner", "enables"])
def test_an_increment_ends_on_dbx2_2_a_new_increment_leaving_jog_another_owner_the_enables(end: str) -> None:
    axis = enabled_x1()
    axis.inputs.key_plus = True
    jog(axis, 20, INC_LATCHED)
    axis.inputs.key_plus = False
    selection, allowed = INC_LATCHED, True
    if end == "reset_movement":
        axis.inputs.reset_movement = True
    elif end == "selection":
        selection = JogSelection(1.0, increment_held=False)  # INC10000 -> INC1000 (L32861)
    elif end == "jog_left":
        allowed = False
    elif end == "owner":
        axis.brake()  # the channel's RESET brakes a JOG axis
    else:
        axis.inputs.controller_enable = False
    jog(axis, 1, selection, allowed)
    assert axis.jog.keys.state is JogKeyState.IDLE and axis.jog.keys.rest == 0.0
    axis.inputs.reset_movement, axis.inputs.controller_enable = False, True
    if axis.owner is Owner.BRAKE:
        axis.release()  # the brake has stopped it
    jog(axis, 300, selection)
    assert axis.setpoint < 159.0 and axis.command_velocity == 0.0  # the rest is not travelled


def test_a_negative_weight_reverses_the_key_of_an_increment() -> None:
    axis = enabled_x1()
    axis.inputs.key_plus = True
    jog(axis, 1000, JogSelection(-10.0))
    assert axis.setpoint == pytest.approx(140.0, abs=1e-9)


def test_the_increment_stops_on_the_software_limit_switch() -> None:
    axis = enabled_x1()
    plus = axis.software_limits[1]
    axis.setpoint = plus - 5.0
    axis.inputs.key_plus = True
    jog(axis, 1000, INC_HELD)
    assert axis.setpoint == plus and axis.jog.keys.state is JogKeyState.AT_END


def test_continuous_jog_in_continuous_mode_runs_on_after_the_release_until_a_key_is_pressed_again() -> None:
    axis = enabled_x1()
    axis.inputs.key_plus = True
    jog(axis, 2, CONTINUOUS_LATCHED)
    axis.inputs.key_plus = False
    jog(axis, 200, CONTINUOUS_LATCHED)
    assert axis.command_velocity == pytest.approx(2000.0 / 60.0)
    axis.inputs.key_minus = True  # the other key stops it (L32658)
    jog(axis, 200, CONTINUOUS_LATCHED)
    assert axis.command_velocity == 0.0 and axis.owner is Owner.NONE
    axis.inputs.key_minus = False
    jog(axis, 1, CONTINUOUS_LATCHED)
    assert axis.jog.keys.state is JogKeyState.IDLE


def test_continuous_jog_in_jog_mode_follows_the_key() -> None:
    axis = enabled_x1()
    axis.inputs.key_plus = True
    jog(axis, 200, CONTINUOUS_JOG)
    assert axis.jog.keys.state is JogKeyState.CONTINUOUS
    axis.inputs.key_plus = False
    jog(axis, 200, CONTINUOUS_JOG)
    assert axis.command_velocity == 0.0 and axis.jog.keys.state is JogKeyState.IDLE
