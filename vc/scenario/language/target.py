"""What the scenario runner needs from a running simulation.

The composed machine (``vc.simulation.lockstep.Simulation``) implements this protocol; the runner
depends only on it.  Time is counted in IPO cycles; every read shows the value as it is
*at the interface* at the end of the last completed cycle.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Protocol

from interfaces.image import Value
from interfaces.plant_io import PlantIoMap
from interfaces.signals import ExpandedCatalog, SignalRef
from vc.config.model import MachineConfig
from vc.core.alarms import Alarm


class ScenarioTarget(Protocol):
    machine: MachineConfig
    catalog: ExpandedCatalog
    plant_io: PlantIoMap

    @property
    def cycle(self) -> int:
        """IPO cycles completed since power-on."""

    @property
    def ipo_cycle_us(self) -> int:
        """Length of one IPO cycle in microseconds."""

    def step(self, cycles: int = 1) -> None:
        """Advance NC, plant and PLC by ``cycles`` IPO cycles in lockstep."""

    def read(self, ref: SignalRef) -> Value:
        """Current value of an interface signal or a plant I/O point."""

    def write(self, ref: SignalRef, value: Value) -> None:
        """Set a signal once, as its owner would: an operator key (plant input ``MCP.*``), a
        PLC-to-NC signal when the scenario acts as the PLC, a plant output when there is no PLC.
        The owner may change it again in a later cycle."""

    def force(self, ref: SignalRef, value: Value) -> None:
        """Hold a signal at ``value`` in every cycle, overriding its owner, until released."""

    def release(self, ref: SignalRef) -> None:
        """End a force; the owner's value applies again from the next cycle."""

    def axis_quantity(self, axis: str, quantity: str) -> float:
        """One of ``vc.simulation.observables.AXIS_QUANTITIES`` for a machine axis or spindle."""

    def link_quantity(self, name: str) -> float:
        """One of ``vc.simulation.observables.LINK_QUANTITIES`` of the CAN link the PLC sits behind."""

    def alarms(self) -> Sequence[Alarm]:
        """Alarms present now."""

    def alarm_history(self) -> Sequence[Alarm]:
        """Every alarm raised since power-on, present or not."""

    def load_mda(self, channel: str, text: str) -> None:
        """Put ``text`` into the channel's MDA buffer (as the operator does on the HMI)."""

    def select_program(self, channel: str, name: str, text: str) -> None:
        """Select a part program for AUTOMATIC in ``channel`` (as the operator does on the HMI)."""

    def machine_datum(self, instance: str, number: int, index: int | None = None) -> float:
        """A machine datum as the control holds it now (including what it wrote itself)."""

    def power_cycle(self, off_seconds: float = 1.0) -> None:
        """Switch the machine off and on again: the NC keeps its memory, the PLC restarts."""

    def inject_fault(self, axis: str, kind: str, start: float = 0.0, end: float = 0.0, amount: float = 0.0,
                     encoder: int = 1) -> None:
        """A fault of the simulated machine: ``vc.simulation.observables.FAULTS``; raises
        :class:`vc.simulation.observables.StepRefused` for a fault the machine cannot have now."""

    def inject_link_fault(self, kind: str, duration_us: int, directions: Sequence[str] = ("nc_to_plc", "plc_to_nc"),
                          areas: Sequence[str] = (), delay_us: int = 0, every: int = 1) -> None:
        """A fault of the CAN bus between NC and PLC from now on: ``vc.simulation.observables.LINK_FAULTS``."""

    def clear_faults(self, axis: str) -> None:
        """The machine's faults on ``axis`` are repaired."""

    def acknowledge_alarms(self) -> None:
        """The operator's alarm acknowledge (cancel) key on the HMI: the alarms cleared with it go."""

    def move_by_hand(self, axis: str, velocity: float) -> None:
        """Someone moves the slide from outside (only a slide without position control moves)."""

    def turn_handwheel(self, number: int, detents: int, cycles: int) -> None:
        """The operator turns handwheel ``number`` by ``detents`` evenly over ``cycles`` IPO cycles."""
