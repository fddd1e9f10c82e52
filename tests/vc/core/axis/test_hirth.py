"""The Hirth joint (MD30505, seed 003 §11.3.2.2 L13740-13767, §11.5 L14030-14080): an indexing axis
locked by a Hirth joint goes only to its index positions (17501 [control]) once referenced (17503
[control]); a stop of the channel or the axis lets it run on to the next index position ahead, where
it waits; the reset, DB31.DBX2.2 and FC18 Stop end its motion there; INC JOG released on the way runs
on as well; the handwheel does not move it.  mill_5axis's table C1 with 8 equidistant positions
45 degrees apart (MD30500 = 3, MD30502 = 8) and an absolute encoder, at 295 degrees at power-on;
the test is the PLC."""

from __future__ import annotations

import pytest
from core_rig import FIVE_AXIS, Rig, machine

from vc.core.axis.command_axis import CommandState
from vc.core.axis.index_jog import IndexJogState
from vc.core.axis.plc_axis import Job

HIRTH = "CHAN1: {MD20700: 0}\nC1: {MD30240: [4], MD34210: [2], MD30500: 3, MD30502: 8, MD30505: 1}"
STOPPED = 0.0


def _rig(overrides: str = HIRTH) -> Rig:
    rig = Rig(machine(overrides, FIVE_AXIS))
    rig.ready_mda()
    return rig


def _on_a_position(position: float) -> bool:
    return abs(position / 45.0 - round(position / 45.0)) < 1e-9


def _ended(rig: Rig) -> None:
    rig.run_until(lambda: rig.get("CHAN1.basic.in.stateReset") == 1, 5000)


@pytest.mark.parametrize(("program", "end"), [
    ("POS[C]=CAC(3) FA[C]=7200", 90.0), ("POS[C]=135 FA[C]=7200", 135.0),
    ("POS[C]=CAC(8) FA[C]=7200\nN15 POS[C]=IC(90)", 405.0), ("G1 C=CACP(1) F7200", 360.0),
])
def test_the_axis_goes_to_its_index_positions(program: str, end: float) -> None:
    rig = _rig()
    rig.mda(f"N10 {program}\nN20 M30")
    _ended(rig)
    assert rig.alarm_numbers() == [] and rig.axis("C1").setpoint == pytest.approx(end)


@pytest.mark.parametrize(("overrides", "program", "alarm"), [
    (HIRTH, "POS[C]=100", 17501),  # no index position
    (HIRTH, "G1 C=AC(10) F7200", 17501),
    (HIRTH, "POS[C]=IC(30)", 17501),
    (HIRTH.replace("MD30240: [4], MD34210: [2], ", ""), "POS[C]=CAC(2)", 17503),  # not referenced
])
def test_what_the_hirth_joint_refuses_before_it_moves(overrides: str, program: str, alarm: int) -> None:
    rig = _rig(overrides)
    start = rig.axis("C1").setpoint
    rig.mda(f"N10 {program}\nM30")
    rig.step(20)
    assert alarm in rig.alarm_numbers() and rig.axis("C1").setpoint == start


@pytest.mark.parametrize("stop", ["nc_stop", "feed_stop", "channel_override", "axis_override"])
def test_a_stop_lets_the_axis_run_on_to_the_next_index_position_and_wait(stop: str) -> None:
    rig = _rig()
    c1 = rig.axis("C1")
    rig.mda("N10 POS[C]=CACP(3) FA[C]=3600\nN20 M30")  # from 295 the positive way to 450
    rig.run_until(lambda: c1.setpoint > 330.0, 2000)  # past 315, towards 360
    signal, held, free = {"nc_stop": ("CHAN1.basic.out.ncStop", 1, 0),
                          "feed_stop": ("C1.basic.out.feedStopSpindleStop", 1, 0),
                          "channel_override": ("CHAN1.basic.out.pathFeedrateOvrFactor", 0, 100),
                          "axis_override": ("C1.basic.out.feedrateOvrFactor", 0, 100)}[stop]
    rig.set(signal, held)
    rig.step(2)
    assert c1.command_velocity > 0.0  # it goes on
    rig.run_until(lambda: c1.command_velocity == STOPPED, 1000)
    assert c1.setpoint == 360.0  # the next index position ahead (L14036-14044)
    rig.step(100)
    assert c1.setpoint == 360.0  # DBX76.6 only once the motion has ended
    if stop == "nc_stop":
        rig.set(signal, free)
        rig.pulse("CHAN1.basic.out.ncStart", 2)
    else:
        rig.set(signal, free)
    _ended(rig)
    assert c1.setpoint == 450.0


