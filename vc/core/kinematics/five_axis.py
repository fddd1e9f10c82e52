"""Five-axis kinematics of the Syntec control (seed 001): forward, inverse, tool centre point.

Mechanism types (Pr3001, seed 001 L5-9): 1 spindle (both rotary axes in the head, the 2nd
carried by the 1st), 2 table (both in the table, the 1st carries the 2nd), 3 mixed (1st =
head, 2nd = table), 4 single rotary spindle, 5 single rotary table.

The seed gives the chain vectors and the sign rules but not the equations: the G43.4
chapter and every figure are missing (L42, spec 8.3, 9.1).  The equations below are
assembled from the parameter definitions (spec 8.3 [INF]); docs/kinematics.md explains
each choice.

Rotary axis i (1st, 2nd) turns about the unit vector w_i: the machine axis X, Y, Z of
Pr3005/3006, tilted by the A/B/C components of Pr3015-3020 (L19-21).  The component about
the axis itself is the origin offset, the two others are deviations: a deviation delta_j
about axis e_j turns e_k towards e_j x e_k, so::

    w_k = unit(e_k + sum_j tan(delta_j) (e_j x e_k))     e.g. C: (tan BOC, -tan AOC, 1)

Pr3007/3008: s_i = +1 right-hand, -1 left-hand rule (L12-14), so the physical rotation is::

    R_i = Rot(w_i, s_i theta_i + origin_offset_i)

Tool vector t0 (tip -> holder) at zero angles: Pr3002 axis, turned by RA then RB (L8-11):
3002 = 3: Rz(RB) Ry(RA) z;  = 1: Rx(RB) Rz(RA) x;  = 2: Ry(RB) Rx(RA) y.

With M the machine position of the linear axes, L the tool length and q a point fixed to
the workpiece (machine coordinates when the table axes stand at their zero)::

    holder face F = M - h(theta),  tool t = H(theta) t0,  tip P = F - L t     (head side)
    q' = T(theta) q = Rt(theta) q + b(theta)                                   (table side)

    type 1: H = R1 R2, h = R1 v21 + R1 R2 vT2   (v21 = Pr3024-3026, vT2 = Pr3021-3023)
    type 2: q' = O1 + R1 ((O2 - O1) + R2 (q - O2)),  O1 = Pr3034-3036, O2 = O1 + Pr3031-3033
    type 3: H = R1, h = R1 vT1 (Pr3041-3043);  q' = O2 + R2 (q - O2), O2 = Pr3044-3046
    type 4: H = R1, h = R1 vT1 (project choice: Pr3041-3043, the seed has none)
    type 5: q' = O1 + R1 (q - O1)  (project choice: O1 = Pr3034-3036)

For types 1, 3, 4 an all-zero head vector takes Pr3013 (holder length, rotary centre to
spindle face, L17) along the tool: vT2 = 3013 t0 (type 1), vT1 = 3013 t0 (types 3, 4).

Forward (machine -> pose): the tip P' in machine coordinates is mapped back into the
workpiece, q = Rt^T (P' - b), direction t_w = Rt^T t.  Tool centre point (RTCP, G43.4
type 1): for a tip q and rotary angles, M = T(theta) q + h(theta) + L H(theta) t0, so the
tip stays put while the rotary axes move (L42, L49-53).  Orientation inverse: angles
for a direction t_w, two solutions in general (A10 C0 and A-10 C180, L31), chosen by
G53.1 P (L59-60) within the ranges Pr3009-3012 (L13-15).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from enum import IntEnum

from vc.config import md_dictionary as MD
from vc.config.machine_data import MachineData, MdDef
from vc.core.kinematics.geometry import (
    IDENTITY,
    ORIGIN,
    X_AXIS,
    Y_AXIS,
    Z_AXIS,
    Mat3,
    Vec3,
    rotation,
    rotation_angle,
    signed_degrees,
    wrap_degrees,
)
from vc.core.kinematics.transform_alarm import ROTARY_NO_SOLUTION, TransformAlarm

BLU_DEGREES = 0.001  # a Syntec angle BLU (290 degrees = 290000, seed 001 L15)
BLU_MM = 0.001  # a Syntec length BLU, by the same rule [INF]
ANGLE_TOLERANCE = 1e-9  # degrees: range boundaries are reached, not left
_AXES = {1: X_AXIS, 2: Y_AXIS, 3: Z_AXIS}


class MechanismType(IntEnum):
    SPINDLE = 1  # both rotary axes in the head, the 2nd carried by the 1st
    TABLE = 2  # both in the table, the 1st carries the 2nd
    MIXED = 3  # 1st in the head, 2nd in the table
    SINGLE_SPINDLE = 4
    SINGLE_TABLE = 5

    @property
    def rotary_axes(self) -> int:
        return 1 if self in (MechanismType.SINGLE_SPINDLE, MechanismType.SINGLE_TABLE) else 2


class Preference(IntEnum):
    """G53.1 P: how the 1st (master) rotary axis reaches its target (seed 001 L59-60)."""

    SHORTEST = 0
    POSITIVE = 1
    NEGATIVE = 2


@dataclass(frozen=True, slots=True)
class RotaryAngles:
    """Machine positions of the 1st and 2nd rotary axis in degrees (single types: 2nd unused)."""

    first: float
    second: float = 0.0


NO_ROTATION = RotaryAngles(0.0, 0.0)


@dataclass(frozen=True, slots=True)
class MachinePosition:
    linear: Vec3  # X, Y, Z machine axes: the control point of the head
    rotary: RotaryAngles


@dataclass(frozen=True, slots=True)
class ToolPose:
    """The tool in workpiece coordinates: the tip and the unit vector from the tip to the holder."""

    tip: Vec3
    direction: Vec3


# ------------------------------------------------------------------------------ parameters


@dataclass(frozen=True, slots=True)
class FiveAxisParameters:
    """The mechanism chain as set (Syntec Pr3001-3055, chain group 1), degrees and mm."""

    mechanism: int  # Pr3001, 0 = not set
    tool_direction: int  # Pr3002: 1 = +X, 2 = +Y, 3 = +Z
    tool_tilt_ra: float = 0.0  # Pr3003
    tool_tilt_rb: float = 0.0  # Pr3004
    first_axis: int = 0  # Pr3005: 1 = X, 2 = Y, 3 = Z
    second_axis: int = 0  # Pr3006
    first_hand: int = 0  # Pr3007: 1 = right-hand, 2 = left-hand
    second_hand: int = 0  # Pr3008
    first_range: tuple[float, float] = (0.0, 0.0)  # Pr3009, Pr3010: start, end
    second_range: tuple[float, float] = (0.0, 0.0)  # Pr3011, Pr3012
    holder_length: float = 0.0  # Pr3013
    first_tilt: Vec3 = ORIGIN  # Pr3015-3017: A, B, C components
    second_tilt: Vec3 = ORIGIN  # Pr3018-3020
    tool_to_second: Vec3 = ORIGIN  # Pr3021-3023 (type 1)
    second_to_first: Vec3 = ORIGIN  # Pr3024-3026 (type 1)
    first_to_second: Vec3 = ORIGIN  # Pr3031-3033 (type 2)
    origin_to_first: Vec3 = ORIGIN  # Pr3034-3036 (type 2, and 5)
    tool_to_first: Vec3 = ORIGIN  # Pr3041-3043 (type 3, and 4)
    origin_to_second: Vec3 = ORIGIN  # Pr3044-3046 (type 3)
    rotary_reference: int = 0  # Pr3055: 0 = machine rotary origin, 1 = the work offset's


def parameters_from_machine_data(md: MachineData) -> FiveAxisParameters:
    """The channel's MD63001-63055 (MD630nn = Pr30nn)."""

    def vector(datum: MdDef) -> Vec3:
        x, y, z = md.floats(datum)
        return Vec3(x, y, z)

    def pair(datum: MdDef) -> tuple[float, float]:
        start, end = md.floats(datum)
        return start, end

    return FiveAxisParameters(
        mechanism=md.int(MD.FIVE_AXIS_TYPE), tool_direction=md.int(MD.FIVE_AXIS_TOOL_DIR),
        tool_tilt_ra=md.float(MD.FIVE_AXIS_TOOL_TILT_RA), tool_tilt_rb=md.float(MD.FIVE_AXIS_TOOL_TILT_RB),
        first_axis=md.int(MD.FIVE_AXIS_ROT1_AXIS), second_axis=md.int(MD.FIVE_AXIS_ROT2_AXIS),
        first_hand=md.int(MD.FIVE_AXIS_ROT1_DIR), second_hand=md.int(MD.FIVE_AXIS_ROT2_DIR),
        first_range=pair(MD.FIVE_AXIS_ROT1_RANGE), second_range=pair(MD.FIVE_AXIS_ROT2_RANGE),
        holder_length=md.float(MD.FIVE_AXIS_HOLDER_LENGTH),
        first_tilt=vector(MD.FIVE_AXIS_ROT1_TILT), second_tilt=vector(MD.FIVE_AXIS_ROT2_TILT),
        tool_to_second=vector(MD.FIVE_AXIS_TOOL_TO_ROT2), second_to_first=vector(MD.FIVE_AXIS_ROT2_TO_ROT1),
        first_to_second=vector(MD.FIVE_AXIS_ROT1_TO_ROT2), origin_to_first=vector(MD.FIVE_AXIS_ORIGIN_TO_ROT1),
        tool_to_first=vector(MD.FIVE_AXIS_TOOL_TO_ROT1), origin_to_second=vector(MD.FIVE_AXIS_ORIGIN_TO_ROT2),
        rotary_reference=md.int(MD.FIVE_AXIS_ROTARY_REFERENCE),
    )


