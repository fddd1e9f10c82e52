"""The drive line-up's DC link and ESR generator operation (seed 003 §22.2.4, L41700-41769).

Turn-mill: 400 V supply (r0208), 4000 uF, 3 kW drawn without supply; SP1's drive in generator
operation: p1248 = 450 V, p2161 = 1000 rev/min, 0.02 kg m^2 x 2 at the motor, gear 7.5:1.
"""

from __future__ import annotations

import dataclasses
import math

import pytest
from core_rig import DT, machine

from vc.config.model import DcLinkConfig
from vc.core.retraction.dc_link import DcLink
from vc.core.retraction.drive_esr import STAT_BELOW_MINIMUM_SPEED, STAT_DC_LINK_UNDERVOLTAGE, STAT_REACTION
from vc.core.retraction.drive_esr import DriveEsrReaction as DriveReaction
from vc.simulation.lockstep import Simulation

CAPACITANCE = 4000e-6
LOAD = 3000.0
DRAWN = LOAD * DT  # J per IPO cycle


class _Generator:
    """A generator with a store of energy, as the link sees it."""

    def __init__(self, energy: float, threshold: float = 450.0):
        self.store = energy
        self.threshold = threshold
        self.buffering = True
        self.asked: list[float] = []

    def feed(self, energy: float) -> float:
        self.asked.append(energy)
        given = min(energy, self.store)
        self.store -= given
        return given


def _link(precharge_time: float = 0.0, charged: bool = True) -> DcLink:
    """The turn-mill's link; by default precharged."""
    link = DcLink(DcLinkConfig(supply_voltage=400.0, capacitance_uf=4000.0, load_power=LOAD,
                               precharge_time=precharge_time), DT)
    while charged and not link.charged:
        link.cycle([])
    return link


def _cycles_to(from_voltage: float, to_voltage: float) -> float:
    return 0.5 * CAPACITANCE * (from_voltage ** 2 - to_voltage ** 2) / DRAWN


def test_at_power_on_the_link_precharges_along_the_rc_curve_for_the_precharge_time() -> None:
    link = _link(precharge_time=0.2, charged=False)  # tau = 40 ms
    assert link.voltage == 0.0 and not link.charged and not link.pulses_cancelled
    cycles = round(0.2 / DT)
    for cycle in range(1, cycles):
        link.cycle([])
        assert link.voltage == pytest.approx(540.0 * (1.0 - math.exp(-cycle * DT / 0.04)))
        assert not link.charged
    assert link.voltage < 540.0 * (1.0 - math.exp(-5.0))  # 536.4 V: the bypass closes in the next cycle
    link.cycle([])
    assert link.charged and link.voltage == 540.0


def test_after_a_mains_failure_the_precharge_starts_from_the_voltage_left() -> None:
    link = _link(precharge_time=1.0)
    link.supply_on = False
    while link.voltage > 400.0:
        link.cycle([])
    assert not link.charged
    left = link.voltage
    link.supply_on = True
    # tau x ln((540 - V0) / (540 x e^-5)) = 0.2 s x ln(140 / 3.64) = 0.73 s
    expected_cycles = math.ceil(0.2 * math.log((540.0 - left) / (540.0 * math.exp(-5.0))) / DT)
    cycles = 0
    while not link.charged:
        link.cycle([])
        cycles += 1
        if cycles == 100:
            assert link.voltage == pytest.approx(540.0 - (540.0 - left) * math.exp(-1.0))
    assert cycles == expected_cycles and 0.72 < cycles * DT < 0.74
    link.supply_on = False  # a failure in the middle of a precharge: the next one starts afresh
    link.cycle([])
    assert not link.charged


def test_the_supply_holds_the_link_at_1_35_times_its_voltage() -> None:
    link = _link()
    assert link.voltage == pytest.approx(540.0)
    assert link.pulse_cancellation_voltage == pytest.approx(360.0)
    link.cycle([])
    assert link.voltage == pytest.approx(540.0) and not link.pulses_cancelled


def test_without_supply_the_load_empties_the_capacitors_and_the_pulses_go_below_0_9_r0208() -> None:
    link = _link()
    link.supply_on = False
    expected_cycles = math.ceil(_cycles_to(540.0, 360.0))  # 324 J / 6 J: the 54th cycle
    cycles = 0
    while not link.pulses_cancelled:
        link.cycle([])
        cycles += 1
        energy = 0.5 * CAPACITANCE * 540.0 ** 2 - cycles * DRAWN
        assert link.voltage == pytest.approx(math.sqrt(2.0 * energy / CAPACITANCE))
    assert cycles == expected_cycles
    link.supply_on = True
    link.cycle([])
    assert link.voltage == pytest.approx(540.0) and not link.pulses_cancelled


