"""The coupling engine's rules without a PLC: definitions, ratios, block change, dynamic matching,
and the part-program calls that reach it (seed 003 chapter 14, seed 002)."""

from __future__ import annotations

from pathlib import Path

import pytest
from core_rig import Rig, machine

from interfaces.catalog import load_catalog
from vc.config.loader import load_machine
from vc.core.nck.nck import Nck
from vc.core.program.block_plan import BlockPlan, DecodeAlarm, ModalState
from vc.core.program.commands import BlockChange, Kind, block_change_of, kind_of
from vc.core.program.interpreter import decode
from vc.core.program.program import parse_program
from vc.core.program.sync_actions import VariableWrite
from vc.core.spindle.coupling import (
    ALARM_COUPLING_ACTIVE,
    ALARM_COUPLING_NOT_DEFINED,
    ALARM_TOO_MANY_COUPLINGS,
    ALARM_WRITE_PROTECTED,
)

TURN_MILL = str(Path(__file__).resolve().parents[4] / "scenarios" / "machines" / "turn_mill.yaml")


@pytest.fixture()
def nck() -> Nck:
    return Nck(load_machine(TURN_MILL), load_catalog())


def test_block_change_takes_only_the_initial_letters() -> None:
    assert block_change_of("Fine") is BlockChange.FINE
    assert block_change_of("COARSE") is BlockChange.COARSE
    assert block_change_of("No") is BlockChange.NOC
    assert block_change_of("IPOSTOP") is BlockChange.IPOSTOP
    assert block_change_of("sometime") is None
    assert kind_of("Dv") is Kind.DV and kind_of("VV") is Kind.VV and kind_of("XY") is None


def test_configured_pair_comes_from_md21300(nck: Nck) -> None:
    definition = nck.couplings.definitions["SP2"]
    assert (definition.following, definition.leading, definition.ratio) == ("SP2", "SP1", 1.0)
    assert definition.configured and definition.kind is Kind.DV  # MD21310 = 1
    assert definition.block_change is BlockChange.FINE  # MD21320 = 1


def test_tv_ss_7_coupdef_ratio_one_quarter_and_only_written_parameters_change(nck: Nck) -> None:
    couplings = nck.couplings
    assert couplings.define("CHAN1", "SP2", "SP1", 1.0, 4.0, None, None) == 0
    definition = couplings.definitions["SP2"]
    assert definition.ratio == 0.25
    assert couplings.define("CHAN1", "SP2", "SP1", None, None, BlockChange.NOC, None) == 0
    assert definition.ratio == 0.25 and definition.block_change is BlockChange.NOC
    assert couplings.define("CHAN1", "SP2", "SP1", -1.0, None, None, None) == 0
    assert definition.ratio == -1.0  # a missing denominator means 1 (L22560-22632)
    assert couplings.restore("SP2") == 0  # COUPRES: the machine data again
    assert definition.ratio == 1.0 and definition.block_change is BlockChange.FINE


def test_write_protection_and_the_fixed_axes_of_the_configured_pair(nck: Nck) -> None:
    couplings = nck.couplings
    couplings.definitions["SP2"].write_protected = True
    assert couplings.define("CHAN1", "SP2", "SP1", 2.0, None, None, None) == ALARM_WRITE_PROTECTED
    assert couplings.define("CHAN1", "SP2", "SP3", 2.0, None, None, None) == ALARM_WRITE_PROTECTED


