"""Fixed feedrates MD12202 / MD12204 (seed 003 L9692-9722): the values per axis and the selection bits."""

from __future__ import annotations

import pytest
from core_rig import FIVE_AXIS, machine

from vc.config import md_dictionary as MD
from vc.core.axis.dynamics import fixed_feed, fixed_feeds_of


@pytest.mark.parametrize(("selection", "expected"), [(0, 0.0), (1, 10.0), (2, 20.0), (4, 30.0), (8, 40.0),
                                                     (6, 20.0)])  # two bits: the lower one
def test_the_lowest_selected_bit_names_the_value(selection: int, expected: float) -> None:
    assert fixed_feed((10.0, 20.0, 30.0, 40.0), selection) == expected


def test_linear_axes_take_md12202_in_mm_per_min_rotary_axes_md12204_in_rev_per_min_within_md32000() -> None:
    config = machine("NC: {MD12202: [600, 120000, 0, 60], MD12204: [10, 0, 0, 100]}", path=FIVE_AXIS)
    x1 = next(axis for axis in config.axes if axis.name == "X1")
    c1 = next(axis for axis in config.axes if axis.name == "C1")
    assert fixed_feeds_of(config.nck, x1)[0] == pytest.approx(10.0)  # 600 mm/min = 10 mm/s
    assert fixed_feeds_of(config.nck, x1)[1] == pytest.approx(x1.md.float(MD.MAX_AX_VELO) / 60.0)  # MD32000
    assert fixed_feeds_of(config.nck, c1)[:1] == pytest.approx((60.0,))  # 10 rev/min = 60 deg/s
    assert fixed_feeds_of(config.nck, c1)[3] == pytest.approx(50 * 6.0)  # 100 rev/min above C1's 50
