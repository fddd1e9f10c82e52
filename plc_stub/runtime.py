"""The scan-cycle runtime of the built-in soft PLC.

It keeps the PLC's own process image and runs a program's OB1 once per scan, in the
order of ``interfaces.plc``: publish the previous outputs, read the inputs, run.  The
runtime does no I/O itself; links (in-process, Modbus, CAN) hand it the images.
"""

from __future__ import annotations

from typing import Protocol

from interfaces.image import ProcessImage, RangeCopy
from interfaces.plc import PlcEnvironment
from interfaces.signals import Direction
from plc_stub.io import PlcIo


class PlcProgram(Protocol):
    def ob1(self) -> None:
        """One pass of the cyclic program."""


class ProgramClass(Protocol):
    def __call__(self, io: PlcIo) -> PlcProgram: ...


class ScanCycleRuntime:
    def __init__(self, environment: PlcEnvironment, program: ProgramClass):
        self.io = PlcIo(environment)
        self.program = program(self.io)
        catalog = environment.catalog
        sizes = environment.plant_io.area_sizes()
        self._publish_ranges = [*catalog.byte_ranges(Direction.PLC_TO_NC), ("Q", 0, sizes["Q"])]
        self._interface_inputs = catalog.byte_ranges(Direction.NC_TO_PLC)
        self._plant_inputs = [("I", 0, sizes["I"])]
        self._interface_outputs = catalog.byte_ranges(Direction.PLC_TO_NC)
        self._plant_outputs = [("Q", 0, sizes["Q"])]
        self.scans = 0
        self._copies: tuple[RangeCopy, RangeCopy, RangeCopy, RangeCopy] | None = None

    def scan(self, interface: ProcessImage, plant: ProcessImage) -> None:
        copies = self._copies
        if copies is None or copies[0].target is not interface or copies[1].target is not plant:
            copies = self._copies = self._bind(interface, plant)
        if self.scans:
            copies[0].run()  # the outputs of the last scan
            copies[1].run()
        copies[2].run()  # the inputs of this one
        copies[3].run()
        self.program.ob1()
        self.scans += 1

    def _bind(self, interface: ProcessImage, plant: ProcessImage) -> tuple[RangeCopy, RangeCopy, RangeCopy, RangeCopy]:
        """The copies between the PLC's image and the images a link hands it (the same ones scan
        after scan; new ones after a power cycle)."""
        image = self.io.image
        return (RangeCopy(interface, image, self._interface_outputs), RangeCopy(plant, image, self._plant_outputs),
                RangeCopy(image, interface, self._interface_inputs), RangeCopy(image, plant, self._plant_inputs))

    @property
    def sign_of_life(self) -> int:
        return self.scans & 0xFFFF
