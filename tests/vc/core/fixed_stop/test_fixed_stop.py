"""Travel to fixed stop (vc/core/fixed_stop/): FXS / FXST / FXSW, the PLC handshake DB31.DBX3.1 /
1.1 / 1.2 / 62.4 / 62.5 and the alarms of seed 003 chapter 17.  The lathe with the tailstock quill
W1 (MD37060 = 3, MD37030 = 1 mm, MD37010 = 20 %); the part's face at 120 mm, 50 kN/mm, 10 kN at
full torque; the test is the PLC."""

from __future__ import annotations

from pathlib import Path

import pytest
from core_rig import Rig, machine, with_start_position

from vc.core.fixed_stop.fixed_stop import State

LATHE = str(Path(__file__).resolve().parents[4] / "scenarios" / "fixed_stop" / "machines" / "lathe_tailstock.yaml")
APPROACH = "N10 G1 G90 F600 W130 FXS[W]=1\nN20 FXS[W]=0\nN30 M30"
HOLD = "N10 G1 G90 F600 W130 FXS[W]=1\nN20 M0\nN30 M30"  # the quill stays clamped at M0
CLAMP = 120.0 + 0.2 * 10000.0 / 50000.0  # the face plus 20 % of 10 kN over 50 kN/mm


def _rig(quill: str = "") -> Rig:
    """The quill at 110 mm with an absolute encoder (its actual value is the physical position) and
    the machine data ``quill`` ("MD37060: 0, ...")."""
    overrides = f"CHAN1: {{MD20700: 0}}\nW1: {{MD30240: [4], MD34210: [2]{', ' + quill if quill else ''}}}"
    rig = Rig(with_start_position(machine(overrides, LATHE), "W1", 110.0))
    rig.ready_mda()
    return rig


def _state(rig: Rig) -> State:
    return rig.nck.fixed_stops[0].state


def _clamped(rig: Rig) -> None:
    rig.mda(HOLD)
    rig.set("W1.basic.out.fixedStopEnable", 1)
    rig.run_until(lambda: rig.get("W1.basic.in.fixedStopReached") == 1, 2000)
    rig.set("W1.basic.out.fixedStopAckReached", 1)
    rig.run_until(lambda: _state(rig) is State.CLAMPED, 10)


@pytest.mark.parametrize(("words", "alarm"), [("FXS[W]=2", 12080), ("FXST[W]=900", 12080), ("FXSW[W]=-1", 12080),
                                               ("FXS[Q]=1", 12550), ("FXS[X]=1", 20090)])
def test_a_wrong_word_or_an_axis_without_md37000_is_refused(words: str, alarm: int) -> None:
    rig = _rig()
    rig.mda(f"N10 G1 F600 W130 {words}\nN20 M30")
    rig.step(5)
    assert alarm in rig.alarm_numbers()
    assert rig.get("W1.basic.in.fixedStopRequest") == 0 and rig.axis("W1").command_velocity == 0.0


def test_the_motion_waits_for_the_plcs_enable_with_md37060_bit_0() -> None:
    rig = _rig()
    rig.mda(APPROACH)
    rig.step(100)
    w1 = rig.axis("W1")
    assert rig.get("W1.basic.in.fixedStopRequest") == 1 and _state(rig) is State.WAIT_ENABLE
    assert w1.actual == pytest.approx(110.0) and w1.torque_limit == 20.0  # limited from the selection on
    rig.set("W1.basic.out.fixedStopEnable", 1)
    rig.step(20)
    assert _state(rig) is State.APPROACH and w1.actual > 110.0


