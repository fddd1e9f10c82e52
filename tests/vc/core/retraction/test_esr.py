"""G33 thread cutting, fast retraction (LIFTFAST) and extended stop and retract (ESR) in the NC core.

Spec sections 2 (ESR, seed 003 chapter 22 and 9.3.3) and 3 (fast retraction, seed 003 §7.2.3.5);
the test acts as the PLC.  Turn-mill: X1 / Z1 / Y1 with absolute encoders, 30 m/min and 4 m/s^2
(Y1 15 m/min, 3 m/s^2); SP1 the master spindle.
"""

from __future__ import annotations

import itertools
import math

import pytest
from core_rig import ABSOLUTE_XYZ, DT, FIVE_AXIS, Rig, machine, spindle_rig

from vc.core.axis.axis import MachineAxis
from vc.core.axis.owner import Owner
from vc.core.interpolation.tool_path import ToolPathSegment
from vc.core.program.block_plan import BlockPlan, DecodeAlarm, ModalState
from vc.core.program.commands import RetractProgramming
from vc.core.program.interpreter import decode
from vc.core.program.program import parse_program
from vc.core.program.sync_actions import SyncActionError, parse_actions, parse_condition
from vc.core.retraction.drive_esr import EXTENDED_RETRACT, EXTENDED_STOP
from vc.core.retraction.retract_motion import direction_targets, retract_groups

ESR_MACHINE = ("CHAN1: {MD20700: 0, MD21380: 0.1, MD21381: 0.04}\n"
               "X1: {MD30240: [4], MD34210: [2], MD37500: 21}\n"
               "Z1: {MD30240: [4], MD34210: [2], MD37500: 22}\n"
               "Y1: {MD30240: [4], MD34210: [2], MD37500: 22}")


def run_mda(rig: Rig, text: str) -> None:
    rig.nck.load_mda("CHAN1", text)
    rig.pulse("CHAN1.basic.out.ncStart", 2)


def axis(rig: Rig, name: str) -> MachineAxis:
    return rig.nck.axes_by_name[name]


def block_number(rig: Rig) -> int | None:
    block = rig.nck.channels[0].current_block
    return block.number if block is not None else None


# ------------------------------------------------------------------------------ decoding


def _decode(text: str, modal: ModalState | None = None) -> tuple[BlockPlan, DecodeAlarm | None, ModalState]:
    rig = Rig(machine(ABSOLUTE_XYZ))
    channel = rig.nck.channels[0]
    state = modal or ModalState()
    plan, alarm = decode(parse_program(text)[0], state, channel.config, channel.axes_by_name)
    return plan, alarm, state


def test_tv_esr_1_esrr_and_esrs_give_the_drive_parameters() -> None:
    rig = Rig(machine(ABSOLUTE_XYZ))
    rig.ready_mda()
    run_mda(rig, "N130 ESRR(X1,20.0,10000.0,Z1,-15.0,20000.0)\nN140 ESRS(Y1,0.5)\nM30")
    rig.step(20)
    drives = rig.nck.esr.drives
    assert (drives["X1"].p0888, drives["X1"].p0892) == (EXTENDED_RETRACT, pytest.approx(0.12))
    assert (drives["Z1"].p0888, drives["Z1"].p0892) == (EXTENDED_RETRACT, pytest.approx(0.045))
    assert (drives["Y1"].p0888, drives["Y1"].p0892) == (EXTENDED_STOP, 0.5)
    # p0893: 10000 mm/min over a 10 mm leadscrew, ratio 1:1 = 1000 motor rev/min; the sign is the direction
    assert (drives["X1"].p0893, drives["Z1"].p0893) == (1000.0, -2000.0)


@pytest.mark.parametrize(("text", "alarm"), [
    ("ESRS(X1,21)", 12080),  # stop time 0.00 .. 20.00 s
    ("ESRR(X1,20,0)", 12080),  # no velocity
    ("ESRS(X1,0.5,Z1)", 12080),  # pairs
    ("ESRS(X1,1,Z1,1,Y1,1,SP1,1,SP2,1,SP3,1)", 12080),  # at most 5 axes
    ("ESRS(X1,0.5) G1 X10 F100", 12080),  # a block of its own
    ("POLF[Q]=10", 12550),
    ("ALF=9", 12080),
    ("$AA_ESR_ENABLE=1", 12080),  # needs its axis
    ("$AC_UNKNOWN=1", 12550),
    ("IDS=1 WHENEVER $A_IN[1]==1 DO $AA_ESR_TRIGGER[Q]=1", 12550),  # refused at decode, not when it fires
    ("IDS=1 WHENEVER $A_IN[1]==1 DO $AC_UNKNOWN=1", 12550),
    ("IDS=1 WHENEVER $A_IN[1] >> 1 DO $AC_ESR_TRIGGER=1", 12080),
    ("G33 Z10", 12080),  # no lead yet
])
def test_bad_retract_words_raise_the_control_alarm(text: str, alarm: int) -> None:
    _, found, _ = _decode(text)
    assert found is not None and found.number == alarm


def test_a_synchronized_action_s_writes_name_machine_axes() -> None:
    plan, alarm, _ = _decode("IDS=1 WHENEVER $A_IN[1]==1 DO $AA_ESR_ENABLE[X]=1 $AA_ESR_TRIGGER[Z]=1")
    assert alarm is None
    (action,) = plan.sync_actions
    assert [(write.name, write.index) for write in action.actions] == [("$AA_ESR_ENABLE", "X1"),
                                                                        ("$AA_ESR_TRIGGER", "Z1")]


def test_g33_is_modal_thread_mode_and_keeps_its_lead() -> None:
    plan, alarm, modal = _decode("G33 Z30 K5 SF=90 LFON DILF=10 LFWP ALF=7")
    assert alarm is None and modal.thread == "G33" and plan.thread is not None
    assert (plan.thread.lead, plan.thread.lead_axis, plan.thread.start_angle) == (5.0, "Z1", 90.0)
    assert (modal.retract.enabled, modal.retract.distance, modal.retract.target_mode, modal.retract.direction) == (
        True, 10.0, "LFWP", 7)
    plan, alarm, modal = _decode("Z55 X15", modal)
    assert alarm is None and plan.thread is not None and plan.thread.lead == 5.0
    _, _, modal = _decode("G1", modal)
    assert modal.thread == ""
    modal.reset()
    assert (modal.retract.enabled, modal.retract.distance, modal.plane) == (False, None, "G17")


# ------------------------------------------------------------------------------ retract targets