def test_the_reset_ends_the_motion_on_the_next_index_position() -> None:
    rig = _rig()
    c1 = rig.axis("C1")
    rig.mda("N10 POS[C]=CACN(2) FA[C]=3600\nN20 M30")  # from 295 the negative way to 45
    rig.step(200)
    rig.pulse("CHAN1.basic.out.reset", 2)
    rig.run_until(lambda: c1.command_velocity == STOPPED, 1000)
    rig.step(50)
    assert _on_a_position(c1.setpoint) and 45.0 < c1.setpoint < 295.0
    assert rig.get("C1.basic.in.indexAxisInPos") == 1
    assert rig.channel.command_axes.by_name["C1"].state is CommandState.IDLE


def test_an_emergency_stop_stops_it_at_once() -> None:
    rig = _rig()
    c1 = rig.axis("C1")
    rig.mda("N10 POS[C]=CACN(2) FA[C]=3600\nN20 M30")
    rig.step(200)
    rig.set("NC.basic.out.emergencyStop", 1)
    rig.run_until(lambda: c1.command_velocity == STOPPED, 1000)
    assert not _on_a_position(c1.setpoint)  # L14048: the operator takes it to a position in JOG


def _fc18(rig: Rig, function: int, position: float) -> None:
    rig.set("C1.plcAxis.out.function", function)
    rig.set("C1.plcAxis.out.position", position)
    rig.set("C1.plcAxis.out.feedrate", 3600.0)
    rig.set("C1.plcAxis.out.start", 1)
    rig.step(2)
    rig.set("C1.plcAxis.out.start", 0)


def test_fc18_goes_to_index_positions_only_and_its_stop_ends_on_the_next_one() -> None:
    rig = _rig()
    plc, c1 = rig.channel.plc_axes.by_name["C1"], rig.axis("C1")
    _fc18(rig, 5, 100.0)
    rig.step(2)
    assert plc.job is Job.FAILED and rig.get("C1.plcAxis.in.errorNumber") == 100
    _fc18(rig, 4, 6)  # index position 6: 225, the way as AC (below 295: negative)
    rig.step(100)
    rig.pulse("C1.plcAxis.out.stop", 2)
    rig.run_until(lambda: c1.command_velocity == STOPPED, 1000)
    assert c1.setpoint == 270.0 and plc.job is Job.IDLE


def _jog_rig() -> Rig:
    rig = Rig(machine(HIRTH, FIVE_AXIS))
    rig.enable_axes()
    rig.select_mode("jog")
    rig.step(2)
    return rig


def test_inc_jog_released_on_the_way_runs_on_to_the_position() -> None:
    rig = _jog_rig()
    c1 = rig.axis("C1")
    rig.set("C1.basic.out.inc1", 1)
    rig.set("C1.basic.out.traversKeyMinus", 1)
    rig.step(150)
    rig.set("C1.basic.out.traversKeyMinus", 0)  # released on the way: a Hirth axis does not stop there
    rig.run_until(lambda: c1.index_jog is not None and c1.index_jog.state is not IndexJogState.TO_INDEX_POSITION,
                  1500)
    assert c1.setpoint == 270.0


def test_continuous_jog_with_the_feed_stop_runs_on_and_the_handwheel_does_not_move_it() -> None:
    rig = _jog_rig()
    c1 = rig.axis("C1")
    rig.set("C1.basic.out.traversKeyPlus", 1)
    rig.step(200)
    rig.set("C1.basic.out.feedStopSpindleStop", 1)
    rig.run_until(lambda: c1.command_velocity == STOPPED, 1500)
    assert c1.setpoint == 315.0
    rig.set("C1.basic.out.traversKeyPlus", 0)
    rig.set("C1.basic.out.feedStopSpindleStop", 0)
    rig.step(20)
    c1.add_handwheel_travel(10.0)
    rig.step(200)
    assert c1.setpoint == 315.0


