"""The axis dynamics from machine data (vc/core/axis/dynamics.py): units and the jerk filter."""

from __future__ import annotations

import pytest
from core_rig import DT, machine

from vc.core.axis.dynamics import dynamics_of, jerk_filter_of


def test_linear_axis_units_are_mm_per_second() -> None:
    dyn = dynamics_of(machine().axis("X1"))  # MD32000 30 m/min, MD32300 4 m/s^2, MD32020 2000 mm/min
    assert dyn.max_velocity == pytest.approx(500.0)
    assert dyn.max_accel == pytest.approx(4000.0)
    assert dyn.jog_velocity == pytest.approx(2000.0 / 60.0)
    assert dyn.display_velocity_factor == pytest.approx(60.0)


@pytest.mark.parametrize(("overrides", "filtered"), [
    ("", False),  # neither MD32400 nor MD32900: the setpoint goes straight to the loop
    ("X1: {MD32400: 1}", True),
    ("X1: {MD32900: 1, MD32910: [0.004, 0.004, 0.004, 0.004, 0.004, 0.004]}", True),
    ("X1: {MD32900: 0, MD32910: [0.004, 0.004, 0.004, 0.004, 0.004, 0.004]}", False),  # MD32910 needs MD32900
])
def test_the_jerk_filter_exists_where_the_data_ask_for_it(overrides: str, filtered: bool) -> None:
    axis = machine(overrides).axis("X1")
    jerk_filter = jerk_filter_of(axis, dynamics_of(axis), DT, 150.0)
    assert (jerk_filter is not None) is filtered
    if jerk_filter is not None:
        assert jerk_filter.apply(150.0) == 150.0  # it starts where the axis stands
