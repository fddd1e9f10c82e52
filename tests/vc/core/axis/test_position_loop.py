"""The position loop alone (vc/core/axis/position_loop.py): the drive's slide integrated here as
the axis does it.  Through the whole NC: test_axis.py and the coupling tests."""

from __future__ import annotations

import dataclasses

import pytest
from core_rig import DT, machine

from vc.core.axis.dynamics import AxisDynamics, CoupledLoop, dynamics_of
from vc.core.axis.position_loop import PositionLoop


def x1_dynamics(feedforward: float) -> AxisDynamics:
    return dataclasses.replace(dynamics_of(machine().axis("X1")), feedforward=feedforward)


def run(loop: PositionLoop, dyn: AxisDynamics, targets: list[float], actual: float) -> tuple[float, bool, float]:
    """The slide moves with the drive's velocity; the settled slide is put on the setpoint.  Returns
    the last actual value, whether the loop settled, and the following error the loop compared last."""
    settled, compared = False, 0.0
    for index, target in enumerate(targets):
        command_velocity = (target - targets[index - 1]) / DT if index else 0.0
        settled = loop.close(dyn, target, actual, command_velocity)
        compared = loop.setpoint - actual
        actual += loop.drive_velocity * DT
        if settled:
            actual = loop.setpoint
    return actual, settled, compared


@pytest.mark.parametrize("feedforward", [0.0, 1.0])
def test_the_slide_follows_a_ramp_and_settles_on_the_end_point(feedforward: float) -> None:
    dyn = x1_dynamics(feedforward)
    loop = PositionLoop(DT, 0.0, None)
    ramp_up = [min(10.0, 0.1 * cycle) for cycle in range(1, 400)]  # 50 mm/s to 10 mm
    actual, settled, _ = run(loop, dyn, ramp_up + [10.0] * 2000, 0.0)
    assert settled and actual == 10.0
    assert loop.drive_velocity == 0.0 and loop.model_velocity == 0.0


def test_with_feedforward_the_following_error_at_constant_velocity_is_lag_per_velocity_times_velocity() -> None:
    dyn = x1_dynamics(1.0)
    loop = PositionLoop(DT, 0.0, None)
    velocity = 50.0
    actual, _, _ = run(loop, dyn, [velocity * DT * cycle for cycle in range(1, 3000)], 0.0)
    assert loop.setpoint - actual == pytest.approx(loop.lag_per_velocity(dyn) * velocity, rel=1e-3)


def test_the_kv_loop_compares_a_following_error_of_velocity_over_kv() -> None:
    dyn = x1_dynamics(0.0)
    loop = PositionLoop(DT, 0.0, None)
    velocity = 50.0
    actual, _, compared = run(loop, dyn, [velocity * DT * cycle for cycle in range(1, 3000)], 0.0)
    assert compared == pytest.approx(loop.lag_per_velocity(dyn) * velocity, rel=1e-3)
    assert loop.setpoint - actual == pytest.approx(compared - velocity * DT)  # the slide moved on in the cycle


def test_the_lag_per_velocity_of_the_kv_loop_is_one_over_kv() -> None:
    dyn = x1_dynamics(0.0)
    assert PositionLoop(DT, 0.0, None).lag_per_velocity(dyn) == pytest.approx(1.0 / dyn.kv)


def test_a_coupled_loop_replaces_the_axis_parameters_and_shifts_the_model_to_its_lag() -> None:
    dyn = x1_dynamics(1.0)
    loop = PositionLoop(DT, 0.0, None)
    run(loop, dyn, [50.0 * DT * cycle for cycle in range(1, 500)], 0.0)
    before_position, velocity = loop.model_position, loop.model_velocity
    coupled = CoupledLoop(kv=5.0, feedforward=1.0, symmetrising_time=dyn.drive_time_constant + 0.004)
    loop.set_coupled(dyn, coupled)
    assert loop.parameters(dyn) == (5.0, 1.0, dyn.drive_time_constant + 0.004)
    assert loop.model_position == pytest.approx(before_position - velocity * 0.004)
    loop.set_coupled(dyn, None)
    assert loop.parameters(dyn) == (dyn.kv, 1.0, dyn.drive_time_constant)
    assert loop.model_position == pytest.approx(before_position)


def test_hold_and_shift_move_every_setpoint_stage() -> None:
    loop = PositionLoop(DT, 0.0, None)
    loop.model_velocity = 3.0
    loop.hold_at(12.5)
    assert (loop.setpoint, loop.model_position, loop.model_velocity) == (12.5, 12.5, 0.0)
    loop.shift(-2.5)
    assert (loop.setpoint, loop.model_position) == (10.0, 10.0)
