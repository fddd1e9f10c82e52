"""A PLC program alone on the bench: the test plays the NC and the plant, scan by scan.

The test writes the PLC's inputs (plant I, NC->PLC bytes) and reads what it published (plant Q,
PLC->NC bytes).  Outputs computed in a scan reach the images at the start of the next scan
(``interfaces.plc``: publish, read, run), so a copied input shows one scan after the scan that
read it.  No ``vc`` import: the PLC meets the NC only through ``interfaces``.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from interfaces.catalog import load_catalog
from interfaces.commissioning import Commissioning
from interfaces.image import ProcessImage, Value
from interfaces.plant_io import PlantIoMap
from interfaces.plc import PlcEnvironment
from interfaces.signals import InterfaceLayout, expand
from plc_stub.runtime import ProgramClass, ScanCycleRuntime

SCAN = 0.01  # s, OB1 period
OVERRIDE_SWITCHES = ("MCP.feedOverride", "MCP.rapidOverride", "MCP.spindleOverride")


class PlcBench:
    def __init__(self, program: ProgramClass, io_list: Mapping[str, str], axes: tuple[str, ...],
                 parameters: Mapping[str, Any] | None = None, commissioning: Commissioning | None = None):
        self.plant_io = PlantIoMap.from_mapping(io_list, axes)
        self.catalog = expand(load_catalog(), InterfaceLayout(channels=("CHAN1",), axes=axes))
        environment = PlcEnvironment(self.catalog, self.plant_io, SCAN, parameters or {}, commissioning=commissioning)
        self.runtime = ScanCycleRuntime(environment, program)
        self.interface = ProcessImage(self.catalog.area_sizes)
        self.plant = ProcessImage(self.plant_io.area_sizes())
        # a healthy machine at power-on: e-stop chain closed, drives ready, limit switches free,
        # override switches at 100 %
        for point in self.plant_io.points:
            if point.name in ("EStop.chainOk", "Drives.ready") or ".hwLimit" in point.name:
                self.input(point.name, 1)
            elif point.name in OVERRIDE_SWITCHES:
                self.input(point.name, 100)

    def input(self, name: str, value: Value) -> None:
        self.plant.write(self.plant_io.resolve(name), value)

    def nc(self, name: str, value: Value) -> None:
        """An NC->PLC signal as the NC publishes it."""
        self.interface.write(self.catalog.resolve(name), value)

    def out(self, name: str) -> Value:
        """A published PLC output: PLC->NC interface signal or plant output Q."""
        try:
            return self.plant.read(self.plant_io.resolve(name))
        except KeyError:
            return self.interface.read(self.catalog.resolve(name))

    def scan(self, count: int = 1) -> None:
        for _ in range(count):
            self.runtime.scan(self.interface, self.plant)

    def tap(self, name: str) -> None:
        self.input(name, 1)
        self.scan()
        self.input(name, 0)
        self.scan(2)
