"""The speed side of a spindle (seed 003 §13.8): limits of the gear stage, ramp, set speed, on turn_mill's SP1.

SP1: MD35130 [800, 2000, 4500], MD35140 [5, 10, 20] (gear stages 1..3), MD35100 chuck 4500.
The whole spindle with its speed control runs in test_spindle.py.
"""

from __future__ import annotations

import pytest
from core_rig import Rig, spindle_rig

from vc.core.spindle.speed_control import RPM
from vc.core.spindle.spindle import Spindle


def sp1(rig: Rig) -> Spindle:
    return rig.nck.spindles[0]


def test_the_set_speed_is_clamped_to_the_gear_stage_and_raised_to_its_minimum() -> None:
    speed = sp1(spindle_rig()).speed_control  # gear stage 1
    assert speed.setpoint(1, 900.0, False, False) == pytest.approx(800.0 * RPM)
    assert speed.limited and not speed.raised and speed.set_speed == 800.0
    assert speed.setpoint(-1, 3.0, False, False) == pytest.approx(-5.0 * RPM)
    assert speed.raised and not speed.limited
    assert speed.setpoint(1, 500.0, True, False) == 0.0  # held (feed stop, a coupled FS's stop)
    assert not speed.raised and not speed.limited and speed.set_speed == 0.0
    assert speed.setpoint(1, 900.0, True, False) == 0.0 and speed.limited  # 83.1 also while held


def test_position_control_keeps_a_control_reserve_below_the_limits() -> None:
    speed = sp1(spindle_rig()).speed_control
    assert speed.max_speed(False) == pytest.approx(800.0)
    assert speed.max_speed(True) == pytest.approx(0.9 * 800.0)
    speed.speed_cap = 500.0  # a coupled FS limits its leading spindle
    assert speed.max_speed(False) == pytest.approx(500.0)


@pytest.mark.parametrize(("kind", "at_1500", "at_2000", "above"), [
    (0, 0.6, 0.6, 0.6),  # constant: 1 - MD35230 at once above the speed point
    (1, 1.0 / (1.0 + 0.4 / 0.6 * 0.5), 0.6, 0.6),  # hyperbola from 1 at the point to 0.6 at MD35130
    (2, 0.8, 0.6, 0.6),  # straight line
])
def test_acceleration_reduction_above_the_speed_point(kind: int, at_1500: float, at_2000: float,
                                                      above: float) -> None:
    # MD35130 = 2000 rev/min, MD35220 = 0.5: the reduction starts at 1000 rev/min and reaches
    # 1 - MD35230 = 0.6 at 2000 rev/min (seed 003 L23797-23810)
    rig = spindle_rig("SP1: {MD35130: [2000, 2000, 2000, 2000, 2000, 2000], MD35220: 0.5, MD35230: 0.4,"
                      f" MD35242: {kind}}}")
    spindle = sp1(rig)
    rpm = 6.0  # deg/s per rev/min
    assert spindle.speed_control.acceleration_reduction(900 * rpm) == 1.0
    assert spindle.speed_control.acceleration_reduction(1000 * rpm) == 1.0
    assert spindle.speed_control.acceleration_reduction(-1500 * rpm) == pytest.approx(at_1500)
    assert spindle.speed_control.acceleration_reduction(2000 * rpm) == pytest.approx(at_2000)
    assert spindle.speed_control.acceleration_reduction(2500 * rpm) == pytest.approx(above)


def test_no_acceleration_reduction_without_md35230() -> None:
    rig = spindle_rig("SP1: {MD35220: 0.1}")
    assert sp1(rig).speed_control.acceleration_reduction(5000 * 6.0) == 1.0