def test_alf_directions_in_the_working_planes() -> None:
    geometry = {"X": "X1", "Y": "Y1", "Z": "Z1"}
    where = {"X1": 0.0, "Y1": 0.0, "Z1": 0.0}
    assert direction_targets(7, 10.0, "G18", geometry, where) == {"X1": pytest.approx(-10.0)}  # TV-LF-1
    assert direction_targets(3, 10.0, "G18", geometry, where) == {"X1": pytest.approx(10.0)}
    assert direction_targets(1, 10.0, "G18", geometry, where) == {"Z1": 10.0}
    assert direction_targets(1, 10.0, "G17", geometry, where) == {"X1": 10.0}
    assert direction_targets(3, 10.0, "G19", geometry, where) == {"Z1": pytest.approx(10.0)}
    diagonal = direction_targets(2, 10.0, "G17", geometry, where)
    assert diagonal == {"X1": pytest.approx(10 / math.sqrt(2)), "Y1": pytest.approx(10 / math.sqrt(2))}


def _groups(program: RetractProgramming, rig: Rig) -> list[dict[str, float]]:
    axes = rig.nck.channels[0].axes_by_name
    return [{axis.name: target for axis, target in group.items()}
            for group in retract_groups(program, axes, ["X1", "Y1", "Z1"])]


def test_tv_esr_4_5_6_polf_positions_axial_and_linear() -> None:
    rig = Rig(machine(ABSOLUTE_XYZ))  # X1 at 150, Z1 at 300, Y1 at 0
    # TV-ESR-4: POLFMASK(X, Y) absolute; then POLFMASK(Z) alone
    program = RetractProgramming(positions={"X1": (19.5, False), "Y1": (33.3, False), "Z1": (100.0, False)},
                                 axial=("X1", "Y1"))
    assert _groups(program, rig) == [{"X1": 19.5}, {"Y1": 33.3}]
    program.axial = ("Z1",)
    assert _groups(program, rig) == [{"Z1": 100.0}]
    # TV-ESR-5: X incremental + 3, Y absolute -4
    program = RetractProgramming(positions={"X1": (3.0, True), "Y1": (-4.0, False), "Z1": (100.0, False)},
                                 axial=("X1", "Y1"))
    assert _groups(program, rig) == [{"X1": 153.0}, {"Y1": -4.0}]
    # TV-ESR-6: POLFMLIN(X, Y) together on a line, POLFMASK(Z) on its own
    program = RetractProgramming(positions={"X1": (3.0, True), "Z1": (-4.0, False), "Y1": (100.0, False)},
                                 linear=("X1", "Y1"), axial=("Z1",))
    assert _groups(program, rig) == [{"X1": 153.0, "Y1": 100.0}, {"Z1": -4.0}]


def test_polfmask_and_polfmlin_keep_an_axis_in_one_set() -> None:
    _, _, modal = _decode("POLFMLIN(X,Y)")
    _, _, modal = _decode("POLFMASK(Z)", modal)
    assert (modal.retract.linear, modal.retract.axial) == (("X1", "Y1"), ("Z1",))
    _, _, modal = _decode("POLFMASK(X)", modal)
    assert (modal.retract.linear, modal.retract.axial) == (("Y1",), ("X1",))
    _, _, modal = _decode("POLFMASK()", modal)
    assert modal.retract.axial == ()


# ------------------------------------------------------------------------------ synchronized actions


def test_condition_language() -> None:
    values = {("$AC_ALARM_STAT", ""): float(0x2000), ("$A_IN", "1"): 1.0}

    def read(name: str, index: str) -> float:
        return values[(name, index)]

    assert parse_condition("($AC_ALARM_STAT B_AND 'H2000') > 0")(read) == 1.0
    assert parse_condition("($AC_ALARM_STAT B_AND 'H0040') > 0")(read) == 0.0
    assert parse_condition("$A_IN[1]==1 AND NOT $A_IN[1]<>1")(read) == 1.0
    assert parse_condition("$A_IN[1] == 0 OR 'B11' == 3")(read) == 1.0
    assert [(a.name, a.index, a.value) for a in parse_actions("$AA_ESR_ENABLE[X1]=0 $AN_ESR_TRIGGER=-1")] == [
        ("$AA_ESR_ENABLE", "X1", 0.0), ("$AN_ESR_TRIGGER", "", -1.0)]
    with pytest.raises(SyncActionError):
        parse_condition("$A_IN[1] ==")


@pytest.mark.parametrize(("text", "message"), [
    ("$A_IN[1] > " + "(" * 600 + "1" + ")" * 600, "more than 32 parentheses and signs inside one another"),
    ("$A_IN[1] > " + "- " * 600 + "1", "more than 32 parentheses and signs inside one another"),
    ("$A_IN[1] > 1" + " OR $A_IN[1] > 2" * 300, "more than 100 operators"),
    (" B_OR ".join(["$A_IN[1]"] * 150) + " == 1", "more than 100 operators"),
    ("$A_IN[1] > " + "9" * 400, "99999999999999999999... (400 digits): beyond 1e+15"),
    ("$A_IN[1] > 'H" + "F" * 400 + "'", ": beyond 1e+15"),
])
def test_conditions_beyond_the_limits_are_refused(text: str, message: str) -> None:
    """500 parentheses and long chains ended in RecursionError, 400 digits in an infinite value."""
    with pytest.raises(SyncActionError) as caught:
        parse_condition(text)
    assert str(caught.value).endswith(message)


def test_conditions_within_the_limits_are_read() -> None:
    def read(name: str, index: str) -> float:
        return 1.0

    assert parse_condition("$A_IN[1] == " + "(" * 32 + "1" + ")" * 32)(read) == 1.0
    assert parse_condition(" OR ".join(["$A_IN[1] > 2"] * 32 + ["$A_IN[1] == 1"]))(read) == 1.0  # 65 operators
    with pytest.raises(SyncActionError):
        parse_actions("$AC_ESR_TRIGGER=" + "9" * 400)


# ------------------------------------------------------------------------------ G33 and fast retraction


def test_g33_follows_the_master_spindle_and_ignores_the_feed_override() -> None:
    rig = spindle_rig()
    run_mda(rig, "N10 M3 S500 G90 G18\nN20 G0 Z5\nN30 X10\nN40 G33 Z60 K5\nM30")
    rig.run_until(lambda: block_number(rig) == 40 and axis(rig, "Z1").actual > 20, 20000)
    rig.channel_overrides(feed=10)
    rig.step(10)
    assert rig.sim.axis_quantity("Z1", "velocity") == pytest.approx(2500.0, abs=1.0)  # 5 mm x 500 rev/min
    assert rig.nck.channels[0].modal.thread == "G33"


