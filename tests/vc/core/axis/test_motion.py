"""Velocity ramp, stopping velocity and the axial jerk filter (MD32400/32402/32410)."""

from __future__ import annotations

import itertools
import math

import pytest

from vc.core.axis.motion import JerkFilter, braking_distance, ramp, stopping_distance, stopping_velocity

DT = 0.002  # s, one IPO cycle
ACCEL = 4000.0  # mm/s^2 = MD32300 4 m/s^2


def brake(speed: float, accel: float, dt: float) -> tuple[float, int]:
    """Travel one cycle at ``speed``, then lose ``accel*dt`` per cycle: distance and cycles to standstill."""
    distance, cycles = 0.0, 0
    while speed > 0.0:
        distance += speed * dt
        cycles += 1
        speed = max(0.0, speed - accel * dt)
    return distance, cycles


# ------------------------------------------------------------------------------ ramp


def test_ramp_accelerates_by_at_most_accel_times_dt() -> None:
    # 4000 mm/s^2 * 0.002 s = 8 mm/s per cycle
    assert ramp(0.0, 100.0, ACCEL, DT) == pytest.approx(8.0)
    assert ramp(8.0, 100.0, ACCEL, DT) == pytest.approx(16.0)


def test_ramp_decelerates_and_reverses_by_at_most_accel_times_dt() -> None:
    assert ramp(20.0, 0.0, ACCEL, DT) == pytest.approx(12.0)
    assert ramp(4.0, -100.0, ACCEL, DT) == pytest.approx(-4.0)


def test_ramp_lands_exactly_on_the_target_without_overshoot() -> None:
    assert ramp(95.0, 100.0, ACCEL, DT) == 100.0
    assert ramp(3.0, 0.0, ACCEL, DT) == 0.0
    assert ramp(-3.0, 0.0, ACCEL, DT) == 0.0
    assert ramp(33.3, 33.3, ACCEL, DT) == 33.3


def test_ramp_reaches_a_velocity_in_the_cycles_the_acceleration_allows() -> None:
    # 33.333 mm/s (2000 mm/min) at 8 mm/s per cycle: ceil(33.333 / 8) = 5 cycles
    velocity, cycles = 0.0, 0
    while velocity != 2000.0 / 60.0:
        velocity = ramp(velocity, 2000.0 / 60.0, ACCEL, DT)
        cycles += 1
    assert cycles == 5


# ------------------------------------------------------------------------------ stopping velocity


@pytest.mark.parametrize("speed", [0.5, 8.0, 100.0, 123.456])
def test_stopping_distance_is_the_distance_of_braking_as_hard_as_allowed(speed: float) -> None:
    distance, _ = brake(speed, ACCEL, DT)
    assert stopping_distance(speed, ACCEL, DT) == pytest.approx(distance, rel=1e-12)
    assert stopping_velocity(stopping_distance(speed, ACCEL, DT), ACCEL, DT) == pytest.approx(speed, rel=1e-12)
    assert stopping_distance(0.0, ACCEL, DT) == 0.0


def test_stopping_velocity_is_zero_without_distance() -> None:
    assert stopping_velocity(0.0, ACCEL, DT) == 0.0
    assert stopping_velocity(-1.0, ACCEL, DT) == 0.0


@pytest.mark.parametrize("steps", [1, 2, 5, 13, 40])
def test_braking_from_an_exact_multiple_of_accel_dt_ends_exactly_on_the_distance(steps: int) -> None:
    # Speed v = m*a*dt: one cycle at v, then v - a*dt, ... , a*dt: distance
    # dt * a*dt * (m + (m-1) + ... + 1) = a*dt^2 * m(m+1)/2.  Given that distance,
    # stopping_velocity must return exactly v, and braking from it covers exactly the distance.
    speed = steps * ACCEL * DT
    distance = ACCEL * DT * DT * steps * (steps + 1) / 2
    assert stopping_velocity(distance, ACCEL, DT) == pytest.approx(speed, rel=1e-12)
    covered, cycles = brake(speed, ACCEL, DT)
    assert covered == pytest.approx(distance, rel=1e-12)
    assert cycles == steps


@pytest.mark.parametrize("distance", [0.001, 1.0, 123.4])
def test_braking_from_the_stopping_velocity_stops_within_the_distance(distance: float) -> None:
    # The docstring: the largest speed from which a motion braking with accel in steps of dt
    # stops within the remaining distance.  Braking from it (one cycle at that speed, then
    # a*dt less per cycle) must not pass the end point; 1 nm of rounding is allowed.
    # (The distance covered grows continuously with the speed, so the largest such speed
    # covers the distance exactly.)
    speed = stopping_velocity(distance, ACCEL, DT)
    covered, _ = brake(speed, ACCEL, DT)
    assert covered <= distance + 1e-9


@pytest.mark.parametrize("distance", [0.001, 0.0137, 0.5, 1.0, 7.3, 123.4])
def test_braking_from_the_stopping_velocity_does_not_stop_sooner_than_needed(distance: float) -> None:
    speed = stopping_velocity(distance, ACCEL, DT)
    covered, _ = brake(speed, ACCEL, DT)
    assert covered >= distance - 1e-9


def test_stopping_velocity_is_close_to_the_continuous_braking_speed() -> None:
    # Continuous braking: v = sqrt(2*a*s); for s = 100 mm: sqrt(2*4000*100) = 894.43 mm/s.
    # The discrete speed is lower by about a*dt/2 = 4 mm/s (one cycle at full speed first).
    speed = stopping_velocity(100.0, ACCEL, DT)
    assert math.sqrt(2 * ACCEL * 100.0) - 4.0 - 0.01 <= speed <= math.sqrt(2 * ACCEL * 100.0)


