"""What the NC publishes for observers through the composed machine (vc/simulation/published.py):
the state view of the present power-on, the alarm list, the functions of an axis or channel; and
reading it changes nothing the NC does."""

from __future__ import annotations

from pathlib import Path

import pytest

from vc.config.loader import load_machine
from vc.simulation.lockstep import Simulation
from vc.simulation.published import STATE_MACHINES, NcFunction, StateReading

ROOT = Path(__file__).resolve().parents[3]
MACHINES = ROOT / "scenarios" / "machines"


def mda_simulation() -> Simulation:
    """turn_mill with its basic PLC, X1 referenced at power-on, an MDA program moving X1 and turning SP1."""
    from vc.located_yaml import load_text

    overrides, problems = load_text("CHAN1: {MD20700: 0}\nX1: {MD30240: [4], MD34210: [2]}", "<test>")
    assert not problems
    simulation = Simulation(load_machine(str(MACHINES / "turn_mill.yaml"), overrides, "<test>"), "spindle")
    simulation.load_mda("CHAN1", "G1 X120 F2000\nM3 S500\nG4 F0.2\nM5\nM30")
    return simulation


def press(simulation: Simulation, key: str, cycles: int) -> None:
    simulation.write(simulation.plant_io.resolve(key), 1)
    simulation.step(cycles)
    simulation.write(simulation.plant_io.resolve(key), 0)


def test_reading_every_state_every_cycle_changes_nothing() -> None:
    read, unread = mda_simulation(), mda_simulation()
    seen: set[tuple[str, str]] = set()
    for simulation in (read, unread):
        simulation.step(100)
        press(simulation, "MCP.mda", 10)
        press(simulation, "MCP.ncStart", 10)
    view = read.state_view()
    for _ in range(800):
        read.step()
        unread.step()
        seen.update((reading.machine, reading.state) for reading in view)
    assert ("program", "RUNNING") in seen and ("program", "ABORTED") in seen
    assert read.image_areas() == unread.image_areas()
    assert [(a.number, a.cycle) for a in read.alarm_history()] == [(a.number, a.cycle) for a in unread.alarm_history()]


def test_a_power_cycle_publishes_the_new_power_on() -> None:
    simulation = mda_simulation()
    before = simulation.state_view()
    simulation.power_cycle()
    after = simulation.state_view()
    assert after is not before and after is simulation.nck.state_view()
    assert [reading.machine for reading in after] == [reading.machine for reading in before]
    assert simulation.alarm_list is simulation.nck.alarms


def test_every_reading_is_names_of_a_declared_state() -> None:
    simulation = mda_simulation()
    declared = {machine.name: machine for machine in STATE_MACHINES}
    readings = list(simulation.state_view())
    assert readings and all(isinstance(reading, StateReading) for reading in readings)
    for reading in readings:
        assert declared[reading.machine].state(reading.state) is not None


@pytest.mark.parametrize(("machine", "instance", "functions"), [
    ("turn_mill", "SP1", {NcFunction.SPINDLE}),
    ("turn_mill", "X1", set()),
    ("turn_mill", "CHAN1", {NcFunction.INCLINED_AXIS}),
    ("mill_5axis", "CHAN1", {NcFunction.FIVE_AXIS}),
    ("mill_3axis", "CHAN1", set()),
    ("mill_3axis", "NOTHING", set()),
])
def test_the_functions_an_axis_or_a_channel_has(machine: str, instance: str, functions: set[NcFunction]) -> None:
    simulation = Simulation(load_machine(str(MACHINES / f"{machine}.yaml")), None)
    assert simulation.functions_of(instance) == functions
