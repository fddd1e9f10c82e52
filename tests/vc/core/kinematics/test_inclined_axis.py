"""Inclined-axis control (seed 000): the test vectors of spec 6.7 and the decision rules.

Theta = -30 degrees throughout, Y inclined, X orthogonal, as in the seed's examples:
cos(-30) = 0.866025, tan(-30) = -0.577350, sin(-30) = -0.5.
"""

from __future__ import annotations

import math
from pathlib import Path

import pytest
from hypothesis import given
from hypothesis import strategies as st

from vc.config.loader import load_machine
from vc.core.kinematics.inclined_axis import (
    IS_C_DEGREES,
    AxisFallback,
    AxisPair,
    ConflictingFunction,
    InclinedAxisOff,
    InclinedAxisParameters,
    Motion,
    Role,
    StrokeLimit,
    configuration_alarms,
    g28_block_alarm,
    g28_leg_motion,
    incompatibility_alarms,
    machine_increment,
    move_inclined_axis,
    parameters_for_channel,
    reference_lost,
    reference_order_alarm,
    reference_return_motion,
    resolve,
    return_path,
    rigid_tapping_alarm,
    settings_from_gsk,
    stroke_check_position,
    to_machine,
    to_program,
)
from vc.core.kinematics.transform_alarm import (
    INCLINED_CONFIGURATION,
    INCLINED_G28_BLOCK,
    INCLINED_INCOMPATIBLE,
    INCLINED_ORDER,
)

TURN_MILL = str(Path(__file__).resolve().parents[4] / "scenarios" / "machines" / "turn_mill.yaml")
Y_INCLINED, X_ORTHOGONAL = 3, 1  # channel axes of turn_mill: X1 = 1, Z1 = 2, Y1 = 3
SEED = InclinedAxisParameters(angle=-30.0, inclined_axis=Y_INCLINED, orthogonal_axis=X_ORTHOGONAL)
ARF_1 = InclinedAxisParameters(-30.0, Y_INCLINED, X_ORTHOGONAL, g28_cartesian=True)
P0 = AxisPair(0.0, 0.0)


def close(actual: AxisPair, expected: tuple[float, float], tolerance: float = 5e-4) -> bool:
    """Equal to the seed's three decimals."""
    return all(abs(a - e) <= tolerance for a, e in zip(actual, expected, strict=True))


# ------------------------------------------------------------------------------ spec 6.7 test vectors


def test_tv_ia_1_g00_y100_moves_both_machine_axes() -> None:
    # Ya = 100 / cos(-30) = 100 / 0.866025 = 115.470
    # Xa = 0 - 1 * 100 * tan(-30) = 0 + 57.735 = 57.735
    assert close(to_machine(SEED, AxisPair(0.0, 100.0)), (57.735, 115.470))
    assert close(P0.plus(machine_increment(SEED, AxisPair(0.0, 100.0), nozagc=False)), (57.735, 115.470))


def test_tv_ia_2_g00_x200_moves_the_orthogonal_axis_only() -> None:
    # P1 -> P2 is X +200: Xa = 57.735 + 200 = 257.735, Ya stays 115.470
    p1 = AxisPair(57.73503, 115.47005)
    assert close(p1.plus(machine_increment(SEED, AxisPair(200.0, 0.0), nozagc=False)), (257.735, 115.470))
    assert close(to_machine(SEED, AxisPair(200.0, 100.0)), (257.735, 115.470))


def test_tv_ia_3_4_nozagc_leaves_the_orthogonal_axis_alone() -> None:
    # NOZAGC = 1: Y100 -> Ya = 115.470, Xa = 0 (not compensated); then X200 -> Xa = 200
    p1 = P0.plus(machine_increment(SEED, AxisPair(0.0, 100.0), nozagc=True))
    assert close(p1, (0.0, 115.470))
    p2 = p1.plus(machine_increment(SEED, AxisPair(200.0, 0.0), nozagc=True))
    assert close(p2, (200.0, 115.470))
    # the move lost the Cartesian relation: a manual reference return is due (L378)
    assert reference_lost(AxisPair(0.0, 100.0), nozagc=True)
    assert not reference_lost(AxisPair(200.0, 0.0), nozagc=True)
    assert not reference_lost(AxisPair(0.0, 100.0), nozagc=False)


def test_tv_ia_5_6_g53_absolute_display() -> None:
    # G53 Y100 (machine): Yp = 100 cos(-30) = 86.603; Xp = 0 + 86.603 * tan(-30) = -50.000
    assert close(to_program(SEED, AxisPair(0.0, 100.0)), (-50.0, 86.603))
    # G53 X200: Xp = 200 - 50 = 150.000, Yp unchanged
    assert close(to_program(SEED, AxisPair(200.0, 100.0)), (150.0, 86.603))