def test_g33_with_a_standing_spindle_raises_65870() -> None:
    rig = spindle_rig()
    run_mda(rig, "N10 G90 G0 Z5\nN20 G33 Z30 K5\nM30")
    rig.run_until(lambda: rig.nck.alarms.is_present(65870), 5000)
    assert axis(rig, "Z1").setpoint == 5.0


def test_tv_lf_1_nc_stop_during_g33_retracts_10_mm_in_minus_x() -> None:
    rig = spindle_rig()
    run_mda(rig, "N55 M3 S500 G90 G18\nN67 $AC_LIFTFAST=0\nN68 G0 Z5\nN69 X10\n"
                 "N70 G33 Z30 K5 LFON DILF=10 LFWP ALF=7\nN71 G33 Z55 X15\nN72 G1 X20 F100\nM30")
    x1, z1 = axis(rig, "X1"), axis(rig, "Z1")
    rig.run_until(lambda: block_number(rig) == 70 and z1.actual > 15, 20000)
    channel = rig.nck.channels[0]
    assert channel.esr is not None and channel.esr.liftfast == 0.0
    rig.set("CHAN1.basic.out.ncStop", 1)
    cycles = rig.run_until(lambda: x1.at_rest and z1.at_rest and abs(x1.velocity) < 1e-6 and abs(z1.velocity) < 1e-6,
                           500)
    assert x1.actual == pytest.approx(0.0, abs=1e-3) and channel.esr.liftfast == 1.0
    assert 0.08 <= cycles * DT <= 0.16  # 10 mm at 4 m/s^2: 0.1 s plus the drive's lag
    rig.set("CHAN1.basic.out.ncStop", 0)
    rig.step(2)
    stopped_at = z1.setpoint
    rig.pulse("CHAN1.basic.out.ncStart", 2)  # NC start goes on after the thread chain: N71 is dropped too
    rig.run_until(lambda: block_number(rig) == 72, 50)
    rig.step(100)
    assert z1.setpoint == stopped_at and x1.setpoint > 0.0  # N72 G1 X20 moves X alone


# ------------------------------------------------------------------------------ NC-controlled ESR


def test_tv_esr_2_retract_axis_and_stop_axes() -> None:
    rig = Rig(machine(ESR_MACHINE))
    rig.ready_mda()
    run_mda(rig, "N10 LFPOS\nN20 POLF[X]=IC(10)\nN30 POLFMASK(X)\n"
                 "N40 $AA_ESR_ENABLE[X]=1 $AA_ESR_ENABLE[Y]=1 $AA_ESR_ENABLE[Z]=1\n"
                 "N50 IDS=1 WHENEVER $A_IN[1]==1 DO $AC_ESR_TRIGGER=1\nN60 G1 X100 Y50 Z100 F3000\nM30")
    x1, y1, z1 = axis(rig, "X1"), axis(rig, "Y1"), axis(rig, "Z1")
    rig.run_until(lambda: z1.actual < 250, 20000)
    rig.set("NC.basic.out.setDigitalInputs", 1)
    rig.step(1)
    x_at_trigger = x1.setpoint
    trigger_cycle = rig.nck.cycle
    rig.run_until(lambda: y1.command_velocity == 0.0 and z1.command_velocity == 0.0, 200)
    stopped_after = (rig.nck.cycle - trigger_cycle) * DT
    assert 0.1 <= stopped_after <= 0.14 + 1e-9  # MD21380, then braked within MD21381
    rig.run_until(lambda: x1.at_rest, 200)
    assert x1.setpoint == pytest.approx(x_at_trigger + 10.0, abs=0.02)  # +10 from where X was at the trigger


def test_an_alarm_with_follow_up_waits_for_the_retraction() -> None:
    rig = Rig(machine(ESR_MACHINE))
    rig.ready_mda()
    run_mda(rig, "N10 LFPOS POLF[X]=IC(10) POLFMASK(X)\nN20 $AA_ESR_ENABLE[X]=1\n"
                 "N30 IDS=2 WHENEVER ($AC_ALARM_STAT B_AND 'H2000') > 0 DO $AC_ESR_TRIGGER=1\nN40 G1 Z100 F3000\nM30")
    x1 = axis(rig, "X1")
    rig.run_until(lambda: axis(rig, "Z1").actual < 250, 20000)
    rig.nck.alarms.raise_alarm(2000, rig.nck.cycle)
    rig.run_until(lambda: x1.at_rest and x1.setpoint > 159.99, 200)
    rig.step(1)
    assert x1.actual == pytest.approx(160.0, abs=0.01)
    rig.step(200)
    assert not x1.servo_on  # the rapid stop's servo off came after the retraction


# ------------------------------------------------------------------------------ drive-autonomous ESR


def test_seq_esr_1_trigger_two_cycles_reaction_and_acknowledge() -> None:
    rig = Rig(machine(ABSOLUTE_XYZ))
    rig.ready_mda()
    run_mda(rig, "ESRR(X1,20.0,10000.0)\n$AA_ESR_ENABLE[X1]=1\nM30")
    rig.step(20)
    drive = rig.nck.esr.drives["X1"]
    assert drive.enabled and rig.get("X1.drive.in.esrResponseInitiated") == 0
    rig.nck.esr.trigger = True
    rig.step(1)
    assert not drive.triggered  # one cycle is not enough
    rig.step(1)
    assert drive.triggered and drive.status == 4
    rig.step(1)
    assert rig.get("X1.drive.in.esrResponseInitiated") == 1
    assert rig.get("X1.drive.in.autonomousMotionActive") == 1  # DB31.DBX92.4 while the drive moves on its own
    drive.set_enable(False)  # acknowledged while the reaction runs: 95.2 falls when it ends
    rig.step(10)
    assert drive.triggered
    rig.step(150)
    assert not drive.triggered and axis(rig, "X1").actual == pytest.approx(170.0, abs=0.01)
    assert rig.get("X1.drive.in.autonomousMotionActive") == 0
    rig.nck.esr.trigger = False
    drive.set_enable(True)
    rig.step(3)
    assert rig.get("X1.drive.in.esrResponseInitiated") == 0


# ------------------------------------------------------------------------------ single-axis ESR