def test_the_stop_is_found_by_the_following_error_and_the_block_waits_for_the_acknowledgement() -> None:
    rig = _rig()
    rig.mda(APPROACH)
    rig.set("W1.basic.out.fixedStopEnable", 1)
    w1 = rig.axis("W1")
    rig.run_until(lambda: rig.get("W1.basic.in.fixedStopReached") == 1, 2000)
    assert abs(w1.following_error) > 1.0 and w1.physical == pytest.approx(CLAMP)
    assert _state(rig) is State.DETECTED
    rig.step(100)  # without DBX1.1 the block does not change
    assert rig.channel.run.block_index == 0 and w1.physical == pytest.approx(CLAMP)
    assert w1.setpoint == pytest.approx(w1.actual + 1.0, abs=1e-6)  # MD37030 beyond: the drive keeps pushing
    rig.set("W1.basic.out.fixedStopAckReached", 1)
    rig.step(3)
    assert _state(rig) is State.DESELECTING  # N20 FXS[W]=0 follows at once
    assert rig.get("W1.basic.in.fixedStopRequest") == 0 and rig.get("W1.basic.in.fixedStopReached") == 0
    rig.step(50)
    assert _state(rig) is State.DESELECTING and w1.torque_limit == 20.0  # the PLC still acknowledges
    rig.set("W1.basic.out.fixedStopEnable", 0)
    rig.set("W1.basic.out.fixedStopAckReached", 0)
    rig.step(3)
    assert _state(rig) is State.OFF and w1.torque_limit is None and w1.setpoint == pytest.approx(w1.actual)


def test_without_md37060_nothing_waits_and_the_sensor_variant_needs_no_following_error() -> None:
    rig = _rig("MD37060: 0, MD37040: 1, MD37030: 5.0")
    rig.mda(HOLD)
    w1 = rig.axis("W1")
    rig.run_until(lambda: w1.physical >= 120.0, 2000)  # no enable needed
    rig.step(20)
    assert _state(rig) is State.APPROACH and abs(w1.following_error) < 5.0  # no sensor yet
    rig.set("W1.basic.out.fixedStopSensor", 1)
    rig.step(2)
    assert _state(rig) is State.CLAMPED and rig.get("W1.basic.in.fixedStopReached") == 1  # no acknowledgement
    rig.step(5)
    assert rig.channel.run.block_index >= 1  # the block changed


def test_at_the_stop_the_controller_enable_and_the_axis_disable_do_not_act() -> None:
    rig = _rig()
    _clamped(rig)
    w1 = rig.axis("W1")
    rig.set("W1.basic.out.enableCtrl", 0)
    rig.set("W1.basic.out.disable", 1)
    rig.step(100)
    assert w1.servo_on and w1.physical == pytest.approx(CLAMP) and not rig.alarm_numbers()


def test_leaving_the_window_raises_20093_and_ends_the_function() -> None:
    rig = _rig("MD37060: 0")
    rig.mda("N10 G1 G90 F600 W130 FXS[W]=1 FXSW[W]=0.5\nN20 M0\nN30 M30")
    rig.run_until(lambda: rig.get("W1.basic.in.fixedStopReached") == 1, 2000)
    rig.sim.inject_fault("", "stop_lost")
    rig.run_until(lambda: 20093 in rig.alarm_numbers(), 100)
    assert _state(rig) in (State.FAILED, State.OFF) and rig.axis("W1").torque_limit is None
    assert rig.get("W1.basic.in.fixedStopRequest") == 0


@pytest.mark.parametrize(("control", "alarm"), [(0, True), (1, False)])
def test_pulses_taken_away_at_the_stop_abort_or_interrupt_by_md37002(control: int, alarm: bool) -> None:
    rig = _rig(f"MD37002: {control}")
    _clamped(rig)
    rig.set("W1.drive.out.enablePulses", 0)
    rig.step(20)
    assert (20094 in rig.alarm_numbers()) is alarm
    assert (_state(rig) is State.CLAMPED) is not alarm
    if not alarm:
        assert rig.axis("W1").physical == pytest.approx(120.0)  # nothing pushes: the part springs back
        rig.set("W1.drive.out.enablePulses", 1)
        rig.step(20)
        assert rig.axis("W1").physical == pytest.approx(CLAMP)  # the torque is back at once (bit 1 = 0)


