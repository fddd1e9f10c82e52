"""The in-process target of a scenario: a fresh power-on of its machine with its PLC program.

The factory every run falls back to: ``vc run`` without a link, the PLC-process runners of
:mod:`vc.harness.external_plc` for scenarios they do not serve, and the tests of the library.
"""

from __future__ import annotations

from collections.abc import Callable

from vc.scenario.language.model import LINK_CAN, Scenario
from vc.simulation.lockstep import Simulation

TargetFactory = Callable[[Scenario], Simulation]


def simulation_for(scenario: Scenario) -> Simulation:
    """A fresh power-on of the scenario's machine with its PLC program (or none); a scenario that
    asks for a CAN link gets its program behind a virtual CAN bus in this process."""
    if scenario.plc_program is not None and scenario.link == LINK_CAN:
        from vc.harness.links.can import virtual_can_simulation  # python-can only for such a scenario

        return virtual_can_simulation(scenario.machine, scenario.plc_program)
    return Simulation(scenario.machine, scenario.plc_program)
