"""Rotary axes (vc/core/axis/rotary.py, seed 003 chapter 10): the end points of AC, ACP, ACN, DC,
IC and G90 on a modulo rotary axis, a rotary axis without modulo and a linear axis, with the
seed's examples; and the modulo limit switch DB31.DBX12.4 / 74.4 on mill_5axis's table C1."""

from __future__ import annotations

import pytest
from core_rig import FIVE_AXIS, Rig, machine

from vc.config.model import AxisConfig
from vc.core.axis.rotary import end_point


def _axis(name: str, overrides: str = "") -> AxisConfig:
    config = machine(overrides, FIVE_AXIS)
    return next(axis for axis in config.axes if axis.name == name)


def _walk(config: AxisConfig, start: float, *steps: tuple[str, float]) -> list[float]:
    positions = []
    for mode, value in steps:
        start, alarm = end_point(config, start, mode, value)
        assert alarm == 0
        positions.append(start)
    return positions


def test_acp_acn_and_ac_on_a_modulo_axis_as_figure_10_5() -> None:
    # L13023-13029: from 0, ACP(100), ACN(300), ACP(240), AC(0)
    assert _walk(_axis("C1"), 0.0, ("ACP", 100.0), ("ACN", 300.0), ("ACP", 240.0), ("AC", 0.0)) == \
        [100.0, -60.0, 240.0, 0.0]


def test_dc_takes_the_shorter_way_and_the_positive_one_on_a_tie_as_figure_10_6() -> None:
    # L13056-13063: from 0, DC(100), DC(300), DC(240), DC(60) (180 degrees: positive)
    assert _walk(_axis("C1"), 0.0, ("DC", 100.0), ("DC", 300.0), ("DC", 240.0), ("DC", 60.0)) == \
        [100.0, -60.0, -120.0, 60.0]


def test_ic_is_the_way_itself_and_g90_follows_md30455_bit_2() -> None:
    c1 = _axis("C1")
    assert _walk(c1, 10.0, ("IC", 720.0), ("IC", -180.0)) == [730.0, 550.0]  # L13093-13100
    assert _walk(c1, 350.0, ("G90", 10.0)) == [10.0]  # AC: 10 < 350, the negative way (L12762)
    shortest = _axis("C1", "C1: {MD30455: 4}")
    assert _walk(shortest, 350.0, ("G90", 10.0)) == [370.0]  # DC (L12764-12766)


def test_a_rotary_axis_without_modulo_as_in_the_seed() -> None:
    # L13176-13185: AC(7200), then DC(300) turns back to 7140, AC(7000)
    a1 = _axis("C1", "C1: {MD30310: 0}")
    assert _walk(a1, 0.0, ("AC", 7200.0), ("DC", 300.0), ("AC", 7000.0)) == [7200.0, 7140.0, 7000.0]


@pytest.mark.parametrize(("name", "overrides", "mode", "value", "alarm"), [
    ("X1", "", "DC", 10.0, 16800),  # L13164
    ("X1", "", "ACP", 10.0, 16810),
    ("C1", "C1: {MD30310: 0}", "ACP", 10.0, 16810),  # L13123
    ("C1", "C1: {MD30310: 0}", "ACN", 10.0, 16820),
    ("C1", "C1: {MD30310: 0}", "DC", 360.0, 16830),  # L13150-13152
    ("C1", "", "AC", -10.0, 16830),  # a modulo position lies in 0 .. 359.999 (L12980)
    ("C1", "", "ACP", 360.0, 16830),
])
def test_what_an_axis_cannot_take_is_refused(name: str, overrides: str, mode: str, value: float,
                                              alarm: int) -> None:
    assert end_point(_axis(name, overrides), 0.0, mode, value)[1] == alarm


def test_a_shifted_modulo_range_takes_negative_positions() -> None:
    c1 = _axis("C1", "C1: {MD30340: -180}")  # L12730-12736: -180 .. +180
    assert _walk(c1, 0.0, ("DC", -90.0), ("ACP", 170.0)) == [-90.0, 170.0]


def test_the_modulo_limit_switch_acts_only_with_db31_dbx12_4() -> None:
    # L12890-12930: MD36110 = 340, MD36100 = 350 on the modulo axis: the gap 340 .. 350 is forbidden
    rig = Rig(machine("CHAN1: {MD20700: 0}\nC1: {MD36100: 350, MD36110: 340, MD30240: [4], MD34210: [2]}",
                      FIVE_AXIS))
    rig.ready_mda()
    c1 = rig.axis("C1")
    assert not c1.software_limits_active and rig.get("C1.basic.in.moduloLimitSwitchActive") == 0
    rig.set("C1.basic.out.enableModuloLimitSwitch", 1)
    rig.step(2)
    assert rig.get("C1.basic.in.moduloLimitSwitchActive") == 1
    start = c1.setpoint
    assert c1.software_limits == pytest.approx((-10.0, 340.0))  # the turn C1 stands in
    rig.mda("G90 G0 C345\nM30")
    rig.step(10)
    assert 10720 in rig.alarm_numbers() and c1.setpoint == pytest.approx(start)
    rig.pulse("CHAN1.basic.out.reset", 2)
    rig.set("C1.basic.out.enableModuloLimitSwitch", 0)
    rig.step(2)
    rig.mda("G90 G0 C345\nM30")
    rig.run_until(lambda: rig.get("CHAN1.basic.in.stateReset") == 1, 3000)
    assert c1.setpoint == pytest.approx(345.0) and 10720 not in rig.alarm_numbers()