def test_couple_rules_undefined_compound_and_type_change(nck: Nck) -> None:
    couplings = nck.couplings
    assert couplings.couple("CHAN1", "SP3", "SP1", None, False, 0, "N10") == ALARM_COUPLING_NOT_DEFINED
    assert couplings.couple("CHAN1", "SP2", "SP1", None, False, 0, "N10") == 0
    assert nck.spindles[1].mode.value == "synchronous"
    # the FS of one pair cannot lead another (a cascade)
    assert couplings.define("CHAN1", "SP3", "SP2", None, None, None, None) == 0
    assert couplings.couple("CHAN1", "SP3", "SP2", None, False, 0, "N20") == ALARM_TOO_MANY_COUPLINGS
    # the type changes only while decoupled (L22616)
    assert couplings.define("CHAN1", "SP2", "SP1", None, None, None, Kind.AV) == ALARM_COUPLING_ACTIVE
    assert couplings.decouple("SP2", stop=False) == 0
    assert couplings.define("CHAN1", "SP2", "SP1", None, None, None, Kind.AV) == 0
    assert couplings.delete("SP3") == 0 and "SP3" not in couplings.definitions
    assert couplings.delete("SP2") == 0 and "SP2" in couplings.definitions  # MD21300's pair stays


def _decode(nck: Nck, text: str) -> tuple[BlockPlan, DecodeAlarm | None]:
    channel = nck.channels[0]
    plan, alarm = decode(parse_program(text)[0], ModalState(), channel.config, channel.axes_by_name)
    return plan, alarm


def test_interpreter_coupling_calls(nck: Nck) -> None:
    plan, alarm = _decode(nck, 'N52 COUPDEF(S2,S1,1,1,"FINE","DV")')
    assert alarm is None
    command = plan.couplings[0]
    assert (command.function, command.following, command.leading, command.numerator, command.block_change,
            command.kind) == ("COUPDEF", "SP2", "SP1", 1.0, "FINE", "DV")
    plan, alarm = _decode(nck, "N53 COUPON(S2,S1,77)")
    assert alarm is None and plan.couplings[0].offset == 77.0
    plan, alarm = _decode(nck, "N53 COUPON(S2,S1,360)")  # POSFS 0 .. 359.999 (L22196)
    assert alarm is not None and alarm.number == 12080
    plan, alarm = _decode(nck, 'N54 COUPDEF(S2,S1,1,1,"SOMETIME")')
    assert alarm is not None and alarm.number == 16795
    plan, alarm = _decode(nck, "N55 COUPON(S2,S2)")
    assert alarm is not None and alarm.number == 16785
    plan, alarm = _decode(nck, 'N56 WAITC(S2,"FINE") FA[S2]=3600 SPCON(2)')
    assert alarm is None
    assert plan.couplings[0].block_change == "FINE"
    assert plan.feeds == {"SP2": 3600.0} and plan.position_control == {"SP2": True}
    plan, alarm = _decode(nck, "N57 G4 S50")  # 50 revolutions of the master spindle
    assert alarm is None and plan.dwell_revolutions == 50.0 and not plan.spindles
    assert plan.dwell_spindle == "SP1"
    plan, alarm = _decode(nck, "N58 G4 S2=10")  # 10 revolutions of spindle 2
    assert alarm is None and plan.dwell_revolutions == 10.0 and plan.dwell_spindle == "SP2"
    assert not plan.spindles


def test_tv_ss_9_threshold_keywords_name_the_machine_data_they_replace(nck: Nck) -> None:
    plan, alarm = _decode(nck, "N60 CPSYNCOP[S2]=0.5 CPSYNFIP[S2]=0.25 CPSYNCOP2[S2]=1.6 CPSYNFIP2[S2]=0.8")
    assert alarm is None
    assert plan.coupling_thresholds == {"SP2": {37200: 0.5, 37210: 0.25, 37202: 1.6, 37212: 0.8}}
    plan, alarm = _decode(nck, "N61 CPSYNCOV[S2]=3 CPSYNFIV[S2]=1.5 CPSYNCOP2[S2]=0")  # 0: stage 2 off
    assert alarm is None
    assert plan.coupling_thresholds == {"SP2": {37220: 3.0, 37230: 1.5, 37202: 0.0}}


