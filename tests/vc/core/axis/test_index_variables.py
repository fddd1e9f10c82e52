"""$AA_PROG_INDEX_AX_POS_NO and $AA_ACT_INDEX_AX_POS_NO (seed 003 §11.3.3, L13779-13820) and MD10940's
display rule (L13618-13680): the index positions (vc/core/axis/indexing.py ``reached``), the channel's
reader (vc/core/axis/index_variables.py) and a synchronized action that waits for a position.
mill_5axis's table C1 with the seed's turret of example 1 (8 positions 45 degrees apart), at 295."""

from __future__ import annotations

import pytest
from core_rig import FIVE_AXIS, Rig, machine

from vc.config.model import IndexDivision
from vc.core.axis.indexing import IndexPositions

TURRET = ("NC: {MD10900: 8, MD10910: [0, 45, 90, 135, 180, 225, 270, 315]%s}\n"
          "CHAN1: {MD20700: 0}\nC1: {MD30240: [4], MD34210: [2], MD30500: 1}")
TABLE = IndexPositions(IndexDivision(table=(0.0, 45.0, 90.0, 135.0, 180.0, 225.0, 270.0, 315.0)), (0.0, 360.0))


@pytest.mark.parametrize(("position", "fine_window_rule", "halfway_rule"), [
    (89.0, 2, 3), (89.995, 3, 3),  # half way (67.5) passed: 3  # going up: 3 from the edge of its fine window (0.01) on
    (90.0, 3, 3), (112.0, 3, 3), (113.0, 3, 4),  # half way to 4 (112.5): bit 0 = 1 shows 4
    (134.99, 4, 4), (359.0, 8, 1), (-10.0, 8, 1), (365.0, 1, 1),
])
def test_the_position_shown_changes_at_the_fine_window_or_half_way(position: float, fine_window_rule: int,
                                                                   halfway_rule: int) -> None:
    assert TABLE.reached(position, 0.01, halfway=False) == fine_window_rule
    assert TABLE.reached(position, 0.01, halfway=True) == halfway_rule


def test_equidistant_positions_and_a_linear_table() -> None:
    turn = IndexPositions(IndexDivision(offset=5.0, spacing=20.0, count=18), (0.0, 360.0))
    assert turn.reached(2.0, 0.01, False) == 18 and turn.reached(24.995, 0.01, False) == 2
    assert turn.reached(356.0, 0.01, True) == 1
    pallet = IndexPositions(IndexDivision(table=(-100.0, 0.0, 100.0)), None)
    assert pallet.reached(-150.0, 0.01, False) == 0 and pallet.reached(500.0, 0.01, True) == 3  # [INF]


def _rig(md10940: int = 0) -> Rig:
    rig = Rig(machine(TURRET % (f", MD10940: {md10940}" if md10940 else ""), FIVE_AXIS))
    rig.ready_mda()
    return rig


def _read(rig: Rig, name: str, axis: str = "C") -> float:
    return rig.channel.esr.read(name, axis)


def test_the_variables_follow_a_coded_motion_and_jog_takes_the_programmed_one_away() -> None:
    rig = _rig()
    assert _read(rig, "$AA_ACT_INDEX_AX_POS_NO") == 7.0 and _read(rig, "$AA_PROG_INDEX_AX_POS_NO") == 0.0
    rig.mda("N10 POS[C]=CACP(3) FA[C]=3600\nN20 M30")
    rig.step(20)
    assert _read(rig, "$AA_PROG_INDEX_AX_POS_NO") == 3.0  # on its way to position 3
    rig.run_until(lambda: rig.get("CHAN1.basic.in.stateReset") == 1, 3000)
    assert _read(rig, "$AA_ACT_INDEX_AX_POS_NO") == 3.0 and _read(rig, "$AA_PROG_INDEX_AX_POS_NO") == 3.0
    rig.mda("N10 POS[C]=100\nN20 M30")  # no index position
    rig.run_until(lambda: rig.get("CHAN1.basic.in.stateReset") == 1, 3000)
    assert _read(rig, "$AA_PROG_INDEX_AX_POS_NO") == 0.0 and _read(rig, "$AA_ACT_INDEX_AX_POS_NO") == 3.0
    assert _read(rig, "$AA_ACT_INDEX_AX_POS_NO", "X") == 0.0  # no indexing axis
    with pytest.raises(KeyError):
        _read(rig, "$AA_ACT_INDEX_AX_POS_NO", "Q")


def test_md10940_bit_0_shows_the_next_position_half_way() -> None:
    rig = _rig(1)
    rig.mda("N10 POS[C]=100\nN20 M30")
    rig.run_until(lambda: rig.get("CHAN1.basic.in.stateReset") == 1, 3000)
    assert _read(rig, "$AA_ACT_INDEX_AX_POS_NO") == 3.0  # 100 is nearer to 90 than to 135


def test_a_synchronized_action_waits_for_the_index_position_shown() -> None:
    rig = _rig()
    rig.mda("N10 IDS=1 WHEN $AA_ACT_INDEX_AX_POS_NO[C]==5 DO POS[X]=-100\n"
            "N20 POS[C]=CACN(4) FA[C]=1800\nN30 M30")
    c1, x1 = rig.axis("C1"), rig.axis("X1")
    start = x1.setpoint
    rig.run_until(lambda: x1.setpoint != start, 5000)
    # going down, 5 is shown once the table leaves position 6's fine window (225 - 0.01)
    assert 224.7 <= c1.actual <= 224.99
