"""PLC axes (seed 003 §9.3.2, §9.7): FC18 SINU_TraversePosAxis on the axis interpolator, the PLC's
control of an axis (DB31.DBX28.7, 28.1, 28.2, 30.0 -> DBX63.0-63.2, DBB68), MD30460 bits 4-7 and the
alarms 26075 / 26076 / 20143.  Turn-mill (Z1 linear at 300, software limits -8 .. 608) and the
mill's modulo table C1 (at 0 degrees until referenced); the test is the PLC."""

from __future__ import annotations

import pytest
from core_rig import ABSOLUTE_XYZ, DT, FIVE_AXIS, Rig, machine

from vc.core.axis.command_axis import CommandState
from vc.core.axis.plc_axis import AxisType, Job


def _rig(z1: str = "", path: str | None = None) -> Rig:
    """Turn-mill with absolute encoders, ``z1`` more machine data of Z1; or the machine of ``path``."""
    if path is None:
        overrides = ABSOLUTE_XYZ.replace("Z1: {MD30240: [4], MD34210: [2]}",
                                         "Z1: {MD30240: [4], MD34210: [2]" + (", " + z1 if z1 else "") + "}")
        rig = Rig(machine(overrides))
    else:
        rig = Rig(machine("", path))
    rig.ready_mda()
    return rig


def _start(rig: Rig, axis: str, position: float, feed: float, mode: int = 0) -> None:
    """What FC18 hands the NC: Mode, Pos, FRate, then the Start edge."""
    rig.set(f"{axis}.plcAxis.out.mode", mode)
    rig.set(f"{axis}.plcAxis.out.position", position)
    rig.set(f"{axis}.plcAxis.out.feedrate", feed)
    rig.set(f"{axis}.plcAxis.out.start", 1)
    rig.step(2)
    rig.set(f"{axis}.plcAxis.out.start", 0)


def _job(rig: Rig, axis: str = "Z1") -> Job:
    return rig.channel.plc_axes.by_name[axis].job


def _type(rig: Rig, axis: str = "Z1") -> AxisType:
    return rig.channel.plc_axes.by_name[axis].type


def test_fc18_moves_the_axis_as_a_plc_axis_at_frate_and_reports_in_position() -> None:
    rig = _rig()
    assert rig.get("Z1.plcCtrl.in.assignedChanNumber") == 1 and rig.get("Z1.plcCtrl.in.changeoverPossible") == 1
    _start(rig, "Z1", 250.0, 3000.0)
    rig.step(100)
    z1 = rig.axis("Z1")
    assert z1.command_velocity * 60.0 == pytest.approx(-3000.0)  # G01 at FRate, mm/min (G94)
    assert rig.get("Z1.plcAxis.in.active") == 1 and rig.get("Z1.plcCtrl.in.assignedToPlc") == 1
    assert rig.channel.command_axes.by_name["Z1"].state is CommandState.PLC_POSITIONING
    assert rig.get("Z1.basic.in.isPosAxis") == 0  # no positioning axis of the program
    rig.run_until(lambda: rig.get("Z1.plcAxis.in.inPosition") == 1, 1000)
    assert abs(z1.actual - 250.0) <= z1.dyn.fine_window  # exact stop fine (G09)
    assert rig.nck.cycle * DT == pytest.approx(1.1, abs=0.1)
    assert rig.get("Z1.plcAxis.in.active") == 0 and rig.get("Z1.plcAxis.in.error") == 0
    rig.step(2)
    assert rig.get("Z1.plcCtrl.in.assignedToPlc") == 0 and _type(rig) is AxisType.CHANNEL
    rig.mda("N10 G1 Z260 F3000\nN20 M30")  # the channel's axis again
    rig.run_until(lambda: rig.get("CHAN1.basic.in.stateReset") == 1 and z1.setpoint == 260.0, 1000)


def test_frate_zero_is_md32060_and_incremental_mode_is_the_way_itself() -> None:
    rig = _rig("MD32060: 1200")
    _start(rig, "Z1", -20.0, 0.0, mode=1)
    rig.step(100)
    assert rig.axis("Z1").command_velocity * 60.0 == pytest.approx(-1200.0)
    rig.run_until(lambda: _job(rig) is Job.IN_POSITION, 2000)
    assert rig.axis("Z1").setpoint == 280.0


