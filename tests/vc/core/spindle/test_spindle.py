"""Spindles and gear stages (seed 003 chapter 13) in the NC core, the test acting as the PLC.

Turn-mill SP1 (spindle 1, master spindle of CHAN1): 3 gear stages, ratios 7.5:1 / 3:1 / 1.33:1
(MD31050/31060), a motor encoder (zero mark every 360 / 7.5 = 48 degrees of the spindle in
gear 1), MD35110 [800, 2000, 4500] / MD35120 [10, 700, 1800] M40 thresholds, MD35130 limits
[800, 2000, 4500], MD35140 [5, 10, 20], MD35200 [60, 40, 25] rev/s^2, MD35210 [30, 20, 15],
MD35100 chuck 4500, MD35400 oscillation 60 rev/min, MD35410 20 rev/s^2, MD35440 0.2 s (M3),
MD35450 0.15 s (M4),
MD35010 = 1 (change with oscillation).  SP2 spindle 2, a motor spindle without gears.
"""

from __future__ import annotations

import itertools
import struct

import pytest
from core_rig import ABSOLUTE_XYZ, Rig, machine, spindle_rig

from vc.config import md_dictionary as MD
from vc.core.spindle.spindle import Spindle, SpindleMode

IPO = 0.002


def sp1(rig: Rig) -> Spindle:
    return rig.nck.spindles[0]


def speed(rig: Rig, name: str = "SP1") -> float:
    return rig.sim.axis_quantity(name, "velocity")  # rev/min


def bit(rig: Rig, name: str) -> int:
    return int(rig.get(name))


def run_seconds(rig: Rig, seconds: float) -> None:
    rig.step(round(seconds / IPO))


def acknowledge(rig: Rig, gear: int) -> None:
    """The PLC reports the gear engaged and gear changed (16.0-16.2, 16.3), as at t3 (L19411-19422)."""
    rig.set("SP1.spindle.out.gearStageSelection", gear)
    rig.set("SP1.spindle.out.gearChangeoverDone", 1)
    rig.set("SP1.spindle.out.oscillEnable", 0)


# ------------------------------------------------------------------------------ control mode


def test_m3_ramps_to_the_set_speed_with_md35200_and_reports_speed_reached() -> None:
    rig = spindle_rig()
    rig.mda("M3 S500")
    rig.step(20)
    # MD35200[1] = 60 rev/s^2 = 3600 rev/min per second: 500 rev/min after 0.139 s
    run_seconds(rig, 0.05)
    assert 0 < speed(rig) < 500
    assert bit(rig, "SP1.spindle.in.speedSetpointReached") == 0
    run_seconds(rig, 0.2)
    assert speed(rig) == pytest.approx(500.0)
    assert bit(rig, "SP1.spindle.in.speedSetpointReached") == 1
    assert bit(rig, "SP1.spindle.in.cwRotActive") == 1 and bit(rig, "SP1.spindle.in.ctrlModeActive") == 1
    assert bit(rig, "SP1.basic.in.posCtrlActive") == 0  # speed control (L16163-16167)
    assert rig.get("SP1.spindle.in.mFuncNumber") == 3
    assert rig.get("SP1.spindle.in.sFuncValue") == pytest.approx(500.0)


def test_m4_turns_the_other_way_and_m5_stops_to_stationary() -> None:
    rig = spindle_rig()
    rig.mda("M4 S300")
    run_seconds(rig, 0.5)
    assert speed(rig) == pytest.approx(-300.0)
    assert bit(rig, "SP1.spindle.in.cwRotActive") == 0
    rig.mda("M5")
    run_seconds(rig, 0.5)
    assert speed(rig) == 0.0
    assert bit(rig, "SP1.basic.in.isStationary") == 1


def test_speed_limits_of_the_gear_clamp_and_raise_the_setpoint() -> None:
    rig = spindle_rig()
    rig.mda("M41 M3 S900")  # gear 1 (already engaged): MD35130[1] = 800
    run_seconds(rig, 0.5)
    assert speed(rig) == pytest.approx(800.0)
    assert bit(rig, "SP1.spindle.in.speedSetpointAboveMax") == 1
    rig.mda("S3")  # below MD35140[1] = 5: raised to 5
    run_seconds(rig, 0.5)
    assert speed(rig) == pytest.approx(5.0)
    assert bit(rig, "SP1.spindle.in.speedSetpointAboveMax") == 0
    assert bit(rig, "SP1.spindle.in.speedSetpointBelowMin") == 1


@pytest.mark.parametrize(("override", "expected"), [(50, 250.0), (120, 600.0), (0, 0.0)])
def test_the_spindle_override_scales_the_set_speed(override: int, expected: float) -> None:
    rig = spindle_rig()
    rig.set("SP1.spindle.out.ovrFactor", override)
    rig.mda("M3 S500")
    run_seconds(rig, 0.5)
    assert speed(rig) == pytest.approx(expected)


def test_the_axis_override_acts_on_the_spindle_with_dbx17_0() -> None:
    rig = spindle_rig()
    rig.set("SP1.basic.out.feedrateOvrFactor", 40)
    rig.set("SP1.spindle.out.useFeedrateOvr", 1)
    rig.mda("M3 S500")
    run_seconds(rig, 0.5)
    assert speed(rig) == pytest.approx(200.0)