def test_fxst_changes_the_torque_on_the_ramp_md37012() -> None:
    rig = _rig("MD37012: 0.1")
    _clamped(rig)
    rig.pulse("CHAN1.basic.out.reset", 2)  # the clamp outlasts the reset
    rig.step(2)
    rig.mda("N10 FXST[W]=40\nN20 M30")
    w1 = rig.axis("W1")
    rig.step(25)  # 0.05 s into the ramp of 0.1 s
    assert 25.0 < (w1.torque_limit or 0.0) < 35.0
    rig.step(40)
    assert w1.torque_limit == 40.0 and w1.physical == pytest.approx(120.0 + 0.4 * 10000.0 / 50000.0)


def test_a_reset_aborts_the_approach_but_keeps_the_clamp() -> None:
    rig = _rig()
    rig.mda(APPROACH)
    rig.set("W1.basic.out.fixedStopEnable", 1)
    rig.run_until(lambda: rig.axis("W1").actual > 115.0, 2000)
    rig.pulse("CHAN1.basic.out.reset", 2)
    rig.step(2)
    assert _state(rig) is State.FAILED and rig.nck.fixed_stops[0].info == 3 and not rig.alarm_numbers()
    rig.set("W1.basic.out.fixedStopEnable", 0)
    rig.step(2)
    assert _state(rig) is State.OFF
    rig.run_until(lambda: rig.get("CHAN1.basic.in.stateReset") == 1, 10)
    _clamped(rig)
    rig.pulse("CHAN1.basic.out.reset", 2)
    rig.step(5)
    assert _state(rig) is State.CLAMPED and rig.get("W1.basic.in.fixedStopReached") == 1


@pytest.mark.parametrize(("part", "end"), [(True, 0.0), (False, 50.0)])
def test_a_program_reads_the_state_in_aa_fxs_and_branches_on_it(part: bool, end: float) -> None:
    """The seed's example (L37917-37941) without alarms (MD37050 = 0): the program asks $AA_FXS."""
    rig = _rig("MD37060: 0, MD37050: 0")
    if not part:
        rig.sim.inject_fault("", "no_part")
    rig.mda("N10 G1 G90 F600 W130 FXS[W]=1 FXST[W]=25 FXSW[W]=5\nN20 IF $AA_FXS[W]==2 GOTOF FXS_ERROR\n"
            "N30 FXS[W]=0\nN40 G0 W0\nN50 M30\nFXS_ERROR: IF $VA_FXS_INFO[W]==2 GOTOF LABEL_2\nN60 M30\n"
            "LABEL_2: G0 W50\nN70 M30")
    rig.run_until(lambda: rig.get("CHAN1.basic.in.stateReset") == 1 and rig.axis("W1").at_rest, 5000, 10)
    assert rig.axis("W1").actual == pytest.approx(end, abs=0.01) and not rig.alarm_numbers()


def test_fxst_in_the_selecting_block_acts_from_its_start_without_a_ramp() -> None:
    """Selected with FXST in its block, the torque is that value at once, also with MD37012."""
    rig = _rig("MD37012: 0.1")
    rig.mda("N10 G1 G90 F600 W130 FXS[W]=1 FXST[W]=35 FXSW[W]=2\nN20 M30")
    rig.step(3)
    fixed_stop = rig.nck.fixed_stops[0]
    assert rig.axis("W1").torque_limit == 35.0 and (fixed_stop.torque, fixed_stop.window) == (35.0, 2.0)