def test_a_generator_holds_the_link_at_its_threshold_while_it_has_energy() -> None:
    link = _link()
    link.supply_on = False
    generator = _Generator(energy=1000.0)
    for _ in range(math.ceil(_cycles_to(540.0, 450.0)) + 100):
        link.cycle([generator])
    assert link.voltage == pytest.approx(450.0)
    assert [asked for asked in generator.asked if asked > 0][1:] == pytest.approx([DRAWN] * 100)
    while generator.store > 0:
        link.cycle([generator])
    for _ in range(math.ceil(_cycles_to(450.0, 360.0))):
        link.cycle([generator])
    assert link.pulses_cancelled


def test_a_generator_that_is_not_buffering_is_not_asked() -> None:
    link = _link()
    link.supply_on = False
    generator = _Generator(energy=600.0)
    generator.buffering = False
    for _ in range(math.ceil(_cycles_to(540.0, 360.0))):
        link.cycle([generator])
    assert generator.asked == [] and link.pulses_cancelled


# ------------------------------------------------------------------------------ SP1's drive


@pytest.fixture()
def sp1_turning() -> Simulation:
    """SP1's drive reacting in generator operation at 600 rev/min (4500 rev/min at the motor)."""
    simulation = Simulation(machine(), plc=None)
    drive = simulation.nck.esr.drives["SP1"]
    drive.enabled = True
    drive.cycle(trigger_cycles=2)
    axis = drive.axis
    axis.set_path_setpoint(axis.setpoint, 600.0 * 6.0)  # deg/s
    return simulation


def _motor_energy(load_velocity: float) -> float:
    omega = load_velocity / 360.0 * 7.5 * 2.0 * math.pi
    return 0.5 * 0.04 * omega ** 2


def test_the_vdc_min_controller_takes_the_energy_from_the_motor(sp1_turning: Simulation) -> None:
    drive = sp1_turning.nck.esr.drives["SP1"]
    assert drive.reaction is DriveReaction.REACTING and drive.buffering
    before = drive.axis.command_velocity
    given = drive.feed(100.0)
    assert given == pytest.approx(100.0)
    assert _motor_energy(before) - _motor_energy(drive.axis.command_velocity) == pytest.approx(100.0)
    assert drive.status == STAT_REACTION | STAT_DC_LINK_UNDERVOLTAGE
    assert drive.feed(0.0) == 0.0 and drive.status == STAT_REACTION  # the link above p1248 again


def test_the_generator_stops_giving_below_its_minimum_speed(sp1_turning: Simulation) -> None:
    drive = sp1_turning.nck.esr.drives["SP1"]
    total = 0.0
    for _ in range(2000):
        total += drive.feed(50.0)
    floor = (1000.0 - 2.0) / 7.5 * 6.0  # deg/s: p2161 less the comparison's hysteresis, at the load
    assert drive.axis.command_velocity == pytest.approx(floor)
    assert total == pytest.approx(_motor_energy(3600.0) - _motor_energy(floor))
    drive.axis.velocity = drive.axis.command_velocity
    drive.watch_speed()
    assert drive.status & STAT_BELOW_MINIMUM_SPEED
    assert sp1_turning.read(sp1_turning.catalog.resolve("SP1.drive.in.esrSpeedBelowMin")) == 1


def test_a_minimum_speed_inside_the_hysteresis_never_drives_the_motor() -> None:
    # the loader refuses p2161 <= 2 rev/min; the controller itself still only brakes, down to standstill
    config = machine()
    axes = tuple(dataclasses.replace(item, drive=dataclasses.replace(item.drive, p2161=0.0))
                 if item.name == "SP1" else item for item in config.axes)
    simulation = Simulation(dataclasses.replace(config, axes=axes), plc=None)
    drive = simulation.nck.esr.drives["SP1"]
    drive.enabled = True
    drive.cycle(trigger_cycles=2)
    axis = drive.axis
    axis.set_path_setpoint(axis.setpoint, 0.05)  # deg/s: almost standing
    given = [drive.feed(50.0) for _ in range(5)]
    assert axis.command_velocity == 0.0
    assert sum(given) == pytest.approx(_motor_energy(0.05))  # what was left in the motor, nothing more
