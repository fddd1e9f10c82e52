"""JOG to a fixed point / to a position through the NC (vc/core/nck/jog_targets.py): the PLC's
DB31.DBX13.0..13.3, the feedback DB31.DBX75.0..75.7, MD30600 / MD30610 / SD43320, alarms 17810 and
17812, JOG left; the test is the PLC."""

from __future__ import annotations

from core_rig import ABSOLUTE_X1, Rig, machine

FIXED_POINTS = ", MD30610: 2, MD30600: [100.0, 200.0, 0.0, 0.0], MD43320: 120.0"


def jog_rig(x1: str = FIXED_POINTS, base: str = ABSOLUTE_X1) -> Rig:
    rig = Rig(machine(base.replace("MD34210: [2]", "MD34210: [2]" + x1)))
    rig.enable_axes("X1")
    rig.select_mode("jog")
    rig.step(20)
    return rig


def hold(rig: Rig, sign: str, cycles: int) -> None:
    rig.set(f"X1.basic.out.traversKey{sign}", 1)
    rig.step(cycles)
    rig.set(f"X1.basic.out.traversKey{sign}", 0)
    rig.step(50)


def test_fixed_point_2_selected_acknowledged_travelled_to_and_reported_reached() -> None:
    rig = jog_rig()
    x1 = rig.axis("X1")
    assert rig.get("X1.basic.in.jogFixedPointSelectedNumber") == 0
    rig.set("X1.basic.out.jogFixedPointSelection", 2)
    rig.step(2)
    assert rig.get("X1.basic.in.jogFixedPointSelectedNumber") == 2
    assert rig.get("X1.basic.in.jogFixedPointReachedNumber") == 0
    hold(rig, "Plus", 2500)
    assert x1.setpoint == 200.0 and rig.get("X1.basic.in.jogFixedPointReachedNumber") == 2
    hold(rig, "Minus", 200)  # not away from it (MD10735 bit 2 = 0)
    assert x1.setpoint == 200.0
    rig.set("X1.basic.out.jogFixedPointSelection", 0)
    rig.step(2)
    assert rig.get("X1.basic.in.jogFixedPointSelectedNumber") == 0
    assert rig.get("X1.basic.in.jogFixedPointReachedNumber") == 2  # it still stands on it
    hold(rig, "Minus", 200)
    assert x1.setpoint < 199.0 and rig.get("X1.basic.in.jogFixedPointReachedNumber") == 0


def test_jog_to_position_sd43320_and_jog_left_withdraws_the_selection() -> None:
    rig = jog_rig()
    x1 = rig.axis("X1")
    rig.set("X1.basic.out.jogToPos", 1)
    rig.step(2)
    assert rig.get("X1.basic.in.jogToPosActive") == 1 and rig.get("X1.basic.in.jogPosReached") == 0
    hold(rig, "Minus", 2500)
    assert x1.setpoint == 120.0 and rig.get("X1.basic.in.jogPosReached") == 1
    rig.select_mode("mda")
    rig.step(5)
    assert rig.get("X1.basic.in.jogToPosActive") == 0 and rig.get("X1.basic.in.jogPosReached") == 0
    rig.select_mode("jog")
    rig.step(5)
    assert rig.get("X1.basic.in.jogToPosActive") == 1 and rig.get("X1.basic.in.jogPosReached") == 1


def test_another_fixed_point_while_travelling_ends_the_motion_with_alarm_17812() -> None:
    rig = jog_rig()
    x1 = rig.axis("X1")
    rig.set("X1.basic.out.jogFixedPointSelection", 2)
    rig.set("X1.basic.out.traversKeyPlus", 1)
    rig.step(300)
    assert x1.command_velocity > 0.0
    rig.set("X1.basic.out.jogFixedPointSelection", 1)
    rig.step(300)
    assert 17812 in rig.alarm_numbers() and x1.command_velocity == 0.0
    stopped = x1.setpoint
    rig.step(300)  # the key held on: no new motion
    assert x1.setpoint == stopped and rig.get("X1.basic.in.jogFixedPointSelectedNumber") == 1


def test_an_axis_not_referenced_does_not_travel_and_raises_alarm_17810() -> None:
    rig = jog_rig(base="CHAN1: {MD20700: 0}\nX1: {MD30240: [1], MD34210: [2]}")
    x1 = rig.axis("X1")
    assert not x1.referenced
    start = x1.setpoint
    rig.set("X1.basic.out.jogFixedPointSelection", 1)
    rig.step(2)
    assert rig.get("X1.basic.in.jogFixedPointSelectedNumber") == 1
    hold(rig, "Plus", 200)
    assert x1.setpoint == start and 17810 in rig.alarm_numbers()


def test_an_axis_without_fixed_points_and_without_selection_is_not_followed() -> None:
    rig = jog_rig(x1="")
    targets = rig.nck.manual.jog_targets
    assert not targets._watched
    rig.set("X1.basic.out.jogToPos", 1)
    rig.step(2)
    assert targets._watched == {"X1"}
    rig.set("X1.basic.out.jogToPos", 0)
    rig.step(2)
    assert not targets._watched