@pytest.mark.parametrize(("text", "number", "shown"), [
    ("N62 CPSYNFIP[S2]=-0.1", 12080, "CPSYNFIP[S2]=-0.1"), ("N62 CPSYNCOP=0.5", 12080, "CPSYNCOP=0.5"),
    ("N62 CPSYNFIP2[S9]=0.8", 16105, "9"), ("N62 CPSYNCOP2[X]=1.6", 16105, "X"),
])
def test_bad_threshold_words_raise_the_alarm_with_the_block(nck: Nck, text: str, number: int, shown: str) -> None:
    _, alarm = _decode(nck, text)
    assert alarm is not None and alarm.number == number
    assert alarm.parameters[1] == "N62" and str(alarm.parameters[2]) == shown


def test_programmed_thresholds_act_from_the_next_coupon_until_coupres(nck: Nck) -> None:
    couplings = nck.couplings
    definition = couplings.definitions["SP2"]
    couplings.program_thresholds("SP2", {37210: 0.25})
    assert definition.thresholds == {}  # only the next switching command takes them (L29849)
    assert couplings.couple("CHAN1", "SP2", "SP1", None, False, 0, "N10") == 0
    assert definition.thresholds == {37210: 0.25}
    couplings.program_thresholds("SP2", {37200: 0.5})
    assert couplings.couple("CHAN1", "SP2", "SP1", None, False, 0, "N20") == 0  # coupled already: taken too
    assert definition.thresholds == {37210: 0.25, 37200: 0.5}
    couplings.program_thresholds("SP2", {37212: 0.8})
    couplings.reset("CHAN1")  # MD21330 = 0: the pair and what it took stay; what no COUPON took is gone
    assert couplings.couple("CHAN1", "SP2", "SP1", None, False, 0, "N30") == 0
    assert definition.thresholds == {37210: 0.25, 37200: 0.5}
    assert couplings.restore("SP2") == 0 and definition.thresholds == {}  # COUPRES: the machine data


@pytest.mark.parametrize(("text", "number"), [
    ("G51.2 P0 Q6", 65840), ("G51.2 P1000 Q6", 65840), ("G51.2 P2 Q0", 65840), ("G51.2 P2 Q1000", 65840),
    ("G51.2 P2", 65840), ("G51.2 P2 Q6 X10", 65842), ("G50.2 P2", 65842),
])
def test_tv_pg_7_g51_2_ranges_and_own_block(nck: Nck, text: str, number: int) -> None:
    _, alarm = _decode(nck, text)
    assert alarm is not None and alarm.number == number


def test_g51_2_arguments_and_signed_master_speed(nck: Nck) -> None:
    channel = nck.channels[0]
    modal = ModalState()
    blocks = parse_program("G51.2 P5 Q-12 R15 A390\nS-300\n")
    plan, alarm = decode(blocks[0], modal, channel.config, channel.axes_by_name)
    assert alarm is None and modal.polygon
    polygon = plan.polygon
    assert polygon is not None and (polygon.p, polygon.q, polygon.r, polygon.a) == (5.0, -12.0, 15.0, 390.0)
    plan, alarm = decode(blocks[1], modal, channel.config, channel.axes_by_name)
    command = plan.spindles["SP1"]
    assert alarm is None and command.speed == 300.0 and command.direction == 4  # S < 0: M4 (seed 002 L41-47)


def test_waits_names_the_spindles_or_the_master_spindle(nck: Nck) -> None:
    plan, alarm = _decode(nck, "N365 WAITS(2)")
    assert alarm is None and plan.spindle_waits == ["SP2"] and not plan.spindles
    plan, alarm = _decode(nck, "N366 WAITS")
    assert alarm is None and plan.spindle_waits == ["SP1"]
    plan, alarm = _decode(nck, "N367 WAITS(2,3)")
    assert alarm is None and plan.spindle_waits == ["SP2", "SP3"]
    _, alarm = _decode(nck, "N368 WAITS(7)")
    assert alarm is not None and alarm.number == 16105


