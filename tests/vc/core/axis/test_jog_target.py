"""JOG to a fixed point / to a position of one axis (vc/core/axis/jog_target.py): the selection, the
directions JOG may take, the reached fixed point, and the motion of vc/core/axis/jog.py stopping
exactly on the target.  Through the whole NC (DB31.DBX13.x / 75.x, alarms 17810 / 17812):
tests/vc/core/nck/test_jog_targets.py."""

from __future__ import annotations

import pytest
from core_rig import ABSOLUTE_X1, Rig, machine

from vc.core.axis.axis import MachineAxis
from vc.core.axis.jog import FREE_JOG, JogLimits
from vc.core.axis.jog_keys import CONTINUOUS_JOG, JogKeyState, JogSelection
from vc.core.axis.jog_target import JogTarget, JogTargetState
from vc.core.axis.owner import Owner

POINTS = (100.0, 200.0)


def target(reverse: bool = False) -> JogTarget:
    return JogTarget(POINTS, 250.0, 0.01, reverse)


def test_a_fixed_point_wins_over_jog_to_position_and_one_beyond_md30610_is_not_taken() -> None:
    jog_target = target()
    jog_target.select(2, True, True)
    assert (jog_target.fixed_point, jog_target.to_position, jog_target.target) == (2, False, 200.0)
    jog_target.select(0, True, True)
    assert (jog_target.fixed_point, jog_target.to_position, jog_target.target) == (0, True, 250.0)
    jog_target.select(3, False, True)  # MD30610 = 2
    assert jog_target.target is None and jog_target.state is JogTargetState.OFF


def test_outside_jog_nothing_is_active_and_only_a_change_between_two_fixed_points_counts() -> None:
    jog_target = target()
    assert not jog_target.select(1, True, False)
    assert jog_target.target is None and not jog_target.to_position
    assert not jog_target.select(1, False, True)
    assert jog_target.select(2, False, True)  # 1 -> 2: alarm 17812 if the axis travels
    assert not jog_target.select(0, False, True)
    assert not jog_target.select(1, False, True)


def test_towards_the_target_only_unless_md10735_bit_2_and_nowhere_without_the_reference_point() -> None:
    jog_target = target()
    assert jog_target.jog_limits(150.0, True) is FREE_JOG
    jog_target.select(2, False, True)
    below = jog_target.jog_limits(150.0, True)
    assert (below.plus, below.minus, below.target) == (True, False, 200.0)
    above = jog_target.jog_limits(230.0, True)
    assert (above.plus, above.minus) == (False, True)
    on = jog_target.jog_limits(200.0, True)
    assert (on.plus, on.minus) == (False, False)
    unreferenced = jog_target.jog_limits(150.0, False)
    assert (unreferenced.plus, unreferenced.minus) == (False, False)
    free = target(reverse=True)
    free.select(2, False, True)
    assert (free.jog_limits(200.0, True).plus, free.jog_limits(200.0, True).minus) == (True, True)


def test_reached_is_the_fixed_point_within_md36010_and_the_position_only_while_active() -> None:
    jog_target = target()
    assert jog_target.fixed_point_at(100.005, True) == 1
    assert jog_target.fixed_point_at(100.02, True) == 0
    assert jog_target.fixed_point_at(200.0, False) == 0  # not referenced
    jog_target.select(0, True, True)
    jog_target.follow(250.004, True)
    assert jog_target.state is JogTargetState.REACHED and jog_target.position_reached
    jog_target.follow(249.9, True)
    assert jog_target.state is JogTargetState.TOWARDS and not jog_target.position_reached
    jog_target.select(0, False, True)
    assert jog_target.state is JogTargetState.OFF and not jog_target.position_reached


# ------------------------------------------------------------------ the motion (vc/core/axis/jog.py)
def enabled_x1() -> MachineAxis:
    axis = Rig(machine(ABSOLUTE_X1)).axis("X1")  # referenced, standing on 150 mm
    axis.inputs.controller_enable = axis.inputs.pulse_enable = True
    return axis


def jog(axis: MachineAxis, cycles: int, limits: JogLimits, selection: JogSelection = CONTINUOUS_JOG) -> None:
    for _ in range(cycles):
        axis.jog.cycle(axis, True, False, limits, selection)


def limits_to(jog_target: JogTarget, axis: MachineAxis) -> JogLimits:
    return jog_target.jog_limits(axis.setpoint, True)


def test_continuous_jog_stops_exactly_on_the_target_and_the_key_held_on_does_nothing() -> None:
    axis, jog_target = enabled_x1(), target()
    jog_target.select(2, False, True)
    axis.inputs.key_plus = True
    for _ in range(3000):
        jog(axis, 1, limits_to(jog_target, axis))
        assert axis.setpoint <= 200.0
    assert axis.setpoint == 200.0 and axis.command_velocity == 0.0 and axis.owner is Owner.NONE
    axis.inputs.key_plus, axis.inputs.key_minus = False, True
    jog(axis, 200, limits_to(jog_target, axis))
    assert axis.setpoint == 200.0  # not away from it (MD10735 bit 2 = 0)


def test_an_increment_that_reaches_the_target_is_done_there() -> None:
    axis, jog_target = enabled_x1(), target()
    jog_target.select(1, False, True)  # 100 mm, the axis on 150 mm
    axis.inputs.key_minus = True
    jog(axis, 2000, limits_to(jog_target, axis), JogSelection(40.0))
    assert axis.setpoint == pytest.approx(110.0, abs=1e-9)
    axis.inputs.key_minus = False
    jog(axis, 2, limits_to(jog_target, axis))
    axis.inputs.key_minus = True
    for _ in range(2000):
        jog(axis, 1, limits_to(jog_target, axis), JogSelection(40.0))
    assert axis.setpoint == 100.0 and axis.jog.keys.state is JogKeyState.AT_END and axis.jog.keys.rest == 0.0


def test_the_handwheel_stops_on_the_target_and_its_rest_is_dropped() -> None:
    axis, jog_target = enabled_x1(), target()
    jog_target.select(0, True, True)  # 250 mm
    axis.add_handwheel_travel(300.0)
    jog(axis, 5000, limits_to(jog_target, axis))
    assert axis.setpoint == 250.0 and axis.handwheel_rest == 0.0 and axis.owner is Owner.NONE


def test_with_md10735_bit_2_the_motion_that_reaches_the_target_ends_and_a_new_press_leaves_it() -> None:
    axis, jog_target = enabled_x1(), target(reverse=True)
    jog_target.select(2, False, True)
    axis.inputs.key_plus = True
    jog(axis, 3000, limits_to(jog_target, axis))
    assert axis.setpoint == 200.0 and axis.jog.keys.state is JogKeyState.AT_END  # not through it
    axis.inputs.key_plus = False
    jog(axis, 2, limits_to(jog_target, axis))
    axis.inputs.key_plus = True
    jog(axis, 300, limits_to(jog_target, axis))
    assert axis.setpoint > 201.0  # away from it, a new press