def test_gray_coded_spindle_override_uses_md12070() -> None:
    rig = spindle_rig("NC: {MD12060: 1}")
    position = 10
    rig.set("SP1.spindle.out.ovrFactor", position ^ (position >> 1))
    rig.mda("M3 S500")
    run_seconds(rig, 0.5)
    factor = rig.nck.machine.nck.floats(MD.OVR_FACTOR_SPIND_SPEED)[position - 1]
    assert speed(rig) == pytest.approx(500.0 * factor)


def test_invert_m3_m4_reverses_the_direction() -> None:
    rig = spindle_rig()
    rig.set("SP1.spindle.out.invertM3M4", 1)
    rig.mda("M3 S400")
    run_seconds(rig, 0.5)
    assert speed(rig) == pytest.approx(-400.0)


def test_spindle_stop_brakes_and_the_spindle_turns_again_when_it_goes() -> None:
    rig = spindle_rig()
    rig.mda("M3 S500")
    run_seconds(rig, 0.5)
    rig.set("SP1.basic.out.feedStopSpindleStop", 1)
    run_seconds(rig, 0.5)
    assert speed(rig) == 0.0
    rig.set("SP1.basic.out.feedStopSpindleStop", 0)
    run_seconds(rig, 0.5)
    assert speed(rig) == pytest.approx(500.0)


def test_spindle_reset_stops_and_forgets_s() -> None:
    rig = spindle_rig()
    rig.mda("M3 S500")
    run_seconds(rig, 0.5)
    rig.pulse("SP1.basic.out.resetMovement", 5)
    run_seconds(rig, 0.5)
    assert speed(rig) == 0.0
    assert sp1(rig).speed == 0.0 and sp1(rig).direction == 0


@pytest.mark.parametrize(("after_reset", "turning"), [(0, False), (1, True)])
def test_md35040_decides_whether_a_reset_stops_the_spindle(after_reset: int, turning: bool) -> None:
    rig = spindle_rig(f"SP1: {{MD35040: {after_reset}}}")
    rig.mda("M3 S500")
    run_seconds(rig, 0.5)
    rig.pulse("CHAN1.basic.out.reset", 5)
    run_seconds(rig, 0.5)
    assert (speed(rig) == pytest.approx(500.0)) is turning
    assert (speed(rig) == 0.0) is not turning


def test_axis_mode_above_the_chuck_speed_raises_22100_and_83_0() -> None:
    # M70: the spindle is a rotary axis at up to MD32000 = 5000 rev/min; MD35100 = 1000 with
    # MD35150 = 0.1: 83.0 and alarm 22100 above 1100 rev/min (L20932-21020)
    rig = spindle_rig("SP1: {MD35100: 1000, MD32300: [100, 100, 100, 100, 100]}")
    rig.mda("M70\nG0 SP1=7200")
    rig.run_until(lambda: rig.alarm_numbers() == [22100], 2000)
    assert bit(rig, "SP1.spindle.in.speedLimitationExceeded") == 1
    assert abs(speed(rig)) > 1100


# ------------------------------------------------------------------------------ gear change


def test_m40_gear_change_follows_t1_to_t4_of_the_timing_diagram() -> None:
    # spec B.4.6: t1 82.3 with the set gear, t2 stationary, oscillation with 18.5, t3 the PLC's
    # 16.0-16.2 and 16.3, t4 82.3 and 84.6 off, 84.7 on, the spindle accelerates to S1300
    rig = spindle_rig()
    rig.mda("M3 S500\nS1300")  # MDA without M30: the spindle keeps turning after the program
    rig.run_until(lambda: bit(rig, "SP1.spindle.in.gearChangeoverRequested") == 1, 200)
    assert rig.get("SP1.spindle.in.requestedGearStageNumber") == 2
    assert bit(rig, "SP1.spindle.in.oscillModeActive") == 1 and bit(rig, "SP1.spindle.in.ctrlModeActive") == 0
    rig.run_until(lambda: bit(rig, "SP1.basic.in.isStationary") == 1, 500)
    rig.set("SP1.spindle.out.oscillEnable", 1)
    run_seconds(rig, 0.3)
    assert abs(speed(rig)) > 10  # oscillating (MD35400 = 60 rev/min, MD35410 = 20 rev/s^2)
    assert rig.channel.program_state.value == "running" and rig.channel.run.block_index == 1  # block held
    acknowledge(rig, 2)
    rig.step(2)
    assert bit(rig, "SP1.spindle.in.gearChangeoverRequested") == 0
    assert bit(rig, "SP1.spindle.in.ctrlModeActive") == 1 and bit(rig, "SP1.spindle.in.oscillModeActive") == 0
    assert rig.get("SP1.drive.in.posCtrlParameterSetNumber") == 2  # gear n -> parameter set index n
    rig.set("SP1.spindle.out.gearChangeoverDone", 0)
    run_seconds(rig, 1.0)
    assert speed(rig) == pytest.approx(1300.0)
    assert rig.alarm_numbers() == []