def _coupling_rig(overrides: str = "", channel: str = "") -> Rig:
    """The turn_mill machine in MDA with the test as PLC: enables, overrides 100 %, SP1 in gear 1."""
    channel_data = "CHAN1: {MD20700: 0" + (", " + channel if channel else "") + "}"
    rig = Rig(machine(channel_data + ("\n" + overrides if overrides else "")))
    rig.ready_mda()
    for spindle in ("SP1", "SP2"):
        rig.set(f"{spindle}.spindle.out.ovrFactor", 100)
    rig.set("SP1.spindle.out.gearStageSelection", 1)  # the gearbox reports stage 1
    rig.step(12)
    return rig


def test_coupon_offset_moves_at_the_largest_position_control_speed_of_the_gear_stage() -> None:
    # "the highest possible velocity" (L22015-22021) is the FS's MD35135 here: 100 rev/min
    rig = _coupling_rig("SP2: {MD35135: [100, 100]}")
    rig.mda("N10 COUPON(S2,S1,180)\nN20 G4 F1\n")
    fastest = 0.0
    for _ in range(400):
        rig.step()
        fastest = max(fastest, abs(rig.sim.axis_quantity("SP2", "velocity")))
    assert abs(fastest - 100.0) < 1e-6
    assert abs(rig.nck.couplings.quantity("SP2", "couplingOffset") - 180.0) < 1e-6


def test_differential_speed_that_cancels_the_coupled_speed_shows_no_deviation() -> None:
    # TV-SS-4 with S2=500: n_FS = -1 x 500 + 500 = 0.  The FS stands without following error
    # while the LS lags by its own (MD32810 4 ms - 2 ms cycle: 3000 deg/s x 2 ms = 6 degrees);
    # the lag of the differential part comes from the FS's loop, so the deviation stays 0
    rig = _coupling_rig()
    rig.set("SP2.coupling.out.enableFollowOverlay", 1)
    rig.mda("N10 M3 S500\nN20 COUPDEF(S2,S1,-1)\nN30 COUPON(S2,S1)\nN40 M2=3 S2=500\nN50 G4 F3\n")
    rig.step(1000)
    fs, ls = rig.axis("SP2"), rig.axis("SP1")
    assert abs(ls.velocity / 6.0 - 500.0) < 1e-6 and fs.velocity == 0.0
    assert abs(ls.following_error - 6.0) < 1e-6 and fs.following_error == 0.0
    assert rig.nck.couplings.quantity("SP2", "syncDeviation") < 1e-6
    assert rig.get("SP2.coupling.in.syncFineReached") == 1 and rig.get("SP2.spindle.in.speedSetpointReached") == 1


def test_relation_error_shows_a_disturbed_following_spindle_and_nothing_else() -> None:
    # DV with matched dynamics: the actual relation is the commanded one; a load that pushes the FS
    # puts it ahead by the load over the position controller's gain, which the monitoring sees too
    rig = _coupling_rig()
    rig.mda('N10 M3 S500\nN20 COUPDEF(S2,S1,1,1,"FINE","DV")\nN30 COUPON(S2,S1,90)\nN40 G4 F3\n')
    rig.step(800)
    couplings = rig.nck.couplings
    assert rig.get("SP2.coupling.in.syncFineReached") == 1
    assert abs(couplings.quantity("SP2", "couplingRelationError")) < 1e-6
    rig.sim.inject_fault("SP2", "load_disturbance", amount=30.0)
    rig.step(100)
    error = couplings.quantity("SP2", "couplingRelationError")
    assert error > 0.5 and abs(error - couplings.quantity("SP2", "syncDeviation")) < 1e-9
    assert rig.get("SP2.coupling.in.syncFineReached") == 0
    assert couplings.quantity("SP3", "couplingRelationError") == 0.0  # follows nobody


