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
                       golden: str | None = None, update_golden: bool = False, link: str = "inprocess") -> int:
    """``link``: ``inprocess`` runs the PLC programs in lockstep in this process; ``modbus`` runs
    them in a ``python -m plc_stub`` process over a lockstep Modbus TCP link."""
    if link == "modbus":
        from vc.harness.external_plc import PlcProcess

        with PlcProcess() as process:
            return run_command(paths, process.target_factory(), plc_programs().keys(), junit=junit,
                               trace_dir=trace_dir, golden=golden, update_golden=update_golden)
    return run_command(paths, simulation_for, plc_programs().keys(), junit=junit, trace_dir=trace_dir,
                       golden=golden, update_golden=update_golden)
