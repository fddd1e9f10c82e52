"""The coolant supply: a pump the PLC switches, a pressure switch that tells it the coolant flows.

``Coolant.pump`` on: the pressure builds up and ``Coolant.pressureOk`` closes after
``pressure_time``; pump off: the pressure is gone at once::

    OFF ──pump on──▶ BUILDING ──pressure_time──▶ PRESSURE (pressureOk = 1)
    BUILDING, PRESSURE ──pump off──▶ OFF (pressureOk = 0)

Fault (``fault: {kind: coolant_pressure_lost}``, repaired with ``clear_faults: Coolant``): the
filter is clogged or the tank runs dry, the switch opens and stays open while the pump runs.

Time is counted in IPO cycles, so the model is deterministic; it does no I/O.
"""

from __future__ import annotations

from interfaces.image import ProcessImage
from interfaces.plant_io import COOLANT, PlantIoMap
from vc.config.model import CoolantPlant
from vc.plant.indexing import Output, Sensors, cycles_of

FAULTS = ("coolant_pressure_lost",)


class Coolant:
    name = COOLANT

    def __init__(self, config: CoolantPlant, io: PlantIoMap, ipo_cycle_us: int):
        self._pump = Output(io, f"{COOLANT}.pump")
        self._switch = Sensors(io, (f"{COOLANT}.pressureOk",))
        self._build_up_cycles = cycles_of(config.pressure_time_s, ipo_cycle_us)
        self.running_cycles = 0  # IPO cycles the pump has run, up to the build-up time
        self.pressure_lost = False

    @property
    def pressure(self) -> bool:
        return self.running_cycles >= self._build_up_cycles and not self.pressure_lost

    def step(self, io: ProcessImage) -> bool:
        """One IPO cycle; True while the pressure builds up."""
        if self._pump.on(io.areas["Q"]):
            if self.running_cycles >= self._build_up_cycles:
                self._switch.write(io, (int(self.pressure),))
                return False
            self.running_cycles += 1
        elif not self.running_cycles:
            return False
        else:
            self.running_cycles = 0
        self.write_sensors(io)
        return self.running_cycles > 0

    def write_sensors(self, io: ProcessImage) -> None:
        self._switch.write(io, (int(self.pressure),))

    def forget_sensors(self) -> None:
        self._switch.forget()

    def inject(self, kind: str) -> None:
        self.pressure_lost = True

    def repair(self) -> None:
        self.pressure_lost = False
