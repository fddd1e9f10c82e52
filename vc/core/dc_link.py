"""The DC link of the drive line-up, buffered by ESR generator operation (seed 003 L41700-41769).

With the supply on, the line module holds the link at its voltage.  When the supply fails, the
line-up draws ``load_power`` from the capacitors and the voltage falls; below 0.9 x r0208 the
power units cancel their pulses (L41749-41754): every drive loses its torque at once.

A drive in generator operation (p0888 = 3, p1240 = 2) that the ESR trigger has reached brakes its
motor whenever the link falls to p1248: its Vdc_min controller takes just the energy the link needs
to stay at p1248 from the motor's kinetic energy (L41723-41747), as long as the motor turns faster
than p2161 (L41762-41769).  The energy balance, per IPO cycle::

    1/2 C V'^2 = 1/2 C V^2 - load_power x dt + energy the generators give back

The link's voltage on the supply is 1.35 x r0208 (a rectified three-phase supply) [control]; the
capacitors recharge within one IPO cycle when the supply returns (precharge is not modelled) [INF].
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Protocol

from vc.config.model import DC_LINK_PER_SUPPLY_VOLT, PULSE_CANCELLATION_PER_SUPPLY_VOLT, DcLinkConfig


class Generator(Protocol):
    """A drive that can feed the link from its motor's kinetic energy."""

    @property
    def buffering(self) -> bool:
        """Its ESR generator reaction runs: it may brake the motor for the link."""

    @property
    def threshold(self) -> float:
        """p1248, V."""

    def feed(self, energy: float) -> float:
        """Brake the motor to give ``energy`` (J, 0 while the link is above p1248) to the link;
        returns the energy given."""


class DcLink:
    """Voltage of the drive line-up's DC link and the pulse cancellation at its lower limit."""

    def __init__(self, config: DcLinkConfig, dt: float):
        self.nominal_voltage = DC_LINK_PER_SUPPLY_VOLT * config.supply_voltage
        self.pulse_cancellation_voltage = PULSE_CANCELLATION_PER_SUPPLY_VOLT * config.supply_voltage
        self._capacitance = config.capacitance_uf * 1e-6
        self._drawn_per_cycle = config.load_power * dt
        self.voltage = self.nominal_voltage
        self.supply_on = True
        self.pulses_cancelled = False

    def cycle(self, generators: Sequence[Generator]) -> None:
        if self.supply_on:
            self.voltage = self.nominal_voltage
            self.pulses_cancelled = False
            return
        capacitance = self._capacitance
        energy = max(0.0, 0.5 * capacitance * self.voltage ** 2 - self._drawn_per_cycle)
        for generator in generators:
            if generator.buffering:
                held = 0.5 * capacitance * generator.threshold ** 2
                energy += generator.feed(max(0.0, held - energy))
        self.voltage = math.sqrt(2.0 * energy / capacitance)
        if self.voltage < self.pulse_cancellation_voltage:
            self.pulses_cancelled = True
