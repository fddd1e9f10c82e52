"""Referencing core (seed 003 chapter 4): distance-coded decoding by the procedure, the NC's
machine-data memory and the positioning of the referencing procedure.

Turn-mill X1: measuring system 1 = motor encoder (zero marks every 10 mm at ..., 265, 275,
285), measuring system 2 = linear scale with distance-coded marks (MD34300 = B = 20 mm,
MD34310 = I = 0.02 mm, first mark at physical -20, MD34090[1] = -20: actual = physical).
Scale 2 layout (vc/core/axis/encoder.py): mark 2k at -20 + 20k, mark 2k+1 at -20 + 20k + 10 +
(k+1)*0.02.  The slide stands at 150 at power-on.
"""

from __future__ import annotations

import dataclasses
import itertools

import pytest
from core_rig import DT, Rig, machine
from hypothesis import given, settings
from hypothesis import strategies as st

from vc.config import md_dictionary as MD
from vc.core.axis.encoder import DistanceCode
from vc.core.axis.owner import Owner
from vc.core.nc_memory import NcMemory
from vc.core.referencing.referencing import AxisReferencing

SCALE = DistanceCode(20.0, 0.02, -20.0)  # measuring system 2 of X1


def mark(index: int) -> float:
    return SCALE.position(index)


def test_scale_2_marks_around_the_start_position() -> None:
    # mark 15 = -20 + 140 + 10 + 8*0.02, mark 16 = -20 + 160, mark 17 = -20 + 160 + 10 + 9*0.02
    assert [round(mark(i), 6) for i in (13, 14, 15, 16, 17, 18)] == [110.14, 120.0, 130.16, 140.0, 150.18, 160.0]


# ------------------------------------------------------------------------------ distance-coded decoding


def scale_procedure(overrides: str = "") -> AxisReferencing:
    """X1 on measuring system 2 (the distance-coded scale), enabled; the test is the PLC."""
    rig = Rig(machine(overrides))
    rig.enable_axes("X1")
    rig.set("X1.basic.out.enc1Activation", 0)
    rig.set("X1.basic.out.enc2Activation", 1)
    rig.step(2)
    procedure = rig.nck.referencing.of["X1"]
    assert procedure.axis.active_encoder == 1
    return procedure


def decode(procedure: AxisReferencing, marks: list[float], direction: int) -> bool:
    procedure._marks = list(marks)
    procedure._direction = direction
    return procedure._decode_marks()


@pytest.mark.parametrize(("indices", "direction"), [
    ((16, 15), -1),  # minus from 150: 140.000 then 130.160 (distance 9.84 = B/2 - 8I)
    ((17, 18), 1),  # plus from 150: 150.180 then 160.000 (distance 9.82 = B/2 - 9I)
    ((30, 29), -1),  # 280.000 then 270.300 (distance 9.70 = B/2 - 15I)
    ((2, 3), 1),  # 0.000 then 10.040 (distance 10.04 = B/2 + 2I)
])
def test_two_marks_give_the_absolute_position_in_both_directions(indices: tuple[int, int], direction: int) -> None:
    procedure = scale_procedure()
    assert decode(procedure, [mark(i) for i in indices], direction)
    encoder = procedure.encoder
    # MD34090[1] = -20 = the first mark's physical position: the actual value is the physical one
    assert encoder.offset == pytest.approx(0.0, abs=1e-9)
    assert encoder.actual(123.456) == pytest.approx(123.456)
    assert procedure.axis.actual == pytest.approx(procedure.axis.physical)


@pytest.mark.parametrize(("indices", "direction"), [
    ((16, 15, 14, 13), -1),  # 140.000, 130.160, 120.000, 110.140
    ((17, 18, 19, 20), 1),  # 150.180, 160.000, 170.200, 180.000
])
def test_four_consistent_marks_give_the_absolute_position(indices: tuple[int, ...], direction: int) -> None:
    procedure = scale_procedure("X1: {MD34200: [1, 8]}")
    assert decode(procedure, [mark(i) for i in indices], direction)
    assert procedure.encoder.offset == pytest.approx(0.0, abs=1e-9)


@pytest.mark.parametrize(("marks", "direction"), [
    ([140.0, 130.16, 120.0, 100.0], -1),  # 110.140 not seen: the fourth does not fit the first pair
    ([150.18, 160.0, 170.2, 190.22], 1),  # 180.000 not seen
    ([140.0, 130.16, 119.9, 110.14], -1),  # the third 0.1 mm off its place (> I/4)
])
def test_four_marks_that_do_not_fit_the_scale_are_rejected(marks: list[float], direction: int) -> None:
    # MD34200 = 8: the NC checks the four marks for plausibility (seed 003 L1455-1462)
    procedure = scale_procedure("X1: {MD34200: [1, 8]}")
    offset = procedure.encoder.offset
    assert not decode(procedure, marks, direction)
    assert procedure.encoder.offset == offset  # the actual value system is left alone


