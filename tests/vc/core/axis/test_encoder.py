"""Position measuring system: zero-mark spacing, zero marks crossed, distance-coded marks,
actual value at power-on.

Turn-mill X1: MD31030 = 10 mm pitch, motor encoder, ratio 1:1, zero marks at ... 265, 275,
285 ... (sim zero_mark_offset 275), slide at 150 at power-on.
"""

from __future__ import annotations

import pytest
from core_rig import FIVE_AXIS, Rig, machine
from hypothesis import given
from hypothesis import strategies as st

from vc.config.model import AxisConfig
from vc.core.axis.encoder import DistanceCode, MeasuringSystem, zero_mark_spacing


def axis(name: str, overrides: str = "") -> AxisConfig:
    return machine(overrides).axis(name)


# ------------------------------------------------------------------------------ zero-mark spacing


def test_linear_motor_encoder_with_direct_drive_has_one_mark_per_pitch() -> None:
    assert zero_mark_spacing(axis("X1")) == pytest.approx(10.0)


@pytest.mark.parametrize(("pitch", "load_revs", "motor_revs", "spacing"), [
    (10.0, 1, 2, 5.0),  # motor turns twice per leadscrew turn: 10 mm * 1/2 = 5 mm per motor turn
    (5.0, 3, 1, 15.0),  # 3 leadscrew turns per motor turn: 5 mm * 3 = 15 mm
    (20.0, 2, 5, 8.0),  # 20 mm * 2/5 = 8 mm
])
def test_linear_motor_encoder_spacing_is_pitch_times_load_over_motor_revolutions(
        pitch: float, load_revs: int, motor_revs: int, spacing: float) -> None:
    # MD31050 DRIVE_AX_RATIO_DENOM = load revolutions, MD31060 DRIVE_AX_RATIO_NUMERA = motor
    # revolutions: one motor revolution (one zero mark) moves the slide pitch * DENOM / NUMERA.
    overrides = f"X1: {{MD31030: {pitch}, MD31050: [{load_revs}], MD31060: [{motor_revs}]}}"
    assert zero_mark_spacing(axis("X1", overrides)) == pytest.approx(spacing)


def test_direct_encoder_on_a_spindle_has_one_mark_per_load_revolution() -> None:
    assert zero_mark_spacing(axis("SP1", "SP1: {MD31040: [1]}")) == pytest.approx(360.0)


# ------------------------------------------------------------------------------ zero marks crossed


@pytest.fixture
def x1_encoder() -> MeasuringSystem:
    return MeasuringSystem.for_axis(axis("X1"), 0, 150.0, 275.0)


@pytest.mark.parametrize(("start", "end", "mark"), [
    (270.0, 280.0, 275.0),  # moving plus across one mark
    (280.0, 270.0, 275.0),  # moving minus across the same mark
    (260.0, 290.0, 265.0),  # plus across three marks: the first one passed
    (290.0, 260.0, 285.0),  # minus across three marks: the first one passed
    (270.0, 275.0, 275.0),  # ending exactly on a mark: it is reached
    (280.0, 275.0, 275.0),
    (-7.0, -3.0, -5.0),  # marks continue below zero: ..., -5, 5, ...
])
def test_first_zero_mark_passed(x1_encoder: MeasuringSystem, start: float, end: float, mark: float) -> None:
    assert x1_encoder.zero_mark_between(start, end) == pytest.approx(mark)


@pytest.mark.parametrize(("start", "end"), [
    (276.0, 284.0),  # between two marks
    (284.0, 276.0),
    (275.0, 280.0),  # starting exactly on a mark: it was passed when the slide arrived there
    (275.0, 270.0),
    (275.0, 275.0),  # no motion
])
def test_no_zero_mark_passed(x1_encoder: MeasuringSystem, start: float, end: float) -> None:
    assert x1_encoder.zero_mark_between(start, end) is None


