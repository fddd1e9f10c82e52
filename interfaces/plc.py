"""The PLC side of the contract: what a soft PLC gets and what it must do each scan.

The harness (``vc``) and the built-in soft PLC (``plc_stub``) never import each other:
the harness finds PLC programs by name through the ``vc_harness.plc_programs`` entry
point (``interfaces.links.inprocess.plc_programs``) and drives them through
:class:`SoftPlc`, exactly as a real NC and PLC meet only through the interface DBs.

One scan (OB1) in lockstep with the NC::

    1. publish the outputs of the previous scan (PLC->NC data blocks, plant outputs Q)
    2. read the inputs (NC->PLC data blocks, plant inputs I)
    3. run the program

So a signal the PLC copies (a cam input to DB31.DBX12.7) reaches the NC one scan after
the PLC read it, as on a real machine where the outputs are written at the end of the
scan.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from typing import Any, Protocol, runtime_checkable

from interfaces.commissioning import Commissioning
from interfaces.image import ProcessImage
from interfaces.plant_io import PlantIoMap
from interfaces.signals import ExpandedCatalog


@dataclass(frozen=True, slots=True)
class PlcEnvironment:
    catalog: ExpandedCatalog  # the interface of this machine (every DB instance)
    plant_io: PlantIoMap  # the machine's I/O list
    scan_time_s: float  # OB1 period
    parameters: Mapping[str, Any] = field(default_factory=dict)  # the machine file's ``plc:`` section
    machine: str = ""  # the machine's name, for links that describe the interface to a remote PLC
    ipo_cycle_us: int = 0  # the NC's IPO cycle ...
    plc_cycle_ipo: int = 0  # ... and the PLC period in IPO cycles (scan_time_s = their product)
    commissioning: Commissioning | None = None  # referencing, wiring: what a link describes to a remote PLC


class SoftPlc(Protocol):
    def scan(self, interface: ProcessImage, plant: ProcessImage) -> None:
        """One OB1 scan: publish the previous outputs, read the inputs, run the program."""

    @property
    def sign_of_life(self) -> int:
        """A number that changes with every scan while the PLC runs (the NC watches it)."""


@runtime_checkable
class CyclicPlc(Protocol):
    """A PLC behind a link that also works between the scans, every IPO cycle: CAN sends the NC's
    frames cyclically and delivers the PLC's frames whenever they arrive."""

    def sends_at(self, cycle: int) -> bool:
        """Whether the NC-to-PLC signals go out in IPO cycle ``cycle`` (the harness refreshes them first)."""

    def ipo_cycle(self, cycle: int, interface: ProcessImage, plant: ProcessImage) -> bool:
        """Send what is due and take what arrived; True when PLC-to-NC bytes or plant outputs changed."""


PlcFactory = Callable[[PlcEnvironment], SoftPlc]


class PlcConnector(Protocol):
    """Where the harness gets its PLC from at every power-on: the built-in programs in-process,
    or a link to a PLC in another process (Modbus TCP, S7, CAN: the harness's ``Link`` contract in
    vc/harness/links/)."""

    def connect(self, environment: PlcEnvironment, program: str) -> SoftPlc: ...
