"""Indexing axes (seed 003 chapter 11): the index positions of a table and equidistant ones
(vc/core/axis/indexing.py), the coded positions CAC / CACP / CACN / CDC / CIC in programs, DB31.DBX76.6,
JOG to the next index position (vc/core/axis/index_jog.py) and what the machine reader refuses.
mill_5axis's table C1 (modulo, 30 deg/s in JOG, 540 deg/s^2) with an absolute encoder; the test is
the PLC."""

from __future__ import annotations

import pytest
from core_rig import FIVE_AXIS, Rig, machine

from interfaces.errors import VcError
from vc.config.model import IndexDivision
from vc.core.axis.index_jog import IndexJogState
from vc.core.axis.indexing import IndexPositions

# seed example 1 (L14131-14155): a turret of 8 positions 45 degrees apart in table 1
TURRET = ("NC: {MD10900: 8, MD10910: [0, 45, 90, 135, 180, 225, 270, 315]}\n"
          "CHAN1: {MD20700: 0}\nC1: {MD30240: [4], MD34210: [2], MD30500: 1}")
# seed example 3 (L14200-14235): equidistant from 5 degrees, 18 positions
EQUIDISTANT = "CHAN1: {MD20700: 0}\nC1: {MD30240: [4], MD34210: [2], MD30500: 3, MD30502: 18, MD30503: 5.0}"
PALLET = (-100.0, 0.0, 100.0, 200.0, 300.0, 500.0, 700.0, 900.0, 1250.0, 1650.0)  # example 2 (L14170-14183)


def _rig(overrides: str = TURRET) -> Rig:
    rig = Rig(machine(overrides, FIVE_AXIS))
    rig.ready_mda()
    return rig


def _run(rig: Rig, program: str, cycles: int = 3000) -> None:
    rig.mda(program + "\nM30")
    rig.run_until(lambda: rig.get("CHAN1.basic.in.stateReset") == 1, cycles)


# ---------------------------------------------------------------------- the positions
def test_a_table_on_a_modulo_axis_wraps_after_its_last_position() -> None:
    table = IndexPositions(IndexDivision(table=(0.0, 45.0, 90.0, 135.0, 180.0, 225.0, 270.0, 315.0)), (0.0, 360.0))
    assert table.position(1) == 0.0 and table.position(8) == 315.0 and table.position(9) is None
    assert table.standing_on(405.004, 0.01) == 2 and table.standing_on(50.0, 0.01) == 0
    assert table.ahead(320.0, 1, 0.0) == 360.0 and table.ahead(370.0, -1, 0.01) == 360.0  # L13586-13592
    assert table.below(50.0) == 2


def test_a_linear_table_numbers_0_below_and_ends_at_its_last_position() -> None:
    pallet = IndexPositions(IndexDivision(table=PALLET), None)
    assert pallet.below(-200.0) == 0 and pallet.below(150.0) == 3  # L13920-13930
    assert pallet.ahead(1700.0, 1, 0.0) is None and pallet.ahead(1700.0, -1, 0.0) == 1650.0


def test_equidistant_positions_as_the_seeds_examples() -> None:
    turn = IndexPositions(IndexDivision(offset=5.0, spacing=20.0, count=18), (0.0, 360.0))  # example 3
    assert [turn.position(n) for n in (1, 2, 18)] == [5.0, 25.0, 345.0] and turn.position(19) is None
    assert turn.ahead(350.0, 1, 0.0) == 365.0 and turn.ahead(26.0, -1, 0.0) == 25.0
    line = IndexPositions(IndexDivision(offset=-200.0, spacing=10.0), None)  # example 5 (L14280-14300)
    assert line.position(1) == -200.0 and line.position(41) == 200.0 and line.position(0) == -210.0


# ---------------------------------------------------------------------- the program
@pytest.mark.parametrize(("program", "end"), [
    ("POS[C]=CAC(3)", 90.0),
    ("POS[C]=CACN(3)", -270.0),  # negative, to the same position (L13866)
    ("POS[C]=CACP(8)", 315.0),
    ("POS[C]=CDC(8)", -45.0),  # the shorter way
    ("POS[C]=CIC(-2)", -90.0),  # from position 1 two on, negative: position 7
    ("POS[C]=CIC(10)", 90.0),  # round the turn without a whole turn (L13890-13893): position 3
    ("C=CAC(2) G0", 45.0),  # a coded position is an end point of a path axis too
])
def test_coded_positions_on_the_turret(program: str, end: float) -> None:
    rig = _rig()
    _run(rig, f"N5 POS[C]=0 FA[C]=36000\nN10 {program}")  # from index position 1
    c1 = rig.axis("C1")
    assert c1.setpoint == pytest.approx(end) and rig.alarm_numbers() == []
    assert rig.get("C1.basic.in.indexAxisInPos") == 1


