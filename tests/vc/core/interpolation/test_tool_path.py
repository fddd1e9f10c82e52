"""The tool path segment: interpolation along a curve of machine positions, within the axis limits.

The axes are real ones of turn_mill (X1, Z1) with the two limits the segment reads (MD32000 /
MD32300 as ``dyn.max_velocity`` / ``dyn.max_accel``, per second) set by the test; after every
cycle the test records the setpoints the segment handed them.
"""

from __future__ import annotations

import dataclasses
import math
from typing import Any

import pytest

from tests.vc.core.core_rig import Rig, machine
from vc.core.axis.axis import MachineAxis
from vc.core.interpolation.tool_path import ToolPathSegment

DT = 0.002


@dataclasses.dataclass
class _Axis:
    """An axis of the rig and the setpoints it got, cycle by cycle."""

    axis: MachineAxis
    positions: list[float] = dataclasses.field(default_factory=list)
    velocities: list[float] = dataclasses.field(default_factory=list)

    def record(self) -> None:
        self.positions.append(self.axis.setpoint)
        self.velocities.append(self.axis.command_velocity)


def _run(segment: ToolPathSegment, axes: list[_Axis], override: float = 1.0, cycles: int = 100_000) -> int:
    for cycle in range(cycles):
        if segment.finished:
            return cycle
        _cycle(segment, axes, override)
    raise AssertionError("the segment did not finish")


def _cycle(segment: ToolPathSegment, axes: list[_Axis], override: float = 1.0, hold: bool = False) -> None:
    segment.cycle(override, hold, DT)
    if segment.length > 0.0:  # the segment hands out setpoints only along a path
        for axis in axes:
            axis.record()


def _quarter_circle(radius: float) -> Any:
    """X, Y on a quarter circle of ``radius`` around the origin while the path runs 0 .. 1."""
    def positions_at(fraction: float) -> list[float]:
        angle = fraction * math.pi / 2
        return [radius * math.cos(angle), radius * math.sin(angle)]
    return positions_at


def _axes(velocity: float, accel: float) -> list[_Axis]:
    rig = Rig(machine())
    axes = [rig.axis("X1"), rig.axis("Z1")]
    for axis in axes:
        axis.dyn = dataclasses.replace(axis.dyn, max_velocity=velocity, max_accel=accel)
    return [_Axis(axis) for axis in axes]


def _plan(axes: list[_Axis], *arguments: Any, rapid: bool = False) -> ToolPathSegment:
    return ToolPathSegment.plan([axis.axis for axis in axes], *arguments, rapid=rapid)


def test_a_straight_path_runs_at_the_feed_and_ends_exactly_on_its_end_point() -> None:
    axes = _axes(1000.0, 5000.0)
    segment = _plan(axes, lambda f: [100.0 * f, 50.0 * f],
                                   100.0, 20.0, rapid=False)
    assert segment.command_velocity == 20.0
    _run(segment, axes)
    assert axes[0].positions[-1] == 100.0 and axes[1].positions[-1] == 50.0
    assert max(axes[0].velocities) == pytest.approx(20.0)  # X carries the whole feed along the path length


def test_on_a_curve_no_axis_exceeds_its_velocity_or_acceleration() -> None:
    # Quarter circle r = 100 mm, path length 157.08 mm, F = 600 mm/s: far above what the axes allow.
    axes = _axes(200.0, 1000.0)
    segment = _plan(axes, _quarter_circle(100.0), 157.08, 600.0,
                                   rapid=False)
    # The curvature term v^2 / r may use half of 1000 mm/s^2: v <= sqrt(500 x 100) = 223.6 mm/s,
    # and the velocity limit 200 mm/s per axis (|dx/ds| <= 1) is lower still.
    assert segment.command_velocity == pytest.approx(200.0, rel=1e-3)
    _run(segment, axes)
    for axis in axes:
        accelerations = [abs(b - a) / DT for a, b in zip(axis.velocities, axis.velocities[1:], strict=False)]
        assert max(abs(v) for v in axis.velocities) <= 200.0 * 1.001
        assert max(accelerations) <= 1000.0 * 1.02  # the finite-difference curve, a little rounding
    assert axes[0].positions[-1] == pytest.approx(0.0, abs=1e-9)
    assert axes[1].positions[-1] == pytest.approx(100.0)


def test_the_override_does_not_lift_the_path_above_the_axis_limits() -> None:
    axes = _axes(10.0, 1000.0)
    segment = _plan(axes, lambda f: [20.0 * f, 0.0], 20.0, 10.0,
                                   rapid=False)
    _run(segment, axes, override=1.2)
    assert max(axes[0].velocities) == pytest.approx(10.0)


def test_a_hold_brakes_on_the_path_and_nc_start_continues_it() -> None:
    axes = _axes(100.0, 1000.0)
    segment = _plan(axes, _quarter_circle(10.0), 15.708, 50.0, rapid=False)
    for _ in range(50):
        _cycle(segment, axes)
    for _ in range(100):
        _cycle(segment, axes, hold=True)
    assert segment.velocity == 0.0 and not segment.finished
    x, y = axes[0].positions[-1], axes[1].positions[-1]
    assert math.hypot(x, y) == pytest.approx(10.0)  # stopped on the contour
    _run(segment, axes)
    assert axes[1].positions[-1] == pytest.approx(10.0)


def test_a_block_without_travel_is_finished_at_once() -> None:
    axes = _axes(100.0, 1000.0)
    segment = _plan(axes, lambda f: [1.0, 2.0], 0.0, 50.0, rapid=False)
    assert segment.finished


def test_a_swing_with_little_tip_travel_is_sampled_by_the_largest_axis_travel() -> None:
    # 1 mm of tip path while a rotary axis turns 300 degrees: one sample per degree, not 32
    axes = _axes(1000.0, 5000.0)
    segment = _plan(axes, lambda f: [1.0 * f, 300.0 * f],
                                   1.0, 20.0, rapid=False)
    assert len(segment.samples) == 301
    assert segment.samples[150] == pytest.approx([0.5, 150.0])