def test_tv_esr_7_single_axis_trigger_acts_only_on_a_single_axis() -> None:
    rig = Rig(machine(ESR_MACHINE + "\nSP3: {MD37500: 21}"))
    rig.ready_mda()
    run_mda(rig, "N10 $AA_ESR_ENABLE[X]=1 $AA_ESR_ENABLE[SP3]=1\nN20 POLFA(SP3,1,20.0)\nN30 POLFA(X,1,20.0)\n"
                 "N40 $AA_ESR_TRIGGER[X]=1\nN50 $AA_ESR_TRIGGER[SP3]=1\nM30")
    rig.step(300)
    assert axis(rig, "X1").setpoint == 150.0  # X1 is a path axis, not a single axis: ignored
    assert axis(rig, "SP3").setpoint == pytest.approx(20.0, abs=1e-6)  # the spindle retracts to 20 degrees


def test_the_channel_trigger_acts_again_after_a_reset() -> None:
    rig = Rig(machine(ESR_MACHINE))
    rig.ready_mda()
    program = ("N10 LFPOS POLF[X]=IC(10) POLFMASK(X)\nN20 $AA_ESR_ENABLE[X]=1\n"
               "N30 IDS=1 WHENEVER $A_IN[1]==1 DO $AC_ESR_TRIGGER=1\nN40 G1 Z100 F3000\nM30")
    x1, z1 = axis(rig, "X1"), axis(rig, "Z1")
    for expected in (160.0, 170.0):
        run_mda(rig, program)
        rig.run_until(lambda: z1.command_velocity < 0.0, 20000)
        rig.set("NC.basic.out.setDigitalInputs", 1)
        rig.run_until(lambda end=expected: x1.at_rest and x1.setpoint > end - 0.01, 300)
        assert x1.setpoint == pytest.approx(expected, abs=0.01)
        rig.set("NC.basic.out.setDigitalInputs", 0)
        rig.pulse("CHAN1.basic.out.reset", 2)
        rig.step(200)


def test_an_nc_alarm_does_not_cut_the_drives_own_retraction_short() -> None:
    rig = Rig(machine(ABSOLUTE_XYZ))
    rig.ready_mda()
    run_mda(rig, "ESRR(X1,20.0,1000.0)\n$AA_ESR_ENABLE[X1]=1\nM30")
    rig.step(20)
    rig.nck.esr.trigger = True
    rig.step(50)
    rig.nck.alarms.raise_alarm(2000, rig.nck.cycle)  # the NC fails while the drive retracts
    x1 = axis(rig, "X1")
    rig.run_until(lambda: not rig.nck.esr.drives["X1"].reacting, 3000)
    rig.step(5)
    assert x1.actual == pytest.approx(170.0, abs=0.05)  # the whole 20 mm of ESRR
    rig.step(300)
    assert not x1.servo_on  # then the alarm's rapid stop takes the enable


# ------------------------------------------------------------------------------ POLF programs end to end
# Seed 003 §22.4.3-22.4.5 (TV-ESR-4/5/6): the fast input is $A_IN[1] with a static synchronized action.
# Turn-mill with the inclined-axis control off (MD62800 = 0): X1, Y1, Z1 orthogonal, all retract axes.
POLF_MACHINE = ("CHAN1: {MD20700: 0, MD21380: 0.1, MD21381: 0.04, MD62800: 0}\n"
                "X1: {MD30240: [4], MD34210: [2], MD37500: 21}\n"
                "Z1: {MD30240: [4], MD34210: [2], MD37500: 21}\n"
                "Y1: {MD30240: [4], MD34210: [2], MD37500: 21}")
POLF_ARMING = ("N1 IDS=1 WHENEVER $A_IN[1]==1 DO $AC_ESR_TRIGGER=1\n"
               "N2 $AA_ESR_ENABLE[X]=1 $AA_ESR_ENABLE[Y]=1 $AA_ESR_ENABLE[Z]=1\nN3 LFPOS\n")


def _trigger_in_block(rig: Rig, program: str, number: int, moving: str, cycles_into_block: int = 50) -> None:
    """Run ``program`` from reset, give $A_IN[1] ``cycles_into_block`` cycles into block ``number``
    (while ``moving`` moves) and wait until every axis of the channel stands."""
    run_mda(rig, program)
    rig.run_until(lambda: block_number(rig) == number and axis(rig, moving).command_velocity != 0.0, 20000)
    rig.step(cycles_into_block)
    rig.set("NC.basic.out.setDigitalInputs", 1)
    rig.step(2)
    esr = rig.nck.channels[0].esr
    assert esr is not None
    rig.run_until(lambda: not esr.running and all(axis(rig, name).command_velocity == 0.0
                                                  for name in ("X1", "Y1", "Z1")), 2000)
    rig.set("NC.basic.out.setDigitalInputs", 0)


def _polf_rig() -> tuple[Rig, MachineAxis, MachineAxis, MachineAxis]:
    rig = Rig(machine(POLF_MACHINE))
    rig.ready_mda()
    return rig, axis(rig, "X1"), axis(rig, "Y1"), axis(rig, "Z1")


def _reset(rig: Rig) -> None:
    rig.pulse("CHAN1.basic.out.reset", 2)
    rig.step(100)


def test_tv_esr_4_fast_input_retracts_x_and_y_then_the_new_mask_only_z() -> None:
    rig, x1, y1, z1 = _polf_rig()
    head = POLF_ARMING + "N40 POLF[X]=19.5 POLF[Y]=33.3\nN50 POLF[Z]=100\nN60 G0 X0 Y0\nN65 POLFMASK(X,Y)\n"
    _trigger_in_block(rig, head + "N70 Z100 G1 F1000\nN80 POLFMASK(Z)\nN90 Y10\nM30", 70, "Z1")
    assert (x1.setpoint, y1.setpoint) == (pytest.approx(19.5, abs=1e-6), pytest.approx(33.3, abs=1e-6))
    assert 100.0 < z1.setpoint < 300.0  # Z1 (no POLFMASK) stopped on the path, short of Z100
    _reset(rig)
    _trigger_in_block(rig, head + "N70 Z100 G1 F1000\nN80 POLFMASK(Z)\nN90 Y10\nM30", 90, "Y1", 20)
    assert x1.setpoint == pytest.approx(0.0, abs=1e-6)  # X1 left the mask: no retraction to 19.5
    assert 0.0 < y1.setpoint < 10.0  # Y1 stopped on the path of N90
    assert z1.setpoint == pytest.approx(100.0, abs=1e-6)  # Z1 to its POLF 100 (it stands there already)