def test_a_distance_that_fits_no_pair_is_rejected() -> None:
    procedure = scale_procedure()
    assert not decode(procedure, [140.0, 120.0], -1)  # 20 mm: 130.160 missed
    assert not decode(procedure, [140.0, 130.0], -1)  # exactly B/2: no pair of the scale


def test_the_absolute_offset_md34090_shifts_the_decoded_position() -> None:
    # MD34090 = offset between machine zero and the first mark (seed 003 L1400-1444): with 0 the
    # first mark (physical -20) is machine zero, every actual value is 20 higher than physical
    procedure = scale_procedure("X1: {MD34090: [0.0, 0.0]}")
    assert decode(procedure, [140.0, 130.16], -1)
    assert procedure.encoder.actual(140.0) == pytest.approx(160.0)


@settings(max_examples=60, deadline=None)
@given(st.integers(min_value=1, max_value=60), st.sampled_from([1, -1]), st.sampled_from([2, 4]))
def test_any_adjacent_marks_decode_to_the_physical_position(first: int, direction: int, count: int) -> None:
    procedure = scale_procedure("X1: {MD34200: [1, 8]}" if count == 4 else "")
    indices = [first + direction * n for n in range(count)]
    if min(indices) < 0:
        indices = [i - min(indices) for i in indices]
    assert decode(procedure, [mark(i) for i in indices], direction)
    assert procedure.encoder.offset == pytest.approx(0.0, abs=1e-9)


def inverted_scale_procedure(md34090: float) -> AxisReferencing:
    """X1 with its scale mounted the other way round (MD34320 = 1): first mark at physical 320,
    marks counted towards minus."""
    config = machine(f"X1: {{MD34320: [false, true], MD34090: [0.0, {md34090}]}}")
    axes = tuple(dataclasses.replace(item, sim=dataclasses.replace(item.sim, zero_mark_offset_2=320.0))
                 if item.name == "X1" else item for item in config.axes)
    rig = Rig(dataclasses.replace(config, axes=axes))
    rig.enable_axes("X1")
    rig.set("X1.basic.out.enc1Activation", 0)
    rig.set("X1.basic.out.enc2Activation", 1)
    rig.step(2)
    return rig.nck.referencing.of["X1"]


@pytest.mark.parametrize("direction", [1, -1])
def test_an_inverted_scale_counts_against_the_machine_axis(direction: int) -> None:
    inverted = DistanceCode(20.0, 0.02, 320.0, orientation=-1)
    # mark 17 lies 170.18 from the first mark, towards minus: physical 149.82
    assert inverted.position(17) == pytest.approx(149.82)
    crossed = [17, 16] if direction > 0 else [16, 17]
    procedure = inverted_scale_procedure(0.0)
    assert decode(procedure, [inverted.position(i) for i in crossed], direction)
    # MD34090 = 0: the actual value is minus the distance from the first mark (seed 003 L1404-1407)
    assert procedure.encoder.actual(149.82) == pytest.approx(-170.18)


def test_the_calibration_of_an_inverted_scale_gives_machine_positions() -> None:
    # seed 003 L1420-1437: reference with MD34090 = 0, measure, enter the offset, reference again
    inverted = DistanceCode(20.0, 0.02, 320.0, orientation=-1)
    marks = [inverted.position(i) for i in (16, 17)]
    procedure = inverted_scale_procedure(0.0)
    assert decode(procedure, marks, -1)
    measured, displayed = 149.82, procedure.encoder.actual(149.82)
    procedure = inverted_scale_procedure(measured - displayed)
    assert decode(procedure, marks, -1)
    assert procedure.encoder.actual(149.82) == pytest.approx(149.82)
    assert procedure.encoder.actual(12.5) == pytest.approx(12.5)


# ------------------------------------------------------------------------------ NC memory


def test_memory_writes_one_element_of_an_array_and_keeps_the_others() -> None:
    base = machine().axis("X1").md  # MD34090 = [0.0, -20.0]
    memory = NcMemory()
    memory.write("X1", MD.REFP_MOVE_DIST_CORR, 12.5, 0, base)
    view = memory.view("X1", base)
    assert view.float(MD.REFP_MOVE_DIST_CORR, 0) == 12.5
    assert view.float(MD.REFP_MOVE_DIST_CORR, 1) == -20.0
    memory.write("X1", MD.REFP_MOVE_DIST_CORR, 3.0, 1, base)
    view = memory.view("X1", base)
    assert view.value(MD.REFP_MOVE_DIST_CORR) == (12.5, 3.0)  # the second write keeps the first
    assert base.value(MD.REFP_MOVE_DIST_CORR) == (0.0, -20.0)  # the machine file is not changed


