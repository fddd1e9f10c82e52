"""MD30460 bit 8 (seed 003 L10843-10858): an axis defined as a positioning axis / auxiliary spindle
only is no path axis, no geometry axis and cuts no thread: the block that asks for it raises 14092
[control] before anything moves, the machine reader refuses it as a geometry axis; POS / POSA,
FC18 and its own spindle functions stay.  mill_5axis's C1 and turn_mill's main spindle SP1."""

from __future__ import annotations

import pytest
from core_rig import FIVE_AXIS, MILL, Rig, machine, spindle_rig

from interfaces.errors import VcError

C1_ONLY = "CHAN1: {MD20700: 0}\nC1: {MD30240: [4], MD34210: [2], MD30460: 0x100}"


def _rig() -> Rig:
    rig = Rig(machine(C1_ONLY, FIVE_AXIS))
    rig.ready_mda()
    return rig


@pytest.mark.parametrize("program", ["G1 C=90 F1000", "G0 X10 C90"])
def test_a_positioning_axis_only_as_path_axis_raises_14092(program: str) -> None:
    rig = _rig()
    start = rig.axis("C1").setpoint
    rig.mda(f"N10 {program}\nN20 M30")
    rig.step(20)
    assert 14092 in rig.alarm_numbers() and rig.axis("C1").setpoint == start


def test_it_moves_as_a_positioning_axis_and_by_fc18() -> None:
    rig = _rig()
    rig.mda("N10 POS[C]=90 FA[C]=7200\nN20 M30")
    rig.run_until(lambda: rig.get("CHAN1.basic.in.stateReset") == 1, 3000)
    assert rig.alarm_numbers() == [] and rig.axis("C1").setpoint == 90.0
    rig.set("C1.plcAxis.out.position", 45.0)
    rig.set("C1.plcAxis.out.feedrate", 7200.0)
    rig.set("C1.plcAxis.out.start", 1)
    rig.run_until(lambda: rig.get("C1.plcAxis.in.inPosition") == 1, 3000)
    assert rig.axis("C1").setpoint == 45.0


@pytest.mark.parametrize("program", ["G331 Z-10 K1 S500", "G33 Z-10 K1"])
def test_an_auxiliary_spindle_cuts_no_thread(program: str) -> None:
    rig = spindle_rig("SP1: {MD30460: 0x100}")
    rig.mda(f"N10 {program}\nN20 M30")
    rig.step(20)
    assert 14092 in rig.alarm_numbers()


def test_the_reader_refuses_it_as_a_geometry_axis() -> None:
    with pytest.raises(VcError, match="a positioning axis only"):
        machine("X1: {MD30460: 0x100}", MILL)