def parameters_from_syntec(values: Mapping[int, int]) -> FiveAxisParameters:
    """Parameter values as the Syntec screen shows them: {3001: 2, 3011: 290000, ...} in BLU.

    Angles and lengths are divided by 1000 (0.001 degree, 0.001 mm).  The seed's example
    "Pr3017 = 50000" for a 30 degree origin offset (L20) does not follow this rule and is
    taken as a misprint of 30000 (spec 9.2).
    """

    def angle(number: int) -> float:
        return values.get(number, 0) * BLU_DEGREES

    def vector(first: int, unit: float) -> Vec3:
        return Vec3(*(values.get(number, 0) * unit for number in range(first, first + 3)))

    return FiveAxisParameters(
        mechanism=values.get(3001, 0), tool_direction=values.get(3002, 0),
        tool_tilt_ra=angle(3003), tool_tilt_rb=angle(3004),
        first_axis=values.get(3005, 0), second_axis=values.get(3006, 0),
        first_hand=values.get(3007, 0), second_hand=values.get(3008, 0),
        first_range=(angle(3009), angle(3010)), second_range=(angle(3011), angle(3012)),
        holder_length=values.get(3013, 0) * BLU_MM,
        first_tilt=vector(3015, BLU_DEGREES), second_tilt=vector(3018, BLU_DEGREES),
        tool_to_second=vector(3021, BLU_MM), second_to_first=vector(3024, BLU_MM),
        first_to_second=vector(3031, BLU_MM), origin_to_first=vector(3034, BLU_MM),
        tool_to_first=vector(3041, BLU_MM), origin_to_second=vector(3044, BLU_MM),
        rotary_reference=values.get(3055, 0),
    )