@pytest.mark.parametrize(("mode", "target", "way"), [
    (2, 350.0, -1), (2, 170.0, +1),  # shortest path (DC) both ways from 0 degrees
    (3, 10.0, +1), (4, 200.0, -1),  # absolute positive / negative (ACP / ACN)
])
def test_the_modes_on_a_modulo_axis_choose_the_way(mode: int, target: float, way: int) -> None:
    rig = _rig(path=FIVE_AXIS)
    c1 = rig.axis("C1")
    _start(rig, "C1", target, 7200.0, mode)
    rig.step(20)
    assert c1.command_velocity * way > 0.0
    rig.run_until(lambda: _job(rig, "C1") is Job.IN_POSITION, 5000)
    assert c1.shown(c1.setpoint) == pytest.approx(target)
    assert abs(c1.setpoint) < 360.0


@pytest.mark.parametrize(("extra", "axis", "mode", "position", "feed", "number"), [
    ("", "Z1", 2, 100.0, 1000.0, 125),  # shortest path on a linear axis
    ("", "Z1", 3, 100.0, 1000.0, 126),  # absolute positive without modulo
    ("", "Z1", 0, 700.0, 1000.0, 130),  # beyond the software limit switch plus
    ("", "Z1", 0, -50.0, 1000.0, 131),
    ("", "Z1", 0, 100.0, -5.0, 110),  # a negative FRate
    ("", "Z1", 7, 100.0, 1000.0, 1),  # no such Mode
    ("", "Z1", 0, float("nan"), 1000.0, 1),
])
def test_a_refused_start_reports_error_and_its_number(extra: str, axis: str, mode: int, position: float,
                                                      feed: float, number: int) -> None:
    rig = _rig(extra)
    _start(rig, axis, position, feed, mode)
    rig.step(2)
    assert rig.get(f"{axis}.plcAxis.in.error") == 1 and rig.get(f"{axis}.plcAxis.in.errorNumber") == number
    assert rig.get(f"{axis}.plcAxis.in.active") == 0 and rig.axis(axis).command_velocity == 0.0
    assert rig.get(f"{axis}.plcCtrl.in.assignedToPlc") == 0
    _start(rig, axis, 290.0, 3000.0)  # the next Start takes Error away
    assert rig.get(f"{axis}.plcAxis.in.error") == 0 and rig.get(f"{axis}.plcAxis.in.errorNumber") == 0


def test_a_modulo_position_outside_the_range_is_error_100() -> None:
    rig = _rig(path=FIVE_AXIS)
    _start(rig, "C1", 400.0, 3600.0, 2)
    rig.step(2)
    assert rig.get("C1.plcAxis.in.errorNumber") == 100


def test_a_start_on_an_axis_the_program_moves_is_refused_with_40() -> None:
    rig = _rig()
    rig.mda("N10 G1 Z200 F1000\nN20 M30")
    rig.step(20)
    _start(rig, "Z1", 250.0, 3000.0)
    rig.step(2)
    assert rig.get("Z1.plcAxis.in.errorNumber") == 40 and rig.axis("Z1").command_velocity * 60 == pytest.approx(-1000)


def test_nc_stop_holds_a_plc_axis_nc_start_continues_and_the_reset_aborts_it() -> None:
    rig = _rig()
    z1 = rig.axis("Z1")
    _start(rig, "Z1", 200.0, 2000.0)
    rig.step(50)
    rig.pulse("CHAN1.basic.out.ncStop", 2)  # the 9.7.2 table: AX1 stops
    rig.step(60)
    assert z1.command_velocity == 0.0 and _job(rig) is Job.HELD and rig.get("Z1.plcAxis.in.active") == 1
    assert rig.get("Z1.plcCtrl.in.stopped") == 0  # no axis stop
    rig.pulse("CHAN1.basic.out.ncStart", 2)  # AX1 goes on
    rig.step(60)
    assert z1.command_velocity * 60.0 == pytest.approx(-2000.0) and _job(rig) is Job.TRAVERSING
    rig.set("CHAN1.basic.out.disableFeed", 1)  # MD30460 bit 6 = 0: the feed disable acts
    rig.step(60)
    assert z1.command_velocity == 0.0
    rig.set("CHAN1.basic.out.disableFeed", 0)
    rig.step(30)
    rig.pulse("CHAN1.basic.out.reset", 2)  # abort by reset
    rig.step(60)
    assert z1.command_velocity == 0.0 and 200.0 < z1.setpoint < 300.0
    assert rig.get("Z1.plcAxis.in.error") == 1 and rig.get("Z1.plcAxis.in.errorNumber") == 30
    assert rig.get("Z1.plcCtrl.in.assignedToPlc") == 0 and _type(rig) is AxisType.CHANNEL