def test_each_mark_is_found_once_when_moving_cycle_by_cycle(x1_encoder: MeasuringSystem) -> None:
    # 0.0667 mm per cycle (2000 mm/min, 2 ms) from 250 to 300 passes 255, 265, 275, 285, 295 once each,
    # in both directions.
    for step in (2000.0 / 60.0 * 0.002, -2000.0 / 60.0 * 0.002):
        position = 250.0 if step > 0 else 300.0
        found = []
        for _ in range(750):
            mark = x1_encoder.zero_mark_between(position, position + step)
            if mark is not None:
                found.append(round(mark, 6))
            position += step
        expected = [255.0, 265.0, 275.0, 285.0, 295.0]
        assert found == (expected if step > 0 else expected[::-1])


# ------------------------------------------------------------------------------ distance-coded marks

# Basic distance B = 20 mm, increment I = 0.02 mm, first mark at 100: marks at 100 (0), 110.02 (1),
# 120 (2), 130.04 (3), 140 (4), 150.06 (5) ...: mark 2k at 100 + 20k, mark 2k+1 at 100 + 20k + 10 + 0.02(k+1).
CODE = DistanceCode(20.0, 0.02, 100.0)


def test_distance_coded_layout() -> None:
    assert [round(CODE.position(i), 6) for i in range(6)] == [100.0, 110.02, 120.0, 130.04, 140.0, 150.06]
    # adjacent gaps: 10.02, 9.98, 10.04, 9.96, 10.06: pairs sum to B
    assert CODE.marks_between(105.0, 131.0) == [1, 2, 3]
    assert CODE.marks_between(131.0, 105.0) == [3, 2, 1]
    assert CODE.marks_between(110.02, 120.0) == [2]  # start excluded, end included


@given(st.integers(min_value=0, max_value=400), st.sampled_from([1, -1]))
def test_two_adjacent_marks_identify_their_place_in_both_directions(first: int, direction: int) -> None:
    lower, upper = CODE.position(first), CODE.position(first + 1)
    crossed_first = first if direction > 0 else first + 1
    assert CODE.identify(upper - lower, direction) == crossed_first


def test_a_gap_that_fits_no_pair_is_not_identified() -> None:
    assert CODE.identify(10.0, 1) is None  # exactly B/2: no pair has it
    assert CODE.identify(10.031, 1) is None  # between 10.02 and 10.04
    assert CODE.identify(25.0, 1) is None


# A rotary encoder with 36 marks a turn (B = 20 deg, I = 0.02 deg), first mark at 200 deg.
ROTARY = DistanceCode(20.0, 0.02, 200.0, period=360.0)


def test_a_rotary_code_repeats_every_turn() -> None:
    assert ROTARY.marks_per_period == 36
    assert ROTARY.position(26) == pytest.approx(460.0)  # 13 x 20 from the first mark
    assert ROTARY.position(26 + 36) == pytest.approx(820.0)  # the same mark one turn on
    assert ROTARY.position(26 - 36) == pytest.approx(100.0)  # ... and one turn back
    assert ROTARY.position(26 - 72) == pytest.approx(-260.0)  # ... and two
    assert ROTARY.reading(26 - 72) == pytest.approx(260.0)  # the encoder cannot tell the turns apart
    # the last mark of a turn (35: 340 + 10 + 18 x 0.02 = 350.36) and the first of the next
    assert ROTARY.position(35) == pytest.approx(550.36)
    assert ROTARY.position(36) == pytest.approx(560.0)
    assert ROTARY.marks_between(95.0, 111.0) == [-10, -9]  # 100 and 110.28
    assert ROTARY.marks_between(111.0, 95.0) == [-9, -10]
    assert ROTARY.marks_between(545.0, 565.0) == [35, 36]


