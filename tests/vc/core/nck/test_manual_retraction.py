"""Rigid tapping G331 / G332 and manual retraction along the tool axis (seed 003 §13.2.8, §16.12).

The test is the PLC: it gives the enables, reports SP1's gear stage and selects the retraction
with the project's PI-service request DB21.DBX396.0.
"""

from __future__ import annotations

import pytest
from core_rig import MILL, Rig, machine, spindle_rig

from vc.config.model import MachineConfig
from vc.core.nc_memory import RetractData

# X1, Y1, Z1 absolute and calibrated; SP1 restores its position (MD34210 = 3) and ramps with 40 rev/s^2.
BASE = ("X1: {MD30240: [4], MD34210: [2]}\nY1: {MD30240: [4], MD34210: [2]}\nZ1: {MD30240: [4], MD34210: [2]}\n"
        "SP1: {MD34210: [3], MD32300: [40, 40, 40, 40, 40]}\n")
TAPPING = "SPOS=0\nG0 Z-300\nG331 Z-320 K2 S600\nG332 Z-300 K2\nM30"


def mill(extra: str = "CHAN1: {MD20700: 0}") -> MachineConfig:
    return machine(BASE + extra, MILL)


def prepared(rig: Rig, mode: str = "mda") -> Rig:
    rig.enable_axes()
    rig.channel_overrides()
    rig.set("SP1.spindle.out.gearStageSelection", 1)
    rig.set("SP1.spindle.out.ovrFactor", 100)
    rig.select_mode(mode)
    rig.step(12)
    return rig


def abort_tapping_by_power_failure(config: MachineConfig, below: float = -310.0) -> Rig:
    rig = prepared(Rig(config))
    rig.mda(TAPPING)
    rig.run_until(lambda: rig.axis("Z1").actual < below, 20_000, 10)
    rig.sim.power_cycle(1.0)
    rig.nck = rig.sim.nck
    return prepared(rig, mode="")


def select(rig: Rig, wcs: bool = True) -> tuple[int, int]:
    """The PI service RETRAC: request, answer (done, refused), request off; then the PLC shows
    the WCS (DB19.DBX0.7), or leaves the MCS with ``wcs=False``."""
    rig.set("CHAN1.piService.out.retracRequest", 1)
    rig.step(2)
    answer = (int(rig.get("CHAN1.piService.in.retracDone")), int(rig.get("CHAN1.piService.in.retracError")))
    rig.set("CHAN1.piService.out.retracRequest", 0)
    rig.set("HMI.basic.out.displayWcsValues", int(wcs))
    rig.step(2)
    return answer


def jog(rig: Rig, axis: str, key: str, cycles: int) -> None:
    rig.set(f"{axis}.basic.out.traversKey{key}", 1)
    rig.step(cycles)
    rig.set(f"{axis}.basic.out.traversKey{key}", 0)
    rig.step(400)


# ------------------------------------------------------------------------------ G331 / G332


def test_g331_interpolates_the_spindle_with_the_drilling_axis_and_g332_reverses_it() -> None:
    rig = prepared(Rig(mill()))
    z, spindle = rig.axis("Z1"), rig.axis("SP1")
    rig.mda(TAPPING)
    rig.run_until(lambda: z.actual < -310.0, 20_000)
    assert z.display_velocity == pytest.approx(-1200.0, abs=0.01)  # F = S x pitch = 600 x 2 (L8573-8581)
    assert spindle.display_velocity == pytest.approx(600.0, abs=0.01)  # K > 0: M3 (L17626-17628)
    assert rig.channel.modal.thread == "G331"
    rig.run_until(lambda: z.actual > -310.0 and rig.channel.modal.thread == "G332", 20_000)
    assert spindle.display_velocity == pytest.approx(-600.0, abs=0.01)  # G332: reversed (L17662-17664)
    rig.run_until(lambda: rig.get("CHAN1.basic.in.stateReset") == 1, 20_000)
    rig.step(100)
    assert z.actual == pytest.approx(-300.0, abs=1e-3) and spindle.actual == pytest.approx(360.0, abs=1e-3)


