"""The dry-run feed (seed 003 L9380-9490): SD42100 in place of F by SD42101, DB21.DBX318.6."""

from __future__ import annotations

import pytest
from core_rig import spindle_rig

BASE = ("CHAN1: {MD20700: 0, MD42100: 3000, MD42101: MODE}\nX1: {MD30240: [4], MD34210: [2]}\n"
        "Z1: {MD30240: [4], MD34210: [2]}\nY1: {MD30240: [4], MD34210: [2]}")


@pytest.mark.parametrize(("mode", "programmed", "expected"), [
    (0, 600.0, 3000.0), (0, 6000.0, 6000.0), (1, 600.0, 600.0), (1, 6000.0, 3000.0), (2, 6000.0, 3000.0),
    (10, 600.0, 3000.0), (12, 600.0, 3000.0)])
def test_sd42101_chooses_the_path_feed(mode: int, programmed: float, expected: float) -> None:
    rig = spindle_rig("", base=BASE.replace("MODE", str(mode)))
    rig.set("CHAN1.basic.out.dryRunFeedrate", 1)
    rig.step(2)
    assert int(rig.get("CHAN1.basic.in.dryRunFeedrateActive")) == 1  # in reset: taken at once
    rig.mda(f"G1 Z500 F{programmed:g}\n")
    rig.step(300)
    assert rig.sim.axis_quantity("Z1", "velocity") == pytest.approx(expected)


def test_a_change_in_a_running_block_waits_for_the_next_block() -> None:
    rig = spindle_rig("", base=BASE.replace("MODE", "0"))
    rig.mda("G1 Z330 F600\nZ360\n")
    rig.step(100)
    rig.set("CHAN1.basic.out.dryRunFeedrate", 1)
    rig.step(100)
    assert int(rig.get("CHAN1.basic.in.dryRunFeedrateActive")) == 0
    assert rig.sim.axis_quantity("Z1", "velocity") == pytest.approx(600.0)
    rig.run_until(lambda: rig.axis("Z1").setpoint > 330.0, 10000, step=10)
    rig.step(200)
    assert int(rig.get("CHAN1.basic.in.dryRunFeedrateActive")) == 1
    assert rig.sim.axis_quantity("Z1", "velocity") == pytest.approx(3000.0)
