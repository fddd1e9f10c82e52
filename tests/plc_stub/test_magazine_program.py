"""The PLC program magazine and the FC18-like block TraversePosAxis (plc_stub/blocks.py) on
mill_magazine: the block's handshake with the NC (Start held until DBX104.3), its own refusals
(State 1, 20), and the program's T function with the magazine on the PLC axis MG1."""

from __future__ import annotations

from pathlib import Path

import pytest

from plc_stub.blocks import FC18_PARAMETERS, FC18_STILL_RUNNING, TraversePosAxis
from plc_stub.programs.magazine import Magazine, MagazineStep
from vc.config.loader import load_machine
from vc.located_yaml import load_text
from vc.simulation.lockstep import Simulation

MACHINE = Path(__file__).resolve().parents[2] / "scenarios" / "plc_axes" / "machines" / "mill_magazine.yaml"


def _simulation() -> tuple[Simulation, Magazine]:
    document, problems = load_text("CHAN1: {MD20700: 0}", "<test>")
    assert not problems
    sim = Simulation(load_machine(str(MACHINE), document, "<test>"), plc="magazine")
    program = getattr(sim.plc, "program", None)
    assert isinstance(program, Magazine)
    sim.write(sim.plant_io.resolve("MCP.mda"), 1)
    sim.step(20)
    return sim, program


def _mda(sim: Simulation, text: str) -> None:
    sim.load_mda("CHAN1", text)
    start = sim.plant_io.resolve("MCP.ncStart")
    sim.write(start, 1)
    sim.step(12)
    sim.write(start, 0)


def _run_until(sim: Simulation, condition: object, cycles: int) -> None:
    for _ in range(cycles):
        if condition():  # type: ignore[operator]
            return
        sim.step(4)
    raise AssertionError("not reached")


def test_t_words_turn_the_magazine_the_shortest_way_and_hold_the_program_until_it_is_locked() -> None:
    sim, program = _simulation()
    mg1 = sim.nck.axes_by_name["MG1"]
    _mda(sim, "N10 T4\nN20 T11\nN30 M30")
    _run_until(sim, lambda: program.magazine_step is MagazineStep.POSITION and mg1.command_velocity, 200)
    assert mg1.command_velocity > 0.0  # 0 -> 90 degrees
    assert sim.read(sim.catalog.resolve("CHAN1.basic.out.disableReadIn")) == 1
    _run_until(sim, lambda: program.pocket == 4 and program.magazine_step is MagazineStep.IDLE, 1000)
    _run_until(sim, lambda: program.magazine_step is MagazineStep.POSITION and mg1.command_velocity, 400)
    assert mg1.command_velocity < 0.0  # 90 -> 300 degrees: -150, not +210
    _run_until(sim, lambda: sim.read(sim.catalog.resolve("CHAN1.basic.in.stateReset")) == 1, 2000)
    assert program.pocket == 11 and mg1.shown(mg1.setpoint) == pytest.approx(300.0)
    assert program.fc18 is not None and program.fc18.in_pos and not program.fc18.error and program.fc18.done


def test_the_block_refuses_a_start_while_its_motion_runs_and_parameters_it_cannot_hand_on() -> None:
    sim, program = _simulation()
    assert program.fc18 is not None
    block: TraversePosAxis = program.fc18
    assert block.axis == "MG1"
    _mda(sim, "N10 T7\nN20 M30")
    _run_until(sim, lambda: block.active and not block._pending, 400)
    block(start=True, stop=False, funct=5, mode=2, pos=10.0, frate=3600.0)  # a second start in the same job
    assert block.error and block.state == FC18_STILL_RUNNING and block.active
    # the program sees the block's Error: its fault 700042, and FC18 Stop brakes the motion
    _run_until(sim, lambda: sim.read(sim.catalog.resolve("MG1.plcAxis.in.active")) == 0, 200)
    assert program.magazine_step is MagazineStep.FAULT
    block(start=False, stop=False, funct=5, mode=2, pos=10.0, frate=3600.0)
    block(start=True, stop=False, funct=5, mode=2, pos=float("inf"), frate=3600.0)  # no S7 REAL
    assert block.error and block.state == FC18_PARAMETERS and not block.active
    block(start=False, stop=False, funct=5, mode=2, pos=10.0, frate=3600.0)
    block(start=True, stop=False, funct=3, mode=2, pos=10.0, frate=3600.0)  # an oscillating spindle: not offered
    assert block.error and block.state == FC18_PARAMETERS
    sim.step(40)
    assert sim.read(sim.catalog.resolve("MG1.plcAxis.in.active")) == 0  # nothing went to the NC


def test_no_axis_behind_axis_no_is_refused_when_the_program_is_built() -> None:
    _, program = _simulation()
    with pytest.raises(ValueError, match="AxisNo 4 is no axis"):
        TraversePosAxis(program._io, 4)  # machine axis 4 is the spindle SP1