def test_tv_ia_7_g28_with_arf_1_is_cartesian() -> None:
    # G28 Y100 from P0: intermediate P1 = machine (57.735, 115.470) as TV-IA-1;
    # Cartesian leg to the reference Ya = 0: dYa = -115.470,
    # Xa = 57.735 - 1 * (-115.470) * sin(-30) = 57.735 - 57.735 = 0
    path = return_path(ARF_1, P0, Role.INCLINED, intermediate=100.0, reference=0.0, nozagc=False)
    assert close(path.intermediate, (57.735, 115.470))
    assert close(path.reference, (0.0, 0.0))
    assert path.motion is Motion.CARTESIAN
    assert close(to_program(ARF_1, path.intermediate), (0.0, 100.0))  # absolute X 0.000 Y 100.000


def test_tv_ia_8_g28_with_arf_0_keeps_the_orthogonal_axis_on_the_last_leg() -> None:
    # The last leg as printed: from P1 (machine X 0.000, Y 115.470) the inclined axis alone
    # goes to its reference, X stays 0 -> P0 (0, 0).
    assert g28_leg_motion(SEED) is Motion.INCLINED
    assert move_inclined_axis(SEED, AxisPair(0.0, 115.470), 0.0, Motion.INCLINED) == AxisPair(0.0, 0.0)
    # The printed P1 itself is the seed's inconsistent case (spec 6.7): the leg to the
    # intermediate point acts on the orthogonal axis (L72-74) and ends at machine X 57.735,
    # not 0.000; machine X 0 / Y 115.470 would show absolute X -57.735, not 0.000.
    path = return_path(SEED, P0, Role.INCLINED, intermediate=100.0, reference=0.0, nozagc=False)
    assert close(path.intermediate, (57.735, 115.470))
    assert close(path.reference, (57.735, 0.0))
    assert close(to_program(SEED, AxisPair(0.0, 115.470)), (-57.735, 100.0))
    # ... the printed values are those of the NOZAGC = 1 mapping (Xa = Xp, Ya = Yp / cos)
    assert close(P0.plus(machine_increment(SEED, AxisPair(0.0, 100.0), nozagc=True)), (0.0, 115.470))


def test_tv_ia_9_feed_components() -> None:
    # The machine axes move by their increments in the same time, so their velocities are in the
    # ratio of the increments.  Pure Y move at F = 1000: F_ay = 1000 / cos(-30) = 1154.70,
    # F_ax = 0 - 1000 * tan(-30) = +577.35 (the orthogonal axis compensates at that speed)
    feeds = machine_increment(SEED, AxisPair(0.0, 1000.0), nozagc=False)
    assert close(feeds, (577.35, 1154.70), 0.005)
    # The formula as printed, F_p - F_p tan(theta) = 1000 + 577.35 = 1577.35, is not what results:
    assert abs(feeds.orthogonal - 1577.35) > 999.0
    # NOZAGC = 1: no compensation; a pure X move is not converted at all
    assert close(machine_increment(SEED, AxisPair(0.0, 1000.0), nozagc=True), (0.0, 1154.70), 0.005)
    assert machine_increment(SEED, AxisPair(800.0, 0.0), nozagc=False) == AxisPair(800.0, 0.0)


def test_tv_ia_10_diameter_programming_doubles_the_compensation() -> None:
    # C = 2: Xa = 0 - 2 * 100 * tan(-30) = 115.470, Ya = 115.470
    diameter = InclinedAxisParameters(-30.0, Y_INCLINED, X_ORTHOGONAL, diameter_factor=2)
    assert close(to_machine(diameter, AxisPair(0.0, 100.0)), (115.470, 115.470))
    assert close(to_program(diameter, AxisPair(115.470, 115.470)), (0.0, 100.0))


@given(st.floats(-180.0, 180.0).filter(lambda angle: not 84.0 <= abs(angle) <= 96.0),
       st.floats(-2000.0, 2000.0), st.floats(-2000.0, 2000.0), st.sampled_from([1, 2]))
def test_program_machine_program_round_trip(angle: float, x: float, y: float, factor: int) -> None:
    p = InclinedAxisParameters(angle, Y_INCLINED, X_ORTHOGONAL, diameter_factor=factor)
    back = to_program(p, to_machine(p, AxisPair(x, y)))
    assert math.isclose(back.orthogonal, x, abs_tol=1e-6) and math.isclose(back.inclined, y, abs_tol=1e-6)


# ------------------------------------------------------------------------------ parameters