def test_tv_esr_5_incremental_then_absolute_polf_and_the_new_mask() -> None:
    rig, x1, y1, z1 = _polf_rig()
    program = (POLF_ARMING + "N40 POLF[X]=IC(3.0) POLF[Y]=-4.0\nN50 POLF[Z]=100\nN60 G0 X50 Y20\n"
               "N80 POLFMASK(X,Y)\nN90 Z100 G1 F1000\nN100 POLF[X]=10\nN110 Y0\nN120 POLFMASK(Z)\nN130 Y10\nM30")
    _trigger_in_block(rig, program, 90, "Z1")
    assert (x1.setpoint, y1.setpoint) == (pytest.approx(53.0, abs=1e-6), pytest.approx(-4.0, abs=1e-6))
    _reset(rig)
    _trigger_in_block(rig, program, 110, "Y1", 20)
    assert (x1.setpoint, y1.setpoint) == (pytest.approx(10.0, abs=1e-6), pytest.approx(-4.0, abs=1e-6))
    _reset(rig)
    _trigger_in_block(rig, program, 130, "Y1", 20)
    assert x1.setpoint == pytest.approx(50.0, abs=1e-6) and 0.0 < y1.setpoint < 10.0
    assert z1.setpoint == pytest.approx(100.0, abs=1e-6)


def test_tv_esr_6_polfmlin_axes_arrive_together_on_a_line() -> None:
    rig, x1, y1, z1 = _polf_rig()
    program = (POLF_ARMING + "N40 POLF[X]=IC(3.0) POLF[Z]=-4.0\nN50 POLF[Y]=100\nN60 G0 X50 Y0\n"
               "N70 POLFMLIN(X,Y)\nN80 POLFMASK(Z)\nN90 Z100 G1 F1000\nM30")
    run_mda(rig, program)
    rig.run_until(lambda: block_number(rig) == 90 and z1.command_velocity != 0.0, 20000)
    rig.step(50)
    x_start = x1.setpoint  # N90 moves only Z1
    rig.set("NC.basic.out.setDigitalInputs", 1)
    arrivals: dict[str, int] = {}
    for count in range(1, 2000):
        rig.step(1)
        # on the line: X1's share of the way equals Y1's in every cycle
        assert (x1.setpoint - x_start) / 3.0 == pytest.approx(y1.setpoint / 100.0, abs=1e-9)
        for name, target in (("X1", x_start + 3.0), ("Y1", 100.0), ("Z1", -4.0)):
            if name not in arrivals and abs(axis(rig, name).setpoint - target) < 1e-9:
                arrivals[name] = count
        if len(arrivals) == 3:
            break
    assert arrivals["X1"] == arrivals["Y1"]  # POLFMLIN: together
    assert arrivals["Z1"] != arrivals["X1"]  # POLFMASK: Z1 on its own (about 200 mm, longer)


def test_seq_esr_3_single_axis_stop_runs_on_for_md37510_and_stops_within_md37511() -> None:
    rig = Rig(machine(ESR_MACHINE + "\nSP3: {MD37500: 22, MD37510: 0.3, MD37511: 0.06}"))
    rig.ready_mda()
    rig.set("SP3.spindle.out.ovrFactor", 100)
    spindle = axis(rig, "SP3")
    run_mda(rig, "N10 M3=3 S3=1000\nN20 $AA_ESR_ENABLE[SP3]=1\nN30 G4 F1\nN40 $AA_ESR_TRIGGER[SP3]=1\nN50 G4 F5\nM30")
    rig.run_until(lambda: block_number(rig) == 40, 20000)
    assert spindle.command_velocity == pytest.approx(6000.0)  # 1000 rev/min
    trigger_cycle = rig.nck.cycle
    rig.run_until(lambda: spindle.command_velocity < 6000.0, 1000)
    assert (rig.nck.cycle - trigger_cycle) * DT == pytest.approx(0.3, abs=DT)  # MD37510: turning on
    rig.run_until(lambda: spindle.command_velocity == 0.0, 1000)
    assert (rig.nck.cycle - trigger_cycle) * DT <= 0.36 + DT  # MD37511: stopped within 0.06 s


def _spindle_stopped_by_its_esr(trigger: str) -> Rig:
    """SP3 at 600 rev/min by the program, stopped by its single-axis ESR (MD37510 0.3 s, MD37511 0.06 s)."""
    rig = Rig(machine(ESR_MACHINE + "\nSP3: {MD37500: 22, MD37510: 0.3, MD37511: 0.06}"))
    rig.ready_mda()
    rig.set("SP3.spindle.out.ovrFactor", 100)
    spindle = axis(rig, "SP3")
    run_mda(rig, "N10 M3=3 S3=600\nN20 $AA_ESR_ENABLE[SP3]=1\n"
                 "N25 IDS=1 WHENEVER $A_IN[3]==1 DO $AA_ESR_TRIGGER[SP3]=1\n"
                 f"N30 G4 F1\n{trigger}\nN50 G4 F0.5\nM30")
    rig.run_until(lambda: block_number(rig) == 30, 20000)
    rig.run_until(lambda: spindle.command_velocity == 3600.0, 1000)
    if "ESR_TRIGGER" in trigger:  # in the program
        rig.run_until(lambda: block_number(rig) == 40, 1000)
    else:  # by the synchronized action
        rig.set("NC.basic.out.setDigitalInputs", 4)
    rig.run_until(lambda: spindle.command_velocity == 0.0, 1000)
    return rig


@pytest.mark.parametrize("trigger", ["N40 $AA_ESR_TRIGGER[SP3]=1", "N40 G4 F0.1"])
def test_a_spindle_stopped_by_its_single_axis_esr_stays_stopped_until_a_reset(trigger: str) -> None:
    # seed 003 L11541-11548, L41528-41530: the stop is an orderly stop; its M3 S600 must not turn it again
    rig = _spindle_stopped_by_its_esr(trigger)
    spindle, program = axis(rig, "SP3"), rig.nck.channels[0].spindles["SP3"]
    assert program.direction == 0 and program.speed == 600.0  # the direction is deleted, S stays (L16215-16217)
    for _ in range(500):  # 1 s: the block after the trigger, program end; the synchronized action stays
        rig.step(1)
        assert spindle.command_velocity == 0.0 and rig.get("SP3.basic.in.traversPlusCommandActive") == 0
    assert rig.get("SP3.basic.in.isStationary") == 1 and rig.get("SP3.spindle.in.cwRotActive") == 0
    rig.set("NC.basic.out.setDigitalInputs", 0)  # else IDS=1 triggers again after each program end
    run_mda(rig, "N10 M3=3 S3=600\nN20 G4 F0.5\nM30")  # a new start is no reset: it stays stopped
    rig.step(300)
    assert spindle.command_velocity == 0.0
    rig.pulse("CHAN1.basic.out.reset", 2)  # the reset ends the stop; the spindle turns when started again
    rig.step(5)
    assert spindle.command_velocity == 0.0
    run_mda(rig, "N10 M3=3 S3=600\nN20 G4 F0.5\nM30")
    rig.run_until(lambda: spindle.command_velocity == 3600.0, 1000)


