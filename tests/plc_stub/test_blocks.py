"""IEC 61131-3 standard function blocks, counted in PLC scans.

IEC 61131-3 timers measure the elapsed time ET from the scan in which their input changed:
in that scan ET = 0, one scan later ET = one scan time, and so on.  With an OB1 period of
10 ms, TON with PT = 50 ms therefore sets Q in the 6th scan with IN = 1 (ET = 50 ms), never
earlier; TOF with PT = 50 ms resets Q in the 6th scan with IN = 0.
"""

from __future__ import annotations

from plc_stub.blocks import F_TRIG, R_TRIG, SR, TOF, TON

SCAN = 0.01  # s, OB1 period


def run(block: TON | TOF, inputs: list[bool]) -> list[bool]:
    return [block(value) for value in inputs]


# ------------------------------------------------------------------------------ TON


def test_ton_sets_q_when_in_has_been_1_for_the_preset_time() -> None:
    # IN rises in scan 0 (ET = 0 ms); ET = 50 ms in scan 5: Q from scan 5 on.
    assert run(TON(0.05, SCAN), [True] * 8) == [False] * 5 + [True] * 3


def test_ton_with_a_preset_of_one_scan_still_delays() -> None:
    # A timer of one scan time does not switch in the scan in which IN rises (ET = 0 < PT).
    assert TON(SCAN, SCAN)(True) is False


def test_ton_resets_at_once_when_in_falls_and_starts_again_from_zero() -> None:
    timer = TON(0.05, SCAN)
    first = run(timer, [True] * 10)
    assert timer(False) is False
    second = run(timer, [True] * 10)
    assert second == first  # a full preset again after the new rising edge


def test_ton_delay_grows_with_the_preset() -> None:
    # 0.1 s and 0.5 s at 10 ms per scan: Q 40 scans later for the longer preset
    short = run(TON(0.1, SCAN), [True] * 60).index(True)
    long = run(TON(0.5, SCAN), [True] * 60).index(True)
    assert long - short == 40


def test_ton_interrupted_input_never_sets_q() -> None:
    assert not any(run(TON(0.05, SCAN), [True, True, True, False] * 5))


def test_ton_q_attribute_shows_the_last_output() -> None:
    timer = TON(0.02, SCAN)
    run(timer, [True] * 3)
    assert timer.q is True


# ------------------------------------------------------------------------------ TOF


def test_tof_q_follows_in_at_once_when_in_rises() -> None:
    assert TOF(0.05, SCAN)(True) is True


def test_tof_is_off_without_input_after_power_on() -> None:
    assert run(TOF(0.05, SCAN), [False] * 3) == [False] * 3


def test_tof_keeps_q_for_the_preset_time_after_in_falls() -> None:
    # IN falls in scan 0 (ET = 0); ET = 50 ms in scan 5: Q = 1 in scans 0..4, 0 from scan 5.
    timer = TOF(0.05, SCAN)
    run(timer, [True] * 3)
    assert run(timer, [False] * 8) == [True] * 5 + [False] * 3


def test_tof_restarts_when_in_returns_before_the_time_is_up() -> None:
    reference = TOF(0.05, SCAN)
    reference(True)
    full_hold = run(reference, [False] * 10)
    timer = TOF(0.05, SCAN)
    timer(True)
    outputs = run(timer, [False] * 3 + [True] + [False] * 10)
    assert all(outputs[:4])
    assert outputs[4:] == full_hold  # the whole off delay again from the second falling edge


# ------------------------------------------------------------------------------ edges


def test_r_trig_is_1_for_exactly_one_scan_per_rising_edge() -> None:
    trig = R_TRIG()
    outputs = [trig(value) for value in [False, True, True, True, False, True, False, False, True]]
    assert outputs == [False, True, False, False, False, True, False, False, True]
    assert trig.q is True


def test_r_trig_sees_an_input_that_is_1_in_the_first_scan_as_an_edge() -> None:
    assert R_TRIG()(True) is True


def test_f_trig_is_1_for_exactly_one_scan_per_falling_edge() -> None:
    trig = F_TRIG()
    outputs = [trig(value) for value in [False, True, True, False, False, True, False, True]]
    assert outputs == [False, False, False, True, False, False, True, False]


def test_f_trig_sees_no_edge_at_power_on_with_input_0() -> None:
    assert F_TRIG()(False) is False


# ------------------------------------------------------------------------------ SR


def test_sr_latches_on_set_until_reset() -> None:
    latch = SR()
    assert [latch(s1, r) for s1, r in [(False, False), (True, False), (False, False), (False, False),
                                      (False, True), (False, False)]] == [False, True, True, True, False, False]


def test_sr_set_wins_while_both_inputs_are_1() -> None:
    latch = SR()
    assert latch(True, True) is True
    assert latch(False, True) is False
    assert latch.q1 is False