def test_memory_keeps_owners_apart_and_shows_the_base_without_writes() -> None:
    config = machine()
    memory = NcMemory()
    x1, z1 = config.axis("X1").md, config.axis("Z1").md
    memory.write("X1", MD.ENC_REFP_STATE, 2, 0, x1)
    assert memory.view("X1", x1).int(MD.ENC_REFP_STATE, 0) == 2
    assert memory.view("Z1", z1) is z1
    assert memory.view("Z1", z1).int(MD.ENC_REFP_STATE, 0) == 0


def test_memory_writes_a_scalar() -> None:
    base = machine().axis("X1").md
    memory = NcMemory()
    memory.write("X1", MD.REFP_MAX_MARKER_DIST, 55.0, None, base)
    assert memory.view("X1", base).float(MD.REFP_MAX_MARKER_DIST) == 55.0


# ------------------------------------------------------------------------------ positioning (phase 3 / target)


def positioning_rig() -> tuple[AxisReferencing, float]:
    rig = Rig(machine())
    procedure = rig.nck.referencing.of["X1"]
    procedure.axis.take(Owner.REF)
    return procedure, procedure.axis.dyn.max_accel


def approach(procedure: AxisReferencing, target: float, speed: float, max_cycles: int = 20000) -> list[float]:
    """Run ``_approach`` until it reports arrival; the velocities of every cycle."""
    axis = procedure.axis
    velocities = [axis.command_velocity]
    for _ in range(max_cycles):
        arrived = procedure._approach(target, speed, False)
        velocities.append(axis.command_velocity)
        if arrived:
            return velocities
    raise AssertionError(f"not arrived at {target} within {max_cycles} cycles (setpoint {axis.setpoint})")


@settings(max_examples=200, deadline=None)
@given(
    st.floats(min_value=-200.0, max_value=200.0, allow_nan=False),  # target - start
    st.floats(min_value=-1.0, max_value=1.0, allow_nan=False),  # start velocity as a share of the speed
    st.floats(min_value=10.0, max_value=150.0, allow_nan=False),  # positioning speed, mm/s
)
def test_approach_lands_exactly_and_never_brakes_harder_than_md32300(distance: float, share: float,
                                                                     speed: float) -> None:
    procedure, accel = positioning_rig()
    axis = procedure.axis
    axis.setpoint = 150.0
    axis.command_velocity = share * speed
    target = 150.0 + distance
    velocities = approach(procedure, target, speed)
    assert axis.setpoint == target  # exactly, not merely close
    assert axis.command_velocity == 0.0
    for before, after in itertools.pairwise(velocities):
        assert abs(after - before) <= accel * DT * (1 + 1e-9)  # MD32300 = 4 m/s^2
        assert abs(after) <= max(speed, abs(velocities[0])) + 1e-9


@settings(max_examples=100, deadline=None)
@given(st.floats(min_value=0.0, max_value=100.0, allow_nan=False), st.floats(min_value=10.0, max_value=150.0))
def test_approach_from_standstill_never_passes_the_target(distance: float, speed: float) -> None:
    procedure, _ = positioning_rig()
    axis = procedure.axis
    axis.setpoint = 150.0
    axis.command_velocity = 0.0
    positions = [axis.setpoint]
    for _ in range(20000):
        arrived = procedure._approach(150.0 - distance, speed, False)
        positions.append(axis.setpoint)
        if arrived:
            break
    assert axis.setpoint == 150.0 - distance
    assert all(later <= earlier for earlier, later in itertools.pairwise(positions))


def test_approach_too_fast_to_stop_brakes_overshoots_and_comes_back() -> None:
    # L1341-1349: the reference point closer than the braking distance: stop, then return
    procedure, accel = positioning_rig()
    axis = procedure.axis
    axis.setpoint = 150.0
    axis.command_velocity = 83.333  # MD34070 = 5000 mm/min; braking distance 0.87 mm
    velocities = approach(procedure, 150.2, 83.333)
    assert min(velocities) < 0.0  # it came back
    assert axis.setpoint == 150.2
    assert max(abs(b - a) for a, b in itertools.pairwise(velocities)) <= accel * DT * (1 + 1e-9)


def test_approach_held_brakes_with_md32300_and_waits() -> None:
    procedure, accel = positioning_rig()
    axis = procedure.axis
    axis.setpoint = 150.0
    axis.command_velocity = 50.0
    velocities = [50.0]
    for _ in range(100):
        assert not procedure._approach(200.0, 50.0, True)
        velocities.append(axis.command_velocity)
    assert axis.command_velocity == 0.0
    assert axis.setpoint < 200.0
    assert max(abs(b - a) for a, b in itertools.pairwise(velocities)) <= accel * DT * (1 + 1e-9)
