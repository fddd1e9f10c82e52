"""The 2nd software limit switches: DB31.DBX12.2 / 12.3 put MD36120 / MD36130 in place of MD36100 /
MD36110 (seed 003 L12835-12843, L12940-12941)."""

from __future__ import annotations

from core_rig import spindle_rig

BASE = ("CHAN1: {MD20700: 0}\nX1: {MD30240: [4], MD34210: [2]}\nY1: {MD30240: [4], MD34210: [2]}\n"
        "Z1: {MD30240: [4], MD34210: [2], MD36120: 250, MD36130: 400}")


def test_the_plc_selects_each_side_on_its_own_and_the_program_check_follows() -> None:
    rig = spindle_rig("", base=BASE)
    z1 = rig.axis("Z1")
    assert z1.software_limits == (-8.0, 608.0)
    rig.set("Z1.basic.out.swLimitSwitch2Plus", 1)
    rig.step(2)
    assert z1.software_limits == (-8.0, 400.0)
    rig.set("Z1.basic.out.swLimitSwitch2Minus", 1)
    rig.set("Z1.basic.out.swLimitSwitch2Plus", 0)
    rig.step(2)
    assert z1.software_limits == (250.0, 608.0)
    rig.mda("G90 G1 Z200 F1000\n")
    rig.step(5)
    assert 10720 in rig.alarm_numbers()