def test_db31_dbx2_2_ends_the_single_axis_esr_stop_of_a_spindle() -> None:
    rig = _spindle_stopped_by_its_esr("N40 G4 F0.1")
    spindle = axis(rig, "SP3")
    rig.set("NC.basic.out.setDigitalInputs", 0)
    rig.step(500)  # the program has ended
    rig.pulse("SP3.basic.out.resetMovement", 2)
    rig.pulse("SP3.spindle.out.startCw", 2)  # DBB30: start with the last S - deleted by DBX2.2
    rig.step(100)
    assert spindle.command_velocity == 0.0
    run_mda(rig, "N10 M3=3 S3=300\nN20 G4 F0.5\nM30")
    rig.run_until(lambda: spindle.command_velocity == 1800.0, 1000)


@pytest.mark.parametrize("program", ["N20 M2=3 S2=300\nN25 COUPDEF(S3,S2,1,1)\nN30 COUPON(S3,S2)",
                                     "N20 M2=3 S2=300\nN30 M3=70"])
def test_a_single_axis_trigger_ignores_a_following_spindle_and_a_spindle_in_axis_mode(program: str) -> None:
    # L11523-11527: only a single axis at the trigger reacts; a coupled SP3 moves with SP2 (L11390-11392),
    # SP3 in axis mode (M70) is an axis of the channel's path
    rig = Rig(machine(ESR_MACHINE + "\nSP3: {MD37500: 22, MD37510: 0.0}"))
    rig.ready_mda()
    rig.set("SP2.spindle.out.ovrFactor", 100)
    run_mda(rig, f"N10 $AA_ESR_ENABLE[SP3]=1\n{program}\nN50 G4 F1\nN60 $AA_ESR_TRIGGER[SP3]=1\nN70 G4 F1\nM30")
    rig.run_until(lambda: block_number(rig) == 70, 20000)
    rig.step(100)
    assert not rig.nck.channels[0].spindles["SP3"].esr_stopped and axis(rig, "SP3").owner is not Owner.BRAKE
    if "COUPON" in program:
        assert axis(rig, "SP3").command_velocity == pytest.approx(axis(rig, "SP2").command_velocity)


def test_a_single_axis_trigger_leaves_the_running_retraction_alone() -> None:
    rig = Rig(machine(ESR_MACHINE + "\nSP3: {MD37500: 21}"))
    rig.ready_mda()
    run_mda(rig, "N10 LFPOS POLF[X]=IC(100) POLFMASK(X)\nN20 $AA_ESR_ENABLE[X]=1 $AA_ESR_ENABLE[SP3]=1\n"
                 "N30 POLFA(SP3,1,90.0)\nN40 IDS=1 WHENEVER $A_IN[1]==1 DO $AC_ESR_TRIGGER=1\n"
                 "N50 IDS=2 WHENEVER $A_IN[2]==1 DO $AA_ESR_TRIGGER[SP3]=1\nN60 G1 Z100 F3000\nM30")
    x1, spindle = axis(rig, "X1"), axis(rig, "SP3")
    rig.run_until(lambda: axis(rig, "Z1").command_velocity < 0.0, 20000)
    rig.set("NC.basic.out.setDigitalInputs", 1)
    rig.run_until(lambda: x1.command_velocity > 200.0, 200)  # X1 retracting, accelerating
    rig.set("NC.basic.out.setDigitalInputs", 3)  # now SP3 on its own trigger
    velocities = [x1.command_velocity]
    while x1.command_velocity > 0.0 or len(velocities) < 3:
        rig.step(1)
        velocities.append(x1.command_velocity)
    # the velocity of X1's retraction goes on without a jump (MD32300 4 m/s^2 = 8 mm/s per cycle)
    assert max(abs(b - a) for a, b in itertools.pairwise(velocities)) <= 4000.0 * DT + 1e-6
    rig.run_until(lambda: spindle.command_velocity == 0.0, 1000)
    assert x1.setpoint == pytest.approx(250.0, abs=1e-6) and spindle.setpoint == pytest.approx(90.0, abs=1e-6)


# ------------------------------------------------------------------------------ transformations


def test_without_esr_on_every_axis_of_the_inclined_pair_its_group_is_dissolved() -> None:
    # seed 003 L42098-42104: Y1 of the inclined pair without $AA_ESR_ENABLE - POLF[X] is a machine X1 position
    rig = Rig(machine(ESR_MACHINE))
    rig.ready_mda()
    run_mda(rig, "N10 G0 G90 X100 Y0\nN20 LFPOS POLF[X]=150 POLFMASK(X)\nN30 $AA_ESR_ENABLE[X]=1\n"
                 "N40 IDS=1 WHENEVER $A_IN[1]==1 DO $AC_ESR_TRIGGER=1\nN50 G1 X120 Y80 F3000\nM30")
    x1, y1 = axis(rig, "X1"), axis(rig, "Y1")
    rig.run_until(lambda: rig.nck.program_position("Y1") > 40.0, 20000)
    rig.set("NC.basic.out.setDigitalInputs", 1)
    rig.step(2)
    esr = rig.nck.channels[0].esr
    assert esr is not None
    rig.run_until(lambda: not esr.running, 500)
    assert x1.setpoint == pytest.approx(150.0, abs=1e-6)  # the machine axis, not program X
    assert y1.command_velocity == 0.0


def test_a_retract_axis_leaves_a_tool_path_and_the_others_follow_it() -> None:
    rig = Rig(machine(ABSOLUTE_XYZ))
    x1, z1, y1 = axis(rig, "X1"), axis(rig, "Z1"), axis(rig, "Y1")
    segment = ToolPathSegment.plan([x1, z1, y1], lambda f: (150.0 + 10.0 * f, 300.0 + 20.0 * f, 30.0 * f), 30.0,
                                   600.0, False)
    segment.release_axis(z1)
    while not segment.finished:
        segment.cycle(1.0, False, DT)
    assert (x1.setpoint, z1.setpoint, y1.setpoint) == (160.0, 300.0, 30.0)  # Z1 stays where it was left


def test_esrr_converts_with_the_gear_ratio_of_the_active_gear_stage() -> None:
    # SP1 in gear stage 1 (7.5 motor revolutions per load revolution); parameter set 0 would give 1:1
    rig = spindle_rig("SP1: {MD31050: [1, 2, 1, 3], MD31060: [1, 15, 3, 4]}")
    run_mda(rig, "ESRR(SP1,90.0,3600.0)\nM30")
    rig.step(20)
    assert rig.nck.esr.drives["SP1"].p0893 == pytest.approx(75.0)  # 10 rev/min at the load x 7.5


