"""Constant cutting speed G96 / G961 (seed 003 §7.2.2) in the NC core, the test acting as the PLC.

Turn-mill CHAN1 with X as its transverse axis (MD20100); SP1 the master spindle in gear stage 1
(5 .. 800 rev/min, MD35140 / MD35130), X1 an absolute encoder standing at 150 mm.
"""

from __future__ import annotations

import math

import pytest
from core_rig import Rig, spindle_rig

from vc.core.channel.cutting_speed import CuttingSpeedState

LATHE = ("CHAN1: {MD20700: 0, MD20100: X}\nX1: {MD30240: [4], MD34210: [2]}\nZ1: {MD30240: [4], MD34210: [2]}\n"
         "Y1: {MD30240: [4], MD34210: [2]}")


def lathe(extra: str = "") -> Rig:
    return spindle_rig(extra, base=LATHE)


def speed_at(cutting_speed: float, radius: float) -> float:
    return cutting_speed * 1000.0 / (2.0 * math.pi * radius)


def test_the_speed_follows_the_transverse_axis_every_cycle_and_84_0_shows_it() -> None:
    rig = lathe()
    rig.mda("G96 S300 M3\nG1 X100 F1\n")
    rig.step(20)
    spindle, x1 = rig.nck.spindles[0], rig.axis("X1")
    assert rig.channel.cutting_speed.state is CuttingSpeedState.FOLLOWING
    assert int(rig.get("SP1.spindle.in.constantCuttingSpeedActive")) == 1
    assert int(rig.get("CHAN1.basic.in.revolutionalFeedrateActive")) == 1
    for _ in range(5):
        rig.step(100)
        assert spindle.speed == pytest.approx(speed_at(300.0, x1.setpoint))
    assert float(rig.get("SP1.spindle.in.sFuncValue")) == 300.0  # DBD88: the programmed S


def test_the_gear_stage_maximum_and_lims_limit_the_speed_without_83_1() -> None:
    rig = lathe()
    rig.mda("G96 S800 M3\nG4 F0.5\n")  # 848.8 rev/min at X150: above gear 1's 800
    rig.step(150)
    assert rig.nck.spindles[0].speed == 800.0
    assert int(rig.get("SP1.spindle.in.speedSetpointAboveMax")) == 0  # L7760-7761
    rig.step(300)
    rig.mda("G96 S300 LIMS=250 M3\nG4 F0.5\n")
    rig.step(20)
    assert rig.nck.spindles[0].speed == 250.0


def test_sd43230_is_the_limit_until_lims_writes_it() -> None:
    rig = lathe("SP1: {MD43230: 200}")
    rig.mda("G96 S300 M3\nG4 F0.2\n")
    rig.step(20)
    assert rig.nck.spindles[0].speed == 200.0


def test_the_radius_0_turns_at_the_limit_not_at_infinity() -> None:
    rig = lathe()
    rig.mda("G96 S300 M3\nG1 X0 F5\n")
    rig.run_until(lambda: rig.axis("X1").setpoint == 0.0, 20000, step=50)
    rig.step(5)
    assert rig.nck.spindles[0].speed == 800.0


def test_g97_ends_it_and_keeps_the_speed_and_costs_no_more_cycles() -> None:
    rig = lathe()
    rig.mda("G96 S300 M3\nG97\nG1 X100 F1\n")
    rig.step(30)
    cutting = rig.channel.cutting_speed
    assert (cutting.state, cutting.following) == (CuttingSpeedState.OFF, False)
    assert rig.nck.spindles[0].speed == pytest.approx(speed_at(300.0, 150.0))
    rig.step(200)
    assert rig.nck.spindles[0].speed == pytest.approx(speed_at(300.0, 150.0))  # X moves, the speed stays
    assert int(rig.get("SP1.spindle.in.constantCuttingSpeedActive")) == 0


def test_reset_ends_it_and_md35040_0_deletes_the_speed() -> None:
    rig = lathe()
    rig.mda("G96 S300 M3\nG1 X100 F1\n")
    rig.step(50)
    rig.pulse("CHAN1.basic.out.reset")
    rig.step(2)
    assert rig.channel.cutting_speed.state is CuttingSpeedState.OFF
    assert rig.nck.spindles[0].speed == 0.0
    assert int(rig.get("CHAN1.basic.in.revolutionalFeedrateActive")) == 0


def test_a_rapid_block_holds_the_speed_with_md20750_0() -> None:
    rig = lathe()
    rig.mda("G96 S300 M3\nG0 X60\nG4 F0.1\n")
    rig.step(10)
    assert rig.channel.cutting_speed.state is CuttingSpeedState.HELD
    rig.step(100)
    assert rig.nck.spindles[0].speed == pytest.approx(speed_at(300.0, 150.0))
