"""Five-axis kinematics (seed 001): hand-computed poses of every type, round trips, ranges.

Rotations used in the comments (right-hand, angles in degrees):
Rx(a) (x, y, z) = (x, y cos a - z sin a, y sin a + z cos a)
Ry(a) (x, y, z) = (x cos a + z sin a, y, -x sin a + z cos a)
Rz(a) (x, y, z) = (x cos a - y sin a, x sin a + y cos a, z)
A left-hand axis (Pr3007/3008 = 2) turns by -angle.
"""

from __future__ import annotations

import math
from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from vc.config.loader import load_machine
from vc.core.kinematics.five_axis import (
    NO_ROTATION,
    FiveAxisParameters,
    Kinematics,
    KinematicsOff,
    MachinePosition,
    MechanismType,
    Preference,
    RotaryAngles,
    ToolPose,
    choose_solution,
    forward,
    in_travel_range,
    inverse,
    leaving_range,
    orientation_solutions,
    parameters_from_machine_data,
    parameters_from_syntec,
    resolve,
    table_zero,
    tool_axes,
    tool_center_point,
)
from vc.core.kinematics.geometry import ORIGIN, Vec3, signed_degrees
from vc.core.kinematics.transform_alarm import ROTARY_NO_SOLUTION, TransformAlarm

MILL_5AXIS = str(Path(__file__).resolve().parents[4] / "scenarios" / "machines" / "mill_5axis.yaml")
RIGHT, LEFT = 1, 2  # Pr3007/3008
X, Y, Z = 1, 2, 3  # Pr3002, Pr3005/3006


def chain(**values: object) -> Kinematics:
    parameters = FiveAxisParameters(**values)  # type: ignore[arg-type]
    kinematics = resolve(parameters)
    assert isinstance(kinematics, Kinematics), kinematics
    return kinematics


def near(actual: Vec3, expected: tuple[float, float, float], tolerance: float = 1e-3) -> bool:
    return all(abs(a - e) <= tolerance for a, e in zip((actual.x, actual.y, actual.z), expected, strict=True))


# C (1st, about Z) carrying A (2nd, about X), both right-hand, tool +Z: the head of TV-5X-2.
SPINDLE_CA = chain(mechanism=1, tool_direction=Z, first_axis=Z, second_axis=X, first_hand=RIGHT, second_hand=RIGHT,
                   second_to_first=Vec3(10.0, 0.0, 0.0), tool_to_second=Vec3(0.0, 0.0, 120.0))


# ------------------------------------------------------------------------------ hand-computed poses


def test_type_1_spindle_head() -> None:
    # C = 90, A = 30, L = 100, tip at the origin.
    # t = Rz(90) Rx(30) z = Rz(90) (0, -0.5, 0.866025) = (0.5, 0, 0.866025)
    # h = R1 v21 + R1 R2 vT2 = Rz(90) (10, 0, 0) + 120 t = (0, 10, 0) + (60, 0, 103.923)
    # M = tip + L t + h = (50, 0, 86.603) + (60, 10, 103.923) = (110, 10, 190.526)
    angles = RotaryAngles(90.0, 30.0)
    machine = tool_center_point(SPINDLE_CA, ORIGIN, angles, 100.0)
    assert near(machine, (110.0, 10.0, 190.526))
    pose = forward(SPINDLE_CA, MachinePosition(machine, angles), 100.0)
    assert near(pose.tip, (0.0, 0.0, 0.0), 1e-9)
    assert near(pose.direction, (0.5, 0.0, 0.866025), 1e-6)


def test_type_1_holder_length_when_the_head_vectors_are_zero() -> None:
    # Pr3013 = 200 along the tool: C = 0, A = 90: t = Rx(90) z = (0, -1, 0)
    # M = tip + (L + 200) t = (0, 0, 0) + 250 (0, -1, 0) = (0, -250, 0)
    head = chain(mechanism=1, tool_direction=Z, first_axis=Z, second_axis=X, first_hand=RIGHT,
                 second_hand=RIGHT, holder_length=200.0)
    assert near(tool_center_point(head, ORIGIN, RotaryAngles(0.0, 90.0), 50.0), (0.0, -250.0, 0.0))