def test_the_nc_oscillates_in_alternating_directions_for_md35440_and_md35450() -> None:
    # MD35400 = 60 rev/min, MD35410 = 20 rev/s^2 (60 rev/min in 0.05 s), MD35440 = 0.2 s in M3,
    # MD35450 = 0.15 s in M4, MD35430 = 3: starts in M3
    rig = spindle_rig("SP1: {MD35400: 60, MD35410: 20, MD35440: 0.2, MD35450: 0.15, MD35430: 3}")
    rig.mda("M42")
    rig.run_until(lambda: bit(rig, "SP1.basic.in.isStationary") == 1, 200)
    rig.set("SP1.spindle.out.oscillEnable", 1)
    speeds = []
    for _ in range(700):  # 1.4 s = 4 pairs of 0.35 s
        rig.step(1)
        speeds.append(speed(rig))
    assert max(speeds) == pytest.approx(60.0) and min(speeds) == pytest.approx(-60.0)
    assert speeds[30] > 0  # M3 first
    reversals = [i for i, (a, b) in enumerate(itertools.pairwise(speeds)) if a > 0 >= b or a < 0 <= b]
    assert len(reversals) == 7  # the first after 0.2 s + half the 0.05 s ramp, then every 0.15 or 0.2 s
    # from M3 to M4 every 0.35 s: 0.2 s in M3, then 0.15 s in M4 (reversal half-way down the ramp)
    assert (reversals[2] - reversals[0]) * IPO == pytest.approx(0.35, abs=0.01)


def test_oscillation_by_the_plc_follows_18_6_and_18_7() -> None:
    rig = spindle_rig()
    rig.mda("M42")
    rig.run_until(lambda: bit(rig, "SP1.basic.in.isStationary") == 1, 200)
    rig.set("SP1.spindle.out.oscillRequest", 1)
    rig.set("SP1.spindle.out.oscillEnable", 1)
    rig.set("SP1.spindle.out.oscillSetDirCcw", 1)
    run_seconds(rig, 0.2)
    assert speed(rig) == pytest.approx(-60.0)  # MD35400 = 60 rev/min in the PLC's direction
    rig.set("SP1.spindle.out.oscillSetDirCcw", 0)
    rig.set("SP1.spindle.out.oscillSetDirCw", 1)
    run_seconds(rig, 0.2)
    assert speed(rig) == pytest.approx(60.0)


def test_a_wrong_gear_reported_raises_22010_and_takes_the_reported_gear() -> None:
    rig = spindle_rig()
    rig.mda("M43")
    rig.run_until(lambda: bit(rig, "SP1.spindle.in.gearChangeoverRequested") == 1, 200)
    acknowledge(rig, 2)  # the PLC engaged gear 2 instead of 3
    rig.step(2)
    assert rig.alarm_numbers() == [22010]
    assert sp1(rig).gear_change.gear == 2


def test_md11410_bit_3_suppresses_22010() -> None:
    rig = spindle_rig("NC: {MD11410: 8}")
    rig.mda("M43")
    rig.run_until(lambda: bit(rig, "SP1.spindle.in.gearChangeoverRequested") == 1, 200)
    acknowledge(rig, 2)
    rig.step(2)
    assert rig.alarm_numbers() == []


def test_no_acknowledgement_within_md10192_raises_the_alarm_and_a_reset_ends_the_change() -> None:
    rig = spindle_rig("NC: {MD10192: 1.0}")
    rig.mda("M42")
    rig.run_until(lambda: bit(rig, "SP1.spindle.in.gearChangeoverRequested") == 1, 200)
    run_seconds(rig, 0.9)
    assert rig.alarm_numbers() == []
    run_seconds(rig, 0.2)
    assert rig.alarm_numbers() == [65830]
    rig.set("SP1.spindle.out.gearStageSelection", 1)
    rig.pulse("CHAN1.basic.out.reset", 5)
    rig.step(5)
    assert bit(rig, "SP1.spindle.in.gearChangeoverRequested") == 0
    assert rig.alarm_numbers() == [] and sp1(rig).gear_change.gear == 1  # the reported gear, no alarm (L18694-18698)


def test_simulated_dialog_needs_no_plc() -> None:
    rig = spindle_rig("SP1: {MD35010: 9}")  # bit 0 + bit 3
    rig.mda("M3 S1300")
    seen_request = False
    for _ in range(600):
        rig.step(1)
        seen_request |= bool(bit(rig, "SP1.spindle.in.gearChangeoverRequested"))
    assert not seen_request
    assert sp1(rig).gear_change.gear == 2 and speed(rig) == pytest.approx(1300.0)


