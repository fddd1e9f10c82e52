"""Tilted working plane basics of the Syntec control (seed 001): G68.2 frames and G53.1.

A tilted plane is a frame in workpiece coordinates: an origin and a rotation whose columns
are the plane's X, Y, Z axes, so that a point p of the plane lies at origin + R p.

G68.2 X Y Z I J K (L59) takes I, J, K as Euler angles Z-X'-Z'' as the Euler teach mode
defines them (L56-57: I about Z -> X'Y'Z, J about X' -> X'Y''Z', K about Z' -> XcYcZc)::

    R = Rz(I) Rx(J) Rz(K)

The chapter on G68.2 did not render in the seed (L59), so reading its I, J, K this way is a
choice (spec 8.4 [INF]).  The HMI teach modes (L54-58) that define a plane from data:

* three points: P1 the origin, P1 -> P2 the +X direction, P3 on the +Y side; collinear
  points fail and the plane stays G69;
* two vectors: the plane's X and Z axes in G54 components; not orthogonal or a zero
  vector fails.

(The tool-direction teach mode needs the viewer's "up" to say where "right" is, which only
the missing figure shows; it is not modelled.)

G53.1 P (L59-60) turns the rotary axes so that the tool stands along the plane's Z axis;
P0 / P1 / P2 choose the way of the 1st axis, other P values give COR-149.
"""

from __future__ import annotations

from dataclasses import dataclass

from vc.core.kinematics.five_axis import (
    NO_ROTATION,
    Kinematics,
    Preference,
    RotaryAngles,
    choose_solution,
    orientation_solutions,
)
from vc.core.kinematics.geometry import X_AXIS, Z_AXIS, Mat3, Vec3, rotation
from vc.core.kinematics.transform_alarm import ROTARY_P_OUT_OF_RANGE, TransformAlarm

ORTHOGONALITY_TOLERANCE = 1e-6  # cosine between the taught X and Z axes still taken as 90 degrees


@dataclass(frozen=True, slots=True)
class Frame:
    origin: Vec3  # the plane's origin in workpiece coordinates
    rotation: Mat3  # columns: the plane's X, Y, Z axes in workpiece coordinates

    def to_workpiece(self, point: Vec3) -> Vec3:
        return self.origin + self.rotation.apply(point)

    def to_plane(self, point: Vec3) -> Vec3:
        return self.rotation.transposed().apply(point - self.origin)

    @property
    def normal(self) -> Vec3:
        """The plane's Z axis: the direction G53.1 stands the tool in."""
        return self.rotation.column(2)


@dataclass(frozen=True, slots=True)
class TeachFailure:
    """A teach mode could not define a plane; the control stays in G69."""

    reason: str


def euler_frame(origin: Vec3, i: float, j: float, k: float) -> Frame:
    """G68.2 X Y Z I J K: R = Rz(I) Rx(J) Rz(K), angles in degrees."""
    turn = rotation(Z_AXIS, i).times(rotation(X_AXIS, j)).times(rotation(Z_AXIS, k))
    return Frame(origin, turn)


def three_point_frame(p1: Vec3, p2: Vec3, p3: Vec3) -> Frame | TeachFailure:
    """P1 origin, P1 -> P2 the +X axis, P3 on the +Y side (L55)."""
    x_direction = p2 - p1
    z_direction = x_direction.cross(p3 - p1)
    span = x_direction.norm() * (p3 - p1).norm()
    if span == 0.0 or z_direction.norm() <= 1e-9 * span:  # the sine of the angle at P1 is (almost) 0
        return TeachFailure("the three points lie on one line")
    return _frame_from_axes(p1, x_direction.unit(), z_direction.unit())


def two_vector_frame(origin: Vec3, x_axis: Vec3, z_axis: Vec3) -> Frame | TeachFailure:
    """The plane's X and Z axes given in G54 components (L57-58)."""
    if x_axis.norm() < 1e-12 or z_axis.norm() < 1e-12:
        return TeachFailure("the X or Z axis is a zero vector")
    x_unit, z_unit = x_axis.unit(), z_axis.unit()
    if abs(x_unit.dot(z_unit)) > ORTHOGONALITY_TOLERANCE:
        return TeachFailure("the X and Z axes are not orthogonal")
    return _frame_from_axes(origin, x_unit, z_unit)


def _frame_from_axes(origin: Vec3, x_unit: Vec3, z_unit: Vec3) -> Frame:
    return Frame(origin, Mat3.from_columns(x_unit, z_unit.cross(x_unit), z_unit))


def align_tool(kinematics: Kinematics, frame: Frame, current: RotaryAngles, p: int = 0,
               zero: RotaryAngles = NO_ROTATION) -> RotaryAngles | TransformAlarm:
    """G53.1 P: the rotary targets that stand the tool along the plane's Z axis.

    COR-149 for P other than 0, 1, 2; COR-153 when no solution fits the ranges (L59-60).
    """
    if p not in tuple(Preference):
        return TransformAlarm(ROTARY_P_OUT_OF_RANGE, "seed 001 L59", code="COR-149")
    solutions = orientation_solutions(kinematics, frame.normal, current, zero)
    return choose_solution(kinematics, solutions, current, Preference(p))
