"""Incremental JOG through the NC (vc/core/nck/jog_functions.py): the PLC's machine function
DB31.DBX5.0..5.6, its feedback DB31.DBX65.0..65.6, the increments MD11330 / SD41010 x MD31090,
MD11300 and SD41050, RESET; the test is the PLC."""

from __future__ import annotations

import pytest
from core_rig import ABSOLUTE_X1, Rig, machine

INCREMENTS = ("inc1", "inc10", "inc100", "inc1000", "inc10000", "incVar")


def jog_rig(overrides: str = "", x1: str = "") -> Rig:
    rig = Rig(machine(ABSOLUTE_X1.replace("MD34210: [2]", "MD34210: [2]" + x1) + overrides))
    rig.enable_axes("X1")
    rig.select_mode("jog")
    rig.step(20)
    assert rig.get("MODEGROUP.basic.in.jogModeActive") == 1
    return rig


def active(rig: Rig) -> dict[str, int]:
    names = [f"{name}Active" for name in INCREMENTS] + ["contTraversActive"]
    return {name: int(rig.get(f"X1.basic.in.{name}")) for name in names if rig.get(f"X1.basic.in.{name}")}


def key(rig: Rig, sign: str, cycles: int) -> None:
    rig.set(f"X1.basic.out.traversKey{sign}", 1)
    rig.step(cycles)
    rig.set(f"X1.basic.out.traversKey{sign}", 0)
    rig.step(2)


@pytest.mark.parametrize(("selection", "travel"), [("inc1", 0.001), ("inc10", 0.01), ("inc100", 0.1),
                                                   ("inc1000", 1.0), ("inc10000", 10.0)])
def test_each_fixed_increment_travels_md11330_times_md31090_and_is_reported(selection: str, travel: float) -> None:
    rig = jog_rig()
    x1 = rig.axis("X1")
    start = x1.setpoint
    rig.set(f"X1.basic.out.{selection}", 1)
    rig.step(2)
    assert active(rig) == {f"{selection}Active": 1}
    key(rig, "Plus", 600)
    rig.step(100)
    assert x1.setpoint == pytest.approx(start + travel, abs=1e-9)
    key(rig, "Minus", 600)
    rig.step(100)
    assert x1.setpoint == pytest.approx(start, abs=1e-9)


def test_incvar_travels_sd41010_and_a_negative_md31090_reverses_the_key() -> None:
    rig = jog_rig("\nNC: {MD41010: 2500}", ", MD31090: [-0.001, 0.00254]")
    x1 = rig.axis("X1")
    start = x1.setpoint
    rig.set("X1.basic.out.incVar", 1)
    rig.step(2)
    assert active(rig) == {"incVarActive": 1}
    key(rig, "Plus", 600)
    rig.step(100)
    assert x1.setpoint == pytest.approx(start - 2.5, abs=1e-9)


def test_feedback_follows_the_selection_continuous_too_and_is_empty_outside_jog() -> None:
    rig = jog_rig()
    assert active(rig) == {}  # nothing selected: nothing reported (the keys traverse continuously)
    rig.set("X1.basic.out.contTravers", 1)
    rig.step(2)
    assert active(rig) == {"contTraversActive": 1}
    rig.set("X1.basic.out.inc100", 1)
    rig.set("X1.basic.out.inc10", 1)
    rig.step(2)
    assert active(rig) == {"inc10Active": 1}  # the smallest increment selected counts
    rig.select_mode("mda")
    rig.step(2)
    assert active(rig) == {}


def test_jog_mode_release_stops_the_increment_the_same_key_finishes_it() -> None:
    rig = jog_rig()
    x1 = rig.axis("X1")
    start = x1.setpoint
    rig.set("X1.basic.out.inc10000", 1)
    key(rig, "Plus", 50)
    rig.step(200)
    paused = x1.setpoint
    assert start < paused < start + 10.0 and x1.command_velocity == 0.0
    key(rig, "Minus", 100)  # the other key does nothing until the increment is done
    assert x1.setpoint == paused
    key(rig, "Plus", 600)
    rig.step(50)
    assert x1.setpoint == pytest.approx(start + 10.0, abs=1e-9)


def test_continuous_mode_md11300_0_a_tap_travels_the_increment_and_reset_ends_it() -> None:
    rig = jog_rig("\nNC: {MD11300: 0}")
    x1 = rig.axis("X1")
    start = x1.setpoint
    rig.set("X1.basic.out.inc10000", 1)
    key(rig, "Plus", 4)
    rig.step(600)
    assert x1.setpoint == pytest.approx(start + 10.0, abs=1e-9)
    key(rig, "Plus", 4)
    rig.step(50)
    rig.pulse("CHAN1.basic.out.reset", 4)  # RESET ends the increment (L32850)
    rig.step(300)
    assert start + 10.0 < x1.setpoint < start + 19.0 and x1.command_velocity == 0.0


def test_continuous_jog_in_continuous_mode_sd41050_0_runs_on_until_the_key_again() -> None:
    rig = jog_rig("\nNC: {MD41050: 0}")
    x1 = rig.axis("X1")
    key(rig, "Plus", 4)
    rig.step(200)
    assert x1.command_velocity == pytest.approx(2000.0 / 60.0)
    key(rig, "Plus", 4)
    rig.step(200)
    assert x1.command_velocity == 0.0


@pytest.mark.parametrize(("weight", "travel"), [("0.001", 2.0), ("-0.002", -4.0)])
def test_the_handwheel_takes_md11330_times_md31090_a_negative_weight_turns_it_around(weight: str,
                                                                                     travel: float) -> None:
    rig = jog_rig("\nNC: {MD11330: [1, 10, 200, 1000, 10000]}", f", MD31090: [{weight}, 0.00254]")
    x1 = rig.axis("X1")
    start = x1.setpoint
    rig.set("X1.basic.out.handwheelSelection", 1)
    rig.set("X1.basic.out.inc100", 1)  # MD11330[2] = 200 increments
    rig.step(2)
    rig.sim.turn_handwheel(1, 10, 50)
    rig.step(600)
    assert x1.setpoint == pytest.approx(start + travel, abs=1e-9)


def test_geometry_axis_1_reports_its_machine_function_in_db21_dbx41() -> None:
    rig = jog_rig()
    names = ("inc1Active", "inc10Active", "inc100Active", "inc1000Active", "inc10000Active", "incVarActive",
             "contManualTraversActive")

    def active() -> list[str]:
        return [name for name in names if rig.get(f"CHAN1.geoAxis1.in.{name}")]

    assert active() == []
    rig.set("CHAN1.geoAxis1.out.inc100", 1)
    rig.step(2)
    assert active() == ["inc100Active"]
    rig.set("CHAN1.geoAxis1.out.inc100", 0)
    rig.set("CHAN1.geoAxis1.out.incVar", 1)
    rig.step(2)
    assert active() == ["incVarActive"]
    rig.select_mode("mda")
    rig.step(2)
    assert active() == []
