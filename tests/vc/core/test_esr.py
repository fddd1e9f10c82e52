"""G33 thread cutting, fast retraction (LIFTFAST) and extended stop and retract (ESR) in the NC core.

Spec sections 2 (ESR, seed 003 chapter 22 and 9.3.3) and 3 (fast retraction, seed 003 §7.2.3.5);
the test acts as the PLC.  Turn-mill: X1 / Z1 / Y1 with absolute encoders, 30 m/min and 4 m/s^2
(Y1 15 m/min, 3 m/s^2); SP1 the master spindle.
"""

from __future__ import annotations

import math

import pytest
from core_rig import ABSOLUTE_XYZ, DT, Rig, machine
from test_spindle import spindle_rig

from vc.core.axis import MachineAxis
from vc.core.drive_esr import EXTENDED_RETRACT, EXTENDED_STOP
from vc.core.interpreter import ModalState, decode
from vc.core.program import parse_program
from vc.core.retract_motion import RetractProgramming, direction_targets, retract_groups
from vc.core.sync_actions import SyncActionError, parse_actions, parse_condition

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


def _decode(text: str, modal: ModalState | None = None) -> tuple[object, object, ModalState]:
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
    ("IDS=1 WHENEVER $A_IN[1] >> 1 DO $AC_ESR_TRIGGER=1", 12080),
    ("G33 Z10", 12080),  # no lead yet
])
def test_bad_retract_words_raise_the_control_alarm(text: str, alarm: int) -> None:
    _, found, _ = _decode(text)
    assert found is not None and found.number == alarm


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
    drive.set_enable(False)  # acknowledged while the reaction runs: 95.2 falls when it ends
    rig.step(10)
    assert drive.triggered
    rig.step(150)
    assert not drive.triggered and axis(rig, "X1").actual == pytest.approx(170.0, abs=0.01)
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
