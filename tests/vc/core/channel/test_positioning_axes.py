"""Positioning axes of the part program (seed 003 chapter 9): POS / POSA on the axis interpolators
of vc/core/axis/command_axis.py, the block change of types 1 and 2, WAITP, FA, the motion-end
conditions, NC stop and reset, DB31.DBX76.5 and DBD78.  Turn-mill with absolute encoders: X1 at
150, Z1 at 300; MD32300 4 m/s^2; the test is the PLC."""

from __future__ import annotations

import pytest
from core_rig import ABSOLUTE_XYZ, DT, Rig, machine

from vc.core.axis.command_axis import CommandState
from vc.core.axis.owner import Owner
from vc.core.program.block_plan import BlockPlan, DecodeAlarm, PositioningMotion
from vc.core.program.interpreter import decode
from vc.core.program.program import parse_program


def _rig(overrides: str = ABSOLUTE_XYZ) -> Rig:
    rig = Rig(machine(overrides))
    rig.ready_mda()
    return rig


def _block(rig: Rig) -> int:
    return rig.channel.run.block_index


def _state(rig: Rig, name: str = "Z1") -> CommandState:
    return rig.channel.command_axes.by_name[name].state


def test_pos_holds_the_block_until_the_axis_is_in_its_fine_window_and_runs_at_fa() -> None:
    rig = _rig()
    rig.mda("N10 G1 X140 F6000 POS[Z]=200 FA[Z]=3000\nN20 M30")
    z1 = rig.axis("Z1")
    rig.step(200)
    assert z1.command_velocity * 60.0 == pytest.approx(-3000.0)  # FA, not the path's F
    assert rig.get("Z1.basic.in.isPosAxis") == 1 and rig.get("Z1.basic.in.posAxisFeedrateValue") == 3000.0
    assert rig.axis("X1").setpoint == 140.0 and _block(rig) == 0  # the path is there, the block waits (type 1)
    rig.run_until(lambda: _block(rig) == 1, 2000)
    assert abs(z1.actual - 200.0) <= z1.dyn.fine_window and rig.nck.cycle * DT == pytest.approx(2.0, abs=0.1)
    assert rig.get("Z1.basic.in.isPosAxis") == 0


def test_posa_lets_the_program_go_on_and_waitp_waits_for_the_axis() -> None:
    rig = _rig()
    rig.mda("N10 POSA[Z]=200 FA[Z]=1500\nN20 G1 X140 F6000\nN30 WAITP(Z)\nN40 X130\nN50 M30")
    rig.run_until(lambda: _block(rig) == 2, 200)  # N10 and N20 are done while Z1 still travels (type 2)
    assert _state(rig) is CommandState.POSITIONING
    rig.step(100)
    assert _block(rig) == 2 and rig.axis("X1").setpoint == 140.0  # WAITP holds N40 back
    rig.run_until(lambda: _block(rig) == 3, 5000)
    assert rig.axis("Z1").setpoint == 200.0 and rig.nck.cycle * DT == pytest.approx(4.0, abs=0.1)


def test_a_posa_axis_programmed_again_waits_for_its_end_and_the_program_end_waits_too() -> None:
    rig = _rig()
    rig.mda("N10 POSA[Z]=250 FA[Z]=3000\nN20 Z240 G1 F3000\nN30 POSA[Z]=IC(-10)\nN40 M30")
    rig.step(100)
    assert _block(rig) == 1 and rig.axis("Z1").owner is Owner.COMMAND  # N20 waits before it is decoded
    rig.run_until(lambda: rig.axis("Z1").owner is Owner.PATH, 1000)  # N20 after Z1 arrived at 250
    assert rig.nck.cycle * DT == pytest.approx(1.0, abs=0.05)
    rig.run_until(lambda: rig.get("CHAN1.basic.in.stateReset") == 1, 2000)
    z1 = rig.axis("Z1")
    assert z1.setpoint == 230.0 and _state(rig) is CommandState.IDLE  # M30 ended after Z1 arrived