@dataclass(frozen=True, slots=True)
class RotaryAxis:
    """One rotary axis of the chain, resolved."""

    direction: Vec3  # w: unit vector of the axis (tilt included), rotation right-hand about it
    hand: int  # s: +1 right-hand rule, -1 left-hand rule (Pr3007/3008)
    origin_offset: float  # degrees, right-hand: the tilt component about the axis itself
    travel_range: tuple[float, float]  # start, end in degrees; start = end: no limit
    on_table: bool  # a table axis: the work offset's rotary origin applies with Pr3055 = 1

    def physical(self, angle: float) -> float:
        """The right-hand angle about ``direction`` the axis has turned at machine ``angle``."""
        return self.hand * angle + self.origin_offset

    def machine_angle(self, physical: float) -> float:
        return self.hand * (physical - self.origin_offset)

    def matrix(self, angle: float) -> Mat3:
        return rotation(self.direction, self.physical(angle))


@dataclass(frozen=True, slots=True)
class Kinematics:
    """A checked mechanism chain; build it with :func:`resolve`."""

    mechanism: MechanismType
    tool: Vec3  # t0
    first: RotaryAxis
    second: RotaryAxis | None  # None for the single types
    head_first: Vec3  # type 1: v21 (2nd -> 1st axis); types 3, 4: vT1 (tool axis -> 1st axis)
    head_second: Vec3  # type 1: vT2 (tool axis at the holder face -> 2nd axis)
    table_first: Vec3  # types 2, 5: O1, a point on the 1st axis
    table_second: Vec3  # type 2: O2 = O1 + Pr3031-3033; type 3: O2 = Pr3044-3046
    rotary_reference: int  # Pr3055


