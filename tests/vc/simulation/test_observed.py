"""A simulation with observers: every cycle and every action of the operator reaches them, after it
took effect, and an action done again with perform() has the same effect."""

from __future__ import annotations

from pathlib import Path

import pytest

from vc.config.loader import load_machine
from vc.simulation.lockstep import Simulation
from vc.simulation.observed import ACTION_ARGUMENTS, ObservedSimulation, OperatorAction, perform, resolve

MACHINE = Path(__file__).resolve().parents[3] / "scenarios" / "machines" / "turn_mill.yaml"


class Log:
    def __init__(self) -> None:
        self.events: list[tuple[str, int, object]] = []

    def attached(self, simulation: Simulation) -> None:
        self.events.append(("attached", simulation.cycle, None))

    def cycle_done(self, simulation: Simulation) -> None:
        self.events.append(("cycle", simulation.cycle, None))

    def acted(self, simulation: Simulation, action: OperatorAction) -> None:
        self.events.append(("acted", simulation.cycle, action))


def test_observers_see_every_cycle_and_every_action_after_it_took_effect() -> None:
    log = Log()
    simulation = Simulation(load_machine(str(MACHINE)))
    target = ObservedSimulation(simulation, [log])
    target.step(3)
    key = resolve(simulation, "MCP.jog")
    target.write(key, 1)
    assert simulation.read(key) == 1
    target.load_mda("CHAN1", "G1 X10 F100")
    target.power_cycle(0.5)
    assert target.catalog is simulation.catalog
    assert log.events == [
        ("attached", 0, None), ("cycle", 1, None), ("cycle", 2, None), ("cycle", 3, None),
        ("acted", 3, OperatorAction("write", ("MCP.jog", 1))),
        ("acted", 3, OperatorAction("mda", ("CHAN1", "G1 X10 F100"))),
        ("acted", 3 + 250, OperatorAction("power_cycle", (0.5,))),  # on again: 0.5 s later
    ]
    assert log.events[-1][2].argument("off_seconds") == 0.5  # type: ignore[union-attr]


def test_perform_does_an_action_again() -> None:
    simulation = Simulation(load_machine(str(MACHINE)))
    perform(simulation, OperatorAction("force", ("X1.basic.out.enableCtrl", 1)))
    assert simulation.read(resolve(simulation, "X1.basic.out.enableCtrl")) == 1
    perform(simulation, OperatorAction("program", ("CHAN1", "PART1", "G1 X5 F100\nM30")))
    assert simulation.nck.channels_by_name["CHAN1"].selected_program == ("PART1", "G1 X5 F100\nM30")
    perform(simulation, OperatorAction("move_by_hand", ("X1", 600)))
    assert simulation.nck.axes_by_name["X1"].external_velocity == pytest.approx(600 / 60)
    with pytest.raises(ValueError, match="unknown operator action 'dance'"):
        perform(simulation, OperatorAction("dance"))
    with pytest.raises(KeyError):
        perform(simulation, OperatorAction("write", ("MCP.nothing", 1)))
    assert set(ACTION_ARGUMENTS) >= {"write", "force", "release", "power_cycle", "handwheel"}