# ------------------------------------------------------------------------------ ESR during G33


THREAD_ESR_ARMING = "N1 IDS=1 WHENEVER $A_IN[1]==1 DO $AC_ESR_TRIGGER=1\n"


def _esr_in_thread(program: str, trigger_at_z: float) -> tuple[Rig, int]:
    """Run ``program`` on ESR_MACHINE (SP1 in gear stage 1) and give $A_IN[1] when Z1 passes
    ``trigger_at_z`` in N70; returns the rig one cycle later and the trigger's cycle."""
    rig = spindle_rig(base=ESR_MACHINE)
    run_mda(rig, THREAD_ESR_ARMING + program)
    rig.run_until(lambda: block_number(rig) == 70 and axis(rig, "Z1").setpoint > trigger_at_z, 20000)
    rig.set("NC.basic.out.setDigitalInputs", 1)
    rig.step(1)
    return rig, rig.nck.cycle


def _assert_z1_runs_on_then_brakes(rig: Rig, trigger_cycle: int) -> None:
    """Z1 follows the spindle at 41.7 mm/s for MD21380 = 0.1 s, then stops within MD21381 = 0.04 s."""
    z1 = axis(rig, "Z1")
    rig.run_until(lambda: z1.command_velocity < 41.0, 200)
    assert (rig.nck.cycle - trigger_cycle) * DT == pytest.approx(0.1, abs=2 * DT)
    rig.run_until(lambda: z1.command_velocity == 0.0, 200)
    assert (rig.nck.cycle - trigger_cycle) * DT <= 0.14 + 2 * DT


def test_a_thread_block_ending_in_the_esr_run_on_still_leaves_the_chain() -> None:
    # ESR trigger 2 mm before the end of N70 (LFON): Z1 runs on for MD21380 = 0.1 s (4.2 mm at
    # 41.7 mm/s) and reaches Z30 in the run-on; NC start must not cut N71 from the retract position.
    rig, _ = _esr_in_thread("N55 M3 S500 G90 G18\nN68 G0 Z5\nN69 X10\nN70 G33 Z30 K5 LFON DILF=10 LFWP ALF=7\n"
                            "N71 G33 Z55 X15\nN72 G1 X20 F100\nM30", 28.0)
    x1, z1 = axis(rig, "X1"), axis(rig, "Z1")
    rig.step(400)
    assert x1.setpoint == pytest.approx(0.0, abs=1e-6) and z1.setpoint == pytest.approx(30.0, abs=1e-6)
    rig.set("NC.basic.out.setDigitalInputs", 0)
    rig.pulse("CHAN1.basic.out.ncStart", 2)
    rig.run_until(lambda: block_number(rig) == 72, 50)
    rig.step(100)
    assert z1.setpoint == pytest.approx(30.0, abs=1e-6) and 0.0 < x1.setpoint < 20.0  # N72 moves X alone


def test_an_esr_in_g33_without_lfon_retracts_x_and_runs_z_on_for_md21380() -> None:
    rig, trigger_cycle = _esr_in_thread("N2 $AA_ESR_ENABLE[X]=1 $AA_ESR_ENABLE[Z]=1\n"
                                        "N3 LFPOS POLF[X]=IC(10) POLFMASK(X)\nN55 M3 S500 G90 G18\nN68 G0 Z5\n"
                                        "N69 X10\nN70 G33 Z50 X30 K5\nN71 G33 Z60\nN72 G1 X40 F100\nM30", 20.0)
    x1, z1 = axis(rig, "X1"), axis(rig, "Z1")
    x_at_trigger = x1.setpoint
    _assert_z1_runs_on_then_brakes(rig, trigger_cycle)
    rig.run_until(lambda: x1.at_rest, 500)
    assert x1.setpoint == pytest.approx(x_at_trigger + 10.0, abs=0.02)
    z_stopped = z1.setpoint
    rig.set("NC.basic.out.setDigitalInputs", 0)
    rig.pulse("CHAN1.basic.out.ncStart", 2)  # the thread block and the G33 block chained to it are dropped
    rig.run_until(lambda: block_number(rig) == 72, 50)
    rig.step(100)
    assert z1.setpoint == z_stopped and x1.setpoint > x_at_trigger + 10.0


def test_a_thread_axis_braked_off_the_thread_brakes_the_others_too() -> None:
    rig = spindle_rig(base=ESR_MACHINE)
    run_mda(rig, "N55 M3 S500 G90 G18\nN68 G0 Z5\nN69 X10\nN70 G33 Z50 X30 K5\nN72 G1 X40 F100\nM30")
    x1, z1 = axis(rig, "X1"), axis(rig, "Z1")
    rig.run_until(lambda: block_number(rig) == 70 and z1.setpoint > 20.0, 20000)
    velocity = z1.command_velocity
    x1.rapid_stop(then_servo_off=False)  # a reaction takes X1 off the thread
    cycles = rig.run_until(lambda: z1.command_velocity == 0.0, 200)
    assert cycles * DT == pytest.approx(velocity / 4000.0, abs=2 * DT)  # Z1 brakes at MD32300 4 m/s^2
    assert rig.nck.channels[0].thread_in_progress is None


def test_a_rapid_stop_alarm_waits_for_the_thread_axes_run_on_after_an_esr_in_g33() -> None:
    rig, trigger_cycle = _esr_in_thread("N55 M3 S500 G90 G18\nN68 G0 Z5\nN69 X10\n"
                                        "N70 G33 Z50 K5 LFON DILF=10 LFWP ALF=7\nN72 G1 X20 F100\nM30", 20.0)
    rig.nck.alarms.raise_alarm(2000, rig.nck.cycle)  # rapid stop with follow-up during MD21380
    _assert_z1_runs_on_then_brakes(rig, trigger_cycle)  # the thread axis and its spindle go on regardless


def test_a_rapid_stop_alarm_waits_for_the_whole_thread_after_an_esr_in_g33_without_lfon() -> None:
    # only X1 is ESR-enabled (it retracts); Z1 and SP1 are not, yet they are the thread X1 leaves
    rig, trigger_cycle = _esr_in_thread("N2 $AA_ESR_ENABLE[X]=1\nN3 LFPOS POLF[X]=IC(10) POLFMASK(X)\n"
                                        "N55 M3 S500 G90 G18\nN68 G0 Z5\nN69 X10\nN70 G33 Z50 K5\n"
                                        "N72 G1 X20 F100\nM30", 20.0)
    rig.nck.alarms.raise_alarm(2000, rig.nck.cycle)  # rapid stop with follow-up during MD21380
    sp1, z1 = axis(rig, "SP1"), axis(rig, "Z1")
    turning = sp1.command_velocity
    for _ in range(45):
        rig.step(1)
        assert sp1.command_velocity == turning
        assert z1.command_velocity == pytest.approx(turning / 360.0 * 5.0)  # K5: 5 mm per revolution
    _assert_z1_runs_on_then_brakes(rig, trigger_cycle)
    rig.step(100)
    assert sp1.command_velocity == 0.0  # after the ESR the alarm's rapid stop has braked the spindle


