"""The lockstep simulation: NC, plant and PLC, time, signal access, forces and HMI access.

Turn-mill: IPO cycle 2 ms, OB1 every 5 IPO cycles (10 ms).  X1 is given a calibrated
absolute encoder (referenced, actual = physical = 150) and MD20700 = 0.
"""

from __future__ import annotations

from pathlib import Path

import pytest

from interfaces.links.inprocess import UnknownPlcProgram
from vc.config.loader import load_machine
from vc.config.model import MachineConfig
from vc.located_yaml import load_text
from vc.simulation.lockstep import AXIS_QUANTITIES, Simulation

ROOT = Path(__file__).resolve().parents[3]
TURN_MILL = str(ROOT / "scenarios" / "machines" / "turn_mill.yaml")


@pytest.fixture(scope="module")
def config() -> MachineConfig:
    overrides, problems = load_text("CHAN1: {MD20700: 0}\nX1: {MD30240: [4], MD34210: [2]}", "<test>")
    assert not problems
    return load_machine(TURN_MILL, overrides, "<test>")


def key(sim: Simulation, name: str, value: int = 1) -> None:
    sim.write(sim.plant_io.resolve(name), value)


def signal(sim: Simulation, name: str) -> float:
    return sim.read(sim.catalog.resolve(name))


def set_signal(sim: Simulation, name: str, value: int) -> None:
    sim.write(sim.catalog.resolve(name), value)


# ------------------------------------------------------------------------------ time


def test_time_counts_ipo_cycles(config: MachineConfig) -> None:
    sim = Simulation(config, plc=None)
    assert (sim.cycle, sim.time_s, sim.ipo_cycle_us) == (0, 0.0, 2000)
    sim.step()
    sim.step(249)
    assert sim.cycle == 250
    assert sim.time_s == pytest.approx(0.5)
    assert sim.plc_period == 5


def test_power_on_state_of_plant_and_plc(config: MachineConfig) -> None:
    sim = Simulation(config)
    # the plant has set the panel and the switches; the PLC has run its first scan
    assert sim.read(sim.plant_io.resolve("EStop.chainOk")) == 1
    assert sim.read(sim.plant_io.resolve("MCP.feedOverride")) == 100
    assert sim.read(sim.plant_io.resolve("X1.hwLimitPlus")) == 1
    sim.step(5)  # second scan: the first outputs are published
    assert signal(sim, "MODEGROUP.basic.out.jogMode") == 1
    assert sim.read(sim.plant_io.resolve("Drives.on")) == 1


def test_drives_become_ready_and_the_plc_gives_the_enables(config: MachineConfig) -> None:
    sim = Simulation(config)
    sim.step(120)  # Drives.on at 10 ms, ready 100 ms later, enables one or two scans after that
    assert sim.read(sim.plant_io.resolve("Drives.ready")) == 1
    assert signal(sim, "X1.basic.out.enableCtrl") == 1
    assert signal(sim, "X1.basic.in.posCtrlActive") == 1


# ------------------------------------------------------------------------------ the PLC scan and its latency


def test_panel_key_reaches_the_nc_two_scans_and_one_cycle_later(config: MachineConfig) -> None:
    sim = Simulation(config)
    sim.step(100)  # a scan has just run (cycle 100 = 20 * 5)
    key(sim, "MCP.plus.X1")
    axis = sim.nck.axes_by_name["X1"]
    cycles = 0
    while axis.command_velocity == 0.0:
        sim.step()
        cycles += 1
        assert cycles < 30
    # scan at 105 reads the key, scan at 110 publishes DB31.DBX4.7, the NC reads it in cycle 111
    assert cycles == 11


def test_nc_outputs_reach_the_interface_only_at_the_plc_cycle(config: MachineConfig) -> None:
    sim = Simulation(config, plc=None)
    set_signal(sim, "X1.basic.out.enableCtrl", 1)
    set_signal(sim, "X1.drive.out.enablePulses", 1)
    set_signal(sim, "X1.basic.out.enc1Activation", 1)  # measuring system 1, else the axis is parked
    set_signal(sim, "X1.basic.out.feedrateOvrFactor", 100)  # binary 0 would be 0 % even when inactive
    set_signal(sim, "MODEGROUP.basic.out.jogMode", 1)
    sim.step(5)
    command = sim.catalog.resolve("X1.basic.in.traversPlusCommandActive")
    set_signal(sim, "X1.basic.out.traversKeyPlus", 1)
    sim.step(1)  # cycle 6: the NC sets 64.7 at once
    assert sim.read(command) == 1  # read() shows the NC's own image
    assert sim.interface.read(command) == 0  # the wire is updated at the next PLC cycle
    sim.step(3)  # cycle 9
    assert sim.interface.read(command) == 0
    sim.step(1)  # cycle 10
    assert sim.interface.read(command) == 1