def test_type_2_table_table() -> None:
    # A (1st, about X) carries C (2nd, about Z), both left-hand; O1 = (0, 0, -100) on the A
    # axis, A -> C = (5, 0, 0), so O2 = (5, 0, -100).  A = 90, C = 90, L = 50, tip q = (10, 0, 0).
    # q - O2 = (5, 0, 100);  R2 = Rz(-90): (x, y, z) -> (y, -x, z): (0, -5, 100)
    # + (O2 - O1) = (5, -5, 100);  R1 = Rx(-90): (x, y, z) -> (x, z, -y): (5, 100, 5)
    # + O1 = (5, 100, -95) = q';  M = q' + L t0 = (5, 100, -45)
    # t_w = R2^T R1^T z = Rz(90) Rx(90) z = Rz(90) (0, -1, 0) = (1, 0, 0)
    table = chain(mechanism=2, tool_direction=Z, first_axis=X, second_axis=Z, first_hand=LEFT, second_hand=LEFT,
                  origin_to_first=Vec3(0.0, 0.0, -100.0), first_to_second=Vec3(5.0, 0.0, 0.0))
    angles = RotaryAngles(90.0, 90.0)
    machine = tool_center_point(table, Vec3(10.0, 0.0, 0.0), angles, 50.0)
    assert near(machine, (5.0, 100.0, -45.0))
    pose = forward(table, MachinePosition(machine, angles), 50.0)
    assert near(pose.tip, (10.0, 0.0, 0.0), 1e-9)
    assert near(pose.direction, (1.0, 0.0, 0.0), 1e-9)


def test_tv_5x_7_left_hand_table_turns_clockwise() -> None:
    # 2nd axis C left-hand, O2 = origin, q = (10, 0, 0), C = 90: q' = Rz(-90) q = (0, -10, 0)
    table = chain(mechanism=2, tool_direction=Z, first_axis=X, second_axis=Z, first_hand=LEFT, second_hand=LEFT)
    assert near(tool_center_point(table, Vec3(10.0, 0.0, 0.0), RotaryAngles(0.0, 90.0), 0.0), (0.0, -10.0, 0.0))


@pytest.mark.parametrize(("b", "expected_machine", "expected_tool"), [
    (0.0, (0.0, 0.0, 250.0), (0.0, 0.0, 1.0)),  # M = 250 z
    (90.0, (250.0, 0.0, 0.0), (1.0, 0.0, 0.0)),  # Ry(90) z = (1, 0, 0)
    (30.0, (125.0, 0.0, 216.506), (0.5, 0.0, 0.866025)),  # 250 (sin 30, 0, cos 30)
])
def test_tv_5x_6_mixed_b_head(b: float, expected_machine: tuple[float, float, float],
                              expected_tool: tuple[float, float, float]) -> None:
    # B head (Pr3005 = 2, right-hand), vT1 = (0, 0, 150), L = 100, tip at the origin:
    # M = tip + L t + R1 vT1 = (100 + 150) Ry(B) z
    mixed = chain(mechanism=3, tool_direction=Z, first_axis=Y, second_axis=Z, first_hand=RIGHT, second_hand=LEFT,
                  tool_to_first=Vec3(0.0, 0.0, 150.0))
    machine = tool_center_point(mixed, ORIGIN, RotaryAngles(b, 0.0), 100.0)
    assert near(machine, expected_machine)
    pose = forward(mixed, MachinePosition(machine, RotaryAngles(b, 0.0)), 100.0)
    assert near(pose.tip, (0.0, 0.0, 0.0), 1e-9)
    assert near(pose.direction, expected_tool, 1e-6)


