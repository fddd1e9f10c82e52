"""The DRF offset's travel (vc/core/axis/drf.py): at the DRF velocity, ramped, landing exactly on
its end point; a stop drops the rest.  The whole function through the NC: test_axis.py."""

from __future__ import annotations

import pytest

from vc.core.axis.drf import DrfOffset

DT = 0.002
ACCEL = 4000.0  # mm/s^2
VELOCITY = 100.0  # mm/s


def travel(drf: DrfOffset, cycles: int, stopped: bool = False) -> float:
    moved = 0.0
    for _ in range(cycles):
        moved += drf.step(stopped, ACCEL, VELOCITY)
    return moved


@pytest.mark.parametrize("distance", [2.0, -2.0, 0.0371, -0.001])
def test_the_offset_lands_exactly_on_the_distance(distance: float) -> None:
    drf = DrfOffset(DT)
    drf.add_travel(distance)
    assert drf.moving
    moved = travel(drf, 2000)
    assert drf.offset == pytest.approx(distance, abs=1e-12) and moved == pytest.approx(distance, abs=1e-12)
    assert not drf.moving and drf.rest == 0.0 and drf.velocity == 0.0


def test_the_travel_never_exceeds_the_drf_velocity_nor_the_acceleration() -> None:
    drf = DrfOffset(DT)
    drf.add_travel(10.0)
    velocities = [drf.step(False, ACCEL, VELOCITY) / DT for _ in range(200)]
    assert max(velocities) == pytest.approx(VELOCITY)
    steps = [abs(b - a) for a, b in zip([0.0, *velocities], velocities, strict=False)]
    assert max(steps) <= ACCEL * DT + 1e-9


def test_a_stop_brakes_and_drops_the_rest() -> None:
    drf = DrfOffset(DT)
    drf.add_travel(10.0)
    travel(drf, 50)
    assert drf.velocity == pytest.approx(VELOCITY)
    travel(drf, 100, stopped=True)
    assert drf.rest == 0.0 and drf.velocity == 0.0
    assert 0.0 < drf.offset < 10.0  # what it travelled stays as the offset


def test_clear_forgets_offset_and_travel() -> None:
    drf = DrfOffset(DT)
    drf.add_travel(1.0)
    travel(drf, 5)
    drf.clear()
    assert (drf.offset, drf.rest, drf.velocity, drf.moving) == (0.0, 0.0, 0.0, False)
