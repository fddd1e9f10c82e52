"""The drive's messages DB31.DBX94.0-94.6 / 95.0 (vc/core/axis/drive_messages.py): the speed and
torque thresholds against the motor's speed and torque, the temperature, what an axis at rest
costs.  The lathe with the tailstock quill W1 (5 mm leadscrew, MD32300 2 m/s^2, the part's face
at 120 mm, 20 % clamping torque by MD37010); the test is the PLC."""

from __future__ import annotations

from pathlib import Path

import pytest
from core_rig import Rig, machine, with_start_position

from vc.core.axis.drive_messages import ACCELERATION_TORQUE, AMBIENT_TEMPERATURE, motor_speed

LATHE = str(Path(__file__).resolve().parents[4] / "scenarios" / "fixed_stop" / "machines" / "lathe_tailstock.yaml")


def _rig(drive: str = "messages: 1", quill: str = "", start: float = 110.0) -> Rig:
    overrides = (f"CHAN1: {{MD20700: 0}}\nW1: {{MD30240: [4], MD34210: [2], MD37060: 0{', ' + quill if quill else ''},"
                 f" drive: {{{drive}}}}}")
    rig = Rig(with_start_position(machine(overrides, LATHE), "W1", start))
    rig.ready_mda()
    return rig


def _messages(rig: Rig) -> dict[str, int]:
    names = ("motorTempPrewarning", "speedSetpointReached", "torqueBelowThreshold", "speedBelowMin",
             "speedBelowThreshold", "speedAtSetpoint", "dcLinkBelowWarning")
    return {name: int(rig.get(f"W1.drive.in.{name}")) for name in names}


def test_a_drive_at_rest_reports_low_speed_at_its_setpoint_and_no_torque() -> None:
    rig = _rig()
    rig.step(5)
    assert _messages(rig) == {"motorTempPrewarning": 0, "speedSetpointReached": 1, "torqueBelowThreshold": 1,
                              "speedBelowMin": 1, "speedBelowThreshold": 1, "speedAtSetpoint": 1,
                              "dcLinkBelowWarning": 0}


def test_a_drive_without_messages_reports_none() -> None:
    rig = _rig("p0888: 0")
    rig.mda("N10 G0 G90 W50\nN20 M30")
    rig.step(200)
    assert rig.axis("W1").messages is None
    assert set(_messages(rig).values()) == {0}
    assert rig.nck.motor_temperature("W1", 150.0) is False


def test_the_speed_thresholds_count_the_motors_revolutions() -> None:
    """G0 at 6000 mm/min on a 5 mm leadscrew: 1200 rev/min, above n x = 1000 and n min."""
    rig = _rig("messages: 1, p2155: 1000, p2161: 20")
    rig.mda("N10 G0 G90 W10\nN20 M30")
    rig.run_until(lambda: rig.get("W1.drive.in.speedBelowMin") == 0, 50)
    w1 = rig.axis("W1")
    assert w1.messages is not None and abs(w1.messages.speed) >= 20.0
    rig.run_until(lambda: rig.get("W1.drive.in.speedSetpointReached") == 1, 200)
    assert w1.messages.speed == pytest.approx(-1200.0, abs=90.0)
    assert _messages(rig)["speedBelowThreshold"] == 0 and _messages(rig)["speedAtSetpoint"] == 1
    rig.run_until(lambda: w1.resting, 2000)
    assert _messages(rig)["speedBelowThreshold"] == 1 and _messages(rig)["speedBelowMin"] == 1


def test_the_ramp_up_is_complete_only_once_the_setpoint_stands() -> None:
    rig = _rig()
    rig.mda("N10 G0 G90 W10\nN20 M30")
    rig.run_until(lambda: rig.get("W1.drive.in.speedBelowMin") == 0, 50)
    assert rig.get("W1.drive.in.speedSetpointReached") == 0
    ramp = rig.run_until(lambda: rig.get("W1.drive.in.speedSetpointReached") == 1, 200)
    # 1200 rev/min at 2 m/s^2 on 5 mm: 24000 rev/min per s, the ramp takes 50 ms
    assert 20 <= ramp <= 30