@dataclass(frozen=True, slots=True)
class KinematicsOff:
    """Five-axis functions cannot work with these parameters; ``reason`` says why."""

    reason: str


def resolve(p: FiveAxisParameters) -> Kinematics | KinematicsOff:
    """Check the parameters and build the chain."""
    if p.mechanism not in range(1, 6):
        return KinematicsOff(f"Pr3001 = {p.mechanism}: the mechanism type is not set (1 .. 5)")
    mechanism = MechanismType(p.mechanism)
    if p.tool_direction not in _AXES:
        return KinematicsOff(f"Pr3002 = {p.tool_direction}: the tool direction is not set (1 .. 3)")
    checks = [("Pr3005", p.first_axis, "Pr3007", p.first_hand)]
    if mechanism.rotary_axes == 2:
        checks.append(("Pr3006", p.second_axis, "Pr3008", p.second_hand))
    for axis_name, axis, hand_name, hand in checks:
        if axis not in _AXES:
            return KinematicsOff(f"{axis_name} = {axis}: the rotary axis is not set (1 .. 3)")
        if hand not in (1, 2):
            return KinematicsOff(f"{hand_name} = {hand}: the rotation direction is not set (1, 2)")
    if mechanism.rotary_axes == 2 and p.first_axis == p.second_axis:
        return KinematicsOff(f"Pr3005 = Pr3006 = {p.first_axis}: two rotary axes about the same axis")
    tool = _tool_vector(p.tool_direction, p.tool_tilt_ra, p.tool_tilt_rb)
    first_on_table = mechanism in (MechanismType.TABLE, MechanismType.SINGLE_TABLE)
    first = _rotary_axis(p.first_axis, p.first_hand, p.first_tilt, p.first_range, first_on_table)
    second = None
    if mechanism.rotary_axes == 2:
        second_on_table = mechanism in (MechanismType.TABLE, MechanismType.MIXED)
        second = _rotary_axis(p.second_axis, p.second_hand, p.second_tilt, p.second_range, second_on_table)
    # Pr3013 and the head vectors both describe the head; the seed does not say how they
    # combine.  Choice: an all-zero head vector takes the holder length along the tool.
    holder = tool * p.holder_length
    head_first, head_second = ORIGIN, ORIGIN
    table_first, table_second = ORIGIN, ORIGIN
    if mechanism is MechanismType.SPINDLE:
        head_first = p.second_to_first
        head_second = p.tool_to_second
        if head_first == ORIGIN and head_second == ORIGIN:
            head_second = holder
    elif mechanism in (MechanismType.MIXED, MechanismType.SINGLE_SPINDLE):
        # The seed gives type 4 no head vector (spec 9.1): it takes Pr3041-3043, the vector
        # of the same role (tool axis -> the head's rotary axis) in type 3.
        head_first = p.tool_to_first if p.tool_to_first != ORIGIN else holder
    if mechanism is MechanismType.MIXED:
        table_second = p.origin_to_second
    elif mechanism in (MechanismType.TABLE, MechanismType.SINGLE_TABLE):
        # Type 5 likewise takes Pr3034-3036, a point on the table's 1st axis as in type 2.
        table_first = p.origin_to_first
        table_second = p.origin_to_first + p.first_to_second
    return Kinematics(mechanism, tool, first, second, head_first, head_second, table_first, table_second,
                      p.rotary_reference)


def _tool_vector(direction: int, ra: float, rb: float) -> Vec3:
    """t0: the Pr3002 axis turned by RA, then RB, right-hand (L8-11)."""
    if direction == 1:
        return rotation(X_AXIS, rb).apply(rotation(Z_AXIS, ra).apply(X_AXIS))
    if direction == 2:
        return rotation(Y_AXIS, rb).apply(rotation(X_AXIS, ra).apply(Y_AXIS))
    return rotation(Z_AXIS, rb).apply(rotation(Y_AXIS, ra).apply(Z_AXIS))