@pytest.mark.parametrize("reset_mode", [0, 1025])
@pytest.mark.parametrize("running", [False, True])
def test_reset_that_keeps_the_coupling_ends_the_spos_of_the_following_spindle(reset_mode: int, running: bool) -> None:
    # The configured pair survives reset (MD21330 = 0), with MD20110 bit 0 off or bits 0 and 10 on:
    # the increment queued behind COUPON's 45 degrees, or already running at 6 deg/s, ends [control];
    # COUPON's offset stays
    rig = _coupling_rig(channel=f"MD20110: {reset_mode}")
    rig.mda('N05 M3 S500 M2=4 S2=500\nN10 COUPDEF(S2,S1,1,1,"No","Dv")\nN80 COUPON(S2,S1,45)\n'
            'N200 FA[S2]=360\nN205 SPOS[2]=IC(-90)\nN210 G4 F10\n')
    couplings = rig.nck.couplings

    def spos_started() -> bool:
        coupling = couplings.active.get("SP2")
        if coupling is None:
            return False
        return coupling.overlay is not None and coupling.overlay.positioning if running else bool(coupling.queued)

    rig.run_until(spos_started, 3000)
    coupling = couplings.active["SP2"]
    rig.step(50 if running else 0)
    offset = couplings.quantity("SP2", "couplingOffset")
    rig.pulse("CHAN1.basic.out.reset")
    rig.step(3000)  # 6 s: the 90 degrees at 6 deg/s would still run
    assert couplings.active.get("SP2") is coupling and not coupling.queued
    assert rig.get("SP2.coupling.in.MotionOverlaid") == 0
    # queued: COUPON's 45 degrees reached; running: 0.6 degrees on the way from 45, stopped at once
    expected = offset - 0.0 if running else 45.0
    assert abs(couplings.quantity("SP2", "couplingOffset") - expected) < 0.02


def test_delete_distance_to_go_on_the_fs_ends_the_spos_and_not_couponss_offset_motion() -> None:
    # N60's SPOS waits behind COUPON's 180 degrees (100 rev/min = 600 deg/s, 0.3 s) as a motion of
    # its own at FA 3600 deg/min: DBX2.2 50 ms into COUPON's motion deletes only the SPOS [control]
    rig = _coupling_rig("SP2: {MD35135: [100, 100]}")
    rig.mda('N20 COUPDEF(S2,S1,1,1,"NOC","DV")\nN30 COUPON(S2,S1,0)\nN40 G4 F0.3\nN50 COUPON(S2,S1,180)\n'
            'N60 SPOS[2]=IC(90) FA[S2]=3600\nN70 G4 F10\n')
    couplings = rig.nck.couplings
    rig.run_until(lambda: "SP2" in couplings.active and couplings.active["SP2"].programmed == 270.0, 1000)
    coupling = couplings.active["SP2"]
    assert coupling.overlay is not None and coupling.overlay.limit == pytest.approx(600.0)
    rig.step(25)
    rig.pulse("SP2.basic.out.resetMovement")
    rig.step(500)
    assert coupling.overlay is None and not coupling.queued
    assert abs(couplings.quantity("SP2", "couplingOffset") - 180.0) < 1e-6
    assert coupling.programmed == pytest.approx(180.0)


