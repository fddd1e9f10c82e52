"""Three-dimensional vectors and rotations for the kinematic transforms.

Plain ``math`` on immutable values: a transform evaluates a handful of 3 x 3 products per
IPO cycle, and value objects keep the formulas close to the documentation
(``R1.apply(v)`` for R1 v, ``a - b``, ``t.dot(w)``).  Angles are in degrees, as the
controls program and display them.

Rotation convention: :func:`rotation` is the right-hand (counter-clockwise seen from the
tip of the axis) rotation about a unit axis, Rodrigues' formula::

    Rot(u, phi) v = v cos(phi) + (u x v) sin(phi) + u (u . v)(1 - cos(phi))
"""

from __future__ import annotations

import math
from dataclasses import dataclass


@dataclass(frozen=True, slots=True)
class Vec3:
    x: float
    y: float
    z: float

    def __add__(self, other: Vec3) -> Vec3:
        return Vec3(self.x + other.x, self.y + other.y, self.z + other.z)

    def __sub__(self, other: Vec3) -> Vec3:
        return Vec3(self.x - other.x, self.y - other.y, self.z - other.z)

    def __neg__(self) -> Vec3:
        return Vec3(-self.x, -self.y, -self.z)

    def __mul__(self, factor: float) -> Vec3:
        return Vec3(self.x * factor, self.y * factor, self.z * factor)

    def __rmul__(self, factor: float) -> Vec3:  # a method of its own: mypyc compiles no aliases
        return Vec3(self.x * factor, self.y * factor, self.z * factor)

    def dot(self, other: Vec3) -> float:
        return self.x * other.x + self.y * other.y + self.z * other.z

    def cross(self, other: Vec3) -> Vec3:
        return Vec3(self.y * other.z - self.z * other.y,
                    self.z * other.x - self.x * other.z,
                    self.x * other.y - self.y * other.x)

    def norm(self) -> float:
        return math.sqrt(self.dot(self))

    def unit(self) -> Vec3:
        """This vector scaled to length 1; the caller makes sure it is not the zero vector."""
        length = self.norm()
        return Vec3(self.x / length, self.y / length, self.z / length)

    def distance(self, other: Vec3) -> float:
        return (self - other).norm()


ORIGIN = Vec3(0.0, 0.0, 0.0)
X_AXIS = Vec3(1.0, 0.0, 0.0)
Y_AXIS = Vec3(0.0, 1.0, 0.0)
Z_AXIS = Vec3(0.0, 0.0, 1.0)


@dataclass(frozen=True, slots=True)
class Mat3:
    """A 3 x 3 matrix by rows: ``m.apply(v)`` = m v, ``m.times(n)`` = m n."""

    row0: Vec3
    row1: Vec3
    row2: Vec3

    @staticmethod
    def from_columns(c0: Vec3, c1: Vec3, c2: Vec3) -> Mat3:
        return Mat3(Vec3(c0.x, c1.x, c2.x), Vec3(c0.y, c1.y, c2.y), Vec3(c0.z, c1.z, c2.z))

    def column(self, index: int) -> Vec3:
        return self.transposed().rows()[index]

    def rows(self) -> tuple[Vec3, Vec3, Vec3]:
        return self.row0, self.row1, self.row2

    def transposed(self) -> Mat3:
        return Mat3.from_columns(self.row0, self.row1, self.row2)

    def apply(self, v: Vec3) -> Vec3:
        return Vec3(self.row0.dot(v), self.row1.dot(v), self.row2.dot(v))

    def times(self, other: Mat3) -> Mat3:
        columns = other.transposed().rows()
        return Mat3.from_columns(*(self.apply(column) for column in columns))


IDENTITY = Mat3(X_AXIS, Y_AXIS, Z_AXIS)


def rotation(axis: Vec3, degrees: float) -> Mat3:
    """Right-hand rotation by ``degrees`` about the unit vector ``axis`` (Rodrigues)."""
    phi = math.radians(degrees)
    c, s = math.cos(phi), math.sin(phi)
    k = 1.0 - c
    x, y, z = axis.x, axis.y, axis.z
    return Mat3(Vec3(c + x * x * k, x * y * k - z * s, x * z * k + y * s),
                Vec3(y * x * k + z * s, c + y * y * k, y * z * k - x * s),
                Vec3(z * x * k - y * s, z * y * k + x * s, c + z * z * k))


def rotation_angle(axis: Vec3, start: Vec3, end: Vec3) -> float | None:
    """The right-hand angle (degrees, -180 .. 180) about ``axis`` that turns ``start`` onto ``end``.

    Only the components perpendicular to ``axis`` count.  None when either of them has no
    such component (it lies on the axis): every angle turns it onto itself, the angle is free.
    """
    start_perpendicular = start - axis * axis.dot(start)
    end_perpendicular = end - axis * axis.dot(end)
    if start_perpendicular.norm() < 1e-12 or end_perpendicular.norm() < 1e-12:
        return None
    sine = axis.dot(start_perpendicular.cross(end_perpendicular))
    cosine = start_perpendicular.dot(end_perpendicular)
    return math.degrees(math.atan2(sine, cosine))


def wrap_degrees(angle: float) -> float:
    """``angle`` mapped into [0, 360)."""
    wrapped = math.fmod(angle, 360.0)
    if wrapped < 0.0:
        wrapped += 360.0
    return 0.0 if wrapped >= 360.0 else wrapped


def signed_degrees(angle: float) -> float:
    """``angle`` mapped into (-180, 180]: the shortest turn with that end position."""
    wrapped = wrap_degrees(angle)
    return wrapped - 360.0 if wrapped > 180.0 else wrapped