@given(st.integers(min_value=-200, max_value=200), st.sampled_from([1, -1]))
def test_rotary_marks_identify_their_place_in_the_turn_across_turn_ends(first: int, direction: int) -> None:
    lower, upper = ROTARY.position(first), ROTARY.position(first + 1)
    crossed_first = first if direction > 0 else first + 1
    identified = ROTARY.identify(upper - lower, direction)
    assert identified is not None
    assert ROTARY.reading(identified) == pytest.approx(ROTARY.reading(crossed_first))


def test_a_gap_of_more_pairs_than_one_turn_holds_is_not_identified() -> None:
    # 18 pairs a turn: B/2 + 18 I = 10.36 is the widest; 10.38 would be pair 19
    assert ROTARY.identify(10.36, 1) == 34
    assert ROTARY.identify(10.38, 1) is None
    assert DistanceCode(20.0, 0.02, 200.0).identify(10.38, 1) == 36  # a linear scale goes on


def test_a_rotary_distance_coded_encoder_gets_the_period_of_one_encoder_turn() -> None:
    direct = machine("", FIVE_AXIS).axis("C1")  # MD31040 = 1: on the table
    assert MeasuringSystem.for_axis(direct, 0, 95.0, 200.0).distance_code == DistanceCode(
        20.0, 0.02, 200.0, 1, 360.0)
    # a motor encoder behind 3:1 turns once for 120 deg of the axis
    geared = machine("C1: {MD31040: [0], MD31060: [3, 3, 3, 3, 3, 3]}", FIVE_AXIS).axis("C1")
    code = MeasuringSystem.for_axis(geared, 0, 95.0, 200.0).distance_code
    assert code is not None and code.period == pytest.approx(120.0)


def test_missing_marks_are_not_seen() -> None:
    encoder = MeasuringSystem.for_axis(axis("X1", "X1: {MD34200: [3], MD34300: [20.0], MD34310: [0.02]}"),
                                       0, 150.0, 100.0)
    assert [round(p, 3) for p in encoder.coded_marks_between(105.0, 131.0)] == [110.02, 120.0, 130.04]
    encoder.missing_marks.append((115.0, 125.0))
    assert [round(p, 3) for p in encoder.coded_marks_between(105.0, 131.0)] == [110.02, 130.04]


# ------------------------------------------------------------------------------ actual value at power-on


def test_incremental_encoder_starts_at_zero_and_is_not_referenced() -> None:
    x1 = Rig(machine()).axis("X1")
    assert not x1.encoder.referenced
    assert x1.actual == 0.0
    assert x1.encoder.actual(160.0) == pytest.approx(10.0)


def test_calibrated_absolute_encoder_is_referenced_with_actual_equal_to_physical() -> None:
    # MD30240 = 4 (absolute), MD34210 = 2 (calibrated), MD34090 = 0: seed 003 §4.9, §4.10 (L2584-2586).
    x1 = Rig(machine("X1: {MD30240: [4], MD34210: [2]}")).axis("X1")
    assert x1.encoder.referenced
    assert x1.actual == 150.0


def test_calibrated_absolute_encoder_adds_the_reference_point_offset_md34090() -> None:
    x1 = Rig(machine("X1: {MD30240: [4], MD34210: [2], MD34090: [-12.5]}")).axis("X1")
    assert x1.encoder.referenced
    assert x1.actual == pytest.approx(137.5)


@pytest.mark.parametrize("state", [0, 1])
def test_absolute_encoder_not_calibrated_is_not_referenced(state: int) -> None:
    x1 = Rig(machine(f"X1: {{MD30240: [4], MD34210: [{state}]}}")).axis("X1")
    assert not x1.encoder.referenced


def test_synchronising_sets_the_actual_value_at_the_current_position() -> None:
    encoder = MeasuringSystem.for_axis(axis("X1"), 0, 150.0, 275.0)
    encoder.set_actual(277.0, 273.0)
    assert encoder.referenced
    assert encoder.actual(277.0) == pytest.approx(273.0)
    assert encoder.actual(280.0) == pytest.approx(276.0)