def test_stage_2_monitoring_pauses_while_a_spindle_stops_on_the_rapid_stop_ramp() -> None:
    # L29921: no stage-2 monitoring while FS or LS stops on the rapid-stop ramp.  The emergency stop
    # brakes S1 from 600 rev/min in 0.1 s and S2 in 0.4 s (MD36610): the relation drifts by some 60
    # degrees, far beyond MD37202 = 1.6, without 22025 / 22026; the monitoring is back (with both
    # alarms for the drift left) once neither spindle brakes any more
    rig = _coupling_rig("SP2: {MD37212: 0.8, MD37202: 1.6, MD36610: 0.4}\nSP1: {MD36610: 0.1}")
    rig.mda("N10 SPOS=0 SPOS[2]=0\nN20 COUPON(S2,S1)\nN30 M3 S600\nN40 G4 F30\n")
    rig.run_until(lambda: rig.get("SP2.coupling.in.syncFine2Reached") == 1 and rig.axis("SP1").velocity > 3599.99,
                  3000)
    fs, ls = rig.axis("SP2"), rig.axis("SP1")
    couplings = rig.nck.couplings
    rig.set("NC.basic.out.emergencyStop", 1)
    largest = 0.0
    rig.step()
    while fs.rapid_stopping or ls.rapid_stopping:
        largest = max(largest, couplings.quantity("SP2", "syncDeviation"))
        assert not {22025, 22026} & set(rig.alarm_numbers())
        assert rig.get("SP2.coupling.in.syncFine2Reached") == 0 and rig.get("SP2.coupling.in.syncCoarse2Reached") == 0
        rig.step()
    assert largest > 60.0
    rig.step()
    assert {22025, 22026} <= set(rig.alarm_numbers())


def test_feed_override_acts_on_a_running_spos_of_the_following_spindle() -> None:
    # DBX17.0 (L22017-22021): FA[S2]=3600 deg/min = 60 deg/s.  1 s into SPOS[2]=IC(360) the axis
    # override goes from 100 % to 50 %: the running motion slows to 30 deg/s; 17.0 reset gives 60 again
    rig = _coupling_rig()
    rig.set("SP2.spindle.out.useFeedrateOvr", 1)
    rig.mda('N10 SPOS=0 SPOS[2]=0\nN20 COUPDEF(S2,S1,1,1,"NOC","DV")\nN30 COUPON(S2,S1,0)\n'
            'N40 SPOS[2]=IC(360) FA[S2]=3600\nN50 G4 F1\n')
    couplings = rig.nck.couplings

    def spos_running() -> bool:
        coupling = couplings.active.get("SP2")
        return coupling is not None and coupling.overlay is not None and coupling.overlay.positioning

    rig.run_until(spos_running, 2000)
    rig.step(500)
    fs = rig.axis("SP2")
    assert fs.command_velocity == pytest.approx(60.0)
    rig.set("SP2.basic.out.feedrateOvrFactor", 50)
    rig.step(200)
    assert fs.command_velocity == pytest.approx(30.0) and rig.get("SP2.coupling.in.MotionOverlaid") == 1
    rig.set("SP2.spindle.out.useFeedrateOvr", 0)
    rig.step(200)
    assert fs.command_velocity == pytest.approx(60.0)


def test_coupling_correction_is_written_by_spindle_index(nck: Nck) -> None:
    # $AA_COUP_CORR[Sn] (L31543-31551) is indexed by the spindle number (MD35000) or the axis name
    plan, alarm = _decode(nck, "N10 $AA_COUP_CORR[S2]=0")
    assert alarm is None and plan.variables == [VariableWrite("$AA_COUP_CORR", "SP2", 0.0)]
    plan, alarm = _decode(nck, "N10 ID=1 WHEN $VA_SYNCDIFF[S2]<-1 DO $AA_COUP_CORR[SP2]=-3")
    assert alarm is None
    assert plan.sync_actions[0].actions == (VariableWrite("$AA_COUP_CORR", "SP2", -3.0),)
    _, alarm = _decode(nck, "N10 $AA_COUP_CORR[S7]=0")
    assert alarm is not None and alarm.number == 16105


def test_alarm_22040_is_checked_cyclically_while_a_coupled_spindle_is_not_synchronised() -> None:
    # L30398-30400: FS and LS in position control are checked cyclically.  COUPON of the unreferenced
    # pair raises 22040; cancelled, it returns while the spindles lack their zero marks; once both
    # have passed them (S1 at 100 rev/min, S2 coupled) the cancelled alarm stays away
    rig = _coupling_rig()
    rig.mda("N10 COUPON(S2,S1)\nN20 G4 F0.5\nN30 M3 S100\nN40 G4 F3\n")
    rig.run_until(lambda: "SP2" in rig.nck.couplings.active, 200)
    rig.step()
    assert 22040 in rig.alarm_numbers()
    rig.nck.acknowledge()
    rig.step()
    assert 22040 in rig.alarm_numbers() and not rig.axis("SP1").referenced
    rig.run_until(lambda: rig.axis("SP1").referenced and rig.axis("SP2").referenced, 1500)
    rig.nck.acknowledge()
    rig.step(10)
    assert 22040 not in rig.alarm_numbers() and "SP2" in rig.nck.couplings.active


