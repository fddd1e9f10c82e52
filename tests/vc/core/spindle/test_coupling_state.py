"""A pair and a coupled pair (vc/core/spindle/coupling_state.py): the helpers and the stage-2 judgements."""

from __future__ import annotations

from vc.core.spindle.coupling_state import (
    ALARM_COARSE_2_EXCEEDED,
    ALARM_FINE_2_EXCEEDED,
    Coupling,
    PairDefinition,
    dynamic_matching,
    wrap180,
)


def coupled(deviation: float) -> Coupling:
    coupling = Coupling(PairDefinition("SP2", "SP1"), "CHAN1", deviation=deviation)
    coupling.stage_2_running.add(ALARM_FINE_2_EXCEEDED)  # fine synchronism was reached
    return coupling


def test_stage_2_monitors_only_a_configured_started_unpaused_tolerance() -> None:
    coupling = coupled(0.5)
    assert coupling.stage_2_monitors(ALARM_FINE_2_EXCEEDED, 1.0)
    assert not coupling.stage_2_monitors(ALARM_FINE_2_EXCEEDED, 0.0)  # MD37202 = 0: off
    assert not coupling.stage_2_monitors(ALARM_COARSE_2_EXCEEDED, 1.0)  # coarse never started
    coupling.stage_2_paused = True  # an exclusion holds (L29916-29932)
    assert not coupling.stage_2_monitors(ALARM_FINE_2_EXCEEDED, 1.0)


def test_103_4_shows_the_deviation_within_the_running_tolerance() -> None:
    assert coupled(0.5).stage_2_within(ALARM_FINE_2_EXCEEDED, 1.0)
    assert not coupled(1.5).stage_2_within(ALARM_FINE_2_EXCEEDED, 1.0)
    assert not coupled(0.5).stage_2_within(ALARM_COARSE_2_EXCEEDED, 1.0)


def test_tv_ss_6_dynamic_matching_gives_the_faster_spindle_the_difference() -> None:
    # MD32810 LS 5 ms, FS 3 ms: MD32900[FS] = 1, MD32910[FS] = 5 - 3 = 2 ms (seed 003 L23713-23720)
    assert dynamic_matching(0.005, 0.003) == (1, 0.002)
    assert dynamic_matching(0.003, 0.003) == (0, 0.0)


def test_wrap180_keeps_the_short_way() -> None:
    assert wrap180(350.0) == -10.0
    assert wrap180(-190.0) == 170.0
    assert wrap180(77.0) == 77.0