def test_type_3_mixed_with_a_turned_table() -> None:
    # The B head of TV-5X-6 at B = 30 and a left-hand table C about O2 = (100, 0, 0) at C = 90.
    # q' = O2 + Rz(-90) (q - O2) = (100, 0, 0) + Rz(-90) (-100, 0, 0) = (100, 0, 0) + (0, 100, 0)
    # M = q' + 250 (0.5, 0, 0.866025) = (225, 100, 216.506)
    # t_w = R2^T R1 t0 = Rz(90) (0.5, 0, 0.866025) = (0, 0.5, 0.866025)
    mixed = chain(mechanism=3, tool_direction=Z, first_axis=Y, second_axis=Z, first_hand=RIGHT, second_hand=LEFT,
                  tool_to_first=Vec3(0.0, 0.0, 150.0), origin_to_second=Vec3(100.0, 0.0, 0.0))
    angles = RotaryAngles(30.0, 90.0)
    machine = tool_center_point(mixed, ORIGIN, angles, 100.0)
    assert near(machine, (225.0, 100.0, 216.506))
    assert near(forward(mixed, MachinePosition(machine, angles), 100.0).direction, (0.0, 0.5, 0.866025), 1e-6)


def test_type_4_single_spindle() -> None:
    # B head, right-hand, no Pr3041-3043: the holder length Pr3013 = 200 lies along the tool.
    # B = -90: t = Ry(-90) z = (-1, 0, 0);  M = tip + (L + 200) t = (10, 20, 30) + 250 (-1, 0, 0)
    head = chain(mechanism=4, tool_direction=Z, first_axis=Y, first_hand=RIGHT, holder_length=200.0)
    machine = tool_center_point(head, Vec3(10.0, 20.0, 30.0), RotaryAngles(-90.0), 50.0)
    assert near(machine, (-240.0, 20.0, 30.0))
    assert near(forward(head, MachinePosition(machine, RotaryAngles(-90.0)), 50.0).direction, (-1.0, 0.0, 0.0), 1e-9)


def test_type_5_single_table() -> None:
    # C table, left-hand, axis through O1 = (200, 100, 0) (Pr3034-3036).  C = 180, L = 80,
    # tip q = (250, 100, -10): q - O1 = (50, 0, -10); Rz(-180) -> (-50, 0, -10); + O1 = (150, 100, -10)
    # M = q' + 80 z = (150, 100, 70)
    table = chain(mechanism=5, tool_direction=Z, first_axis=Z, first_hand=LEFT,
                  origin_to_first=Vec3(200.0, 100.0, 0.0))
    machine = tool_center_point(table, Vec3(250.0, 100.0, -10.0), RotaryAngles(180.0), 80.0)
    assert near(machine, (150.0, 100.0, 70.0))


def test_mill_5axis_a_point_on_both_axes_stays_put() -> None:
    # The shipped table-table: the A axis runs along X through Y 250 / Z -380, the C axis
    # stands at X 300.  Their crossing (300, 250, -380) does not move whatever A and C do,
    # so the control point stays L above it.
    md = load_machine(MILL_5AXIS).channel("CHAN1").md
    kinematics = resolve(parameters_from_machine_data(md))
    assert isinstance(kinematics, Kinematics) and kinematics.mechanism is MechanismType.TABLE
    for angles in (RotaryAngles(0.0, 0.0), RotaryAngles(-90.0, 45.0), RotaryAngles(30.0, 270.0)):
        assert near(tool_center_point(kinematics, Vec3(300.0, 250.0, -380.0), angles, 120.0),
                    (300.0, 250.0, -260.0), 1e-9)
    assert leaving_range(kinematics, RotaryAngles(-120.0, 123.0), RotaryAngles(-120.0, 123.0)) == 0
    assert leaving_range(kinematics, RotaryAngles(31.0, 0.0), RotaryAngles(31.0, 0.0)) == 1
    assert leaving_range(kinematics, RotaryAngles(0.0, 0.0), RotaryAngles(31.0, 0.0)) == 1  # on the way
    assert leaving_range(kinematics, RotaryAngles(0.0, 0.0), RotaryAngles(-120.0, 270.0)) == 0


# ------------------------------------------------------------------------------ parameters