def test_delete_distance_to_go_aborts_a_plc_axis_and_a_plc_controlled_axis_error_30() -> None:
    rig = _rig()
    z1 = rig.axis("Z1")
    _start(rig, "Z1", 200.0, 2000.0)
    rig.step(50)
    rig.set("CHAN1.basic.out.deleteDistanceToGo", 1)  # DB21.DBX6.2: use case 1 (L11339-11343)
    rig.step(2)
    assert rig.get("Z1.plcAxis.in.error") == 1 and rig.get("Z1.plcAxis.in.errorNumber") == 30
    assert rig.get("Z1.plcAxis.in.active") == 0 and _type(rig) is AxisType.CHANNEL
    rig.step(60)
    assert z1.command_velocity == 0.0 and 200.0 < z1.setpoint < 300.0
    rig.set("CHAN1.basic.out.deleteDistanceToGo", 0)
    rig.set("Z1.plcCtrl.out.requestPlcCtrl", 1)  # DBX28.7: the PLC takes it
    rig.step(2)
    assert _type(rig) is AxisType.PLC_CONTROLLED
    _start(rig, "Z1", 100.0, 2000.0)
    rig.step(50)
    assert _job(rig) is Job.TRAVERSING
    rig.pulse("CHAN1.basic.out.deleteDistanceToGo", 2)
    rig.step(60)
    assert _job(rig) is Job.FAILED and rig.get("Z1.plcAxis.in.errorNumber") == 30
    assert z1.command_velocity == 0.0 and _type(rig) is AxisType.PLC_CONTROLLED


def test_md30460_bit_6_leaves_the_feed_disable_out_and_bit_7_the_all_axes_stationary() -> None:
    rig = _rig("MD30460: 0xC0")
    z1 = rig.axis("Z1")
    rig.set("CHAN1.basic.out.disableFeed", 1)
    _start(rig, "Z1", 200.0, 2000.0)
    rig.step(60)
    assert z1.command_velocity * 60.0 == pytest.approx(-2000.0)
    assert rig.get("CHAN1.basic.in.allAxesStationary") == 1  # the PLC axis is left out
    rig.run_until(lambda: _job(rig) is Job.IN_POSITION, 5000)
    rig.set("CHAN1.basic.out.disableFeed", 0)
    rig2 = _rig()
    _start(rig2, "Z1", 200.0, 2000.0)
    rig2.step(60)
    assert rig2.get("CHAN1.basic.in.allAxesStationary") == 0


def test_the_plc_takes_the_axis_stops_resumes_resets_it_and_gives_it_back() -> None:
    rig = _rig()
    z1 = rig.axis("Z1")
    rig.set("Z1.plcCtrl.out.requestPlcCtrl", 1)
    rig.step(2)
    assert rig.get("Z1.plcCtrl.in.active") == 1 and rig.get("Z1.plcCtrl.in.assignedToPlc") == 1
    assert _type(rig) is AxisType.PLC_CONTROLLED
    _start(rig, "Z1", 100.0, 3000.0)
    rig.step(50)
    rig.pulse("CHAN1.basic.out.ncStop", 2)  # does not stop a PLC-controlled axis
    rig.pulse("CHAN1.basic.out.reset", 2)  # no effect on it either
    rig.step(20)
    assert z1.command_velocity * 60.0 == pytest.approx(-3000.0) and _job(rig) is Job.TRAVERSING
    rig.set("Z1.spindle.out.stop", 1)  # use case 2: the axis stop
    rig.step(60)
    assert z1.command_velocity == 0.0 and rig.get("Z1.plcCtrl.in.stopped") == 1
    rig.set("Z1.spindle.out.stop", 0)
    rig.pulse("Z1.spindle.out.resume", 2)  # use case 3
    rig.step(60)
    assert z1.command_velocity * 60.0 == pytest.approx(-3000.0) and rig.get("Z1.plcCtrl.in.stopped") == 0
    rig.pulse("Z1.spindle.out.plcCtrl", 2)  # use case 4: the axis reset
    rig.step(60)
    assert z1.command_velocity == 0.0 and rig.get("Z1.plcCtrl.in.resetDone") == 1
    assert rig.get("Z1.plcAxis.in.errorNumber") == 30 and rig.get("Z1.plcCtrl.in.active") == 1
    _start(rig, "Z1", 150.0, 3000.0)
    assert rig.get("Z1.plcCtrl.in.resetDone") == 0
    rig.step(30)
    rig.set("Z1.plcCtrl.out.requestPlcCtrl", 0)  # given back while it moves: stopped and reset
    rig.step(60)
    assert z1.command_velocity == 0.0 and rig.get("Z1.plcCtrl.in.active") == 0
    assert rig.get("Z1.plcCtrl.in.assignedToPlc") == 0 and rig.get("Z1.plcAxis.in.errorNumber") == 30


