"""Circular interpolation G2 / G3: the arc of one block in program coordinates.

An arc lies in the working plane (G17: X Y, G18: Z X, G19: Y Z, abscissa first), from the
start point to the programmed end point, about a centre given either

* by I J K, the centre's coordinates along X Y Z counted from the start point (incremental,
  the default of the SINUMERIK and of the ISO controls of seeds 000-002), or
* by the radius, ``R`` (ISO dialect) or ``CR=`` (SINUMERIK): positive for an arc of at most
  180 degrees, negative for more.

G2 turns clockwise, G3 counter-clockwise, seen from the positive end of the axis normal to
the plane (the third geometry axis, in the order X Y Z, Z X Y, Y Z X).  With I J K and the end
point on the start point the block is a full circle; with a radius it cannot be one (alarm
14040).  The axes of the block outside the plane move linearly with the angle: a helix when
the third geometry axis is among them.

The end point must lie on the circle through the start point: its radius may differ from the
start radius by MD21000 CIRCLE_ERROR_CONST or MD21010 CIRCLE_ERROR_FACTOR x the start radius,
whichever is larger; the centre is then moved onto the perpendicular bisector of start and end
point, so that the path ends on the programmed point.  Beyond, alarm 14040 "error in end point
of circle" [control: the SINUMERIK's check and alarm].

F is the velocity along the path of the geometry axes: the arc and, on a helix, the third axis
(``length``) [control: the SINUMERIK's default FGROUP of the geometry axes].
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

CIRCLE_END_POINT = 14040  # error in end point of circle (also: radius too small, radius with a full circle)
FULL_CIRCLE_DISTANCE = 1e-9  # mm: an end point this close to the start point closes a full circle

# The working planes: indices of the geometry axes (abscissa, ordinate, normal) and the centre words.
PLANES = {"G17": (0, 1, 2), "G18": (2, 0, 1), "G19": (1, 2, 0)}
CENTRE_WORDS = "IJK"  # the centre word of geometry axis 1, 2, 3


@dataclass(frozen=True, slots=True)
class Arc:
    """The arc of one G2 / G3 block; positions are program coordinates keyed by machine axis."""

    plane_axes: tuple[str, str]  # machine axes of the abscissa and the ordinate
    centre: tuple[float, float]
    radius: float
    start_angle: float  # radians, of the start point about the centre
    sweep: float  # radians: + counter-clockwise (G3), - clockwise (G2); +-2 pi a full circle
    linear: tuple[tuple[str, float, float], ...]  # other axes of the block: (axis, start, end)
    length: float  # the path F is measured along

    def point(self, fraction: float) -> dict[str, float]:
        """The program position of every axis of the block at ``fraction`` (0 .. 1) of the path."""
        angle = self.start_angle + self.sweep * fraction
        abscissa, ordinate = self.plane_axes
        positions = {abscissa: self.centre[0] + self.radius * math.cos(angle),
                     ordinate: self.centre[1] + self.radius * math.sin(angle)}
        for axis, start, end in self.linear:
            positions[axis] = start + (end - start) * fraction
        return positions

    def points(self, count: int) -> list[dict[str, float]]:
        """``count`` + 1 evenly spaced points from start to end, for checks along the path."""
        return [self.point(index / count) for index in range(count + 1)]


@dataclass(frozen=True, slots=True)
class ArcTolerance:
    """MD21000 CIRCLE_ERROR_CONST (mm) and MD21010 CIRCLE_ERROR_FACTOR."""

    constant: float = 0.01
    factor: float = 0.001

    def allowed(self, radius: float) -> float:
        return max(self.constant, self.factor * radius)


def plan_arc(counter_clockwise: bool, plane_axes: tuple[str, str], start: tuple[float, float],
             end: tuple[float, float], centre_offset: tuple[float, float] | None, radius: float | None,
             linear: Sequence[tuple[str, float, float, bool]], tolerance: ArcTolerance) -> Arc | str:
    """The arc from ``start`` to ``end`` (plane coordinates) about ``start + centre_offset`` or with
    the signed ``radius``; ``linear``: the block's other axes (axis, start, end, is a geometry axis).
    A text instead of an arc: why the end point does not fit (alarm 14040)."""
    chord = (end[0] - start[0], end[1] - start[1])
    distance = math.hypot(*chord)
    if radius is not None:
        if distance < FULL_CIRCLE_DISTANCE:
            return "full circle programmed with a radius"
        if radius == 0.0 or distance > 2.0 * abs(radius) + tolerance.allowed(abs(radius)):
            return f"radius {radius:g} too small for the end point"
        # the centre on the chord's left (counter-clockwise) or right (clockwise) for an arc up to
        # 180 degrees, on the other side for a negative radius (more than 180 degrees)
        half = min(distance / 2.0, abs(radius))
        height = math.sqrt(abs(radius) ** 2 - half * half)
        left = (-chord[1] / distance, chord[0] / distance)
        side = (1.0 if counter_clockwise else -1.0) * (1.0 if radius > 0 else -1.0)
        middle = ((start[0] + end[0]) / 2.0, (start[1] + end[1]) / 2.0)
        centre = (middle[0] + side * height * left[0], middle[1] + side * height * left[1])
    else:
        assert centre_offset is not None
        centre = (start[0] + centre_offset[0], start[1] + centre_offset[1])
        start_radius = math.hypot(start[0] - centre[0], start[1] - centre[1])
        end_radius = math.hypot(end[0] - centre[0], end[1] - centre[1])
        if start_radius == 0.0 or abs(end_radius - start_radius) > tolerance.allowed(start_radius):
            return f"radius at the end point {end_radius:.4f} differs from the start radius {start_radius:.4f}"
        if distance >= FULL_CIRCLE_DISTANCE:
            centre = _onto_bisector(centre, start, end)
    arc_radius = math.hypot(start[0] - centre[0], start[1] - centre[1])
    start_angle = math.atan2(start[1] - centre[1], start[0] - centre[0])
    if distance < FULL_CIRCLE_DISTANCE:
        sweep = 2.0 * math.pi
    else:
        sweep = (math.atan2(end[1] - centre[1], end[0] - centre[0]) - start_angle) % (2.0 * math.pi)
        if not counter_clockwise:
            sweep = 2.0 * math.pi - sweep
    sweep = sweep if counter_clockwise else -sweep
    helix = math.sqrt(sum((finish - begin) ** 2 for _, begin, finish, geometry in linear if geometry))
    return Arc(plane_axes, centre, arc_radius, start_angle, sweep,
               tuple((axis, begin, finish) for axis, begin, finish, _ in linear),
               math.hypot(arc_radius * abs(sweep), helix))


def _onto_bisector(centre: tuple[float, float], start: tuple[float, float],
                   end: tuple[float, float]) -> tuple[float, float]:
    """The point of the perpendicular bisector of start and end nearest to ``centre``: the
    corrected centre of an end point within the tolerance."""
    middle = ((start[0] + end[0]) / 2.0, (start[1] + end[1]) / 2.0)
    chord = (end[0] - start[0], end[1] - start[1])
    squared = chord[0] ** 2 + chord[1] ** 2
    along = ((centre[0] - middle[0]) * chord[0] + (centre[1] - middle[1]) * chord[1]) / squared
    return centre[0] - along * chord[0], centre[1] - along * chord[1]