def test_gear_change_at_a_fixed_position_positions_waits_and_then_asks() -> None:
    # MD35010 = 2: to MD35012[1] = 120 with gear 1 (84.5), exact stop fine, MD35310[1] = 0.3 s,
    # then the dialog; the motor encoder keeps position control (L19537-19587)
    rig = spindle_rig("SP1: {MD35010: 2, MD35012: [0, 120, 0, 0], MD35310: [0, 0.3, 0, 0]}")
    rig.mda("M3 S1300")
    rig.run_until(lambda: bit(rig, "SP1.spindle.in.posModeActive") == 1, 50)
    rig.run_until(lambda: bit(rig, "SP1.basic.in.posFineReached") == 1, 3000)
    assert rig.sim.axis_quantity("SP1", "position") == pytest.approx(120.0, abs=0.01)
    assert bit(rig, "SP1.spindle.in.gearChangeoverRequested") == 0
    waited = rig.run_until(lambda: bit(rig, "SP1.spindle.in.gearChangeoverRequested") == 1, 400)
    assert waited * IPO == pytest.approx(0.3, abs=0.02)
    assert bit(rig, "SP1.basic.in.posCtrlActive") == 1
    acknowledge(rig, 2)
    rig.step(2)
    assert bit(rig, "SP1.basic.in.enc1Synchronized") == 0  # the motor encoder's reference is gone
    run_seconds(rig, 1.5)
    assert speed(rig) == pytest.approx(1300.0)
    # synchronised again at the next zero mark (L19480); 1300 rev/min in gear 2 is a motor speed of
    # 3900 rev/min, within the encoder's limit frequency
    assert bit(rig, "SP1.basic.in.enc1Synchronized") == 1


def test_the_nc_oscillates_at_the_gear_change_position_when_the_plc_enables_it() -> None:
    # not needed at the fixed position, "but in principle oscillation can still be enabled"
    # (L19593-19603): a gearbox whose teeth mesh only while the motor turns needs it
    rig = spindle_rig("SP1: {MD35010: 2, MD35012: [0, 120, 0, 0], MD35310: [0, 0.1, 0, 0]}")
    rig.mda("M42")
    rig.run_until(lambda: bit(rig, "SP1.spindle.in.gearChangeoverRequested") == 1, 3000)
    run_seconds(rig, 0.1)
    assert speed(rig) == 0.0 and bit(rig, "SP1.basic.in.posCtrlActive") == 1  # stands without 18.5
    rig.set("SP1.spindle.out.oscillEnable", 1)
    run_seconds(rig, 0.3)
    assert abs(speed(rig)) > 10  # MD35400 = 60 rev/min
    assert bit(rig, "SP1.basic.in.posCtrlActive") == 1  # the motor encoder keeps position control
    acknowledge(rig, 2)
    rig.step(2)
    assert bit(rig, "SP1.spindle.in.ctrlModeActive") == 1 and rig.alarm_numbers() == []


def test_in_position_is_not_reported_at_the_gear_change_position() -> None:
    # 85.5 belongs to the function "spindle positioning" (SPOS, SPOSA, M19, FC18, DBX30.4) only
    # (L17059-17068), not to the approach to MD35012
    rig = spindle_rig("SP1: {MD35010: 2, MD35012: [0, 120, 0, 0], MD35310: [0, 0.3, 0, 0]}")
    rig.mda("M42")
    rig.run_until(lambda: bit(rig, "SP1.basic.in.posFineReached") == 1
                  and bit(rig, "SP1.spindle.in.posModeActive") == 1, 3000)
    for _ in range(100):
        rig.step(1)
        assert bit(rig, "SP1.spindle.in.inPos") == 0


def test_the_encoder_limit_frequency_follows_the_gear_ratio_of_the_motor_encoder() -> None:
    # MD36300 = 300 kHz, MD31020 = 2048 lines: the motor encoder turns once per 48 degrees of the
    # spindle in gear 1 (7.5:1), once per 120 degrees in gear 2 (3:1) (§13.8.7, L21117-21203)
    rig = spindle_rig()
    encoder = rig.axis("SP1").encoder
    assert encoder.limit_velocity == pytest.approx(300000 * 48 / 2048)  # 7031 deg/s = 1172 rev/min
    rig.mda("M42")
    rig.run_until(lambda: bit(rig, "SP1.spindle.in.gearChangeoverRequested") == 1, 200)
    acknowledge(rig, 2)
    rig.step(2)
    rig.set("SP1.spindle.out.gearChangeoverDone", 0)
    assert encoder.limit_velocity == pytest.approx(300000 * 120 / 2048)  # 17578 deg/s = 2930 rev/min
    rig.run_until(lambda: bit(rig, "CHAN1.basic.in.stateReset") == 1, 20)  # M42 acknowledged by the PLC
    rig.mda("M3 S1300")
    run_seconds(rig, 1.0)
    assert speed(rig) == pytest.approx(1300.0)
    assert bit(rig, "SP1.basic.in.enc1FreqLimitExceeded") == 0 and bit(rig, "SP1.basic.in.enc1Synchronized") == 1


def test_a_gear_change_position_not_reached_raises_22020_without_a_dialog() -> None:
    rig = spindle_rig("SP1: {MD35010: 2, MD35012: [0, 120, 0, 0]}")
    rig.mda("M3 S1300")
    rig.run_until(lambda: bit(rig, "SP1.spindle.in.posModeActive") == 1, 50)
    rig.set("SP1.basic.out.enableCtrl", 0)  # the spindle cannot position
    rig.run_until(lambda: 22020 in rig.alarm_numbers(), 500)
    run_seconds(rig, 0.2)
    assert bit(rig, "SP1.spindle.in.gearChangeoverRequested") == 0