def test_pulses_taken_away_while_the_deselection_waits_for_the_plc_leave_no_torque() -> None:
    """L37482-37486: the pulses taken away while the deselection waits for the PLC's acknowledgement
    set the torque limit to 0; pulses given back in this phase bring no torque; after the
    deselection the axis travels normally again."""
    rig = _rig("MD37002: 1")  # the pulses may go at the stop without aborting the function
    _clamped(rig)
    rig.pulse("CHAN1.basic.out.reset", 2)  # the clamp outlasts the reset
    rig.step(2)
    rig.mda("N10 FXS[W]=0\nN20 M30")
    rig.run_until(lambda: _state(rig) is State.DESELECTING, 50)
    w1 = rig.axis("W1")
    assert w1.torque_limit == 20.0 and w1.physical == pytest.approx(CLAMP)
    rig.set("W1.drive.out.enablePulses", 0)
    rig.step(5)
    assert w1.torque_limit == 0.0 and _state(rig) is State.DESELECTING
    rig.set("W1.drive.out.enablePulses", 1)
    rig.step(20)
    assert w1.torque_limit == 0.0 and w1.physical == pytest.approx(120.0)  # no torque any more: the part springs back
    rig.set("W1.basic.out.fixedStopEnable", 0)
    rig.set("W1.basic.out.fixedStopAckReached", 0)
    rig.run_until(lambda: rig.get("CHAN1.basic.in.stateReset") == 1, 50)
    assert _state(rig) is State.OFF and w1.torque_limit is None
    rig.mda("N10 G1 G90 F600 W115\nN20 M30")
    rig.run_until(lambda: abs(w1.actual - 115.0) < 1e-3, 3000)
    assert not rig.alarm_numbers()


# ---------------------------------------------------------------------- from synchronized actions, with POSA
# The seed's example 1 (L38047-38090) on the quill: static actions select FXS and move the axis as a
# command axis when the PLC asks through the NC input $A_IN[1] (the seed uses an R parameter), raise
# the torque once the stop is detected, and deselect and retract on $A_IN[2].
EXAMPLE_1 = """N10 IDS=1 WHENEVER ($A_IN[1]==1) AND ($AA_FXS[W]==0) DO FXS[W]=1 FXST[W]=10 FA[W]=600 POS[W]=130
N11 IDS=2 WHENEVER $AA_FXS[W]==4 DO FXST[W]=30
N13 IDS=4 WHENEVER ($A_IN[2]==1) AND ($AA_FXS[W]==1) DO FXS[W]=0 FA[W]=1000 POS[W]=110
N20 M30"""


def test_synchronized_actions_select_fxs_on_a_command_axis_as_the_seeds_example_1() -> None:
    rig = _rig()
    rig.mda(EXAMPLE_1)
    rig.step(20)
    w1 = rig.axis("W1")
    assert _state(rig) is State.OFF and w1.torque_limit is None
    rig.set("NC.basic.out.setDigitalInputs", 1)
    rig.step(20)
    assert _state(rig) is State.WAIT_ENABLE and w1.torque_limit == 10.0
    assert w1.actual == pytest.approx(110.0)  # the command axis waits for the PLC's enable DBX3.1
    rig.set("W1.basic.out.fixedStopEnable", 1)
    rig.run_until(lambda: rig.get("W1.basic.in.fixedStopReached") == 1, 2000)
    rig.step(2)
    assert _state(rig) is State.DETECTED and w1.torque_limit == 30.0  # action 2 raised the torque
    rig.set("W1.basic.out.fixedStopAckReached", 1)
    rig.step(20)
    assert _state(rig) is State.CLAMPED and w1.physical == pytest.approx(120.0 + 0.3 * 10000.0 / 50000.0)
    assert not rig.alarm_numbers()
    rig.set("NC.basic.out.setDigitalInputs", 2)  # action 4: deselect and retract
    rig.step(3)
    assert _state(rig) is State.DESELECTING and rig.get("W1.basic.in.fixedStopRequest") == 0
    rig.set("W1.basic.out.fixedStopEnable", 0)
    rig.set("W1.basic.out.fixedStopAckReached", 0)
    rig.run_until(lambda: abs(w1.actual - 110.0) < 1e-3, 2000)
    assert _state(rig) is State.OFF and w1.torque_limit is None and not rig.alarm_numbers()