def test_the_request_waits_while_the_program_moves_the_axis_and_a_block_waits_for_the_plc() -> None:
    rig = _rig()
    rig.mda("N10 G1 Z250 F3000\nN20 G1 X140 F6000\nN30 Z260\nN40 M30")
    rig.step(20)
    rig.set("Z1.plcCtrl.out.requestPlcCtrl", 1)
    rig.step(4)
    assert rig.get("Z1.plcCtrl.in.newTypeRequested") == 1 and rig.get("Z1.plcCtrl.in.active") == 0
    rig.run_until(lambda: rig.get("Z1.plcCtrl.in.active") == 1, 2000)
    assert rig.get("Z1.plcCtrl.in.newTypeRequested") == 0 and rig.channel.run.block_index >= 1
    rig.run_until(lambda: rig.channel.run.block_index == 2, 2000)
    rig.step(200)
    assert rig.channel.run.block_index == 2 and rig.axis("Z1").setpoint == 250.0  # N30 waits for Z1
    rig.set("Z1.plcCtrl.out.requestPlcCtrl", 0)
    rig.run_until(lambda: rig.get("CHAN1.basic.in.stateReset") == 1, 2000)
    assert rig.axis("Z1").setpoint == 260.0 and rig.alarm_numbers() == []


@pytest.mark.parametrize(("mask", "alarm", "neutral"), [(0x10, 26075, 0), (0x20, 26076, 1)])
def test_an_axis_of_the_plc_named_by_the_program_raises_26075_or_26076(mask: int, alarm: int, neutral: int) -> None:
    rig = _rig(f"MD30460: {mask}")
    assert rig.get("Z1.plcCtrl.in.neutralModeActive") == neutral  # bit 5 starts neutral (L12219)
    assert rig.get("Z1.plcCtrl.in.changeoverPossible") == int(mask != 0x10)
    rig.mda("N10 G1 X140 F6000\nN20 G1 Z200 F1000\nN30 M30")
    rig.run_until(lambda: alarm in rig.alarm_numbers(), 2000)
    assert rig.axis("X1").setpoint == 140.0 and rig.axis("Z1").setpoint == 300.0
    rig.pulse("CHAN1.basic.out.reset", 2)
    rig.step(2)
    assert rig.alarm_numbers() == []
    _start(rig, "Z1", 280.0, 3000.0)  # the PLC moves it
    rig.step(2)
    assert rig.get("Z1.plcCtrl.in.neutralModeActive") == 0 and rig.get("Z1.plcCtrl.in.assignedToPlc") == 1
    rig.run_until(lambda: _job(rig) is Job.IN_POSITION, 2000)
    rig.step(2)
    assert rig.get("Z1.plcCtrl.in.neutralModeActive") == neutral


def test_a_synchronized_action_pos_on_a_plc_axis_raises_20143() -> None:
    rig = _rig()
    rig.set("Z1.plcCtrl.out.requestPlcCtrl", 1)
    rig.step(2)
    rig.mda("N10 ID=1 WHEN $AC_ALARM_STAT==0 DO POS[Z]=100\nN20 G4 F0.1\nN30 M30")
    rig.run_until(lambda: 20143 in rig.alarm_numbers(), 500)
    assert rig.axis("Z1").command_velocity == 0.0


def test_an_emergency_stop_takes_the_axis_error_30() -> None:
    rig = _rig()
    _start(rig, "Z1", 200.0, 3000.0)
    rig.step(50)
    rig.set("NC.basic.out.emergencyStop", 1)
    rig.run_until(lambda: _job(rig) is Job.FAILED, 500)
    assert rig.get("Z1.plcAxis.in.errorNumber") == 30
