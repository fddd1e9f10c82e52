"""The harness's end of a link to a PLC in another process: one contract, one module per technology.

=====================  ====================================================================
:class:`Link`          the contract below: what ``vc serve`` and the PLC-process runners of
                       ``vc run`` (:mod:`vc.harness.external_plc`) ask of a link
``modbus.py``          Modbus TCP, with S7 as a second server of the same link
                       (:class:`~vc.harness.links.modbus.PlcLink`)
``can.py``             a node on a CAN bus (:class:`~vc.harness.links.can.CanLink`)
``patience.py``        how long both wait for the PLC and what they say meanwhile
=====================  ====================================================================

The protocols themselves and the PLC's end of each link live in ``interfaces/links/<technology>/``;
the registry of link kinds (:data:`interfaces.links.LINKS`) names, per technology, the function of
its module here that ``vc serve`` serves (``serving``), the PLC process of ``vc run --link NAME``
(:mod:`vc.harness.external_plc`) and a scenario's ``link: NAME`` in process (:mod:`vc.harness.targets`).

A link is a :class:`~interfaces.plc.PlcConnector`: every power-on of the simulation connects, which
opens a new session and hands the simulation the PLC of that session.  Faults of the bus are a
capability of the CAN link alone, not part of the contract: its PLC is a
:class:`~vc.simulation.link_faults.FaultInjectable` (the simulation, which injects them, stands
below the harness and asks the PLC it got for it).
"""

from __future__ import annotations

import asyncio
from enum import StrEnum
from typing import Protocol

from interfaces.plc import PlcConnector, PlcEnvironment, SoftPlc
from vc.config.model import MachineConfig
from vc.simulation.lockstep import Simulation


class LinkMode(StrEnum):
    """Lockstep: the NC waits for every scan of the PLC; free-running: both run on the wall clock."""

    LOCKSTEP = "lockstep"
    FREE_RUNNING = "free_running"


class Link(PlcConnector, Protocol):
    """The harness's end of a link to a PLC in another process (Modbus TCP / S7, or CAN)."""

    @property
    def loop(self) -> asyncio.AbstractEventLoop | None:
        """The link's event loop, which the real-time pacer shares; None: it has none."""

    @property
    def plc_command(self) -> str:
        """How plc_stub follows the harness on this link."""

    @property
    def watched(self) -> str:
        """What the NC watches besides the PLC's sign of life, for the banner."""

    def connect(self, environment: PlcEnvironment, program: str) -> SoftPlc:
        """A power-on: a new session; the PLC (re)starts ``program`` for it."""

    def configure_for(self, machine: MachineConfig) -> None:
        """The settings of the machine the next power-on uses."""

    def banner(self, machine: MachineConfig) -> list[str]:
        """Where the link listens and where its map comes from."""

    def peer_state(self, simulation: Simulation) -> str:
        """The PLC's side for the statistics line."""

    def close(self) -> None:
        """End the link: its servers or its bus node, its event loop."""