def test_an_action_selects_fxs_during_a_path_block_and_the_path_ends_at_the_stop() -> None:
    """Example 2 (L38092-38110): the selection from a point of the block's motion on; the harness
    has no $AA_IW, the NC input stands for the position condition."""
    rig = _rig("MD37060: 0")
    rig.mda("N10 ID=1 WHEN $A_IN[1]==1 DO FXS[W]=1 FXST[W]=20\nN20 G1 G90 F600 W130\nN30 FXS[W]=0\nN40 M30")
    w1 = rig.axis("W1")
    rig.run_until(lambda: w1.actual > 115.0, 2000)
    assert _state(rig) is State.OFF
    rig.set("NC.basic.out.setDigitalInputs", 1)
    rig.run_until(lambda: _state(rig) is not State.APPROACH and _state(rig) is not State.OFF, 2000)
    assert w1.physical == pytest.approx(CLAMP) and not rig.alarm_numbers()
    rig.run_until(lambda: rig.get("CHAN1.basic.in.stateReset") == 1, 200)
    assert _state(rig) is State.OFF and not rig.alarm_numbers()


def test_an_action_on_an_axis_without_md37000_raises_20090() -> None:
    rig = _rig()
    rig.mda("N10 ID=1 WHEN $AC_ALARM_STAT==0 DO FXS[X]=1\nN20 G4 F0.1\nN30 M30")
    rig.step(20)
    assert 20090 in rig.alarm_numbers()


@pytest.mark.parametrize(("action", "alarm"), [("FXS[W]=2", 12080), ("FXST[W]=900", 12080), ("FXS[Q]=1", 12550)])
def test_a_wrong_fixed_stop_action_is_refused_when_its_block_is_decoded(action: str, alarm: int) -> None:
    rig = _rig()
    rig.mda(f"N10 ID=1 WHEN $AC_ALARM_STAT==0 DO {action}\nN20 M30")
    rig.step(5)
    assert alarm in rig.alarm_numbers() and _state(rig) is State.OFF


def test_with_posa_the_block_changes_before_the_stop_is_reached() -> None:
    """L37775-37778: POSA with FXS; the program runs on while the quill approaches; WAITP ends at the stop."""
    rig = _rig()
    rig.mda("N10 POSA[W]=130 FA[W]=600 FXS[W]=1\nN20 G4 F0.1\nN30 WAITP(W)\nN40 FXS[W]=0\nN50 M30")
    rig.set("W1.basic.out.fixedStopEnable", 1)
    w1 = rig.axis("W1")
    rig.step(5)
    assert rig.channel.run.block_index >= 1  # the block changed at once: N20 runs while the quill travels
    assert _state(rig) is State.APPROACH and w1.actual < 111.0
    rig.run_until(lambda: rig.get("W1.basic.in.fixedStopReached") == 1, 2000)
    assert w1.physical == pytest.approx(CLAMP)
    rig.set("W1.basic.out.fixedStopAckReached", 1)
    rig.run_until(lambda: _state(rig) is State.DESELECTING, 200)  # WAITP(W) ended at the stop, N40 deselects
    rig.set("W1.basic.out.fixedStopEnable", 0)
    rig.set("W1.basic.out.fixedStopAckReached", 0)
    rig.run_until(lambda: rig.get("CHAN1.basic.in.stateReset") == 1, 200)
    assert _state(rig) is State.OFF and not rig.alarm_numbers()


def test_posa_reaching_its_end_point_without_a_stop_raises_20091() -> None:
    rig = _rig("MD37060: 0")
    rig.mda("N10 POSA[W]=115 FA[W]=600 FXS[W]=1\nN20 WAITP(W)\nN30 M30")
    rig.run_until(lambda: rig.get("CHAN1.basic.in.stateReset") == 1 and rig.axis("W1").actual > 114.9, 2000)
    assert 20091 in rig.alarm_numbers() and _state(rig) is State.OFF


def test_a_posa_of_an_axis_at_its_stop_is_refused_with_20092() -> None:
    rig = _rig()
    _clamped(rig)
    rig.pulse("CHAN1.basic.out.reset", 2)  # the clamp outlasts the reset
    rig.step(2)
    rig.mda("N10 POSA[W]=100 FA[W]=600\nN20 M30")
    rig.step(5)
    assert 20092 in rig.alarm_numbers() and _state(rig) is State.CLAMPED
    assert rig.axis("W1").physical == pytest.approx(CLAMP)
