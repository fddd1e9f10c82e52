"""The DC link of the drive line-up, buffered by ESR generator operation (seed 003 L41700-41769).

With the supply on, the line module holds the link at its voltage.  When the supply fails, the
line-up draws ``load_power`` from the capacitors and the voltage falls; below 0.9 x r0208 the
power units cancel their pulses (L41749-41754): every drive loses its torque at once.

A drive in generator operation (p0888 = 3, p1240 = 2) that the ESR trigger has reached brakes its
motor whenever the link falls to p1248: its Vdc_min controller takes just the energy the link needs
to stay at p1248 from the motor's kinetic energy (L41723-41747), as long as the motor turns faster
than p2161 (L41762-41769).  The energy balance, per IPO cycle::

    1/2 C V'^2 = 1/2 C V^2 - load_power x dt + energy the generators give back

The link's voltage on the supply is 1.35 x r0208 (a rectified three-phase supply) [control].

Precharge: at power-on the capacitors are empty, and a mains failure opens the infeed's bypass
contactor.  With the supply there the line module charges the link through its precharge resistors,
an RC curve from the voltage it has (``V0``) towards the nominal one ``Vn``::

    V(t) = Vn - (Vn - V0) x exp(-t / tau),   tau = precharge_time / 5

The bypass contactor closes when the curve reaches 1 - exp(-5) = 99.3 % of ``Vn`` - after
``precharge_time`` from empty capacitors, sooner from a link that kept some charge - and the link
is then on the supply, ``charged``: only then is the infeed ready (``Drives.ready``) and power
units that cancelled their pulses below 0.9 x r0208 take them back [INF: the precharging currents
"decay according to an e-function until the precharging process is completed after typically 1 to
2 s", SINAMICS engineering manual; the resistors charge from line voltage alone, as a Smart Line
Module's do, whether the PLC has switched the infeed on or not].
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


PRECHARGE_TIME_CONSTANTS = 5  # the bypass contactor closes at 1 - exp(-5) = 99.3 % of the nominal voltage [INF]


class DcLink:
    """Voltage of the drive line-up's DC link, its precharge and the pulse cancellation at its lower limit."""

    def __init__(self, config: DcLinkConfig, dt: float):
        self.nominal_voltage = DC_LINK_PER_SUPPLY_VOLT * config.supply_voltage
        self.pulse_cancellation_voltage = PULSE_CANCELLATION_PER_SUPPLY_VOLT * config.supply_voltage
        self._capacitance = config.capacitance_uf * 1e-6
        self._drawn_per_cycle = config.load_power * dt
        self._dt = dt
        self._time_constant = config.precharge_time / PRECHARGE_TIME_CONSTANTS
        self.voltage = 0.0  # power-on: the capacitors are empty
        self.supply_on = True
        self.charged = False  # precharge done, bypass contactor closed: the infeed may report ready
        # at power-on the PLC gives no pulse enable before Drives.ready; the power units' own
        # cancellation is the undervoltage's after a mains failure [INF]
        self.pulses_cancelled = False
        self._precharge: _Precharge | None = None

    def cycle(self, generators: Sequence[Generator]) -> None:
        if self.supply_on:
            if not self.charged:
                self._charge()
            return
        self.charged = False  # the infeed drops its bypass contactor: a return of the supply precharges
        self._precharge = None
        capacitance = self._capacitance
        energy = max(0.0, 0.5 * capacitance * self.voltage ** 2 - self._drawn_per_cycle)
        for generator in generators:
            if generator.buffering:
                held = 0.5 * capacitance * generator.threshold ** 2
                energy += generator.feed(max(0.0, held - energy))
        self.voltage = math.sqrt(2.0 * energy / capacitance)
        if self.voltage < self.pulse_cancellation_voltage:
            self.pulses_cancelled = True

    def _charge(self) -> None:
        """One IPO cycle of the precharge through the resistors."""
        precharge = self._precharge
        if precharge is None:
            precharge = self._precharge = _Precharge.starting_at(self.voltage, self.nominal_voltage,
                                                                 self._time_constant, self._dt)
        precharge.cycles_done += 1
        if precharge.cycles_done >= precharge.cycles:
            self.voltage = self.nominal_voltage
            self.charged = True
            self.pulses_cancelled = False
            self._precharge = None
            return
        gap = self.nominal_voltage - precharge.start_voltage
        self.voltage = self.nominal_voltage - gap * math.exp(-precharge.cycles_done * self._dt / self._time_constant)


class _Precharge:
    """A precharge under way: from which voltage, how many IPO cycles it takes, how many have run."""

    def __init__(self, start_voltage: float, cycles: int):
        self.start_voltage = start_voltage
        self.cycles = cycles
        self.cycles_done = 0

    @classmethod
    def starting_at(cls, voltage: float, nominal: float, time_constant: float, dt: float) -> _Precharge:
        """The curve reaches the bypass threshold nominal x (1 - e^-5) after
        tau x ln((Vn - V0) / (Vn x e^-5)); a link already above it is charged in the next cycle."""
        remaining_gap = nominal * math.exp(-PRECHARGE_TIME_CONSTANTS)
        gap = nominal - voltage
        if time_constant <= 0.0 or gap <= remaining_gap:
            return cls(voltage, 1)
        seconds = time_constant * math.log(gap / remaining_gap)
        return cls(voltage, max(1, math.ceil(seconds / dt - 1e-9)))