def _rotary_axis(axis: int, hand: int, tilt: Vec3, travel_range: tuple[float, float],
                 on_table: bool) -> RotaryAxis:
    """The axis from Pr3005/3006, Pr3007/3008 and its tilt vector Pr3015-3020.

    The seed defines the components by their projections (L19-21: AOC is the angle from +Z
    about A to the tilted axis's projection on YZ), which fixes the tilted direction without
    an order of rotations: the projection on the plane of e_k and e_j x e_k has the slope
    tan(delta_j).  The component about the axis itself, the origin offset, is read as a
    right-hand angle added to the physical rotation [INF: the figure is missing].
    """
    nominal = _AXES[axis]
    components = (tilt.x, tilt.y, tilt.z)  # about A (X), B (Y), C (Z)
    direction = nominal
    for index, deviation in enumerate(components, start=1):
        if index != axis:
            direction = direction + _AXES[index].cross(nominal) * math.tan(math.radians(deviation))
    return RotaryAxis(direction.unit(), 1 if hand == 1 else -1, components[axis - 1], travel_range, on_table)


def table_zero(kinematics: Kinematics, work_offset: RotaryAngles) -> RotaryAngles:
    """The rotary positions at which workpiece and machine coordinates coincide (Pr3055, L33-41):
    the machine rotary origin (0) or the work offset's rotary values (1, e.g. G54 C15)."""
    return work_offset if kinematics.rotary_reference == 1 else NO_ROTATION


# ------------------------------------------------------------------------------ the chain


def _second(kinematics: Kinematics) -> RotaryAxis:
    assert kinematics.second is not None  # two-axis mechanism types only
    return kinematics.second


def _relative(axis: RotaryAxis, angle: float, zero: float) -> float:
    """A table axis turns the workpiece away from where it was set up: relative to ``zero``."""
    return angle - zero if axis.on_table else angle


def _head(kinematics: Kinematics, angles: RotaryAngles) -> tuple[Mat3, Vec3]:
    """H(theta) and h(theta): the head's rotation and the holder face -> control point vector."""
    mechanism = kinematics.mechanism
    if mechanism is MechanismType.SPINDLE:
        r1 = kinematics.first.matrix(angles.first)
        r12 = r1.times(_second(kinematics).matrix(angles.second))
        return r12, r1.apply(kinematics.head_first) + r12.apply(kinematics.head_second)
    if mechanism in (MechanismType.MIXED, MechanismType.SINGLE_SPINDLE):
        r1 = kinematics.first.matrix(angles.first)
        return r1, r1.apply(kinematics.head_first)
    return IDENTITY, ORIGIN


def _table(kinematics: Kinematics, angles: RotaryAngles, zero: RotaryAngles) -> tuple[Mat3, Vec3]:
    """Rt(theta) and b(theta) of q' = Rt q + b: where the table carries a workpiece point."""
    mechanism = kinematics.mechanism
    first = kinematics.first
    if mechanism is MechanismType.TABLE:
        second = _second(kinematics)
        r1 = first.matrix(_relative(first, angles.first, zero.first))
        r2 = second.matrix(_relative(second, angles.second, zero.second))
        o1, o2 = kinematics.table_first, kinematics.table_second
        # q' = O1 + R1 ((O2 - O1) + R2 (q - O2))
        return r1.times(r2), o1 + r1.apply((o2 - o1) - r2.apply(o2))
    if mechanism is MechanismType.MIXED:
        second = _second(kinematics)
        r2 = second.matrix(_relative(second, angles.second, zero.second))
        o2 = kinematics.table_second
        return r2, o2 - r2.apply(o2)
    if mechanism is MechanismType.SINGLE_TABLE:
        r1 = first.matrix(_relative(first, angles.first, zero.first))
        o1 = kinematics.table_first
        return r1, o1 - r1.apply(o1)
    return IDENTITY, ORIGIN


def forward(kinematics: Kinematics, machine: MachinePosition, tool_length: float,
            zero: RotaryAngles = NO_ROTATION) -> ToolPose:
    """Machine axes -> tool tip and direction in workpiece coordinates."""
    head, head_vector = _head(kinematics, machine.rotary)
    tool = head.apply(kinematics.tool)
    tip = machine.linear - head_vector - tool * tool_length
    table, shift = _table(kinematics, machine.rotary, zero)
    back = table.transposed()
    return ToolPose(back.apply(tip - shift), back.apply(tool))


def tool_center_point(kinematics: Kinematics, tip: Vec3, rotary: RotaryAngles, tool_length: float,
                      zero: RotaryAngles = NO_ROTATION) -> Vec3:
    """RTCP (G43.4 type 1, manual RTCP R519 = 1): the linear machine position that puts the
    tip at the workpiece point ``tip`` with the rotary axes at ``rotary``.

    M = T(theta) q + h(theta) + L H(theta) t0: the tip stays put while the rotary axes move.
    """
    head, head_vector = _head(kinematics, rotary)
    table, shift = _table(kinematics, rotary, zero)
    return table.apply(tip) + shift + head_vector + head.apply(kinematics.tool) * tool_length