def test_cic_between_two_positions_goes_to_the_next_higher_or_lower_and_cic_0_stays() -> None:
    rig = _rig()
    _run(rig, "N10 POS[C]=100 FA[C]=36000")
    assert rig.get("C1.basic.in.indexAxisInPos") == 0  # between 90 and 135 (L13823-13829)
    _run(rig, "N10 POS[C]=CIC(0)")
    assert rig.axis("C1").setpoint == 100.0
    _run(rig, "N10 POS[C]=CIC(1)")
    assert rig.axis("C1").setpoint == pytest.approx(135.0)  # L13898-13900
    _run(rig, "N10 POS[C]=100\nN20 POS[C]=CIC(-1)")
    assert rig.axis("C1").setpoint == pytest.approx(90.0)


def test_equidistant_indexing_on_the_modulo_table() -> None:
    rig = _rig(EQUIDISTANT)
    _run(rig, "N10 POS[C]=CAC(18) FA[C]=36000")
    assert rig.axis("C1").setpoint == pytest.approx(345.0)
    _run(rig, "N10 POS[C]=CIC(2)")
    assert rig.axis("C1").setpoint == pytest.approx(385.0)  # position 2 (25 degrees) positive


@pytest.mark.parametrize(("overrides", "program", "alarm"), [
    (TURRET, "POS[C]=CAC(9)", 17510),  # the table has 8 positions
    (TURRET, "POS[C]=CAC(60)", 17510),  # 0 .. 59 (L13868)
    (TURRET, "POS[C]=CAC(2.5)", 17510),
    (TURRET, "POS[A]=CAC(1)", 17500),  # A1 is no indexing axis
    (TURRET, "POS[X]=CIC(1)", 17500),
])
def test_what_the_program_cannot_ask_is_refused_before_it_moves(overrides: str, program: str, alarm: int) -> None:
    rig = _rig(overrides)
    start = rig.axis("C1").setpoint  # 295: the table's slide at 95, its first reference mark at 200
    rig.mda(f"N10 {program}\nM30")
    rig.step(20)
    assert alarm in rig.alarm_numbers() and rig.axis("C1").setpoint == start


def test_the_reset_stops_a_coded_motion_between_two_positions() -> None:
    rig = _rig()
    rig.mda("N10 POS[C]=CACN(2) FA[C]=3600\nM30")  # from 295 the negative way to 45
    rig.step(200)
    rig.pulse("CHAN1.basic.out.reset", 2)
    rig.run_until(lambda: rig.axis("C1").command_velocity == 0.0, 200)
    rig.step(50)
    assert 45.0 < rig.axis("C1").setpoint < 295.0 and rig.get("C1.basic.in.indexAxisInPos") == 0


# ---------------------------------------------------------------------- JOG
def _jog_rig(overrides: str = TURRET) -> Rig:
    rig = Rig(machine(overrides, FIVE_AXIS))
    rig.enable_axes()
    rig.select_mode("jog")
    rig.step(2)
    return rig


def _jog_state(rig: Rig) -> IndexJogState:
    jog = rig.axis("C1").index_jog
    assert jog is not None
    return jog.state


def test_continuous_jog_runs_on_to_the_nearest_index_position_it_can_stop_on() -> None:
    rig = _jog_rig()  # C1 at 295
    rig.set("C1.basic.out.traversKeyPlus", 1)
    rig.step(200)  # 30 deg/s: at about 306
    assert _jog_state(rig) is IndexJogState.CONTINUOUS and rig.get("C1.basic.in.indexAxisInPos") == 0
    rig.set("C1.basic.out.traversKeyPlus", 0)
    rig.step(1)
    rig.set("C1.basic.out.traversKeyMinus", 1)  # the other way before it arrives: it still arrives (L13452)
    rig.run_until(lambda: _jog_state(rig) is IndexJogState.ARRIVED, 1000)
    c1 = rig.axis("C1")
    assert c1.setpoint == 315.0
    rig.step(20)
    assert c1.setpoint == 315.0  # the other key must be pressed again (L13454)
    rig.set("C1.basic.out.traversKeyMinus", 0)
    rig.step(20)
    assert _jog_state(rig) is IndexJogState.IDLE and rig.get("C1.basic.in.indexAxisInPos") == 1


def test_continuous_jog_at_speed_stops_on_a_position_it_can_still_brake_for() -> None:
    rig = _jog_rig()
    rig.set("C1.basic.out.enableRapidTravers", 1)  # 120 deg/s: 13.3 degrees to brake
    rig.set("C1.basic.out.traversKeyPlus", 1)
    rig.run_until(lambda: rig.axis("C1").setpoint > 355.0, 1000)
    rig.set("C1.basic.out.traversKeyPlus", 0)
    rig.run_until(lambda: _jog_state(rig) is IndexJogState.ARRIVED, 1000)
    assert rig.axis("C1").setpoint == 405.0  # 360 lies within its braking distance: the next, 45 (L13424-13430)