def test_the_torque_threshold_falls_after_its_delay_at_the_fixed_stop_and_returns_at_once() -> None:
    rig = _rig("messages: 1, p2174: 15, p2176: 100")
    rig.mda("N10 G1 G90 F600 W130 FXS[W]=1 FXST[W]=20\nN20 G4 F0.3\nN30 FXS[W]=0\nN40 G4 F0.2\nN50 M30")
    w1 = rig.axis("W1")
    rig.run_until(lambda: w1.blocked, 2000)
    assert w1.messages is not None and w1.messages.torque == 20.0
    held = rig.run_until(lambda: rig.get("W1.drive.in.torqueBelowThreshold") == 0, 100)
    assert held == 49  # 50 cycles of 2 ms at the torque limit, the first counted as the slide touched
    rig.run_until(lambda: rig.get("W1.basic.in.fixedStopRequest") == 0, 1000)
    rig.step(1)
    assert rig.get("W1.drive.in.torqueBelowThreshold") == 1 and w1.messages.torque == 0.0


def test_a_clamping_torque_below_the_threshold_never_takes_the_message() -> None:
    rig = _rig("messages: 1, p2174: 15")
    rig.mda("N10 G1 G90 F600 W130 FXS[W]=1 FXST[W]=10\nN20 G4 F0.5\nN30 M30")
    seen = set()
    for _ in range(1500):
        rig.step(1)
        seen.add(rig.get("W1.drive.in.torqueBelowThreshold"))
    assert rig.get("W1.basic.in.fixedStopReached") == 1 and seen == {1}


def test_the_accelerations_torque_is_its_share_of_md32300() -> None:
    rig = _rig("messages: 1")
    rig.mda("N10 G0 G90 W10\nN20 M30")
    rig.step(15)  # the interpolator accelerates at MD32300, the drive lags it by MD32810
    assert rig.axis("W1").messages is not None
    assert rig.axis("W1").messages.torque == pytest.approx(ACCELERATION_TORQUE, abs=0.5)  # type: ignore[union-attr]


def test_the_motor_temperature_warns_above_p0604_at_rest() -> None:
    rig = _rig("messages: 1, p0604: 110")
    rig.step(5)
    assert rig.nck.motor_temperature("W1", 111.0)
    assert rig.get("W1.drive.in.motorTempPrewarning") == 1  # at once, the axis need not run its cycle
    rig.nck.motor_temperature("W1", None)
    assert rig.get("W1.drive.in.motorTempPrewarning") == 0
    assert rig.axis("W1").messages.temperature == AMBIENT_TEMPERATURE  # type: ignore[union-attr]


def test_an_axis_at_rest_does_not_evaluate_its_messages() -> None:
    rig = _rig()
    w1 = rig.axis("W1")
    rig.run_until(lambda: w1.resting, 100)
    messages = w1.messages
    assert messages is not None
    messages.torque = 77.0  # a cycle of the messages would compute the torque of the motor at rest anew
    rig.step(500)
    assert w1.resting and messages.torque == 77.0
    rig.mda("N10 G0 G90 W120\nN20 M30")
    rig.step(5)
    assert messages.torque != 77.0  # moving, the axis evaluates them again


@pytest.mark.parametrize(("rotary", "numerator", "denominator", "load", "motor"), [
    (False, 1, 1, 6000.0, 1200.0),  # 6000 mm/min on the 5 mm leadscrew
    (False, 3, 1, 6000.0, 3600.0),  # a 3:1 belt: the motor turns three times per leadscrew turn
    (True, 2, 1, 360.0 * 100, 200.0),  # 100 rev/min of the load through 2:1
])
def test_the_motor_speed_follows_gear_and_leadscrew(rotary: bool, numerator: int, denominator: int, load: float,
                                                   motor: float) -> None:
    extra = "MD30300: 1, " if rotary else ""
    config = machine(f"W1: {{{extra}MD31060: [{numerator}, 1, 1, 1, 1, 1], MD31050: [{denominator}, 1, 1, 1, 1, 1]}}",
                     LATHE).axis("W1")
    assert motor_speed(config, load, 0) == pytest.approx(motor)