def test_gsk_parameter_words_are_decoded() -> None:
    settings = settings_from_gsk(0b101, 0b110, 0b1, -30000, 3, 1)
    assert settings.enabled and settings.reference_keeps_orthogonal_still
    assert settings.limits_cartesian == (False, True, True)
    assert settings.g28_cartesian
    assert settings.angle == pytest.approx(-30.0)  # -30000 x 0.001 degree (IS-B)
    assert settings_from_gsk(1, 0, 0, -300000, 3, 1, angle_unit=IS_C_DEGREES).angle == pytest.approx(-30.0)
    assert resolve(settings, 6, (1, 2, 3)) == InclinedAxisParameters(
        -30.0, 3, 1, 1, reference_keeps_orthogonal_still=True, limits_cartesian=(False, True, True),
        g28_cartesian=True)


def test_aac_0_switches_the_function_off() -> None:
    assert isinstance(resolve(settings_from_gsk(0b100, 0, 0, -30000, 3, 1), 6, (1, 2, 3)), InclinedAxisOff)


@pytest.mark.parametrize("millidegrees", [85000, 90000, 95000, -85000, -95000, -90000])
def test_the_dead_band_85_to_95_degrees_makes_the_function_invalid(millidegrees: int) -> None:
    result = resolve(settings_from_gsk(1, 0, 0, millidegrees, 3, 1), 6, (1, 2, 3))
    assert isinstance(result, InclinedAxisOff) and "dead band" in result.reason


@pytest.mark.parametrize("millidegrees", [84999, 95001, -84999, -95001, 180000, -180000, 0])
def test_angles_outside_the_dead_band_are_valid(millidegrees: int) -> None:
    assert isinstance(resolve(settings_from_gsk(1, 0, 0, millidegrees, 3, 1), 6, (1, 2, 3)),
                      InclinedAxisParameters)


def test_angles_beyond_180_degrees_are_invalid() -> None:
    assert isinstance(resolve(settings_from_gsk(1, 0, 0, 180001, 3, 1), 6, (1, 2, 3)), InclinedAxisOff)


@pytest.mark.parametrize(("p8211", "p8212"), [(0, 1), (3, 0), (2, 2), (7, 1), (3, 9)])
def test_unusable_axis_numbers(p8211: int, p8212: int) -> None:
    basic = (1, 2, 3)  # basic axes X, Y, Z (GSK 1022 = 1, 2, 3) are channel axes 1, 2, 3

    def axes(fallback: AxisFallback) -> tuple[int, int] | None:
        result = resolve(settings_from_gsk(1, 0, 0, -30000, p8211, p8212, fallback=fallback), 6, basic)
        return None if isinstance(result, InclinedAxisOff) else (result.inclined_axis, result.orthogonal_axis)

    assert axes(AxisFallback.INVALID) is None  # L460
    assert axes(AxisFallback.M_SERIES) == (2, 3)  # L48: inclined Y, orthogonal Z
    assert axes(AxisFallback.T_SERIES) == (1, 3)  # L49: inclined X, orthogonal Z


def test_the_fallback_needs_the_basic_axes() -> None:
    settings = settings_from_gsk(1, 0, 0, -30000, 0, 0, fallback=AxisFallback.M_SERIES)
    assert isinstance(resolve(settings, 2, (1, 2, 0)), InclinedAxisOff)  # no basic Z axis


def test_machine_data_of_turn_mill() -> None:
    channel = load_machine(TURN_MILL).channel("CHAN1")
    assert parameters_for_channel(channel) == InclinedAxisParameters(  # shipped on, AZR = 1
        angle=-30.0, inclined_axis=3, orthogonal_axis=1, reference_keeps_orthogonal_still=True,
        limits_cartesian=(True, True, True), g28_cartesian=True)
    off = load_machine(TURN_MILL, {"CHAN1": {"MD62800": 0}}).channel("CHAN1")
    assert isinstance(parameters_for_channel(off), InclinedAxisOff)
    diameter = load_machine(TURN_MILL, {"CHAN1": {"MD62808": 1}}).channel("CHAN1")
    assert parameters_for_channel(diameter) == InclinedAxisParameters(
        angle=-30.0, inclined_axis=3, orthogonal_axis=1, diameter_factor=2, reference_keeps_orthogonal_still=True,
        limits_cartesian=(True, True, True), g28_cartesian=True)
    # MD62807 = 2 (T series) with MD62805 unset: inclined = geometry X (channel axis 1),
    # orthogonal = geometry Z (channel axis 2, MD20050 = [1, 3, 2])
    fallback = load_machine(TURN_MILL, {"CHAN1": {"MD62800": 1, "MD62805": 0, "MD62807": 2}}).channel("CHAN1")
    result = parameters_for_channel(fallback)
    assert isinstance(result, InclinedAxisParameters)
    assert (result.inclined_axis, result.orthogonal_axis) == (1, 2)


