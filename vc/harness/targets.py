"""The in-process target of a scenario: a fresh power-on of its machine with its PLC program.

The factory every run falls back to: ``vc run`` without a link, the PLC-process runners of
:mod:`vc.harness.external_plc` for scenarios they do not serve, and the tests of the library.
"""

from __future__ import annotations

from collections.abc import Callable

from interfaces.links import link_kind, load
from vc.config.model import MachineConfig
from vc.scenario.language.model import Scenario
from vc.simulation.lockstep import Simulation

TargetFactory = Callable[[Scenario], Simulation]


def simulation_for(scenario: Scenario) -> Simulation:
    """A fresh power-on of the scenario's machine with its PLC program (or none); a scenario that
    asks for a link (``link: can``) gets its program behind that link in this process (a virtual CAN
    bus: the ``in_process`` of the link's row in interfaces/links/__init__.py)."""
    if scenario.plc_program is not None and scenario.link is not None:
        in_process = link_kind(scenario.link).in_process
        assert in_process is not None  # the scenario's loader admits only links that offer it
        # the link's library (python-can) is imported only for such a scenario
        behind_link: Callable[[MachineConfig, str], Simulation] = load(in_process)
        return behind_link(scenario.machine, scenario.plc_program)
    return Simulation(scenario.machine, scenario.plc_program)