@pytest.mark.parametrize(("direction", "ra", "rb", "expected"), [
    (Z, 90.0, 0.0, (1.0, 0.0, 0.0)),  # Ry(90) z
    (Z, 90.0, 90.0, (0.0, 1.0, 0.0)),  # Rz(90) Ry(90) z
    (X, 90.0, 0.0, (0.0, 1.0, 0.0)),  # Rz(90) x
    (X, 90.0, 90.0, (0.0, 0.0, 1.0)),  # Rx(90) Rz(90) x
    (Y, 90.0, 0.0, (0.0, 0.0, 1.0)),  # Rx(90) y
    (Y, 90.0, 90.0, (1.0, 0.0, 0.0)),  # Ry(90) Rx(90) y
])
def test_tool_tilt_ra_then_rb(direction: int, ra: float, rb: float, expected: tuple[float, float, float]) -> None:
    head = chain(mechanism=4, tool_direction=direction, tool_tilt_ra=ra, tool_tilt_rb=rb, first_axis=Z,
                 first_hand=RIGHT)
    assert near(head.tool, expected, 1e-12)


def test_tilt_vector_components() -> None:
    # 1st axis C: BOC = 45 about B tilts z towards +x: w = z + tan 45 (y x z) = (1, 0, 1) / sqrt 2
    boc = chain(mechanism=4, tool_direction=Z, first_axis=Z, first_hand=RIGHT, first_tilt=Vec3(0.0, 45.0, 0.0))
    assert near(boc.first.direction, (math.sqrt(0.5), 0.0, math.sqrt(0.5)), 1e-12)
    # AOC = 45 about A tilts z towards -y: w = z + tan 45 (x x z) = (0, -1, 1) / sqrt 2
    aoc = chain(mechanism=4, tool_direction=Z, first_axis=Z, first_hand=RIGHT, first_tilt=Vec3(45.0, 0.0, 0.0))
    assert near(aoc.first.direction, (0.0, -math.sqrt(0.5), math.sqrt(0.5)), 1e-12)
    # COC = 30 is the origin offset of C: C/A head at C = 0, A = 90 points like C = 30:
    # t = Rz(30) Rx(90) z = Rz(30) (0, -1, 0) = (0.5, -0.866025, 0)
    coc = chain(mechanism=1, tool_direction=Z, first_axis=Z, second_axis=X, first_hand=RIGHT, second_hand=RIGHT,
                first_tilt=Vec3(0.0, 0.0, 30.0))
    pose = forward(coc, MachinePosition(ORIGIN, RotaryAngles(0.0, 90.0)), 0.0)
    assert near(pose.direction, (0.5, -0.866025, 0.0), 1e-6)


def test_syntec_parameter_values_in_blu() -> None:
    # The seed's example (L20): 1st axis C, 2nd axis B, COC = 30, BOB = 30 -> Pr3017 and Pr3019
    # in 0.001 degree; the printed Pr3017 = 50000 is read as 30000.  Area 1 of L15: 290 -> 70.
    parameters = parameters_from_syntec({3001: 1, 3002: 3, 3005: 3, 3006: 2, 3007: 1, 3008: 1, 3017: 30000,
                                         3019: 30000, 3011: 290000, 3012: 70000, 3013: 150000,
                                         3021: 0, 3022: 0, 3023: 120500, 3055: 1})
    assert parameters.first_tilt == Vec3(0.0, 0.0, 30.0)
    assert parameters.second_tilt == Vec3(0.0, 30.0, 0.0)
    assert parameters.second_range == (290.0, 70.0)
    assert parameters.holder_length == 150.0
    assert parameters.tool_to_second == Vec3(0.0, 0.0, 120.5)
    kinematics = resolve(parameters)
    assert isinstance(kinematics, Kinematics)
    assert (kinematics.first.origin_offset, kinematics.second and kinematics.second.origin_offset) == (30.0, 30.0)


