"""JOG of one axis alone (vc/core/axis/jog.py): the keys, the handwheel's distance, the limits it
keeps, driven cycle by cycle without the NC around it.  Through the whole NC: test_axis.py."""

from __future__ import annotations

import math

import pytest
from core_rig import ABSOLUTE_X1, Rig, machine

from vc.core.axis.axis import MachineAxis
from vc.core.axis.jog import FREE_JOG, JogLimits
from vc.core.axis.owner import Owner

JOG_V = 2000.0 / 60.0  # mm/s, MD32020 of X1


def enabled_x1() -> MachineAxis:
    """X1 referenced (absolute encoder) at 150, enabled; the test is the NC calling JOG each cycle."""
    axis = Rig(machine(ABSOLUTE_X1)).axis("X1")
    axis.inputs.controller_enable = axis.inputs.pulse_enable = True
    assert axis.drive_ready and axis.software_limits_active
    return axis


def jog(axis: MachineAxis, cycles: int, limits: JogLimits = FREE_JOG, allowed: bool = True) -> None:
    for _ in range(cycles):
        axis.jog.cycle(axis, allowed, False, limits)


def test_a_held_key_takes_the_axis_and_runs_it_at_jog_velocity() -> None:
    axis = enabled_x1()
    axis.inputs.key_plus = True
    jog(axis, 100)
    assert axis.owner is Owner.JOG
    assert axis.command_velocity == pytest.approx(JOG_V)
    axis.inputs.key_plus = False
    jog(axis, 100)
    assert axis.owner is Owner.NONE and axis.command_velocity == 0.0


def test_outside_jog_the_keys_do_nothing() -> None:
    axis = enabled_x1()
    axis.inputs.key_minus = True
    jog(axis, 10, allowed=False)
    assert axis.owner is Owner.NONE and axis.setpoint == 150.0


def test_the_window_of_a_transform_stops_the_axis_exactly_on_its_end() -> None:
    axis = enabled_x1()
    axis.inputs.key_plus = True
    jog(axis, 200, JogLimits(window=(100.0, 150.5)))
    assert axis.setpoint == 150.5 and axis.at_software_limit == 1
    assert axis.owner is Owner.NONE  # resting on the limit the key points to


def test_the_handwheel_distance_is_travelled_exactly() -> None:
    axis = enabled_x1()
    axis.add_handwheel_travel(-1.234)
    jog(axis, 500)
    assert axis.setpoint == pytest.approx(150.0 - 1.234, abs=1e-12)
    assert axis.handwheel_rest == 0.0 and axis.owner is Owner.NONE


def test_a_key_drops_the_handwheel_rest() -> None:
    axis = enabled_x1()
    axis.add_handwheel_travel(5.0)
    jog(axis, 5)
    axis.inputs.key_minus = True
    jog(axis, 1)
    assert axis.handwheel_rest == 0.0


def test_limits_combine_to_the_narrower_of_both() -> None:
    first = JogLimits(plus=False, velocity=10.0, window=(0.0, 100.0))
    second = JogLimits(minus=False, accel=50.0, window=(20.0, 200.0))
    both = first.and_(second)
    assert (both.plus, both.minus, both.velocity, both.accel, both.window) == (False, False, 10.0, 50.0, (20.0, 100.0))
    assert first.and_(FREE_JOG) is first and FREE_JOG.and_(second) is second
    assert JogLimits(velocity=3.0).and_(JogLimits(accel=4.0)).window is None
    assert math.isinf(FREE_JOG.velocity)