@pytest.mark.parametrize(("block", "alarm"), [
    ("G331 Z-320 S600", 12080),  # no pitch
    ("G331 Z-320 I2 S600", 12080),  # the pitch of another axis
    ("G331 Z-320 K2500 S600", 12080),  # beyond 2000 mm/rev (L17675)
    ("G331 X10 Z-320 K2 S600", 12080),  # two drilling axes
    ("G331 Z-320 K2", 14800),  # no spindle speed programmed before
    ("G1 Z-320 K2 F100", 12550),  # K outside a thread is no axis
])
def test_faulty_tapping_blocks_raise_the_alarm_of_the_control(block: str, alarm: int) -> None:
    rig = prepared(Rig(mill()))
    rig.mda(f"SPOS=0\n{block}")
    rig.step(3000)
    assert alarm in rig.alarm_numbers()
    assert rig.axis("Z1").actual == pytest.approx(-200.0)


# ------------------------------------------------------------------------------ retract data


def test_power_failure_during_g331_keeps_the_retract_data_and_md10721_selects_jog() -> None:
    rig = abort_tapping_by_power_failure(mill("CHAN1: {MD20700: 0}\nNC: {MD10720: [0], MD10721: [1]}"))
    data = rig.nck.memory.retract["CHAN1"]
    assert isinstance(data, RetractData)
    assert (data.tool_axis, data.spindle) == ("Z1", "SP1")
    assert data.spindle_per_mm == pytest.approx(-180.0)  # 360 degrees per 2 mm, back up when Z rises
    assert rig.get("CHAN1.basic.in.jogRetractDataAvailable") == 1
    assert rig.get("MODEGROUP.basic.in.jogModeActive") == 1  # MD10720 = 0 would be AUTOMATIC


def test_without_md10721_the_mode_of_md10720_comes_after_power_on() -> None:
    rig = abort_tapping_by_power_failure(mill("CHAN1: {MD20700: 0}\nNC: {MD10720: [0]}"))
    assert rig.get("CHAN1.basic.in.jogRetractDataAvailable") == 1
    assert rig.get("MODEGROUP.basic.in.autoModeActive") == 1


def test_a_reset_outside_a_thread_keeps_no_data() -> None:
    rig = prepared(Rig(mill()))
    rig.mda("G1 Z-320 F1000")
    rig.step(200)
    rig.pulse("CHAN1.basic.out.reset", 3)
    rig.step(5)
    assert rig.nck.memory.retract == {} and rig.get("CHAN1.basic.in.jogRetractDataAvailable") == 0


def test_a_reset_in_g33_keeps_the_lead_axis_the_thread_spindle_and_360_over_the_lead() -> None:
    rig = spindle_rig()  # turn-mill, SP1 the master spindle
    rig.mda("N10 M3 S500 G90 G18\nN20 G0 Z5\nN30 X10\nN40 G33 X60 Z20 K5\nM30")
    rig.run_until(lambda: rig.channel.current_block is not None and rig.channel.current_block.number == 40
                  and rig.axis("X1").actual > 20.0, 20_000)
    rig.pulse("CHAN1.basic.out.reset", 3)
    data = rig.nck.memory.retract["CHAN1"]
    # K names Z: Z1 is the tool axis although X travels farther (50 mm against 15 mm); SP1 turns
    # 360 / 5 degrees per mm of Z1, M3 while Z1 rises
    assert (data.tool_axis, data.spindle) == ("Z1", "SP1")
    assert data.spindle_per_mm == pytest.approx(72.0)


# ------------------------------------------------------------------------------ selection and retraction


def test_selection_needs_jog_and_answers_through_the_pi_service_bits() -> None:
    rig = abort_tapping_by_power_failure(mill("CHAN1: {MD20700: 0}\nNC: {MD10720: [3]}"))
    assert rig.get("MODEGROUP.basic.in.mdaModeActive") == 1
    assert select(rig) == (0, 1)  # MDA: refused
    assert rig.get("CHAN1.basic.in.jogRetractActive") == 0
    rig.select_mode("jog")
    rig.step(2)
    assert select(rig) == (1, 0)
    assert rig.get("CHAN1.basic.in.jogRetractActive") == 1
    assert rig.get("CHAN1.piService.in.retracDone") == 0  # the answer goes with the request