@pytest.mark.parametrize(("values", "reason"), [
    ({}, "Pr3001"),
    ({"mechanism": 2}, "Pr3002"),
    ({"mechanism": 2, "tool_direction": 3}, "Pr3005"),
    ({"mechanism": 2, "tool_direction": 3, "first_axis": 1}, "Pr3007"),
    ({"mechanism": 2, "tool_direction": 3, "first_axis": 1, "first_hand": 2}, "Pr3006"),
    ({"mechanism": 2, "tool_direction": 3, "first_axis": 1, "first_hand": 2, "second_axis": 3}, "Pr3008"),
    ({"mechanism": 2, "tool_direction": 3, "first_axis": 3, "first_hand": 2, "second_axis": 3, "second_hand": 2},
     "same axis"),
])
def test_incomplete_parameters(values: dict[str, int], reason: str) -> None:
    result = resolve(FiveAxisParameters(**{"mechanism": 0, "tool_direction": 0, **values}))
    assert isinstance(result, KinematicsOff) and reason in result.reason


def test_single_types_need_one_rotary_axis_only() -> None:
    assert isinstance(resolve(FiveAxisParameters(5, 3, first_axis=3, first_hand=2)), Kinematics)


# ------------------------------------------------------------------------------ Pr3055 and tool coordinates


def test_rotary_reference_of_the_work_offset() -> None:
    # Table C left-hand about the origin, tip at workpiece (10, 0, 0), C at 15 degrees.
    # Pr3055 = 0: the workpiece frame is the machine's at C = 0: q' = Rz(-15) (10, 0, 0) = (9.659, -2.588, 0)
    # Pr3055 = 1 with G54 C15: the workpiece frame is the machine's at C = 15: q' = (10, 0, 0)
    table = chain(mechanism=5, tool_direction=Z, first_axis=Z, first_hand=LEFT, rotary_reference=1)
    angles = RotaryAngles(15.0)
    assert near(tool_center_point(table, Vec3(10.0, 0.0, 0.0), angles, 0.0), (9.659, -2.588, 0.0))
    zero = table_zero(table, RotaryAngles(15.0))
    assert near(tool_center_point(table, Vec3(10.0, 0.0, 0.0), angles, 0.0, zero), (10.0, 0.0, 0.0))
    machine_origin = chain(mechanism=5, tool_direction=Z, first_axis=Z, first_hand=LEFT)
    assert table_zero(machine_origin, RotaryAngles(15.0)) == NO_ROTATION


def test_tv_5x_5_tool_coordinates_turn_with_the_head() -> None:
    # At zero angles the tool coordinates are the machine axes; C/A head at C = 90: Rz(90)
    axes = tool_axes(SPINDLE_CA, RotaryAngles(90.0, 0.0))
    assert near(axes.column(0), (0.0, 1.0, 0.0), 1e-12)  # tool X = machine +Y
    assert near(axes.column(2), (0.0, 0.0, 1.0), 1e-12)  # tool Z along the tool
    table = chain(mechanism=2, tool_direction=Z, first_axis=X, second_axis=Z, first_hand=LEFT, second_hand=LEFT)
    assert tool_axes(table, RotaryAngles(90.0, 90.0)).column(0) == Vec3(1.0, 0.0, 0.0)  # a table turns nothing


# ------------------------------------------------------------------------------ orientation inverse and ranges


def test_tv_5x_2_two_solutions_for_one_tool_vector() -> None:
    # A10 C0: t = Rz(0) Rx(10) z = (0, -sin 10, cos 10) = (0, -0.17365, 0.98481); A-10 C180 gives the same
    t = forward(SPINDLE_CA, MachinePosition(ORIGIN, RotaryAngles(0.0, 10.0)), 0.0).direction
    assert near(t, (0.0, -0.17365, 0.98481), 1e-5)
    solutions = orientation_solutions(SPINDLE_CA, t, NO_ROTATION)
    found = sorted((round(signed_degrees(s.first), 6) % 360.0, round(s.second, 6)) for s in solutions)
    assert found == [(0.0, 10.0), (180.0, -10.0)]


def test_a_vertical_tool_keeps_the_free_axis_where_it_is() -> None:
    # t = z: A = 0 and C is free: C stays at its current 33 degrees
    solutions = orientation_solutions(SPINDLE_CA, Vec3(0.0, 0.0, 1.0), RotaryAngles(33.0, 5.0))
    assert [(round(s.first, 9), round(s.second, 9)) for s in solutions] == [(33.0, 0.0)]


