"""The retract motion's jerk-limited profile (vc/core/retraction/retract_motion.py, MD32431, seed 003 L8340-8349)."""

from __future__ import annotations

import itertools
import math

import pytest

from vc.core.retraction.retract_motion import SCurve


@pytest.mark.parametrize(
    ("length", "jerk", "duration", "peak"),
    [
        (10.0, 5e4, 4 * (10.0 / 1e5) ** (1 / 3), (5.0 * math.sqrt(5e4)) ** (2 / 3)),  # no held acceleration
        (10.0, 1e6, 2 * (192.16 / 4000 + 0.004), 192.16),  # V (V/A + A/J) = 10
        (100.0, 1e6, 2 * 0.129 + (100 - 500 * 0.129) / 500, 500.0),  # cruises at MD32000
    ],
)
def test_duration_and_peak_velocity_by_hand(length: float, jerk: float, duration: float, peak: float) -> None:
    profile = SCurve.plan(length, 500.0, 4000.0, jerk)  # X1 of turn_mill: 30 m/min, 4 m/s^2
    assert profile.duration == pytest.approx(duration, rel=1e-4)
    assert profile.velocity == pytest.approx(peak, rel=1e-4)


@pytest.mark.parametrize("jerk", [5e4, 1e6])
def test_the_profile_is_continuous_and_keeps_its_limits(jerk: float) -> None:
    profile = SCurve.plan(100.0, 500.0, 4000.0, jerk)
    dt = 1e-4
    samples = [profile.at(k * dt) for k in range(int(profile.duration / dt) + 3)]
    assert samples[0] == (0.0, 0.0) and samples[-1] == (100.0, 0.0)
    velocities = [v for _, v in samples]
    accels = [(b - a) / dt for a, b in itertools.pairwise(velocities)]
    assert max(velocities) <= 500.0 + 1e-9
    assert max(abs(a) for a in accels) <= 4000.0 * 1.001
    assert max(abs(b - a) / dt for a, b in itertools.pairwise(accels)) <= jerk * 1.01
    for (s0, v0), (s1, v1) in itertools.pairwise(samples):
        assert s1 - s0 == pytest.approx((v0 + v1) / 2 * dt, abs=1e-6)