def test_braking_distance_is_v_squared_over_2a() -> None:
    # 33.333 mm/s at 4000 mm/s^2: 1111.1 / 8000 = 0.13889 mm
    assert braking_distance(2000.0 / 60.0, ACCEL) == pytest.approx((2000.0 / 60.0) ** 2 / 8000.0)
    assert braking_distance(10.0, 0.0) == math.inf


# ------------------------------------------------------------------------------ jerk filter


def profile(filter_: JerkFilter, speed: float, moving_cycles: int,
            total: int) -> tuple[list[float], list[float]]:
    """Input: constant speed for ``moving_cycles`` cycles then standstill; returns inputs and outputs."""
    position = 0.0
    inputs, outputs = [], []
    for cycle in range(total):
        if cycle < moving_cycles:
            position += speed * DT
        inputs.append(position)
        outputs.append(filter_.apply(position))
    return inputs, outputs


@pytest.mark.parametrize("mode", [1, 2])
def test_jerk_filter_keeps_the_end_position_exactly(mode: int) -> None:
    filter_ = JerkFilter(mode, 0.016, DT, 0.0)
    inputs, outputs = profile(filter_, 10.0, 100, 600)
    assert outputs[-1] == inputs[-1]  # exactly, not approximately: the axis must end on its end point
    assert filter_.settled(inputs[-1], 0.0)


@pytest.mark.parametrize("mode", [1, 2])
def test_jerk_filter_neither_overshoots_nor_reverses(mode: int) -> None:
    _, outputs = profile(JerkFilter(mode, 0.016, DT, 0.0), 10.0, 100, 600)
    end = outputs[-1]
    assert all(later >= earlier for earlier, later in itertools.pairwise(outputs))
    assert max(outputs) <= end


def test_moving_average_filter_ends_the_motion_the_filter_time_later() -> None:
    # MD32402 = 2, MD32410 = 16 ms = 8 IPO cycles: the moving average of the last 8 setpoints
    # reaches the end point 7 cycles after the input, i.e. the filter time minus one cycle.
    filter_time = 0.016
    inputs, outputs = profile(JerkFilter(2, filter_time, DT, 0.0), 10.0, 100, 300)
    input_end = inputs.index(inputs[-1])
    output_end = outputs.index(outputs[-1])
    delay = (output_end - input_end) * DT
    assert filter_time - DT - 1e-12 <= delay <= filter_time + 1e-12


def test_moving_average_filter_lags_a_constant_speed_by_half_its_window() -> None:
    # Average of x(k), x(k-1) .. x(k-7) at 10 mm/s = 0.02 mm/cycle: lag 0.02 * (0+1+..+7)/8 = 0.07 mm.
    inputs, outputs = profile(JerkFilter(2, 0.016, DT, 0.0), 10.0, 100, 100)
    assert inputs[50] - outputs[50] == pytest.approx(0.07)


def test_second_order_filter_lags_a_constant_speed_by_the_filter_time() -> None:
    # Two first-order stages of T/2 each: the lag of a ramp is v * T = 10 mm/s * 0.016 s = 0.16 mm.
    inputs, outputs = profile(JerkFilter(1, 0.016, DT, 0.0), 10.0, 200, 200)
    assert inputs[199] - outputs[199] == pytest.approx(0.16, rel=1e-3)


@pytest.mark.parametrize("mode", [1, 2])
def test_filter_reset_takes_the_new_position_at_once(mode: int) -> None:
    filter_ = JerkFilter(mode, 0.016, DT, 0.0)
    filter_.apply(5.0)
    filter_.reset(42.0)
    assert filter_.apply(42.0) == 42.0
    assert filter_.settled(42.0, 0.0)


@pytest.mark.parametrize("mode", [1, 2])
def test_filter_with_zero_time_passes_the_setpoint_through(mode: int) -> None:
    filter_ = JerkFilter(mode, 0.0, DT, 0.0)
    assert [filter_.apply(value) for value in (1.0, 2.5, 2.5, -3.0)] == [1.0, 2.5, 2.5, -3.0]


# ------------------------------------------------------------------------------ dynamic-response matching


@pytest.mark.parametrize(("delay", "lag"), [(0.002, 0.02), (0.004, 0.04), (0.003, 0.03)])
def test_dynamic_matching_delays_the_setpoint_by_md32910(delay: float, lag: float) -> None:
    # 10 mm/s = 0.02 mm a cycle: a delay of 2 ms lags 0.02 mm, 4 ms 0.04 mm, and 3 ms (one and a
    # half cycles, interpolated) 0.03 mm; with the jerk filter off the rest passes unchanged.
    filter_ = JerkFilter(1, 0.0, DT, 0.0, delay)
    inputs, outputs = profile(filter_, 10.0, 100, 110)
    assert inputs[50] - outputs[50] == pytest.approx(lag)
    assert outputs[-1] == inputs[-1]
    assert filter_.settled(inputs[-1], 0.0)


def test_dynamic_matching_is_not_settled_while_the_delay_still_holds_motion() -> None:
    filter_ = JerkFilter(1, 0.0, DT, 0.0, 0.004)
    filter_.apply(1.0)
    assert not filter_.settled(1.0, 0.0)
    filter_.apply(1.0)
    filter_.apply(1.0)
    assert filter_.settled(1.0, 0.0)
