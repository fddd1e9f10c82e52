"""``vc run``: scenario files against the lockstep simulation with the built-in PLC programs."""

from __future__ import annotations

from collections.abc import Sequence

from interfaces.links.inprocess import plc_programs
from vc.harness.simulation import Simulation
from vc.scenario.command import run_command
from vc.scenario.model import Scenario


def simulation_for(scenario: Scenario) -> Simulation:
    """A fresh power-on of the scenario's machine with its PLC program (or none)."""
    return Simulation(scenario.machine, scenario.plc_program)


def run_scenario_files(paths: Sequence[str], *, junit: str | None = None, trace_dir: str | None = None,
                       golden: str | None = None, update_golden: bool = False) -> int:
    return run_command(paths, simulation_for, plc_programs().keys(), junit=junit, trace_dir=trace_dir,
                       golden=golden, update_golden=update_golden)