def test_tv_5x_1_range_from_290_to_70_degrees() -> None:
    area_1, area_2 = (290.0, 70.0), (70.0, 290.0)
    for angle in (300.0, 0.0, 45.0, -20.0, 360.0):  # through 0: area 1 only
        assert in_travel_range(area_1, angle) and not in_travel_range(area_2, angle)
    for angle in (71.0, 180.0, 289.0, -100.0):  # area 2 only
        assert not in_travel_range(area_1, angle) and in_travel_range(area_2, angle)
    for angle in (70.0, 290.0):  # the ends belong to both
        assert in_travel_range(area_1, angle) and in_travel_range(area_2, angle)
    assert in_travel_range(area_1, 300.0, 100.0)  # 300 -> 40 through 0
    assert not in_travel_range(area_1, 300.0, -100.0)  # 300 -> 200 leaves at 290
    assert not in_travel_range(area_1, 60.0, 300.0)  # ends at 0 but passes 70 .. 290
    assert in_travel_range((0.0, 0.0), 1234.5, -5000.0)  # start = end: no limit


def test_p0_takes_the_other_solution_when_the_short_one_leaves_the_range() -> None:
    # A range 180 -> 0 (A -180 .. 0): A10 is out, so A-10 C180 although C turns 180 degrees
    limited = chain(mechanism=1, tool_direction=Z, first_axis=Z, second_axis=X, first_hand=RIGHT, second_hand=RIGHT,
                    second_range=(180.0, 0.0))
    t = Vec3(0.0, -math.sin(math.radians(10.0)), math.cos(math.radians(10.0)))
    chosen = choose_solution(limited, orientation_solutions(limited, t, NO_ROTATION), NO_ROTATION)
    assert isinstance(chosen, RotaryAngles)
    assert (round(abs(chosen.first), 6), round(chosen.second, 6)) == (180.0, -10.0)
    # without the limit the shortest way: C stays 0, A 10
    free = choose_solution(SPINDLE_CA, orientation_solutions(SPINDLE_CA, t, NO_ROTATION), NO_ROTATION)
    assert isinstance(free, RotaryAngles) and (round(free.first, 6), round(free.second, 6)) == (0.0, 10.0)


def test_p1_p2_turn_the_first_axis_one_way() -> None:
    # From C = 10 the solutions C0 (A10) and C180:
    # P1 (positive): +350 to C0 or +170 to C180 -> C = 180;  P2 (negative): -10 to C0 -> C = 0
    t = Vec3(0.0, -math.sin(math.radians(10.0)), math.cos(math.radians(10.0)))
    current = RotaryAngles(10.0, 0.0)
    solutions = orientation_solutions(SPINDLE_CA, t, current)
    positive = choose_solution(SPINDLE_CA, solutions, current, Preference.POSITIVE)
    negative = choose_solution(SPINDLE_CA, solutions, current, Preference.NEGATIVE)
    assert isinstance(positive, RotaryAngles) and isinstance(negative, RotaryAngles)
    assert (round(positive.first, 6), round(positive.second, 6)) == (180.0, -10.0)  # 10 + 170
    assert (round(negative.first, 6), round(negative.second, 6)) == (0.0, 10.0)  # 10 - 10
    # P2 with A10 forbidden: the nearest solution that way is out of range -> COR-153 (no fallback)
    limited = chain(mechanism=1, tool_direction=Z, first_axis=Z, second_axis=X, first_hand=RIGHT, second_hand=RIGHT,
                    second_range=(180.0, 0.0))
    alarm = choose_solution(limited, orientation_solutions(limited, t, current), current, Preference.NEGATIVE)
    assert isinstance(alarm, TransformAlarm) and alarm.code == "COR-153" and alarm.number == ROTARY_NO_SOLUTION