def test_a_jump_after_a_fast_retraction_leaves_the_chain_so_its_target_thread_is_cut() -> None:
    rig = spindle_rig()
    run_mda(rig, "N55 M3 S500 G90 G18\nN68 G0 Z5\nN69 X10\nN70 G33 Z30 K5 LFON DILF=10 LFWP ALF=7\n"
                 "N71 G33 Z55 X15\nN72 GOTOF SECOND\nN73 G0 X99\nSECOND: G33 Z90 K5\nN90 G0 X40\nM30")
    x1, z1 = axis(rig, "X1"), axis(rig, "Z1")
    rig.run_until(lambda: block_number(rig) == 70 and z1.setpoint > 15.0, 20000)
    rig.set("CHAN1.basic.out.ncStop", 1)
    rig.step(200)
    rig.set("CHAN1.basic.out.ncStop", 0)
    rig.step(2)
    rig.pulse("CHAN1.basic.out.ncStart", 2)  # N71 is dropped with the chain, the jump ends the chain
    rig.run_until(lambda: rig.get("CHAN1.basic.in.stateReset") == 1, 20000)
    assert z1.setpoint == pytest.approx(90.0, abs=1e-6) and x1.setpoint == pytest.approx(40.0, abs=1e-6)


FIVE_AXIS_CHAIN = ("X1", "Y1", "Z1", "A1", "C1")  # mill_5axis, see transforms/test_five_axis_control.py


def _tool_tip(rig: Rig) -> tuple[float, ...]:
    return tuple(rig.sim.axis_quantity("CHAN1", f"toolTip{axis}") for axis in "XYZ")


def test_an_esr_under_g43_4_retracts_z1_off_the_tool_path_while_the_others_run_on_along_it() -> None:
    # Z1 retract axis (MD37500 = 21, POLF[Z] = IC(20)), the others stop axes: MD21380 0.1 s, MD21381 0.04 s.
    # N50 turns C1 under the fixed tip (350, 250, -280): X1 / Y1 follow on a circle, Z1's share is constant.
    esr = ("CHAN1: {MD20700: 0, MD62950: [100.0, 50.0], MD21380: 0.1, MD21381: 0.04}\n" + "\n".join(
        f"{axis}: {{MD30240: [4], MD34210: [2], MD37500: {21 if axis == 'Z1' else 22}}}" for axis in FIVE_AXIS_CHAIN))
    rig = Rig(machine(esr, FIVE_AXIS))
    rig.ready_mda(*FIVE_AXIS_CHAIN)
    rig.mda("N1 IDS=1 WHENEVER $A_IN[1]==1 DO $AC_ESR_TRIGGER=1\n"
            "N2 $AA_ESR_ENABLE[X]=1 $AA_ESR_ENABLE[Y]=1 $AA_ESR_ENABLE[Z]=1 $AA_ESR_ENABLE[A1]=1 $AA_ESR_ENABLE[C1]=1\n"
            "N3 LFPOS POLF[Z]=IC(20) POLFMASK(Z)\nG90 G0 X350 Y250 Z-180 A0 C0\nG43.4 H1\nN50 G1 C90 F2000\nM30")
    c1, z1 = rig.axis("C1"), rig.axis("Z1")
    rig.run_until(lambda: block_number(rig) == 50 and c1.setpoint > 20.0, 20000)
    velocity = c1.command_velocity  # 33.3 deg/s
    rig.set("NC.basic.out.setDigitalInputs", 1)
    rig.step(1)
    trigger_cycle, z_at_trigger = rig.nck.cycle, z1.setpoint
    rig.run_until(lambda: c1.command_velocity < velocity - 1e-6, 200)
    assert (rig.nck.cycle - trigger_cycle) * DT == pytest.approx(0.1, abs=2 * DT)  # MD21380 along the tool path
    rig.run_until(lambda: c1.command_velocity == 0.0, 200)
    assert (rig.nck.cycle - trigger_cycle) * DT <= 0.14 + 2 * DT  # braked within MD21381
    assert 20.0 + velocity * 0.1 < c1.setpoint < 90.0
    rig.step(300)
    assert z1.setpoint == pytest.approx(z_at_trigger + 20.0, abs=1e-6)  # POLF: the machine axis + 20
    # X1 / Y1 stayed on the tool path: the tip is still above (350, 250), 20 mm higher with Z1
    assert _tool_tip(rig) == pytest.approx((350.0, 250.0, -260.0), abs=5e-3)


def test_a_fast_retraction_under_the_inclined_pair_moves_on_the_program_line() -> None:
    # turn_mill: Y1 inclined at theta = -30 degrees to X1 (radius programming, C = 1): program
    # (Xp, Yp) stands on the slides at Ya = Yp / cos(theta), Xa = Xp - Yp tan(theta).  G17, ALF=3:
    # 10 mm in +Y, from program Y 20 to 30 with X 60 kept.
    rig = spindle_rig()
    channel = rig.nck.channels[0]
    assert channel.inclined is not None and channel.inclined.parameters.diameter_factor == 1.0
    run_mda(rig, "N55 M3 S500 G90 G17\nN68 G0 Z5 Y20\nN69 X60\nN70 G33 Z30 K5 LFON DILF=10 LFWP ALF=3\n"
                 "N72 G1 X70 F100\nM30")
    x1, y1, z1 = axis(rig, "X1"), axis(rig, "Y1"), axis(rig, "Z1")
    rig.run_until(lambda: block_number(rig) == 70 and z1.actual > 15, 20000)
    rig.set("CHAN1.basic.out.ncStop", 1)
    for _ in range(300):
        rig.step(1)
        assert rig.nck.program_position("X1") == pytest.approx(60.0, abs=1e-6)  # on the program line
    theta = math.radians(-30.0)
    assert y1.setpoint == pytest.approx(30.0 / math.cos(theta), abs=1e-6)  # 34.641
    assert x1.setpoint == pytest.approx(60.0 - 30.0 * math.tan(theta), abs=1e-6)  # 77.321
