"""The servo parameter set the PLC selects (vc/core/axis/parameter_sets.py): DB31.DBX9.0-9.2 ->
DBX69.0-69.2 and the gain MD32200[n] with MD35590 = 1 / 2; turn_mill's X1 without feedforward
(its following error is the velocity over Kv); the test is the PLC."""

from __future__ import annotations

import pytest
from core_rig import Rig, machine

GAINS = "MD32200: [16.667, 8.0, 16.667, 16.667, 16.667, 12.5]"


def _rig(md35590: int) -> Rig:
    rig = Rig(machine(f"CHAN1: {{MD20700: 0}}\nX1: {{MD30240: [4], MD34210: [2], MD35590: {md35590},"
                      f" MD32620: 0, {GAINS}}}"))
    rig.ready_mda()
    return rig


def _select(rig: Rig, selection: int) -> None:
    rig.set("X1.basic.out.posCtrlParameterSetSelection", selection)
    rig.step(1)


@pytest.mark.parametrize(("selection", "active", "kv"), [(1, 1, 8.0), (5, 5, 12.5), (7, 5, 12.5), (0, 0, 16.667)])
def test_the_plcs_selection_switches_the_set_and_its_gain_in_the_same_cycle(selection: int, active: int,
                                                                             kv: float) -> None:
    rig = _rig(2)
    _select(rig, 3 if selection == 0 else 0)  # from another set, so that every case switches
    _select(rig, selection)
    assert rig.get("X1.drive.in.posCtrlParameterSetNumber") == active
    assert rig.axis("X1").dyn.kv == kv


@pytest.mark.parametrize("md35590", [1, 2])
def test_the_following_error_follows_the_gain_of_the_selected_set(md35590: int) -> None:
    rig = _rig(md35590)
    rig.mda("N10 G1 G91 X-140 F3000\nN20 M30")
    rig.step(400)
    x1 = rig.axis("X1")
    assert x1.following_error == pytest.approx(-50.0 / 16.667, abs=0.15)
    _select(rig, 1)
    rig.step(400)
    assert x1.following_error == pytest.approx(-50.0 / 8.0, abs=0.15)


def test_without_md35590_the_plcs_selection_is_not_taken() -> None:
    rig = _rig(0)
    _select(rig, 1)
    assert rig.axis("X1").parameter_sets is None
    assert rig.get("X1.drive.in.posCtrlParameterSetNumber") == 0 and rig.axis("X1").dyn.kv == 16.667


def test_a_spindle_keeps_the_set_of_its_gear_stage() -> None:
    rig = Rig(machine("SP1: {MD35590: 2}"))
    assert rig.axis("SP1").parameter_sets is None


def test_the_drives_speeds_count_with_the_gear_ratio_of_the_selected_set() -> None:
    rig = Rig(machine("CHAN1: {MD20700: 0}\nX1: {MD30240: [4], MD34210: [2], MD35590: 2,"
                      " MD31060: [1, 2, 1, 1, 1, 1], drive: {messages: 1}}"))
    rig.ready_mda()
    rig.mda("N10 G1 G91 X-140 F3000\nN20 M30")
    rig.step(300)
    messages = rig.axis("X1").messages
    assert messages is not None and messages.speed == pytest.approx(-300.0, abs=1.0)  # 3000 mm/min, 10 mm pitch
    _select(rig, 1)
    rig.step(2)
    assert messages.speed == pytest.approx(-600.0, abs=1.0)  # the second set's 2:1 belt