def test_without_plc_the_test_writes_the_plc_outputs(config: MachineConfig) -> None:
    sim = Simulation(config, plc=None)
    assert sim.plc is None
    sim.step(100)
    assert signal(sim, "X1.basic.out.enableCtrl") == 0  # nobody gives the enables
    set_signal(sim, "X1.basic.out.enableCtrl", 1)
    set_signal(sim, "X1.drive.out.enablePulses", 1)
    set_signal(sim, "X1.basic.out.enc1Activation", 1)  # measuring system 1, else the axis is parked
    sim.step(1)
    assert signal(sim, "X1.basic.in.posCtrlActive") == 1


def test_unknown_plc_program_names_the_known_ones(config: MachineConfig) -> None:
    with pytest.raises(UnknownPlcProgram, match="basic_machine"):
        Simulation(config, plc="no_such_program")


# ------------------------------------------------------------------------------ forces


def test_forced_plc_output_wins_over_the_plc_program(config: MachineConfig) -> None:
    sim = Simulation(config)
    sim.step(120)
    enable = sim.catalog.resolve("X1.basic.out.enableCtrl")
    sim.force(enable, 0)
    sim.step(50)  # the PLC writes 1 every scan
    assert sim.read(enable) == 0
    assert sim.nck.axes_by_name["X1"].inputs.controller_enable is False
    sim.release(enable)
    sim.step(10)
    assert sim.read(enable) == 1


def test_forced_nc_output_is_what_the_plc_and_the_reader_see(config: MachineConfig) -> None:
    sim = Simulation(config)
    sim.step(120)
    fine = sim.catalog.resolve("X1.basic.in.posFineReached")
    assert sim.read(fine) == 1
    sim.force(fine, 0)
    assert sim.read(fine) == 0
    sim.step(10)
    assert sim.interface.read(fine) == 0  # the PLC's view
    assert sim.nck.image.read(fine) == 1  # the NC itself is unchanged
    sim.release(fine)
    sim.step(5)
    assert sim.read(fine) == 1
    assert sim.interface.read(fine) == 1


def test_forced_plant_input_wins_over_the_plant(config: MachineConfig) -> None:
    sim = Simulation(config)
    sim.step(20)
    cam = sim.plant_io.resolve("X1.refCam")
    assert sim.read(cam) == 0  # X1 at 150, the cam is at 280 .. 295
    sim.force(cam, 1)
    sim.step(20)
    assert sim.read(cam) == 1
    assert signal(sim, "X1.basic.out.refPointApproachCam") == 1  # the PLC copied the forced input


def test_released_plant_input_returns_to_the_plant_value(config: MachineConfig) -> None:
    # Releasing a force hands the input back to its owner: the next plant step writes the
    # real switch state again (the slide is still off the cam), as a PLC force table does.
    sim = Simulation(config)
    sim.step(20)
    cam = sim.plant_io.resolve("X1.refCam")
    sim.force(cam, 1)
    sim.step(20)
    sim.release(cam)
    sim.step(20)
    assert sim.read(cam) == 0
    assert signal(sim, "X1.basic.out.refPointApproachCam") == 0


def test_forced_signal_wins_over_a_write_when_the_scenario_is_the_plc(config: MachineConfig) -> None:
    # "Forces are applied where their owner writes, so a forced value is what the reader sees"
    # (simulation.py): with plc=None the scenario owns the PLC->NC signals.
    sim = Simulation(config, plc=None)
    enable = sim.catalog.resolve("X1.basic.out.enableCtrl")
    sim.force(enable, 0)
    sim.write(enable, 1)
    sim.step(10)
    assert sim.read(enable) == 0
    assert sim.nck.axes_by_name["X1"].inputs.controller_enable is False


# ------------------------------------------------------------------------------ axis quantities


def test_axis_quantities_in_display_units(config: MachineConfig) -> None:
    sim = Simulation(config)
    sim.step(120)
    key(sim, "MCP.plus.X1")
    sim.step(100)
    axis = sim.nck.axes_by_name["X1"]
    assert sim.axis_quantity("X1", "velocity") == pytest.approx(2000.0)  # mm/min, MD32020
    assert sim.axis_quantity("X1", "position") == axis.actual
    assert sim.axis_quantity("X1", "physical") == axis.physical
    assert sim.axis_quantity("X1", "setpoint") == axis.setpoint
    assert sim.axis_quantity("X1", "followingError") == pytest.approx(axis.following_error)
    assert sim.axis_quantity("X1", "position") > 150.0
    assert sim.axis_quantity("X1", "programPosition") == pytest.approx(axis.actual)  # Y1 at 0: Cartesian X = X1
    assert set(AXIS_QUANTITIES) == {"position", "setpoint", "velocity", "followingError", "physical",
                                    "programPosition", "drfOffset", "couplingOffset", "couplingOffsetActual",
                                    "couplingOffsetProgrammed", "couplingCorrection", "syncDeviation",
                                    "couplingRelationError"}
    assert sim.axis_quantity("SP2", "couplingOffset") == 0.0  # follows nobody
    assert sim.axis_quantity("X1", "drfOffset") == 0.0  # no DRF in JOG


