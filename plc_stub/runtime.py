"""The scan-cycle runtime of the built-in soft PLC.

It keeps the PLC's own process image and runs a program's OB1 once per scan, in the
order of ``interfaces.plc``: publish the previous outputs, read the inputs, run.  The
runtime does no I/O itself; links (in-process, Modbus, CAN) hand it the images.
"""

from __future__ import annotations

from typing import Protocol

from interfaces.image import ProcessImage
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

    def scan(self, interface: ProcessImage, plant: ProcessImage) -> None:
        image = self.io.image
        if self.scans:
            interface.copy_from(image, self._interface_outputs)
            plant.copy_from(image, self._plant_outputs)
        image.copy_from(interface, self._interface_inputs)
        image.copy_from(plant, self._plant_inputs)
        self.program.ob1()
        self.scans += 1

    @property
    def sign_of_life(self) -> int:
        return self.scans & 0xFFFF
