"""The NCK cycle: mode group (DB11), emergency stop (DB10), NCK status and determinism.

Turn-mill: X1/Z1 MD32000 30 m/min = 500 mm/s, MD32010 JOG rapid 10000 mm/min = 166.67 mm/s,
MD32300 4000 mm/s^2, MD36610 0.05 s (rapid-stop ramp 500 / 0.05 = 10000 mm/s^2),
MD36620 0.1 s, Kv MD32200 16.667 1/s, IPO 2 ms, OB1 every 5 IPO cycles.
"""

from __future__ import annotations

import pytest
from core_rig import ABSOLUTE_X1, ABSOLUTE_XYZ, DT, Rig, machine

from vc.core.channel.program_run import Mode


def modes(rig: Rig) -> tuple[int, int, int]:
    """DB11.DBX6.0 AUTO, 6.1 MDA, 6.2 JOG as the NC shows them."""
    return (int(rig.get("MODEGROUP.basic.in.autoModeActive")),
            int(rig.get("MODEGROUP.basic.in.mdaModeActive")),
            int(rig.get("MODEGROUP.basic.in.jogModeActive")))


def select(rig: Rig, auto: int, mda: int, jog: int) -> None:
    rig.set("MODEGROUP.basic.out.autoMode", auto)
    rig.set("MODEGROUP.basic.out.mdaMode", mda)
    rig.set("MODEGROUP.basic.out.jogMode", jog)
    rig.step(2)


# ------------------------------------------------------------------------------ NCK and mode group status


def test_power_on_nck_and_mode_group_status() -> None:
    rig = Rig(machine())
    rig.step(1)
    assert rig.get("NC.basic.in.ncReady") == 1  # DB10.DBX108.7
    assert rig.get("NC.basic.in.emergencyStopActive") == 0  # DB10.DBX106.1
    assert rig.get("NC.basic.in.alarmActive") == 0
    assert rig.get("MODEGROUP.basic.in.ready") == 1  # DB11.DBX6.3
    assert modes(rig) == (0, 0, 1)  # JOG after power-on


# ------------------------------------------------------------------------------ mode selection


@pytest.mark.parametrize(("request_bits", "active"), [
    ((1, 0, 0), (1, 0, 0)),
    ((0, 1, 0), (0, 1, 0)),
    ((0, 0, 1), (0, 0, 1)),
    ((1, 1, 0), (0, 1, 0)),  # MDA before AUTO
    ((1, 0, 1), (0, 0, 1)),  # JOG before AUTO
    ((0, 1, 1), (0, 0, 1)),  # JOG before MDA
    ((1, 1, 1), (0, 0, 1)),  # JOG before MDA before AUTO
])
def test_mode_priority_jog_over_mda_over_auto(request_bits: tuple[int, int, int],
                                              active: tuple[int, int, int]) -> None:
    rig = Rig(machine())
    select(rig, 1, 0, 0)  # start from AUTO so that every case is a change
    select(rig, *request_bits)
    assert modes(rig) == active


def test_no_mode_request_keeps_the_active_mode() -> None:
    rig = Rig(machine())
    select(rig, 0, 1, 0)
    select(rig, 0, 0, 0)
    assert modes(rig) == (0, 1, 0)


def test_mode_change_is_refused_while_the_program_runs_and_applied_after_reset() -> None:
    rig = Rig(machine(ABSOLUTE_XYZ))
    rig.ready_mda()
    rig.mda("G1 X200 F1000")
    rig.step(10)
    select(rig, 0, 0, 1)  # JOG requested
    rig.step(50)
    assert modes(rig) == (0, 1, 0)
    assert rig.get("CHAN1.basic.in.progStateRunning") == 1
    rig.pulse("CHAN1.basic.out.reset")
    rig.step(10)
    assert modes(rig) == (0, 0, 1)