def test_selection_is_refused_when_the_spindle_is_neither_referenced_nor_restored() -> None:
    config = machine(BASE.replace("SP1: {MD34210: [3],", "SP1: {") + "CHAN1: {MD20700: 0}", MILL)
    rig = abort_tapping_by_power_failure(config)
    rig.select_mode("jog")
    rig.step(2)
    assert select(rig) == (0, 1)  # L35441-35443


def test_only_the_tool_axis_plus_moves_and_the_spindle_follows_the_pitch() -> None:
    rig = abort_tapping_by_power_failure(mill())
    rig.select_mode("jog")
    rig.step(2)
    assert select(rig) == (1, 0)
    z, x, spindle = rig.axis("Z1"), rig.axis("X1"), rig.axis("SP1")
    start_z, start_spindle = z.physical, spindle.physical
    jog(rig, "Z1", "Minus", 200)
    jog(rig, "X1", "Plus", 200)
    assert (z.physical, x.physical) == (start_z, 400.0)
    jog(rig, "Z1", "Plus", 300)
    assert z.physical - start_z > 5.0
    assert spindle.physical - start_spindle == pytest.approx(-180.0 * (z.physical - start_z), abs=0.05)


def test_in_the_mcs_the_keys_of_the_tool_axis_do_not_retract() -> None:
    rig = abort_tapping_by_power_failure(mill())
    rig.select_mode("jog")
    rig.step(2)
    assert select(rig, wcs=False) == (1, 0)
    z, spindle = rig.axis("Z1"), rig.axis("SP1")
    start_z, start_spindle = z.physical, spindle.physical
    jog(rig, "Z1", "Plus", 300)
    assert (z.physical, spindle.physical) == (start_z, start_spindle)
    rig.set("HMI.basic.out.displayWcsValues", 1)  # the PLC shows the WCS: the same key retracts
    jog(rig, "Z1", "Plus", 300)
    assert z.physical - start_z > 5.0


def test_md10735_bit_8_enables_the_minus_direction() -> None:
    rig = abort_tapping_by_power_failure(mill("CHAN1: {MD20700: 0}\nNC: {MD10735: 0x100}"))
    rig.select_mode("jog")
    rig.step(2)
    select(rig)
    z, spindle = rig.axis("Z1"), rig.axis("SP1")
    start_z, start_spindle = z.physical, spindle.physical
    jog(rig, "Z1", "Minus", 100)
    assert z.physical < start_z
    assert spindle.physical - start_spindle == pytest.approx(-180.0 * (z.physical - start_z), abs=0.05)


def test_reset_cancels_keeps_the_data_and_nc_start_in_mda_deletes_them() -> None:
    rig = abort_tapping_by_power_failure(mill())
    rig.select_mode("jog")
    rig.step(2)
    select(rig)
    rig.pulse("CHAN1.basic.out.reset", 3)
    rig.step(3)
    assert rig.get("CHAN1.basic.in.jogRetractActive") == 0
    assert rig.get("CHAN1.basic.in.jogRetractDataAvailable") == 1
    assert select(rig) == (1, 0)  # again, from where the axes stand
    rig.select_mode("mda")
    rig.step(2)
    assert rig.get("CHAN1.basic.in.jogRetractActive") == 0  # leaving JOG ends it [control]
    rig.mda("G0 Z-100")
    rig.step(2)
    assert rig.get("CHAN1.basic.in.jogRetractDataAvailable") == 0
    assert rig.nck.memory.retract == {}


def test_nc_stop_pauses_the_retraction_and_nc_start_continues_it() -> None:
    rig = abort_tapping_by_power_failure(mill())
    rig.select_mode("jog")
    rig.step(2)
    select(rig)
    z = rig.axis("Z1")
    rig.set("Z1.basic.out.traversKeyPlus", 1)
    rig.step(200)
    rig.pulse("CHAN1.basic.out.ncStop", 3)
    rig.step(400)
    assert z.velocity == 0.0
    rig.pulse("CHAN1.basic.out.ncStart", 3)
    rig.step(100)
    assert z.velocity > 0.0