@pytest.mark.parametrize(("variable", "alarms"), [("$P_COUP_OFFS", [12550]), ("$AA_COUP_OFFS", [])])
def test_a_synchronized_action_may_not_read_the_programmed_offset(variable: str, alarms: list[int]) -> None:
    # L22383-22385: $P_COUP_OFFS is for the part program only; a synchronized action that reads it
    # raises 12550 [control], one on $AA_COUP_OFFS runs
    rig = _coupling_rig()
    rig.mda(f"N10 SPOS=0 SPOS[2]=0\nN20 COUPON(S2,S1,90)\nN30 ID=1 WHENEVER {variable}[S2]>89 DO $AA_COUP_CORR[S2]=1\n"
            "N40 G4 F1\n")
    rig.step(500)
    assert rig.alarm_numbers() == alarms


def test_aa_sync_shows_the_synchronism_and_coup_corr_dist_what_the_correction_has_left() -> None:
    # $AA_SYNC (L29620-29632): 0 not synchronous, 1 coarse, 2 fine; $AA_COUP_CORR_DIST (L31626):
    # the distance the correction still has to travel
    rig = _coupling_rig()
    couplings = rig.nck.couplings
    assert couplings.read_variable("$AA_SYNC", "SP2") == 0.0
    rig.mda("N10 SPOS=0 SPOS[2]=0\nN20 COUPON(S2,S1)\nN30 M3 S600\nN40 G4 F30\n")
    rig.run_until(lambda: rig.get("SP2.coupling.in.syncFineReached") == 1, 3000)
    assert couplings.read_variable("$AA_SYNC", "SP2") == 2.0
    assert couplings.read_variable("$AA_COUP_CORR_DIST", "SP2") == 0.0
    couplings.write_correction("SP2", 4.0)
    rig.step(10)
    assert 0.0 < couplings.read_variable("$AA_COUP_CORR_DIST", "SP2") < 4.0
    rig.run_until(lambda: couplings.read_variable("$AA_COUP_CORR_DIST", "SP2") == 0.0, 3000)
    assert couplings.read_variable("$AA_COUP_CORR", "SP2") == pytest.approx(4.0)


@pytest.mark.parametrize(("feedforward_mode", "switched_on"), [(0, False), (1, True)])
def test_spcon_in_motion_is_refused_when_md32620_takes_the_pairs_feedforward(feedforward_mode: int,
                                                                             switched_on: bool) -> None:
    # L23001-23003: with MD32620 = 0 on LS or FS SPCON cannot switch position control on while the
    # spindle turns.  AV switches position control on the FS only, so the turning LS is still in
    # speed control when SPCON asks for it
    rig = _coupling_rig(f"SP1: {{MD32620: {feedforward_mode}}}")
    rig.mda('N10 SPOS[2]=0\nN20 COUPDEF(S2,S1,1,1,"NOC","AV")\nN30 COUPON(S2,S1)\nN40 M3 S600\n'
            "N50 G4 F0.5\nN60 SPCON\nN70 G4 F0.5\n")
    leading = next(spindle for spindle in rig.nck.spindles if spindle.name == "SP1")
    rig.run_until(lambda: rig.axis("SP1").velocity > 3599.99, 3000)
    assert not leading.position_control
    rig.run_until(lambda: rig.get("CHAN1.basic.in.stateReset") == 1, 3000)
    assert leading.position_control is switched_on
