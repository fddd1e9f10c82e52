"""Distance-coded reference marks (seed 003 §4.6): the decoded position mapped into the modulo
range (L1653-1670).  Decoding the marks themselves is tested through the procedure
(test_referencing.py), which holds the marks it crossed."""

from __future__ import annotations

import pytest
from core_rig import FIVE_AXIS, machine

from vc.core.referencing.distance_coded import modulo_reference_position


@pytest.mark.parametrize(("overrides", "decoded", "expected"), [
    ("", 460.0, 100.0),  # modulo rotary axis (MD30310 = 1): into 0 .. 360
    ("C1: {MD30340: -180.0}", 460.0, 100.0),  # into -180 .. 180
    ("C1: {MD30340: -180.0}", 250.0, -110.0),
    ("C1: {MD30330: 720.0}", 1000.0, 280.0),
    ("C1: {MD30310: 0}", 460.0, 460.0),  # not modulo: as decoded (seed 003 L1653-1656)
    ("C1: {MD30310: 0, MD30455: 2}", 460.0, 100.0),  # MD30455 bit 1: the virtual modulo range
    ("C1: {MD30310: 0, MD30455: 1}", 460.0, 460.0),  # another bit does not map
    ("C1: {MD30300: 0, MD30310: 0, MD30455: 2}", 460.0, 460.0),  # a linear axis is never mapped
])
def test_the_reference_position_of_a_rotary_encoder_is_mapped_into_the_modulo_range(
        overrides: str, decoded: float, expected: float) -> None:
    md = machine(overrides, FIVE_AXIS).axis("C1").md
    assert modulo_reference_position(decoded, md) == pytest.approx(expected)