def test_mode_change_while_the_program_is_stopped_interrupts_it_and_nc_start_in_mda_continues() -> None:
    rig = Rig(machine(ABSOLUTE_XYZ))
    rig.ready_mda()
    x1 = rig.axis("X1")
    rig.mda("G1 X160 F1000")
    rig.step(50)
    rig.pulse("CHAN1.basic.out.ncStop")
    rig.step(10)
    select(rig, 0, 0, 1)
    assert modes(rig) == (0, 0, 1)
    assert rig.get("CHAN1.basic.in.progStateInterrupted") == 1  # 35.3
    assert rig.get("CHAN1.basic.in.stateInterrupted") == 1  # 35.6
    select(rig, 0, 1, 0)
    rig.pulse("CHAN1.basic.out.ncStart")
    rig.run_until(lambda: rig.get("CHAN1.basic.in.stateReset") == 1, 1000)
    assert x1.setpoint == 160.0


def test_mode_group_reset_aborts_the_program_of_its_channels() -> None:
    rig = Rig(machine(ABSOLUTE_XYZ))
    rig.ready_mda()
    rig.mda("G1 X200 F1000")
    rig.step(50)
    rig.pulse("MODEGROUP.basic.out.reset")  # DB11.DBX0.7
    rig.step(10)
    assert rig.get("CHAN1.basic.in.stateReset") == 1
    assert rig.get("CHAN1.basic.in.progStateAborted") == 1
    assert rig.axis("X1").command_velocity == 0.0


def test_machine_function_ref_is_shown_in_jog_and_mda_but_not_in_auto() -> None:
    rig = Rig(machine())
    rig.set("MODEGROUP.basic.out.refPoint", 1)  # DB11.DBX1.2
    select(rig, 0, 0, 1)
    assert rig.get("MODEGROUP.basic.in.refPointActive") == 1  # DB11.DBX7.2
    select(rig, 0, 1, 0)
    assert rig.get("MODEGROUP.basic.in.refPointActive") == 1
    select(rig, 1, 0, 0)
    assert rig.get("MODEGROUP.basic.in.refPointActive") == 0
    assert rig.nck.mode_group.mode is Mode.AUTO


# ------------------------------------------------------------------------------ emergency stop


def estop_rig() -> Rig:
    """basic_machine PLC, X1 and Z1 in JOG with rapid overlay at 166.67 mm/s."""
    rig = Rig(machine(ABSOLUTE_XYZ), plc="basic_machine")
    rig.step(100)  # drives ready after 100 ms, enables
    rig.press("MCP.rapid")
    rig.press("MCP.plus.X1")
    rig.press("MCP.plus.Z1")
    rig.step(100)
    assert rig.axis("X1").velocity == pytest.approx(10000.0 / 60.0)
    assert rig.axis("Z1").velocity == pytest.approx(10000.0 / 60.0)
    return rig


def test_emergency_stop_raises_3000_and_stops_every_moving_axis() -> None:
    rig = estop_rig()
    axes = [rig.axis("X1"), rig.axis("Z1")]
    rig.press("EStop.chainOk", 0)  # the operator presses the button: the NC contact opens
    delay = rig.run_until(lambda: rig.get("NC.basic.in.emergencyStopActive") == 1, 20)
    assert delay <= 2 * rig.sim.plc_period + 1  # the PLC passes it on within two scans
    assert 3000 in rig.alarm_numbers()
    assert rig.get("NC.basic.out.emergencyStop") == 1  # DB10.DBX56.1 from the PLC
    assert rig.get("NC.basic.in.alarmActive") == 1
    # The setpoints stop on the rapid-stop ramp: 166.67 mm/s at 500 / 0.05 = 10000 mm/s^2 in
    # ceil(166.67 / 20) = 9 cycles, well inside MD36610 = 50 ms = 25 cycles.
    setpoint_stop = rig.run_until(lambda: all(a.command_velocity == 0.0 for a in axes), 100)
    assert setpoint_stop <= 9
    # The slides follow within the position loop's settling: MD36610 + 3 / Kv = 0.05 + 0.18 s.
    standstill = rig.run_until(lambda: all(abs(a.velocity) <= a.dyn.standstill_velocity for a in axes), 200)
    assert (setpoint_stop + standstill) * DT <= 0.05 + 3 / 16.667
    braking = [a.physical for a in axes]
    rig.step(200)
    assert [a.physical for a in axes] == pytest.approx(braking, abs=1e-3)
    assert rig.get("X1.basic.in.isStationary") == 1 and rig.get("Z1.basic.in.isStationary") == 1