def test_m40_without_control_mode_raises_22000() -> None:
    rig = spindle_rig()
    rig.mda("SPOS=90\nM40 S1500")
    rig.run_until(lambda: rig.alarm_numbers() != [], 3000)
    assert rig.alarm_numbers() == [22000]


def test_the_plc_sets_the_gear_in_reset_state() -> None:
    rig = spindle_rig()
    rig.set("SP1.spindle.out.gearStageSelection", 3)
    rig.step(20)
    assert sp1(rig).gear_change.gear == 3
    assert rig.get("SP1.spindle.in.requestedGearStageNumber") == 3  # acknowledged (L18610-18616)
    assert rig.get("SP1.drive.in.posCtrlParameterSetNumber") == 3


def test_gear_0_means_the_next_change_always_talks_to_the_plc() -> None:
    rig = spindle_rig()
    rig.set("SP1.spindle.out.gearStageSelection", 2)
    rig.step(20)
    rig.set("SP1.spindle.out.gearStageSelection", 0)  # the gearbox is disengaged
    rig.step(20)
    assert sp1(rig).gear_change.gear == 0
    rig.mda("M41")
    rig.run_until(lambda: bit(rig, "SP1.spindle.in.gearChangeoverRequested") == 1, 100)
    assert rig.get("SP1.spindle.in.requestedGearStageNumber") == 1


def test_stage_0_reported_at_program_start_makes_the_next_change_talk_to_the_plc() -> None:
    # the NC reads the actual stage at program start; 0 (disengaged): the next change runs the
    # dialog, also for the stage the NC had active (L18758-18766, example L18808-18843)
    rig = Rig(machine(ABSOLUTE_XYZ))
    rig.ready_mda()
    rig.set("SP1.spindle.out.ovrFactor", 100)
    rig.step(20)  # the PLC reports 0 in 16.0-16.2 from power-on: the gearbox is disengaged
    assert sp1(rig).gear_change.gear == 1  # the NC's stage after power-on; 0 never changed, so not taken over
    rig.mda("M41")
    rig.run_until(lambda: bit(rig, "SP1.spindle.in.gearChangeoverRequested") == 1, 100)
    assert rig.get("SP1.spindle.in.requestedGearStageNumber") == 1
    acknowledge(rig, 1)
    rig.step(2)
    rig.set("SP1.spindle.out.gearChangeoverDone", 0)
    rig.run_until(lambda: rig.channel.state.value == "reset", 100)
    rig.mda("M41")  # the PLC reports 1 now: no change
    for _ in range(50):
        rig.step(1)
        assert bit(rig, "SP1.spindle.in.gearChangeoverRequested") == 0


def test_dry_run_with_md35035_bit_0_suppresses_the_change() -> None:
    rig = spindle_rig("SP1: {MD35035: 1}")
    rig.set("CHAN1.basic.out.dryRunFeedrate", 1)
    rig.mda("M3 S1300")
    for _ in range(300):
        rig.step(1)
        assert bit(rig, "SP1.spindle.in.gearChangeoverRequested") == 0
    assert sp1(rig).gear_change.gear == 1 and speed(rig) == pytest.approx(800.0)  # clamped to gear 1
    # ... and the signal of that limitation is suppressed too (L19996-20001)
    assert bit(rig, "SP1.spindle.in.speedSetpointAboveMax") == 0


def test_a_later_block_in_dry_run_replaces_the_stage_to_catch_up() -> None:
    # MD35035 bit 2 catches up the last programmed stage: S1300 wanted gear 2, then S600 fits
    # gear 1 again, so nothing is left to change when dry run ends (L20012-20015, L20031-20032)
    rig = spindle_rig("SP1: {MD35035: 5}")
    rig.set("CHAN1.basic.out.dryRunFeedrate", 1)
    rig.mda("M3 S1300\nG4 F0.1\nS600\nG4 F0.3\nG4 F0.3")
    run_seconds(rig, 0.25)
    assert sp1(rig).suppressed_gear is None
    rig.set("CHAN1.basic.out.dryRunFeedrate", 0)
    for _ in range(400):
        rig.step(1)
        assert bit(rig, "SP1.spindle.in.gearChangeoverRequested") == 0
    assert sp1(rig).gear_change.gear == 1


def test_without_md35035_bit_2_the_active_stage_stays_after_dry_run() -> None:
    rig = spindle_rig("SP1: {MD35035: 1}")
    rig.set("CHAN1.basic.out.dryRunFeedrate", 1)
    rig.mda("M3 S1300\nG4 F0.2\nG4 F0.3")
    run_seconds(rig, 0.1)
    assert sp1(rig).suppressed_gear == 2  # programmed, never output
    rig.set("CHAN1.basic.out.dryRunFeedrate", 0)
    for _ in range(300):
        rig.step(1)
        assert bit(rig, "SP1.spindle.in.gearChangeoverRequested") == 0
    assert sp1(rig).gear_change.gear == 1 and sp1(rig).suppressed_gear is None


