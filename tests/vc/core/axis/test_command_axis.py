"""Command axes (vc/core/axis/command_axis.py): POS[ax]= / FA[ax]= of a synchronized action move a
machine axis on its own, as a single axis (seed 003 §9.3.2), and its single-axis ESR stops it
(§9.3.3).  Turn-mill with absolute encoders: X1 at 150, Z1 at 300; MD32300 4 m/s^2; the test is the PLC."""

from __future__ import annotations

import pytest
from core_rig import ABSOLUTE_XYZ, DT, Rig, machine

from vc.core.axis.command_axis import CommandState
from vc.core.axis.owner import Owner

ESR_Z = ABSOLUTE_XYZ.replace("Z1: {MD30240: [4], MD34210: [2]}",
                             "Z1: {MD30240: [4], MD34210: [2], MD37500: 22, MD37510: 0.2, MD37511: 0.05}")
MOVE_Z = "IDS=1 WHENEVER $AC_ALARM_STAT==0 DO POS[Z]=100 FA[Z]=2000"  # goes on commanding while it holds


def _rig(overrides: str = ESR_Z) -> Rig:
    rig = Rig(machine(overrides))
    rig.ready_mda()
    return rig


def _state(rig: Rig, name: str = "Z1") -> CommandState:
    return rig.nck.channels[0].command_axes.by_name[name].state


def test_pos_moves_the_axis_at_fa_to_its_end_point_and_ends_there() -> None:
    rig = _rig()
    rig.mda(f"N10 {MOVE_Z}\nM30")
    z1 = rig.axis("Z1")
    rig.run_until(lambda: z1.command_velocity == -2000.0 / 60.0, 100)
    assert z1.owner is Owner.COMMAND and rig.get("Z1.basic.in.traversMinusCommandActive") == 1
    rig.run_until(lambda: _state(rig) is CommandState.IDLE, 4000)
    assert z1.setpoint == 100.0 and z1.owner is Owner.NONE
    # 200 mm at 2000 mm/min (33.3 mm/s): 6 s, plus 8 ms of acceleration
    assert rig.nck.cycle * DT == pytest.approx(6.0, abs=0.03)
    rig.step(100)
    assert rig.get("Z1.basic.in.posFineReached") == 1 and rig.get("Z1.basic.in.traversMinusCommandActive") == 0


def test_without_fa_the_axis_runs_at_md32060_times_its_own_override() -> None:
    rig = _rig(ESR_Z.replace("MD37500: 22,", "MD32060: 6000, MD37500: 22,"))
    rig.set("Z1.basic.out.feedrateOvrFactor", 50)  # 50 % on the axis's own override, DB31.DBB0
    rig.mda("N10 IDS=1 WHEN $AC_ALARM_STAT==0 DO POS[Z]=250\nM30")
    z1 = rig.axis("Z1")
    rig.step(50)
    assert z1.command_velocity * 60.0 == pytest.approx(-6000.0 * 0.5)


def test_nc_stop_and_program_end_leave_it_alone_feed_stop_holds_it_and_the_reset_stops_it() -> None:
    rig = _rig()
    rig.mda("N10 ID=1 WHEN $AC_ALARM_STAT==0 DO POS[Z]=100 FA[Z]=2000\nN20 G4 F0.2\nM30")  # fires once
    z1 = rig.axis("Z1")
    rig.step(200)
    assert rig.get("CHAN1.basic.in.stateReset") == 1  # L11225: the program has ended, Z1 goes on
    rig.pulse("CHAN1.basic.out.ncStop", 2)  # L11219: NC stop does not act on a single axis
    rig.step(20)
    assert z1.command_velocity * 60.0 == pytest.approx(-2000.0)
    rig.set("Z1.basic.out.feedStopSpindleStop", 1)  # the axis's feed stop holds it
    rig.step(20)
    assert z1.command_velocity == 0.0 and _state(rig) is CommandState.TRAVERSING
    rig.set("Z1.basic.out.feedStopSpindleStop", 0)
    rig.step(20)
    assert z1.command_velocity * 60.0 == pytest.approx(-2000.0)
    rig.pulse("CHAN1.basic.out.reset", 2)  # L24176-24178: the reset of its channel stops it
    rig.step(20)
    assert z1.command_velocity == 0.0 and _state(rig) is CommandState.IDLE and z1.setpoint > 100.0


def test_it_never_runs_on_into_an_actuated_hardware_limit_switch() -> None:
    rig = _rig()
    rig.set("NC.basic.out.setDigitalInputs", 4)
    rig.mda("N10 IDS=1 WHENEVER $A_IN[3]==1 DO POS[Z]=100 FA[Z]=2000\nM30")  # also while 21614 is present
    z1 = rig.axis("Z1")
    rig.step(100)
    rig.set("Z1.basic.out.hwLimitSwitchMinus", 1)  # the switch in its way: 21614, the axis brakes
    rig.step(20)
    stopped_at = z1.setpoint
    rig.step(200)  # the action goes on commanding POS[Z]=100: it takes the axis but does not move it
    assert z1.setpoint == stopped_at and 21614 in [item.number for item in rig.nck.present_alarms()]


@pytest.mark.parametrize(("action", "alarm"), [
    ("POS[SP1]=90", 20141),  # a spindle in speed control (L17574-17575)
    ("POS[Z]=700", 10720),  # beyond the software limit switch 608
])
def test_a_pos_the_axis_cannot_take_is_refused_with_an_alarm(action: str, alarm: int) -> None:
    rig = _rig()
    rig.mda(f"N10 IDS=1 WHEN $AC_ALARM_STAT==0 DO {action}\nM30")
    rig.step(20)
    assert alarm in [item.number for item in rig.nck.present_alarms()]
    assert rig.axis("Z1").setpoint == 300.0