def test_unknown_axis_quantity_lists_the_known_ones(config: MachineConfig) -> None:
    sim = Simulation(config, plc=None)
    with pytest.raises(KeyError, match="followingError"):
        sim.axis_quantity("X1", "speed")


def test_unknown_channel_quantity_or_instance_says_so(config: MachineConfig) -> None:
    sim = Simulation(config, plc=None)
    assert sim.axis_quantity("CHAN1", "tcpActive") == 0.0
    with pytest.raises(KeyError, match=r"unknown channel quantity 'position' .*toolTipX"):
        sim.axis_quantity("CHAN1", "position")
    with pytest.raises(KeyError, match="'X9' is neither an axis nor a channel"):
        sim.axis_quantity("X9", "position")


# ------------------------------------------------------------------------------ alarms and HMI


def test_alarm_history_keeps_alarms_that_are_gone(config: MachineConfig) -> None:
    sim = Simulation(config, plc=None)
    set_signal(sim, "X1.basic.out.enableCtrl", 1)
    set_signal(sim, "X1.drive.out.enablePulses", 1)
    set_signal(sim, "X1.basic.out.enc1Activation", 1)  # measuring system 1, else the axis is parked
    set_signal(sim, "MODEGROUP.basic.out.mdaMode", 1)
    sim.step(2)
    sim.load_mda("CHAN1", "G1 X160")  # no feed: alarm 10860
    set_signal(sim, "CHAN1.basic.out.ncStart", 1)
    sim.step(5)
    assert [a.number for a in sim.alarms()] == [10860]
    set_signal(sim, "CHAN1.basic.out.ncStart", 0)
    set_signal(sim, "CHAN1.basic.out.reset", 1)
    sim.step(2)
    assert list(sim.alarms()) == []
    assert [a.number for a in sim.alarm_history()] == [10860]


def test_selected_program_runs_in_auto(config: MachineConfig) -> None:
    sim = Simulation(config, plc=None)
    set_signal(sim, "X1.basic.out.enableCtrl", 1)
    set_signal(sim, "X1.drive.out.enablePulses", 1)
    set_signal(sim, "X1.basic.out.enc1Activation", 1)  # measuring system 1, else the axis is parked
    set_signal(sim, "CHAN1.basic.out.pathFeedrateOvr", 1)
    set_signal(sim, "CHAN1.basic.out.pathFeedrateOvrFactor", 100)
    set_signal(sim, "MODEGROUP.basic.out.autoMode", 1)
    sim.select_program("CHAN1", "TEST.MPF", "N10 G1 X151 F3000\nN20 M30")
    sim.load_mda("CHAN1", "G1 X200 F3000")  # the MDA buffer is not what AUTO runs
    sim.step(2)
    set_signal(sim, "CHAN1.basic.out.ncStart", 1)
    sim.step(200)
    assert sim.nck.axes_by_name["X1"].setpoint == 151.0
    assert signal(sim, "CHAN1.basic.in.stateReset") == 1


def test_a_fault_the_machine_cannot_have_now_fails_the_step_instead_of_the_run(tmp_path: Path) -> None:
    """A workpiece clamp on a spindle that follows none ended the run in a KeyError traceback."""
    from interfaces.links.inprocess import plc_programs
    from vc.harness.targets import simulation_for
    from vc.scenario.language.loader import load_scenarios
    from vc.scenario.run.runner import run_scenarios

    path = tmp_path / "clamp.yaml"
    path.write_text(f"name: clamp\nmachine: {TURN_MILL}\nplc: basic_machine\nsteps:\n  - wait: 20ms\n"
                    "  - fault: {axis: SP2, kind: workpiece_clamp, by: 4}\n", encoding="utf-8")
    (result,) = run_scenarios(load_scenarios([str(path)], plc_programs()), simulation_for)
    assert not result.error
    assert result.failure is not None and result.failure.mark.line == 6
    assert result.failure.message == "workpiece_clamp: SP2 is not the following spindle of a coupling now"
