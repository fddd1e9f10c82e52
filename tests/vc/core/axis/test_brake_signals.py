"""The holding brake through the NC's interface (vc/core/axis/holding_brake.py and the plant's brake,
vc/plant/holding_brake.py): DB31.DBX20.5 -> the brake -> DBX92.5, a vertical axis's sag and the
standstill monitoring of an axis held without controller enable (seed 003 L14921-14925); the
scenarios' vertical_axis machine (Z1 braked, 50 ms, sags at 600 mm/min); the test is the PLC."""

from __future__ import annotations

from core_rig import ROOT, Rig, machine

VERTICAL = str(ROOT / "scenarios" / "drives" / "machines" / "vertical_axis.yaml")


def _rig() -> Rig:
    rig = Rig(machine("CHAN1: {MD20700: 0}", VERTICAL))
    rig.ready_mda()
    return rig


def _release(rig: Rig, released: bool) -> int:
    rig.set("Z1.drive.out.releaseHoldingBrake", int(released))
    return rig.run_until(lambda: rig.get("Z1.drive.in.holdingBrakeReleased") == int(released), 100)


def test_the_brake_reports_released_after_its_switching_time_and_engaged_after_it_again() -> None:
    rig = _rig()
    assert rig.get("Z1.drive.in.holdingBrakeReleased") == 0 and rig.axis("Z1").holding_brake is not None
    assert rig.axis("X1").holding_brake is None  # only the braked axis pays for it
    assert _release(rig, True) == 25  # 50 ms of 2 ms cycles
    assert _release(rig, False) == 25
    assert rig.alarm_numbers() == []


def test_an_engaged_brake_holds_the_slide_and_a_released_one_lets_the_drive_move_it() -> None:
    rig = _rig()
    z1 = rig.axis("Z1")
    rig.mda("N10 G1 G91 Z-10 F3000\nN20 M30")
    rig.step(100)
    assert z1.physical == -200.0 and abs(z1.following_error) > 1.0  # the motor pushes against the brake
    rig.set("CHAN1.basic.out.reset", 1)
    rig.step(10)
    rig.set("CHAN1.basic.out.reset", 0)
    _release(rig, True)
    rig.mda("N10 G1 G91 Z-10 F3000\nN20 M30")
    rig.run_until(lambda: rig.get("CHAN1.basic.in.stateReset") == 1 and z1.resting, 1000)
    assert abs(z1.physical + 220.0) < 0.001  # released, the drive first caught up with the held setpoint


def test_released_without_torque_the_axis_sags_and_the_standstill_monitoring_raises_25040() -> None:
    rig = _rig()
    z1 = rig.axis("Z1")
    _release(rig, True)
    rig.step(20)
    assert z1.physical == -200.0  # the drive holds the weight
    rig.set("Z1.basic.out.enableCtrl", 0)
    cycles = rig.run_until(lambda: 25040 in rig.alarm_numbers(), 100)
    # 600 mm/min = 0.02 mm per 2 ms cycle; the alarm once the slide is beyond MD36030 (0.2 mm)
    assert 8 <= cycles <= 14 and z1.physical < -200.2
    sunk = z1.physical
    _release(rig, False)
    rig.step(50)
    assert z1.physical < sunk and z1.physical == rig.axis("Z1").physical
    stands = z1.physical
    rig.step(50)
    assert z1.physical == stands and z1.actual == z1.setpoint  # engaged: the NC followed it (follow-up)


def test_in_follow_up_mode_the_sag_is_followed_without_an_alarm() -> None:
    rig = _rig()
    z1 = rig.axis("Z1")
    _release(rig, True)
    rig.set("Z1.basic.out.followUpMode", 1)
    rig.set("Z1.basic.out.enableCtrl", 0)
    rig.step(50)
    assert z1.physical < -200.5 and abs(z1.actual - z1.setpoint) < 1e-9
    assert rig.alarm_numbers() == []


def test_an_axis_held_without_enable_and_pushed_away_raises_25040_also_without_a_brake() -> None:
    rig = _rig()
    rig.set("X1.basic.out.enableCtrl", 0)
    rig.step(5)
    rig.sim.move_by_hand("X1", 600.0)  # someone pushes the slide of the held axis
    rig.run_until(lambda: 25040 in rig.alarm_numbers(), 100)