def test_a_reset_while_it_waits_on_a_position_leaves_no_stop_for_the_next_motion() -> None:
    rig = _rig()
    c1 = rig.axis("C1")
    rig.mda("N10 POS[C]=CACP(3) FA[C]=3600\nN20 M30")
    rig.run_until(lambda: c1.setpoint > 330.0, 2000)
    rig.set("CHAN1.basic.out.ncStop", 1)
    rig.run_until(lambda: c1.command_velocity == STOPPED, 1000)
    rig.set("CHAN1.basic.out.ncStop", 0)
    rig.pulse("CHAN1.basic.out.reset", 2)  # standing on 360, waiting: the reset ends it there
    rig.step(20)
    rig.mda("N10 POS[C]=CACN(7) FA[C]=3600\nN20 M30")  # back to 270
    rig.step(100)
    rig.set("C1.basic.out.feedStopSpindleStop", 1)  # a new hold: the next position ahead, not 360
    rig.run_until(lambda: c1.command_velocity == STOPPED, 1000)
    assert c1.setpoint == 315.0


@pytest.mark.parametrize("program", [
    "PRESETON(C1,90)",  # a zero offset by the actual value (seed 003 L14070)
    "G95 G1 C=90 F0.1",  # a feed per revolution (L14073)
    "G95 F0.1\nN15 G1 X=10 C=90",  # G95 modal from an earlier block
])
def test_the_functions_a_hirth_axis_must_not_be_used_with_are_refused_and_reset_clears_them(program: str) -> None:
    rig = _rig()
    start = rig.axis("C1").setpoint
    rig.mda(f"N10 {program}\nN20 M30")
    rig.step(20)
    assert rig.alarm_numbers() == [17501] and rig.axis("C1").setpoint == start and rig.axis("C1").referenced
    rig.pulse("CHAN1.basic.out.reset", 2)
    rig.step(10)
    assert rig.alarm_numbers() == []


def test_a_hirth_axis_under_g94_again_and_positioning_under_g95_are_not_refused() -> None:
    rig = _rig()  # POS moves at FA in mm/min (deg/min) whatever group 15 says [control]
    rig.mda("N10 G95 F0.1\nN20 POS[C]=CAC(1) FA[C]=7200\nN30 G94 G1 C=90 F7200\nN40 M30")
    _ended(rig)
    assert rig.alarm_numbers() == [] and rig.axis("C1").setpoint == pytest.approx(90.0)


def test_the_handwheel_with_drf_does_not_move_it_in_mda() -> None:
    rig = _rig()  # seed 003 L14074, L14081: no DRF offset on a Hirth axis, as no handwheel in JOG
    c1 = rig.axis("C1")
    rig.set("C1.basic.out.handwheelSelection", 1)
    rig.set("C1.basic.out.inc100", 1)
    rig.set("CHAN1.basic.out.handwheelOffsetDrf", 1)
    rig.step(2)
    start = c1.actual
    rig.nck.turn_handwheel(1, 20, 1)
    rig.step(200)
    assert c1.drf_offset == 0.0 and c1.actual == pytest.approx(start, abs=1e-9)


@pytest.mark.parametrize("program", [
    "G43.4 H1",  # the kinematic transformation (seed 003 L14066)
    "G68.2 X0 Y0 Z0 I0 J30 K0",  # the tilted plane's frame (L14077)
])
def test_a_transformation_or_frame_over_a_hirth_axis_is_refused_at_selection(program: str) -> None:
    rig = _rig()
    rig.mda(f"N10 {program}\nN20 G1 X=10 F1000\nN30 M30")
    rig.step(20)
    assert rig.alarm_numbers() == [17501] and rig.axis("X1").setpoint == 0.0
    rig.pulse("CHAN1.basic.out.reset", 2)
    rig.step(10)
    assert rig.alarm_numbers() == []
    rig.mda("N10 G43 H1\nN20 G49\nN30 M30")  # G43 alone turns no axis: allowed
    _ended(rig)
    assert rig.alarm_numbers() == []