def tool_axes(kinematics: Kinematics, rotary: RotaryAngles) -> Mat3:
    """The tool coordinate system of manual moves with R518 = 2 (L49-51): columns X, Y, Z.

    It coincides with the machine axes at zero angles (the tool along the Pr3002 axis, the
    two others cyclic, TV-5X-5) and turns with the head; a table does not turn it.
    """
    head, _ = _head(kinematics, rotary)
    return head


# ------------------------------------------------------------------------------ orientation inverse


def orientation_solutions(kinematics: Kinematics, direction: Vec3, current: RotaryAngles,
                          zero: RotaryAngles = NO_ROTATION) -> tuple[RotaryAngles, ...]:
    """Rotary angles (each in -180 .. 180 plus offsets) that give the workpiece tool direction
    ``direction``: none, one, or two (e.g. A10 C0 and A-10 C180, L31).

    H t0 = Rt t_w, written per type as Rot(w1, sigma phi1) p = Rot(w2, phi2) r with the
    physical angles phi: v = that common vector lies on both circles, v.w1 = p.w1 and
    v.w2 = r.w2.  An axis whose circle is a point (the vector lies on the axis) keeps its
    ``current`` angle: every angle is a solution there.
    """
    target = direction.unit()
    first, t0 = kinematics.first, kinematics.tool
    mechanism = kinematics.mechanism
    if kinematics.second is None:
        # type 4: R1 t0 = t_w;  type 5: R1^T t0 = t_w
        sigma = 1.0 if mechanism is MechanismType.SINGLE_SPINDLE else -1.0
        if abs(first.direction.dot(t0) - first.direction.dot(target)) > 1e-9:
            return ()
        turned = rotation_angle(first.direction, t0, target)
        angle = current.first if turned is None else first.machine_angle(sigma * turned)
        return (RotaryAngles(_add_zero(first, angle, zero.first), current.second),)
    second = kinematics.second
    if mechanism is MechanismType.SPINDLE:  # R1^T t_w = R2 t0
        sigma, p, r = -1.0, target, t0
    elif mechanism is MechanismType.TABLE:  # R1^T t0 = R2 t_w
        sigma, p, r = -1.0, t0, target
    else:  # mixed: R1 t0 = R2 t_w
        sigma, p, r = 1.0, t0, target
    solutions: list[RotaryAngles] = []
    for common in _circle_intersections(first.direction, first.direction.dot(p),
                                        second.direction, second.direction.dot(r)):
        turned_1 = rotation_angle(first.direction, p, common)
        turned_2 = rotation_angle(second.direction, r, common)
        angle_1 = current.first if turned_1 is None else first.machine_angle(sigma * turned_1)
        angle_2 = current.second if turned_2 is None else second.machine_angle(turned_2)
        candidate = RotaryAngles(_add_zero(first, angle_1, zero.first), _add_zero(second, angle_2, zero.second))
        if candidate not in solutions:
            solutions.append(candidate)
    return tuple(solutions)


def _add_zero(axis: RotaryAxis, angle: float, zero: float) -> float:
    return angle + zero if axis.on_table else angle


def _circle_intersections(w1: Vec3, c1: float, w2: Vec3, c2: float) -> tuple[Vec3, ...]:
    """Unit vectors v with v.w1 = c1 and v.w2 = c2 (w1, w2 unit vectors, not parallel).

    v = a w1 + b w2 + c (w1 x w2); the first two conditions give a and b, |v| = 1 gives c.
    """
    d = w1.dot(w2)
    determinant = 1.0 - d * d
    a = (c1 - d * c2) / determinant
    b = (c2 - d * c1) / determinant
    in_plane = a * w1 + b * w2
    rest = 1.0 - in_plane.dot(in_plane)
    if rest < -1e-9:
        return ()
    normal = w1.cross(w2)
    c = math.sqrt(max(rest, 0.0) / determinant)
    if c < 1e-12:
        return (in_plane,)
    return (in_plane + normal * c, in_plane - normal * c)


# ------------------------------------------------------------------------------ ranges and choice