def test_cor_153_when_no_solution_fits() -> None:
    # A range 0 -> 5: neither A10 nor A-10 fits
    narrow = chain(mechanism=1, tool_direction=Z, first_axis=Z, second_axis=X, first_hand=RIGHT, second_hand=RIGHT,
                   second_range=(0.0, 5.0))
    t = Vec3(0.0, -math.sin(math.radians(10.0)), math.cos(math.radians(10.0)))
    result = inverse(narrow, ToolPose(ORIGIN, t), 100.0, NO_ROTATION)
    assert isinstance(result, TransformAlarm) and result.code == "COR-153"
    # a direction the head cannot reach at all: a single B head cannot tilt the tool towards Y
    single = chain(mechanism=4, tool_direction=Z, first_axis=Y, first_hand=RIGHT)
    assert orientation_solutions(single, Vec3(0.0, 1.0, 0.0), NO_ROTATION) == ()


# ------------------------------------------------------------------------------ round trips over the work space

LENGTH = st.floats(-2000.0, 2000.0)
ANGLE = st.floats(-360.0, 360.0)
OFFSET = st.builds(Vec3, st.floats(-500.0, 500.0), st.floats(-500.0, 500.0), st.floats(-500.0, 500.0))
DEVIATION = st.floats(-5.0, 5.0)  # degrees: a rotary axis a little out of square


@st.composite
def kinematics(draw: st.DrawFn) -> Kinematics:
    mechanism = draw(st.integers(1, 5))
    first_axis, second_axis = draw(st.permutations([1, 2, 3]))[:2]

    def tilt(axis: int) -> Vec3:
        components = [draw(DEVIATION) for _ in range(3)]
        components[axis - 1] = draw(st.floats(-180.0, 180.0))  # the origin offset
        return Vec3(*components)

    return chain(mechanism=mechanism, tool_direction=draw(st.integers(1, 3)),
                 tool_tilt_ra=draw(st.floats(0.0, 360.0)), tool_tilt_rb=draw(st.floats(0.0, 360.0)),
                 first_axis=first_axis, second_axis=second_axis, first_hand=draw(st.integers(1, 2)),
                 second_hand=draw(st.integers(1, 2)), holder_length=draw(st.floats(0.0, 500.0)),
                 first_tilt=tilt(first_axis), second_tilt=tilt(second_axis),
                 tool_to_second=draw(OFFSET), second_to_first=draw(OFFSET), first_to_second=draw(OFFSET),
                 origin_to_first=draw(OFFSET), tool_to_first=draw(OFFSET), origin_to_second=draw(OFFSET))


MACHINE = st.builds(MachinePosition, st.builds(Vec3, LENGTH, LENGTH, LENGTH), st.builds(RotaryAngles, ANGLE, ANGLE))


@settings(max_examples=300)
@given(kinematics(), MACHINE, st.floats(0.0, 300.0), st.builds(RotaryAngles, ANGLE, ANGLE))
def test_tool_center_point_undoes_forward(chain_: Kinematics, machine: MachinePosition, tool_length: float,
                                          zero: RotaryAngles) -> None:
    pose = forward(chain_, machine, tool_length, zero)
    assert math.isclose(pose.direction.norm(), 1.0, abs_tol=1e-12)
    linear = tool_center_point(chain_, pose.tip, machine.rotary, tool_length, zero)
    assert linear.distance(machine.linear) < 1e-7


@settings(max_examples=300)
@given(kinematics(), MACHINE, st.floats(0.0, 300.0), st.builds(RotaryAngles, ANGLE, ANGLE),
       st.builds(RotaryAngles, ANGLE, ANGLE), st.sampled_from(list(Preference)))
def test_forward_after_inverse_returns_the_pose(chain_: Kinematics, machine: MachinePosition, tool_length: float,
                                                current: RotaryAngles, zero: RotaryAngles,
                                                preference: Preference) -> None:
    if chain_.second is None:
        machine = MachinePosition(machine.linear, RotaryAngles(machine.rotary.first))
        current = RotaryAngles(current.first)
    pose = forward(chain_, machine, tool_length, zero)
    solved = inverse(chain_, pose, tool_length, current, preference, zero)
    assert isinstance(solved, MachinePosition)  # no ranges set: a solution always exists
    again = forward(chain_, solved, tool_length, zero)
    assert again.tip.distance(pose.tip) < 1e-7
    assert again.direction.distance(pose.direction) < 1e-6
