"""Vectors and rotations of the transforms: the conventions the kinematics rely on."""

from __future__ import annotations

import math

import pytest
from hypothesis import given
from hypothesis import strategies as st

from vc.core.kinematics.geometry import (
    IDENTITY,
    X_AXIS,
    Y_AXIS,
    Z_AXIS,
    Vec3,
    rotation,
    rotation_angle,
    signed_degrees,
    wrap_degrees,
)


def test_rotations_are_right_handed() -> None:
    # a quarter turn about Z takes X to Y, about X takes Y to Z, about Y takes Z to X
    assert rotation(Z_AXIS, 90.0).apply(X_AXIS).distance(Y_AXIS) < 1e-15
    assert rotation(X_AXIS, 90.0).apply(Y_AXIS).distance(Z_AXIS) < 1e-15
    assert rotation(Y_AXIS, 90.0).apply(Z_AXIS).distance(X_AXIS) < 1e-15


def test_matrix_products() -> None:
    quarter = rotation(Z_AXIS, 90.0)
    assert quarter.times(quarter.transposed()).apply(Vec3(1.0, 2.0, 3.0)).distance(Vec3(1.0, 2.0, 3.0)) < 1e-12
    assert IDENTITY.column(1) == Y_AXIS


@given(st.floats(-179.0, 179.0), st.builds(Vec3, st.floats(-1.0, 1.0), st.floats(-1.0, 1.0), st.floats(-1.0, 1.0)))
def test_rotation_angle_finds_the_turn(angle: float, axis: Vec3) -> None:
    if axis.norm() < 0.1:
        axis = Z_AXIS
    unit = axis.unit()
    start = X_AXIS if abs(unit.dot(X_AXIS)) < 0.9 else Y_AXIS
    found = rotation_angle(unit, start, rotation(unit, angle).apply(start))
    assert found is not None and math.isclose(found, angle, abs_tol=1e-7)


def test_a_vector_on_the_axis_has_no_angle() -> None:
    assert rotation_angle(Z_AXIS, Z_AXIS, X_AXIS) is None


@pytest.mark.parametrize(("angle", "wrapped", "signed"), [
    (0.0, 0.0, 0.0), (360.0, 0.0, 0.0), (-90.0, 270.0, -90.0), (190.0, 190.0, -170.0), (180.0, 180.0, 180.0),
    (-180.0, 180.0, 180.0), (725.0, 5.0, 5.0), (-1e-18, 0.0, 0.0),
])
def test_angle_wrapping(angle: float, wrapped: float, signed: float) -> None:
    assert wrap_degrees(angle) == pytest.approx(wrapped)
    assert signed_degrees(angle) == pytest.approx(signed)