def test_nc_stop_and_the_feed_disable_hold_it_nc_start_continues_the_reset_stops_it() -> None:
    rig = _rig()
    rig.mda("N10 POSA[Z]=100 FA[Z]=2000\nN20 G4 F20\nN30 M30")
    z1 = rig.axis("Z1")
    rig.step(50)
    rig.pulse("CHAN1.basic.out.ncStop", 2)  # the channel's signals act on its positioning axes (L11044)
    rig.step(50)
    assert z1.command_velocity == 0.0 and _state(rig) is CommandState.POSITIONING
    rig.pulse("CHAN1.basic.out.ncStart", 2)
    rig.step(20)
    assert z1.command_velocity * 60.0 == pytest.approx(-2000.0)
    rig.set("CHAN1.basic.out.disableFeed", 1)
    rig.step(20)
    assert z1.command_velocity == 0.0
    rig.set("CHAN1.basic.out.disableFeed", 0)
    rig.set("Z1.basic.out.feedrateOvrFactor", 50)  # its own override, not the channel's (L11597)
    rig.channel_overrides(feed=10)
    rig.step(20)
    assert z1.command_velocity * 60.0 == pytest.approx(-1000.0)
    rig.pulse("CHAN1.basic.out.reset", 2)
    rig.step(30)
    assert z1.command_velocity == 0.0 and _state(rig) is CommandState.IDLE and z1.setpoint > 100.0
    assert rig.get("Z1.basic.in.isPosAxis") == 0


def test_db31_dbx2_2_deletes_its_distance_to_go_and_the_block_goes_on() -> None:
    rig = _rig()
    rig.mda("N10 POS[Z]=100 FA[Z]=2000\nN20 M30")
    rig.step(50)
    rig.set("Z1.basic.out.resetMovement", 1)
    rig.run_until(lambda: rig.get("CHAN1.basic.in.stateReset") == 1, 200)
    assert rig.axis("Z1").setpoint > 290.0


def test_ipoenda_ends_the_block_with_the_interpolation_and_the_condition_is_modal() -> None:
    rig = _rig()
    rig.mda("N10 IPOENDA[Z]\nN20 POS[Z]=290 FA[Z]=3000\nN30 M30")
    rig.run_until(lambda: _block(rig) == 2, 1000)
    z1 = rig.axis("Z1")
    assert z1.setpoint == 290.0 and abs(z1.distance_to_end_point) > z1.dyn.fine_window  # before the window
    assert rig.channel.command_axes.by_name["Z1"].motion_end == "IPOENDA"


def test_an_alarm_that_takes_the_axis_loses_the_block() -> None:
    rig = _rig()
    rig.mda("N10 POS[Z]=100 FA[Z]=2000\nN20 M30")
    rig.step(50)
    rig.axis("Z1").brake()  # as an alarm's rapid stop
    rig.step(50)
    assert rig.get("CHAN1.basic.in.stateInterrupted") == 1 and _block(rig) == 0


def _decode(rig: Rig, text: str) -> tuple[BlockPlan, DecodeAlarm | None]:
    block = parse_program(text)[0]
    return decode(block, rig.channel.run.modal, rig.channel.config, rig.channel.axes_by_name)


def test_decoding_the_positioning_words() -> None:
    rig = _rig()
    plan, alarm = _decode(rig, "POS[Z]=IC(-20) POSA[X]=AC(10) FA[Z]=500 FINEA=X COARSEA[Z]")
    assert alarm is None
    assert plan.positioning == {"Z1": PositioningMotion(280.0, True), "X1": PositioningMotion(10.0, False)}
    assert plan.axis_feeds == {"Z1": 500.0} and plan.motion_ends == {"X1": "FINEA", "Z1": "COARSEA"}
    assert _decode(rig, "WAITP(X, Z)")[0].positioning_waits == ("X1", "Z1")


@pytest.mark.parametrize(("text", "number"), [
    ("X10 POS[X]=20", 12080),  # one type per axis in a block (L11708-11709)
    ("WAITP(Z) X10", 12080),  # WAITP stands alone (L11775)
    ("WAITP()", 12080),
    ("FA[Z]=0", 12080),  # 0.001 .. 999 999.999 (L8869)
    ("FA[Z]=1000000", 12080),
    ("POS[Q9]=10", 12550),  # no such axis
    ("POS[Z]=DC(10)", 16800),  # DC on a linear axis (L13164)
    ("FINEA[Q9]", 12550),
    ("POS[Z]=2000", 10720),  # beyond the software limit switch
])
def test_faulty_positioning_words_are_refused(text: str, number: int) -> None:
    rig = _rig()
    alarm = _decode(rig, text)[1]
    assert alarm is not None and alarm.number == number