def test_a_spindle_without_gears_ignores_m40_and_m41() -> None:
    rig = spindle_rig()
    rig.mda("M2=41 S2=3000 M2=3")
    run_seconds(rig, 2.0)  # MD35200 default 30 rev/s^2: 3000 rev/min after 1.67 s
    assert speed(rig, "SP2") == pytest.approx(3000.0)
    assert rig.get("SP2.spindle.in.gearChangeoverRequested") == 0


# ------------------------------------------------------------------------------ positioning


def test_spos_from_standstill_synchronises_on_a_zero_mark_and_lands_on_the_target() -> None:
    rig = spindle_rig()
    assert bit(rig, "SP1.basic.in.enc1Synchronized") == 0
    rig.mda("SPOS=90\nM30")
    rig.run_until(lambda: bit(rig, "SP1.basic.in.enc1Synchronized") == 1, 1000)
    rig.run_until(lambda: bit(rig, "SP1.spindle.in.inPos") == 1, 3000)
    assert rig.sim.axis_quantity("SP1", "position") == pytest.approx(90.0, abs=0.01)
    assert bit(rig, "SP1.spindle.in.posModeActive") == 1 and bit(rig, "SP1.basic.in.posCtrlActive") == 1


@pytest.mark.parametrize(("program", "direction"), [("SPOS=ACP(10)", 1), ("SPOS=ACN(10)", -1)])
def test_acp_and_acn_approach_from_their_side(program: str, direction: int) -> None:
    rig = spindle_rig()
    rig.mda("SPOS=180")
    rig.run_until(lambda: bit(rig, "SP1.spindle.in.inPos") == 1, 3000)
    rig.mda(program)
    rig.step(30)
    assert speed(rig) * direction > 0
    rig.run_until(lambda: bit(rig, "SP1.spindle.in.inPos") == 1, 3000)
    assert rig.axis("SP1").setpoint % 360 == pytest.approx(10.0, abs=1e-6)  # the setpoint exactly,
    assert rig.sim.axis_quantity("SP1", "position") == pytest.approx(10.0, abs=0.01)  # the actual within MD36010


def test_spos_from_rotation_keeps_the_direction_and_the_block_waits() -> None:
    rig = spindle_rig()
    rig.mda("M4 S600\nG4 F0.5\nSPOS=45\nG91 G1 X1 F600")
    run_seconds(rig, 0.7)
    assert speed(rig) < 0
    while not bit(rig, "SP1.basic.in.posCoarseReached"):
        assert speed(rig) <= 0.0  # never reverses (L16745-16759)
        assert rig.axis("X1").velocity == 0.0  # the next block waits for the spindle (60.6, L21255-21263)
        rig.step(1)
    rig.run_until(lambda: bit(rig, "SP1.spindle.in.inPos") == 1, 500)
    assert rig.sim.axis_quantity("SP1", "position") == pytest.approx(45.0, abs=0.01)


def test_acn_against_the_rotation_brakes_along_the_ramp_before_it_reverses() -> None:
    # ACN / ACP approach from their side, "reversing the motion before positioning if necessary"
    # (L18000-18004): from M3 S300 the spindle brakes with MD35200[1] = 3600 rev/min/s, no step
    rig = spindle_rig()
    rig.mda("M3 S300\nG4 F0.5\nSPOS=ACN(200)")
    rig.run_until(lambda: bit(rig, "SP1.spindle.in.posModeActive") == 1, 1000)
    before = speed(rig)
    assert before > 290
    largest_step = 0.0
    while not bit(rig, "SP1.spindle.in.inPos"):
        rig.step(1)
        now = speed(rig)
        largest_step = max(largest_step, abs(now - before))
        before = now
    assert largest_step <= 3600 * IPO + 1e-6  # 7.2 rev/min per IPO cycle at most
    assert rig.sim.axis_quantity("SP1", "position") == pytest.approx(200.0, abs=0.01)


def test_sposa_does_not_hold_the_block() -> None:
    rig = spindle_rig()
    rig.mda("SPOSA=270\nG91 G1 X5 F3000")
    rig.step(40)
    assert rig.axis("X1").velocity > 0 and abs(speed(rig)) > 0  # both move at once


def test_in_position_goes_when_the_spindle_moves_away() -> None:
    rig = spindle_rig()
    rig.mda("SPOS=30")
    rig.run_until(lambda: bit(rig, "SP1.spindle.in.inPos") == 1, 3000)
    rig.mda("M3 S50")
    rig.step(30)
    assert bit(rig, "SP1.spindle.in.inPos") == 0 and bit(rig, "SP1.spindle.in.posModeActive") == 0


# ------------------------------------------------------------------------------ axis mode


def test_m70_makes_the_spindle_a_rotary_axis_with_parameter_set_0() -> None:
    rig = spindle_rig()
    rig.mda("SPOS=0\nM70\nG91 G1 SP1=90 F3600")
    rig.run_until(lambda: bit(rig, "SP1.basic.in.spindleModeActive") == 0, 4000)
    assert rig.get("SP1.drive.in.posCtrlParameterSetNumber") == 0
    rig.run_until(lambda: rig.channel.state.value == "reset", 4000)
    assert rig.sim.axis_quantity("SP1", "position") == pytest.approx(90.0, abs=1e-3)
    rig.mda("M3 S100")
    rig.step(20)
    assert bit(rig, "SP1.basic.in.spindleModeActive") == 1 and bit(rig, "SP1.spindle.in.ctrlModeActive") == 1
    assert rig.get("SP1.drive.in.posCtrlParameterSetNumber") == 1


