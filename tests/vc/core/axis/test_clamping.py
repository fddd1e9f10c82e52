"""Clamping monitoring (DB31.DBX2.3 "clamping in progress", seed 003 L15436 / L15524; what it does
is the control's): while the PLC clamps a standing axis, the clamping tolerance MD36050 and alarm
26000 take the place of the standstill tolerance MD36030 and alarm 25040.  mill_5axis's table C1
(Kv 16.667/s: a load of v deg/s pushes it v / 16.667 degrees off its position); the test is the PLC."""

from __future__ import annotations

from core_rig import FIVE_AXIS, Rig, machine

ABSOLUTE_C1 = "CHAN1: {MD20700: 0}\nC1: {MD30240: [4], MD34210: [2], MD36050: 0.5}"


def _rig() -> Rig:
    rig = Rig(machine(ABSOLUTE_C1, FIVE_AXIS))
    rig.ready_mda()
    rig.step(300)  # standing still past MD36040
    return rig


def _push(rig: Rig, degrees_per_second: float) -> None:
    c1 = rig.axis("C1")
    c1.disturbance_velocity = degrees_per_second  # a load the drive holds against (the plant's fault)
    c1.resting = False
    rig.step(500)


def test_without_clamping_the_standstill_monitor_raises_25040() -> None:
    rig = _rig()
    _push(rig, 5.0)  # 0.3 degrees: beyond MD36030 0.2
    assert 25040 in rig.alarm_numbers() and 26000 not in rig.alarm_numbers()


def test_clamping_in_progress_allows_the_clamping_tolerance() -> None:
    rig = _rig()
    rig.set("C1.basic.out.clampingInProgress", 1)
    _push(rig, 5.0)  # 0.3 degrees: inside MD36050 0.5
    assert rig.alarm_numbers() == []


def test_a_clamped_axis_pushed_beyond_md36050_raises_26000() -> None:
    rig = _rig()
    rig.set("C1.basic.out.clampingInProgress", 1)
    _push(rig, 15.0)  # 0.9 degrees
    assert 26000 in rig.alarm_numbers() and 25040 not in rig.alarm_numbers()
    assert rig.get("CHAN1.basic.in.stateReset") == 1  # the axes stop; RESET clears it