# ------------------------------------------------------------------------------ reference returns


def test_manual_reference_return_with_azr() -> None:
    # From P1 (57.735, 115.470) the inclined axis returns to its reference Ya = 0:
    # AZR = 0 moves the orthogonal axis along (Cartesian): Xa = 57.735 + 115.470 * (-0.5) = 0
    assert reference_return_motion(SEED) is Motion.CARTESIAN
    assert close(move_inclined_axis(SEED, AxisPair(57.735, 115.470), 0.0, Motion.CARTESIAN), (0.0, 0.0))
    # AZR = 1: the orthogonal axis keeps still
    azr = InclinedAxisParameters(-30.0, Y_INCLINED, X_ORTHOGONAL, reference_keeps_orthogonal_still=True)
    assert reference_return_motion(azr) is Motion.INCLINED
    assert move_inclined_axis(azr, AxisPair(57.735, 115.470), 0.0, Motion.INCLINED) == AxisPair(57.735, 0.0)


def test_g28_of_the_orthogonal_axis_is_a_plain_machine_move() -> None:
    # From P1 (program 0 / 100): G28 X200 -> intermediate program X 200 = machine 257.735,
    # then X to its reference 0; the inclined axis does not move
    path = return_path(ARF_1, AxisPair(57.73503, 115.47005), Role.ORTHOGONAL, 200.0, 0.0, nozagc=False)
    assert close(path.intermediate, (257.735, 115.470))
    assert close(path.reference, (0.0, 115.470))


def test_orthogonal_axis_waits_for_the_inclined_axis_at_its_reference_point() -> None:
    alarm = reference_order_alarm(SEED, X_ORTHOGONAL, inclined_at_reference_point=False)
    assert alarm is not None and alarm.number == INCLINED_ORDER == 65820
    assert reference_order_alarm(SEED, X_ORTHOGONAL, inclined_at_reference_point=True) is None
    assert reference_order_alarm(SEED, Y_INCLINED, inclined_at_reference_point=False) is None
    assert reference_order_alarm(SEED, 2, inclined_at_reference_point=False) is None  # Z1 is not in the pair


def test_g28_block_order() -> None:
    # G28 Y_; then G28 X_; is right (L90-94)
    assert g28_block_alarm(SEED, {Y_INCLINED}, inclined_at_reference_point=False) is None
    assert g28_block_alarm(SEED, {X_ORTHOGONAL}, inclined_at_reference_point=True) is None
    # G28 X_; before G28 Y_; (L96-98)
    before = g28_block_alarm(SEED, {X_ORTHOGONAL}, inclined_at_reference_point=False)
    assert before is not None and before.number == INCLINED_ORDER
    # G28 X_ Y_; (L98)
    together = g28_block_alarm(SEED, {X_ORTHOGONAL, Y_INCLINED}, inclined_at_reference_point=True)
    assert together is not None and together.number == INCLINED_G28_BLOCK
    assert g28_block_alarm(SEED, {2}, inclined_at_reference_point=False) is None


# ------------------------------------------------------------------------------ stroke limits


def test_stroke_limits_in_cartesian_or_inclined_coordinates() -> None:
    # Machine P1 = (57.735, 115.470) is program (0, 100).
    p1 = AxisPair(57.73503, 115.47005)
    cartesian = InclinedAxisParameters(-30.0, Y_INCLINED, X_ORTHOGONAL, limits_cartesian=(True, False, False))
    # AOT = 1: checked at the Cartesian position; AOT = 0: at the machine position
    assert close(stroke_check_position(cartesian, StrokeLimit.FIRST, p1), (0.0, 100.0))
    assert stroke_check_position(SEED, StrokeLimit.FIRST, p1) == p1


# ------------------------------------------------------------------------------ incompatibilities


def test_incompatible_functions() -> None:
    alarms = incompatibility_alarms([ConflictingFunction.POLYGON_TURNING, ConflictingFunction.PMC_AXIS])
    assert [alarm.number for alarm in alarms] == [INCLINED_INCOMPATIBLE] * 2
    assert alarms[0].detail == "polygon turning"
    tapping = rigid_tapping_alarm(SEED, Y_INCLINED)
    assert tapping is not None and tapping.number == INCLINED_INCOMPATIBLE
    assert rigid_tapping_alarm(SEED, 2) is None


def test_configuration_rules() -> None:
    assert configuration_alarms(SEED, False, False, True) == ()
    alarms = configuration_alarms(SEED, True, False, False)
    assert [alarm.number for alarm in alarms] == [INCLINED_CONFIGURATION] * 2
    assert "rotary" in alarms[0].detail and "increment" in alarms[1].detail