def test_m70_from_rotation_brakes_like_m5_then_switches_to_position_control() -> None:
    # control -> axis: "the rotating spindle brakes like M5", then position control and parameter
    # set 0 (L16083-16086, L17425-17433); the axis move of the next block follows
    rig = spindle_rig()
    rig.mda("M3 S300\nG4 F0.3\nM70\nG91 G1 SP1=90 F7200")
    rig.run_until(lambda: bit(rig, "SP1.basic.in.spindleModeActive") == 0, 1000)
    before = speed(rig)
    assert before > 290
    while rig.axis("SP1").owner.value == "spindle":
        assert rig.get("SP1.drive.in.posCtrlParameterSetNumber") == 1  # still the gear's set
        assert bit(rig, "SP1.basic.in.posCtrlActive") == 0
        rig.step(1)
        assert before - speed(rig) <= 3600 * IPO + 1e-6  # MD35200[1] = 3600 rev/min/s, no step
        before = speed(rig)
    rig.step(2)
    assert rig.get("SP1.drive.in.posCtrlParameterSetNumber") == 0
    assert bit(rig, "SP1.basic.in.posCtrlActive") == 1
    start = rig.axis("SP1").setpoint  # where the spindle was brought to a stop
    rig.run_until(lambda: rig.channel.state.value == "reset", 2000)
    assert rig.axis("SP1").setpoint - start == pytest.approx(90.0, abs=0.01)  # G91 SP1=90


# ------------------------------------------------------------------------------ interface and program


def test_address_extensions_reach_spindle_2() -> None:
    rig = spindle_rig()
    rig.mda("S2=1200 M2=4")
    run_seconds(rig, 1.0)
    assert speed(rig, "SP2") == pytest.approx(-1200.0) and speed(rig) == 0.0
    assert rig.get("SP2.spindle.in.mFuncNumber") == 4
    assert struct.unpack(">f", bytes(rig.nck.image.area("DB35")[88:92]))[0] == pytest.approx(1200.0)


def test_a_spindle_that_does_not_exist_raises_16105() -> None:
    rig = spindle_rig()
    rig.mda("S9=100")
    rig.step(10)
    assert rig.alarm_numbers() == [16105]


def test_a_machining_block_waits_until_the_spindle_is_at_speed() -> None:
    # MD35500 = 1: the path starts only with 83.5 (L16517-16540)
    rig = spindle_rig()
    rig.mda("M3 S800\nG91 G1 X1 F600")
    while not bit(rig, "SP1.spindle.in.speedSetpointReached"):
        assert rig.axis("X1").velocity == 0.0
        rig.step(1)
    rig.step(20)
    assert rig.axis("X1").velocity > 0


def test_a_gear_change_drops_the_reference_of_the_motor_encoder_and_changes_its_zero_marks() -> None:
    rig = spindle_rig()
    rig.mda("SPOS=0")
    rig.run_until(lambda: bit(rig, "SP1.spindle.in.inPos") == 1, 3000)
    encoder = rig.axis("SP1").encoder
    assert encoder.spacing == pytest.approx(48.0)  # 360 x 2 / 15
    rig.mda("M42")
    rig.run_until(lambda: bit(rig, "SP1.spindle.in.gearChangeoverRequested") == 1, 200)
    acknowledge(rig, 2)
    rig.step(2)
    assert bit(rig, "SP1.basic.in.enc1Synchronized") == 0
    assert encoder.spacing == pytest.approx(120.0)  # 360 x 1 / 3
    assert sp1(rig).mode is SpindleMode.CONTROL


@pytest.mark.parametrize(("extra", "loses"), [
    ("SP1: {MD30240: [4], MD34210: [2]}", True),  # gear 1 (2:15) to gear 2 (1:3): a new ratio
    ("SP1: {MD30240: [4], MD34210: [2], MD31050: [2, 2, 2, 1], MD31060: [15, 15, 15, 4]}", False),  # same ratio
    ("SP1: {MD30240: [4], MD34210: [2], MD31040: [1]}", False),  # the encoder on the spindle: no gear between
])
def test_a_new_ratio_between_load_and_absolute_motor_encoder_takes_its_calibration(extra: str, loses: bool) -> None:
    """Seed 003 L1992-1996, L2025-2040: MD34210 := 0 and alarm 25022 'warning 0'."""
    rig = spindle_rig(extra)
    assert bit(rig, "SP1.basic.in.enc1Synchronized") == 1  # calibrated: referenced at power-on
    rig.mda("M42")
    rig.run_until(lambda: bit(rig, "SP1.spindle.in.gearChangeoverRequested") == 1, 200)
    acknowledge(rig, 2)
    rig.step(2)
    state = rig.sim.machine_datum("SP1", MD.ENC_REFP_STATE.number, 0)
    assert (state, bit(rig, "SP1.basic.in.enc1Synchronized")) == ((0, 0) if loses else (2, 1))
    assert rig.alarm_numbers() == ([25022] if loses else [])
    if loses:
        assert str(rig.nck.alarms.present[0]) == "25022 Axis SP1 encoder 1 warning 0"


