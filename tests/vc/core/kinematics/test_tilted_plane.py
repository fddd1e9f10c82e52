"""Tilted working plane (seed 001): G68.2 Euler frames, teach modes, G53.1 tool alignment."""

from __future__ import annotations

import math

import pytest
from hypothesis import given
from hypothesis import strategies as st

from vc.core.kinematics.five_axis import FiveAxisParameters, Kinematics, RotaryAngles, resolve
from vc.core.kinematics.geometry import ORIGIN, Vec3
from vc.core.kinematics.tilted_plane import (
    Frame,
    TeachFailure,
    align_tool,
    euler_frame,
    three_point_frame,
    two_vector_frame,
)
from vc.core.kinematics.transform_alarm import ROTARY_P_OUT_OF_RANGE, TransformAlarm


def near(actual: Vec3, expected: tuple[float, float, float], tolerance: float = 1e-4) -> bool:
    return all(abs(a - e) <= tolerance for a, e in zip((actual.x, actual.y, actual.z), expected, strict=True))


def test_tv_5x_8_euler_z_x_z() -> None:
    # G68.2 I30 J45 K0: R = Rz(30) Rx(45) Rz(0);
    # row 1 = (cos 30, -sin 30 cos 45, sin 30 sin 45) = (0.8660, -0.3536, 0.3536)
    # row 2 = (sin 30, cos 30 cos 45, -cos 30 sin 45) = (0.5, 0.6124, -0.6124)
    # row 3 = (0, sin 45, cos 45) = (0, 0.7071, 0.7071)
    frame = euler_frame(Vec3(10.0, 20.0, 30.0), 30.0, 45.0, 0.0)
    assert near(frame.rotation.row0, (0.8660, -0.3536, 0.3536))
    assert near(frame.rotation.row1, (0.5, 0.6124, -0.6124))
    assert near(frame.rotation.row2, (0.0, 0.7071, 0.7071))
    # the plane's point (1, 0, 0) lies at origin + first column
    assert near(frame.to_workpiece(Vec3(1.0, 0.0, 0.0)), (10.8660, 20.5, 30.0))


def test_three_points() -> None:
    # P1 origin, X towards P2 = +X, P3 above P1 (+Z): Z = X x (P3 - P1) = (1, 0, 0) x (0, 0, 5) = (0, -5, 0)
    # Y = Z x X = (0, -1, 0) x (1, 0, 0) = (0, 0, 1): the plane stands upright, its Y up, its Z towards -Y
    frame = three_point_frame(Vec3(100.0, 0.0, 0.0), Vec3(110.0, 0.0, 0.0), Vec3(100.0, 0.0, 5.0))
    assert isinstance(frame, Frame)
    assert near(frame.rotation.column(0), (1.0, 0.0, 0.0))
    assert near(frame.rotation.column(1), (0.0, 0.0, 1.0))
    assert near(frame.normal, (0.0, -1.0, 0.0))
    assert near(frame.to_plane(Vec3(100.0, 0.0, 5.0)), (0.0, 5.0, 0.0))


@pytest.mark.parametrize("points", [
    (Vec3(0.0, 0.0, 0.0), Vec3(10.0, 0.0, 0.0), Vec3(20.0, 0.0, 0.0)),  # on one line
    (Vec3(1.0, 2.0, 3.0), Vec3(1.0, 2.0, 3.0), Vec3(0.0, 0.0, 0.0)),  # P2 = P1
    (Vec3(1.0, 2.0, 3.0), Vec3(4.0, 2.0, 3.0), Vec3(1.0, 2.0, 3.0)),  # P3 = P1
])
def test_collinear_points_fail(points: tuple[Vec3, Vec3, Vec3]) -> None:
    assert isinstance(three_point_frame(*points), TeachFailure)


def test_two_vectors() -> None:
    # X = (1, 0, 0), Z = (0, 1, 1) / sqrt 2; Y = Z x X = (0, 0.7071, -0.7071)
    frame = two_vector_frame(ORIGIN, Vec3(2.0, 0.0, 0.0), Vec3(0.0, 1.0, 1.0))
    assert isinstance(frame, Frame)
    assert near(frame.rotation.column(1), (0.0, 0.7071, -0.7071))
    assert near(frame.normal, (0.0, 0.7071, 0.7071))
    assert isinstance(two_vector_frame(ORIGIN, Vec3(1.0, 0.0, 0.0), Vec3(1.0, 0.0, 1.0)), TeachFailure)
    assert isinstance(two_vector_frame(ORIGIN, Vec3(0.0, 0.0, 0.0), Vec3(0.0, 0.0, 1.0)), TeachFailure)


@given(st.floats(-360.0, 360.0), st.floats(-360.0, 360.0), st.floats(-360.0, 360.0),
       st.builds(Vec3, st.floats(-1000.0, 1000.0), st.floats(-1000.0, 1000.0), st.floats(-1000.0, 1000.0)))
def test_plane_and_workpiece_coordinates_round_trip(i: float, j: float, k: float, point: Vec3) -> None:
    frame = euler_frame(Vec3(5.0, -7.0, 11.0), i, j, k)
    assert frame.to_plane(frame.to_workpiece(point)).distance(point) < 1e-9
    columns = [frame.rotation.column(index) for index in range(3)]
    assert math.isclose(columns[0].cross(columns[1]).dot(columns[2]), 1.0, abs_tol=1e-12)  # right-handed


def table_ac() -> Kinematics:
    kinematics = resolve(FiveAxisParameters(2, 3, first_axis=1, second_axis=3, first_hand=2, second_hand=2,
                                            first_range=(240.0, 30.0)))
    assert isinstance(kinematics, Kinematics)
    return kinematics


def test_g53_1_stands_the_tool_on_the_plane() -> None:
    # G68.2 I0 J30 K0: plane Z = Rx(30) z = (0, -0.5, 0.866).  Table A/C, both left-hand:
    # t_w = R2^T R1^T z = Rz(C) Rx(A) z = (sin A sin C, -sin A cos C, cos A) -> A = 30, C = 0
    # (or A = -30, C = 180; P0 keeps C where it is)
    frame = euler_frame(ORIGIN, 0.0, 30.0, 0.0)
    target = align_tool(table_ac(), frame, RotaryAngles(0.0, 0.0))
    assert isinstance(target, RotaryAngles)
    assert (round(target.first, 6), round(target.second, 6)) == (30.0, 0.0)
    # the range A -120 .. 30 (240 -> 30) allows A = -30 as well: P1 turns A the positive way to the nearest
    # solution, from A = 0 that is +30
    positive = align_tool(table_ac(), frame, RotaryAngles(0.0, 0.0), p=1)
    assert isinstance(positive, RotaryAngles) and round(positive.first, 6) == 30.0


def test_g53_1_p_out_of_range_is_cor_149() -> None:
    alarm = align_tool(table_ac(), euler_frame(ORIGIN, 0.0, 30.0, 0.0), RotaryAngles(0.0, 0.0), p=3)
    assert isinstance(alarm, TransformAlarm)
    assert (alarm.number, alarm.code) == (ROTARY_P_OUT_OF_RANGE, "COR-149")