def test_emergency_stop_removes_the_controller_enable_after_md36620() -> None:
    rig = estop_rig()
    rig.press("EStop.chainOk", 0)
    rig.run_until(lambda: rig.get("NC.basic.in.emergencyStopActive") == 1, 20)
    # MD36620 = 0.1 s = 50 cycles after the rapid stop: position control off, follow-up
    rig.step(50 + 5)
    assert rig.get("X1.basic.in.posCtrlActive") == 0
    assert rig.get("X1.basic.in.followUpModeActive") == 1


def test_nc_start_is_refused_during_emergency_stop() -> None:
    rig = Rig(machine(ABSOLUTE_XYZ), plc="basic_machine")
    rig.step(100)
    rig.press("EStop.chainOk", 0)
    rig.step(20)
    rig.tap("MCP.mda")
    assert modes(rig) == (0, 1, 0)
    rig.sim.load_mda("CHAN1", "G1 X160 F1000")
    rig.press("MCP.ncStart")
    for _ in range(100):
        rig.step()
        assert rig.get("CHAN1.basic.in.progStateRunning") == 0
    assert rig.axis("X1").physical == pytest.approx(150.0, abs=1e-9)


def test_after_the_chain_closes_the_reset_key_clears_3000_and_jog_works_again() -> None:
    rig = estop_rig()
    rig.press("EStop.chainOk", 0)
    rig.step(400)
    for key in ("MCP.plus.X1", "MCP.plus.Z1", "MCP.rapid"):
        rig.release(key)
    rig.press("EStop.chainOk", 1)
    rig.step(100)
    assert 3000 in rig.alarm_numbers()  # closing the chain alone does not clear it
    rig.press("MCP.reset")  # the PLC gives DB10.DBX56.2 and the channel reset together
    rig.run_until(lambda: rig.get("NC.basic.out.emergencyStopAck") == 1, 20)
    rig.step(2 * rig.sim.plc_period)
    rig.release("MCP.reset")
    assert 3000 not in rig.alarm_numbers()
    assert rig.get("NC.basic.in.emergencyStopActive") == 0
    rig.step(100)  # drives on -> ready after 100 ms -> enables
    x1 = rig.axis("X1")
    start = x1.actual
    rig.press("MCP.plus.X1")
    rig.step(100)
    assert x1.actual - start > 2.0  # 33.3 mm/s for ~0.18 s


def test_emergency_stop_ack_without_reset_does_not_clear_3000() -> None:
    rig = Rig(machine(ABSOLUTE_X1))
    rig.enable_axes()
    rig.set("NC.basic.out.emergencyStop", 1)
    rig.step(5)
    assert rig.get("NC.basic.in.emergencyStopActive") == 1
    rig.set("NC.basic.out.emergencyStop", 0)
    rig.set("NC.basic.out.emergencyStopAck", 1)
    rig.step(20)
    assert 3000 in rig.alarm_numbers()
    rig.pulse("CHAN1.basic.out.reset")
    rig.step(2)
    assert 3000 not in rig.alarm_numbers()
    assert rig.get("NC.basic.in.emergencyStopActive") == 0


def test_reset_while_the_emergency_stop_button_is_still_pressed_does_not_clear_3000() -> None:
    rig = Rig(machine(ABSOLUTE_X1))
    rig.enable_axes()
    rig.set("NC.basic.out.emergencyStop", 1)
    rig.set("NC.basic.out.emergencyStopAck", 1)
    rig.step(5)
    rig.pulse("CHAN1.basic.out.reset")
    rig.step(5)
    assert 3000 in rig.alarm_numbers()
    assert rig.get("NC.basic.in.emergencyStopActive") == 1