def test_resync_drops_the_synchronisation_until_the_next_zero_mark() -> None:
    rig = spindle_rig()
    rig.mda("M3 S60")  # 60 rev/min = 360 deg/s: a zero mark every 48 degrees, 0.13 s
    rig.run_until(lambda: bit(rig, "SP1.basic.in.enc1Synchronized") == 1, 500)
    rig.set("SP1.spindle.out.resyncEnc1", 1)
    rig.step(1)
    assert bit(rig, "SP1.basic.in.enc1Synchronized") == 0
    rig.run_until(lambda: bit(rig, "SP1.basic.in.enc1Synchronized") == 1, 100)


def test_the_simple_spindle_interface_starts_and_stops_with_the_last_s() -> None:
    rig = spindle_rig()
    rig.mda("M3 S400\nM5")
    run_seconds(rig, 0.5)
    assert speed(rig) == 0.0
    rig.pulse("SP1.spindle.out.startCcw", 5)  # DB31.DBX30.2
    run_seconds(rig, 0.5)
    assert speed(rig) == pytest.approx(-400.0)
    rig.pulse("SP1.spindle.out.stop", 5)  # DB31.DBX30.0
    run_seconds(rig, 0.5)
    assert speed(rig) == 0.0


def test_nc_stop_axes_and_spindles_holds_the_spindle_until_nc_start() -> None:
    rig = spindle_rig()
    rig.mda("M3 S500\nG4 F2")
    run_seconds(rig, 0.5)
    rig.pulse("CHAN1.basic.out.ncStopAxesAndSpindles", 5)
    run_seconds(rig, 0.5)
    assert speed(rig) == 0.0
    rig.pulse("CHAN1.basic.out.ncStart", 5)
    run_seconds(rig, 0.5)
    assert speed(rig) == pytest.approx(500.0)


def test_md35510_a_machining_block_waits_for_the_spindle_to_stand_after_m5() -> None:
    rig = spindle_rig("SP1: {MD35510: 1}")
    rig.mda("M3 S800")
    run_seconds(rig, 0.5)
    rig.mda("M5\nG91 G1 X1 F600")
    while not bit(rig, "SP1.basic.in.isStationary"):
        assert rig.axis("X1").velocity == 0.0
        rig.step(1)
    rig.step(20)
    assert rig.axis("X1").velocity > 0


def test_position_control_keeps_10_percent_reserve_and_md35135_limits_further() -> None:
    # MD35020 = 1: speed control with position control; S800 in gear 1 (MD35130[1] = 800) runs at
    # 720 rev/min with 83.1 set (L16747-16750); MD35135[1] = 600 limits it further (L18226-18228)
    rig = spindle_rig("SP1: {MD35020: 1}")
    rig.mda("M3 S800")
    run_seconds(rig, 0.5)
    assert speed(rig) == pytest.approx(720.0)
    assert bit(rig, "SP1.spindle.in.speedSetpointAboveMax") == 1
    assert bit(rig, "SP1.basic.in.posCtrlActive") == 1
    rig = spindle_rig("SP1: {MD35020: 1, MD35135: [0, 600, 0, 0]}")
    rig.mda("M3 S800")
    run_seconds(rig, 0.5)
    assert speed(rig) == pytest.approx(600.0)
    rig = spindle_rig()  # without position control the whole range
    rig.mda("M3 S800")
    run_seconds(rig, 0.5)
    assert speed(rig) == pytest.approx(800.0) and bit(rig, "SP1.spindle.in.speedSetpointAboveMax") == 0


def test_spos_without_a_zero_mark_within_md34060_raises_20002() -> None:
    rig = spindle_rig("SP1: {MD34060: 30}")  # gear 1: a zero mark every 48 degrees
    rig.axis("SP1").encoder.zero_marks_visible = False  # a dirty encoder track
    rig.mda("SPOS=90")
    rig.run_until(lambda: rig.alarm_numbers() == [20002], 2000)
    run_seconds(rig, 0.5)
    assert speed(rig) == 0.0 and sp1(rig).mode is SpindleMode.CONTROL


def test_md20850_outputs_m19_for_spos() -> None:
    rig = Rig(machine(ABSOLUTE_XYZ.replace("CHAN1: {MD20700: 0}", "CHAN1: {MD20700: 0, MD20850: 1}")))
    rig.ready_mda()
    rig.mda("SPOSA=45")
    rig.step(10)
    assert rig.get("SP1.spindle.in.mFuncNumber") == 19


def test_a_reset_during_a_change_takes_the_reported_stage_even_0() -> None:
    rig = spindle_rig()
    rig.mda("M42")
    rig.run_until(lambda: bit(rig, "SP1.spindle.in.gearChangeoverRequested") == 1, 200)
    rig.set("SP1.spindle.out.gearStageSelection", 0)  # the gearbox is in neutral
    rig.pulse("CHAN1.basic.out.reset", 5)
    rig.step(5)
    assert sp1(rig).gear_change.gear == 0 and rig.alarm_numbers() == []