def test_inc_jog_goes_to_the_next_position_and_stops_at_once_when_the_key_is_released() -> None:
    rig = _jog_rig()
    c1 = rig.axis("C1")
    rig.set("C1.basic.out.inc1", 1)
    rig.set("C1.basic.out.traversKeyMinus", 1)
    rig.run_until(lambda: _jog_state(rig) is IndexJogState.ARRIVED, 1500)
    rig.step(100)
    assert c1.setpoint == 270.0  # one position per press, whatever the increment (L13463-13465)
    rig.set("C1.basic.out.traversKeyMinus", 0)
    rig.step(5)
    rig.set("C1.basic.out.traversKeyMinus", 1)
    rig.step(300)
    rig.set("C1.basic.out.traversKeyMinus", 0)  # released on the way: it stops between two positions
    rig.step(100)
    assert 225.0 < c1.setpoint < 270.0 and _jog_state(rig) is IndexJogState.IDLE
    assert rig.get("C1.basic.in.indexAxisInPos") == 0
    rig.set("C1.basic.out.traversKeyMinus", 1)
    rig.run_until(lambda: _jog_state(rig) is IndexJogState.ARRIVED, 1500)
    assert c1.setpoint == 225.0  # a new press takes it on to that position (L13471-13473)


def test_jog_goes_at_most_to_the_last_index_position_before_the_software_limit() -> None:
    rig = _jog_rig(TURRET.replace("MD30500: 1}", "MD30500: 1, MD36100: 100, MD36110: 300}"))
    rig.set("C1.basic.out.enableModuloLimitSwitch", 1)  # the limits of the modulo table act (L12780-12946)
    rig.set("C1.basic.out.traversKeyMinus", 1)
    rig.run_until(lambda: _jog_state(rig) is IndexJogState.ARRIVED, 3000)
    rig.step(100)
    assert rig.axis("C1").setpoint == 135.0 and rig.alarm_numbers() == []  # L13993-13997


def test_an_unreferenced_indexing_axis_jogs_as_any_axis() -> None:
    rig = _jog_rig(TURRET.replace("MD30240: [4], MD34210: [2], ", ""))
    c1 = rig.axis("C1")
    start = c1.setpoint
    rig.set("C1.basic.out.traversKeyPlus", 1)
    rig.step(100)
    rig.set("C1.basic.out.traversKeyPlus", 0)
    rig.step(100)
    assert c1.command_velocity == 0.0 and start + 4.0 < c1.setpoint < start + 8.0  # L13405-13407
    assert _jog_state(rig) is IndexJogState.IDLE and rig.get("C1.basic.in.indexAxisInPos") == 0


# ---------------------------------------------------------------------- the machine reader
@pytest.mark.parametrize(("overrides", "message"), [
    ("C1: {MD30500: 1}", "MD10900 INDEX_AX_LENGTH_POS_TAB_1 is 0"),
    ("NC: {MD10900: 3, MD10910: [0, 90, 90]}\nC1: {MD30500: 1}", "must ascend and differ"),
    ("NC: {MD10900: 2, MD10910: [0, 400]}\nC1: {MD30500: 1}", "lie in 0 <= p < 360"),
    ("NC: {MD10900: 2, MD10910: [0, 90]}\nC1: {MD30500: 1, MD30505: 1}", "Hirth joint, needs a rotary axis"),
    ("X1: {MD30500: 3, MD30501: 10, MD30505: 1}", "with equidistant index positions"),
    ("C1: {MD30505: 1}", "here MD30500 = 0"),
    ("X1: {MD30500: 3}", "needs MD30501 INDEX_AX_NUMERATOR above 0"),
    ("C1: {MD30500: 4}", "MD30500"),
])
def test_the_reader_refuses_a_bad_index_table(overrides: str, message: str) -> None:
    with pytest.raises(VcError, match=message):
        machine(overrides, FIVE_AXIS)


def test_the_channels_feed_override_at_0_holds_an_indexing_axis_but_no_other_positioning_axis() -> None:
    rig = _rig()
    rig.mda("N10 POS[C]=CACN(2) FA[C]=3600 POSA[Z]=IC(-50) FA[Z]=1000\nM30")  # L13955-13961
    rig.step(50)
    rig.set("CHAN1.basic.out.pathFeedrateOvrFactor", 0)
    rig.step(100)
    c1, z1 = rig.axis("C1"), rig.axis("Z1")
    assert c1.command_velocity == 0.0 and z1.command_velocity != 0.0
    rig.set("CHAN1.basic.out.pathFeedrateOvrFactor", 100)
    rig.step(20)
    assert c1.command_velocity < 0.0


def test_the_same_key_again_before_it_arrives_runs_on_and_an_estop_ends_the_jog() -> None:
    rig = _jog_rig()
    rig.set("C1.basic.out.traversKeyPlus", 1)
    rig.step(100)
    rig.set("C1.basic.out.traversKeyPlus", 0)
    rig.step(5)
    assert _jog_state(rig) is IndexJogState.TO_INDEX_POSITION
    rig.set("C1.basic.out.traversKeyPlus", 1)  # pressed again: it runs on [INF]
    rig.step(5)
    assert _jog_state(rig) is IndexJogState.CONTINUOUS
    rig.axis("C1").brake()  # another owner takes the axis (an emergency stop's braking)
    rig.step(5)
    assert _jog_state(rig) is IndexJogState.IDLE