def test_emergency_stop_interrupts_a_running_program() -> None:
    rig = Rig(machine(ABSOLUTE_XYZ))
    rig.ready_mda()
    rig.mda("G1 X200 F1000")
    rig.step(50)
    rig.set("NC.basic.out.emergencyStop", 1)
    rig.step(20)
    assert rig.get("CHAN1.basic.in.progStateRunning") == 0
    assert rig.axis("X1").command_velocity == 0.0


# ------------------------------------------------------------------------------ determinism


def drive(rig: Rig) -> None:
    """One fixed operator sequence: JOG X1 with override changes, then an MDA program."""
    rig.step(100)
    rig.press("MCP.plus.X1")
    rig.step(37)
    rig.press("MCP.feedOverride", 63)
    rig.step(41)
    rig.release("MCP.plus.X1")
    rig.press("MCP.minus.Z1")
    rig.step(29)
    rig.release("MCP.minus.Z1")
    rig.tap("MCP.mda")
    rig.sim.load_mda("CHAN1", "G1 X170 Z280 F2000\nG4 F0.05\nG0 X160")
    rig.tap("MCP.ncStart")
    rig.step(233)


def test_same_inputs_give_byte_identical_images() -> None:
    first = Rig(machine(ABSOLUTE_XYZ), plc="basic_machine")
    second = Rig(machine(ABSOLUTE_XYZ), plc="basic_machine")
    drive(first)
    drive(second)
    assert first.sim.cycle == second.sim.cycle
    assert first.nck.image.snapshot() == second.nck.image.snapshot()
    assert first.sim.interface.snapshot() == second.sim.interface.snapshot()
    assert first.sim.plant_image.snapshot() == second.sim.plant_image.snapshot()
    assert [a.physical for a in first.nck.axes] == [a.physical for a in second.nck.axes]
    # ... and the comparison is not trivially true: the run did move the axes
    assert first.axis("X1").physical != 150.0


def test_a_different_input_gives_different_images() -> None:
    first = Rig(machine(ABSOLUTE_XYZ), plc="basic_machine")
    second = Rig(machine(ABSOLUTE_XYZ), plc="basic_machine")
    drive(first)
    second.press("MCP.feedOverride", 64)  # one percent more override
    drive(second)
    assert [a.physical for a in first.nck.axes] != [a.physical for a in second.nck.axes]


# ------------------------------------------------------------------------------ axis alarms with a rapid stop


@pytest.mark.parametrize("number", [21610, 25040, 25050, 25080])
def test_an_axis_alarm_takes_the_controller_enable_and_reset_gives_it_back(number: int) -> None:
    rig = Rig(machine(ABSOLUTE_X1))
    rig.enable_axes()
    rig.step(5)
    assert rig.get("X1.basic.in.posCtrlActive") == 1
    rig.nck.alarms.raise_alarm(number, rig.nck.cycle, "CHAN1", "X1", 1, channel="CHAN1", axis="X1")
    rig.step(50 + 5)  # MD36620 = 0.1 s after the rapid stop
    assert rig.get("X1.basic.in.posCtrlActive") == 0
    assert rig.get("X1.basic.in.followUpModeActive") == 1
    assert rig.get("Z1.basic.in.posCtrlActive") == 1  # the alarm belongs to X1 alone
    rig.pulse("CHAN1.basic.out.reset")
    rig.step(3)
    assert rig.alarm_numbers() == []
    assert rig.get("X1.basic.in.posCtrlActive") == 1


def test_reset_does_not_give_the_enable_back_while_the_emergency_stop_is_on() -> None:
    rig = Rig(machine(ABSOLUTE_X1), plc="basic_machine")
    rig.step(60)
    rig.nck.alarms.raise_alarm(25050, rig.nck.cycle, "X1", channel="CHAN1", axis="X1")
    rig.press("EStop.chainOk", 0)
    rig.step(80)
    rig.pulse("CHAN1.basic.out.reset")  # clears 25050, not 3000: the chain is still open
    rig.step(5)
    assert rig.alarm_numbers() == [3000]
    assert rig.get("X1.basic.in.posCtrlActive") == 0