def test_a_pos_on_an_axis_the_program_moves_is_refused_with_20141() -> None:
    rig = _rig()
    rig.mda("N10 IDS=1 WHENEVER $A_IN[3]==1 DO POS[X]=100\nN20 G1 X200 F1000\nM30")
    rig.step(50)
    rig.set("NC.basic.out.setDigitalInputs", 4)
    rig.step(5)
    assert 20141 in [item.number for item in rig.nck.present_alarms()]


@pytest.mark.parametrize(("text", "alarm"), [
    ("IDS=1 WHEN $A_IN[1]==1 DO POS[Q]=10", 12550),  # no such axis
    ("IDS=1 WHEN $A_IN[1]==1 DO FA[Z]=0", 12080),  # a feed above 0
    ("IDS=1 WHEN $A_IN[1]==1 DO POS=10", 12080),  # POS needs its axis
])
def test_the_words_are_checked_when_the_block_is_decoded(text: str, alarm: int) -> None:
    rig = _rig()
    rig.mda(f"N10 {text}\nM30")
    rig.step(10)
    assert alarm in [item.number for item in rig.nck.present_alarms()]


# ------------------------------------------------------------------------------ single-axis ESR


def _stopped_by_its_esr(rig: Rig) -> None:
    rig.mda(f"N10 $AA_ESR_ENABLE[Z]=1\nN20 {MOVE_Z}\nN30 G4 F1\nN40 $AA_ESR_TRIGGER[Z]=1\nN50 G4 F0.5\nM30")
    z1 = rig.axis("Z1")
    rig.run_until(lambda: rig.nck.channels[0].esr is not None and rig.nck.channels[0].esr.axis_trigger["Z1"], 1000)
    trigger = rig.nck.cycle
    rig.run_until(lambda: z1.command_velocity > -2000.0 / 60.0, 200)
    assert (rig.nck.cycle - trigger) * DT == pytest.approx(0.2, abs=DT)  # MD37510: on at FA
    rig.run_until(lambda: z1.command_velocity == 0.0, 200)
    assert (rig.nck.cycle - trigger) * DT <= 0.25 + DT  # MD37511: stopped within 0.05 s


def test_the_single_axis_esr_stops_a_command_axis_and_it_stays_stopped_until_the_reset() -> None:
    # seed 003 L11541-11548: the stop is reached; the static action commands POS[Z]=100 on and on
    rig = _rig()
    _stopped_by_its_esr(rig)
    z1 = rig.axis("Z1")
    stopped_at = z1.setpoint
    for _ in range(1000):  # 2 s: the program ends, the action goes on
        rig.step(1)
        assert z1.setpoint == stopped_at and z1.command_velocity == 0.0
    assert _state(rig) is CommandState.ESR_STOPPED and rig.get("Z1.basic.in.traversMinusCommandActive") == 0
    assert rig.get("Z1.basic.in.posFineReached") == 1 and rig.get("Z1.basic.in.isStationary") == 1
    rig.pulse("CHAN1.basic.out.reset", 2)  # the reset ends the stop: the action moves it on to 100
    rig.run_until(lambda: z1.setpoint == 100.0, 5000)


def test_with_md37510_0_the_single_axis_brakes_at_once() -> None:
    # MD37510's default is 0: the trigger's block comes after the cycle's reaction, which must still brake
    rig = _rig(ESR_Z.replace("MD37510: 0.2", "MD37510: 0.0"))
    rig.mda(f"N10 $AA_ESR_ENABLE[Z]=1\nN20 {MOVE_Z}\nN30 G4 F1\nN40 $AA_ESR_TRIGGER[Z]=1\nN50 G4 F0.5\nM30")
    z1 = rig.axis("Z1")
    rig.run_until(lambda: rig.nck.channels[0].esr is not None and rig.nck.channels[0].esr.axis_trigger["Z1"], 1000)
    trigger = rig.nck.cycle
    rig.run_until(lambda: z1.command_velocity == 0.0, 100)
    assert (rig.nck.cycle - trigger) * DT <= 0.05 + DT and _state(rig) is CommandState.ESR_STOPPED


def test_db31_dbx2_2_ends_the_single_axis_esr_stop_of_a_command_axis() -> None:
    rig = _rig()
    _stopped_by_its_esr(rig)
    rig.step(100)
    assert _state(rig) is CommandState.ESR_STOPPED
    rig.pulse("Z1.basic.out.resetMovement", 2)
    rig.step(5)
    assert _state(rig) is CommandState.TRAVERSING and rig.axis("Z1").command_velocity < 0.0


def test_the_channel_trigger_ignores_a_command_axis_and_its_trigger_ignores_a_standing_one() -> None:
    # L11529-11534: the channel's ESR leaves the single axes alone; L11523-11527: a trigger on an axis
    # that is no single axis at that moment is ignored
    rig = _rig()
    rig.mda(f"N10 $AA_ESR_ENABLE[Z]=1\nN20 {MOVE_Z}\nN30 $AC_ESR_TRIGGER=1\nN40 G4 F1\nM30")
    rig.step(400)
    assert rig.axis("Z1").command_velocity * 60.0 == pytest.approx(-2000.0)  # runs on through the channel's ESR
    rig.run_until(lambda: _state(rig) is CommandState.IDLE, 5000)
    rig.mda("N10 $AA_ESR_TRIGGER[Z]=1\nN20 G4 F0.5\nM30")
    rig.step(300)
    assert _state(rig) is CommandState.IDLE and rig.axis("Z1").owner is Owner.NONE