def in_travel_range(travel_range: tuple[float, float], start: float, travel: float = 0.0) -> bool:
    """Does an axis at ``start`` that turns by ``travel`` degrees stay inside the range?

    The range runs from its start to its end in the positive direction of the axis,
    measured from machine 0 (L13-15: 290 -> 70 is the 140 degrees through 0).  Start = end
    is the default of both parameters, read as "no limit" [INF].
    """
    low, high = travel_range
    span = wrap_degrees(high - low)
    if span == 0.0:
        return True
    position = wrap_degrees(start - low)
    if position > span + ANGLE_TOLERANCE and 360.0 - position > ANGLE_TOLERANCE:
        return False
    if position > span + ANGLE_TOLERANCE:  # just below the start: at the start
        position = 0.0
    return -ANGLE_TOLERANCE <= position + travel <= span + ANGLE_TOLERANCE


def leaving_range(kinematics: Kinematics, start: RotaryAngles, end: RotaryAngles) -> int:
    """The number (1, 2) of the first rotary axis that is outside its five-axis travel range
    Pr3009-3012 at ``start`` or leaves it turning to ``end`` (L13-15); 0 when both stay inside."""
    axes = [(1, kinematics.first, start.first, end.first)]
    if kinematics.second is not None:
        axes.append((2, kinematics.second, start.second, end.second))
    for number, axis, begin, finish in axes:
        if not in_travel_range(axis.travel_range, begin, finish - begin):
            return number
    return 0


def choose_solution(kinematics: Kinematics, solutions: tuple[RotaryAngles, ...], current: RotaryAngles,
                    preference: Preference = Preference.SHORTEST) -> RotaryAngles | TransformAlarm:
    """The target the rotary axes travel to, as absolute positions reached from ``current``
    (so a non-modulo axis knows its way): G53.1 P (L59-60).

    SHORTEST (P0): the solution with the shortest travel of the 1st axis; if its target or
    path leaves the range, the other one.  POSITIVE / NEGATIVE (P1 / P2): the 1st axis turns
    that way to the nearest solution; out of range -> COR-153, the other solution is not
    tried (the seed names the fallback for P0 only) [INF].  The 2nd axis takes its shortest
    way, or the other way round if only that stays in range [INF: the seed does not say].
    """
    options: list[tuple[float, bool, RotaryAngles]] = []  # travel of the 1st axis, fits the ranges, target
    for solution in solutions:
        first_travel = _first_travel(solution.first - current.first, preference)
        second_travel = _second_travel(kinematics, current.second, solution.second)
        target = RotaryAngles(current.first + first_travel,
                              current.second + (second_travel or 0.0))
        fits = second_travel is not None and in_travel_range(kinematics.first.travel_range, current.first,
                                                              first_travel)
        options.append((abs(first_travel), fits, target))
    options.sort(key=lambda option: option[0])
    if preference is not Preference.SHORTEST:
        options = options[:1]  # the nearest solution in the commanded direction, no other
    for _, fits, target in options:
        if fits:
            return target
    return TransformAlarm(ROTARY_NO_SOLUTION, "seed 001 L59-60", code="COR-153")


def _first_travel(difference: float, preference: Preference) -> float:
    if preference is Preference.POSITIVE:
        return wrap_degrees(difference)
    if preference is Preference.NEGATIVE:
        travel = wrap_degrees(difference)
        return travel - 360.0 if travel > 0.0 else 0.0
    return signed_degrees(difference)


def _second_travel(kinematics: Kinematics, start: float, target: float) -> float | None:
    if kinematics.second is None:
        return 0.0
    shortest = signed_degrees(target - start)
    for travel in (shortest, shortest - math.copysign(360.0, shortest) if shortest else 0.0):
        if in_travel_range(kinematics.second.travel_range, start, travel):
            return travel
    return None


def inverse(kinematics: Kinematics, pose: ToolPose, tool_length: float, current: RotaryAngles,
            preference: Preference = Preference.SHORTEST,
            zero: RotaryAngles = NO_ROTATION) -> MachinePosition | TransformAlarm:
    """Tool tip and direction (workpiece) -> machine axes, the rotary solution chosen from
    ``current`` with ``preference``; COR-153 as a value when none fits."""
    chosen = choose_solution(kinematics, orientation_solutions(kinematics, pose.direction, current, zero),
                             current, preference)
    if isinstance(chosen, TransformAlarm):
        return chosen
    return MachinePosition(tool_center_point(kinematics, pose.tip, chosen, tool_length, zero), chosen)
