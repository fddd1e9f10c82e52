"""Auxiliary function output to the PLC as the NC does it (vc/core/auxiliary/output.py): the change
signals, values and decoded M signals in DB21, the acknowledgement one PLC cycle after the PLC read
them, the read-in disable, M00 / M01 / M30 and the PLC's user alarms from DB2.

The test is the PLC (no PLC program): the composed machine counts a PLC cycle every
``plc_period`` IPO cycles all the same.
"""

from __future__ import annotations

import pytest
from core_rig import ABSOLUTE_XYZ, Rig, machine

from vc.core.auxiliary.output import OutputState

CHAN = "CHAN1"


def _rig(extra: str = "") -> Rig:
    rig = Rig(machine(ABSOLUTE_XYZ + ("\n" + extra if extra else "")))
    rig.ready_mda()
    rig.set("SP1.spindle.out.ovrFactor", 100)
    rig.set("SP1.spindle.out.gearStageSelection", 1)
    rig.step(12)
    return rig


@pytest.fixture
def rig() -> Rig:
    return _rig()


def _m(rig: Rig, slot: int, part: str) -> object:
    return rig.get(f"{CHAN}.auxMFuncs[{slot}].in.{part}")


def _done(rig: Rig) -> bool:
    return rig.program_state()["progStateRunning"] == 0


def test_m_function_is_shown_for_one_plc_cycle_and_acknowledged_after_the_next(rig: Rig) -> None:
    period = rig.sim.plc_period
    rig.mda("M8 M2=10\nM30")
    rig.run_until(lambda: _m(rig, 1, "change") == 1, 10)
    assert (_m(rig, 1, "value"), _m(rig, 1, "extendedAddress")) == (8, 0)
    assert (_m(rig, 2, "value"), _m(rig, 2, "extendedAddress"), _m(rig, 2, "change")) == (10, 2, 1)
    assert rig.get(f"{CHAN}.auxMDynFuncs.in.m08Decoded") == 1
    assert rig.get(f"{CHAN}.auxMDynFuncs.in.m10Decoded") == 0  # with an extended address: not decoded
    shown = rig.run_until(lambda: _m(rig, 1, "change") == 0, 4 * period)
    assert shown <= period + 1
    assert rig.get(f"{CHAN}.auxMDynFuncs.in.m08Decoded") == 0
    assert _m(rig, 1, "value") == 8  # the value stays until a function of the type overwrites it
    rig.run_until(lambda: _done(rig), 20 * period)
    assert rig.channel.aux.state is OutputState.IDLE
    assert rig.get(f"{CHAN}.basic.in.m02M30Active") == 1


def test_read_in_disable_holds_the_next_block(rig: Rig) -> None:
    period = rig.sim.plc_period
    rig.set(f"{CHAN}.basic.out.disableReadIn", 1)
    rig.mda("M8\nM9\nM30")
    rig.run_until(lambda: rig.get(f"{CHAN}.auxMDynFuncs.in.m08Decoded") == 1, 10)
    rig.step(30 * period)
    assert rig.program_state()["progStateWaiting"] == 1
    assert _m(rig, 1, "value") == 8  # M9 is not output
    rig.set(f"{CHAN}.basic.out.disableReadIn", 0)
    rig.run_until(lambda: _m(rig, 1, "value") == 9, 10 * period)
    rig.run_until(lambda: _done(rig), 20 * period)


def test_quick_function_does_not_hold_the_block(rig: Rig) -> None:
    rig.mda("M=QU(8)\nM30")
    rig.run_until(lambda: _m(rig, 1, "change") == 1, 10)
    assert _m(rig, 1, "quick") == 1
    rig.run_until(lambda: _done(rig), 10 * rig.sim.plc_period)  # acknowledged all the same


def test_m0_stops_until_nc_start(rig: Rig) -> None:
    period = rig.sim.plc_period
    rig.mda("M0\nM30")
    rig.run_until(lambda: rig.program_state()["progStateStopped"] == 1, 20 * period)
    assert rig.get(f"{CHAN}.basic.in.m00M01Active") == 1
    rig.step(20 * period)
    assert rig.program_state()["progStateStopped"] == 1
    rig.pulse(f"{CHAN}.basic.out.ncStart")
    rig.run_until(lambda: _done(rig), 20 * period)
    assert rig.get(f"{CHAN}.basic.in.m00M01Active") == 0


@pytest.mark.parametrize("selected", [0, 1])
def test_m1_stops_only_with_activate_m01(rig: Rig, selected: int) -> None:
    period = rig.sim.plc_period
    rig.set(f"{CHAN}.basic.out.activateM01", selected)
    rig.mda("M1\nM30")
    stopped = False
    for _ in range(40 * period):
        rig.step()
        stopped |= rig.program_state()["progStateStopped"] == 1
        if _done(rig):
            break
    assert stopped == bool(selected)
    assert rig.get(f"{CHAN}.auxMDynFuncs.in.m01Decoded") == 0  # shown for one PLC cycle only


def test_reset_drops_functions_not_acknowledged(rig: Rig) -> None:
    rig.set(f"{CHAN}.basic.out.disableReadIn", 1)
    rig.mda("M8\nM9\nM30")
    rig.run_until(lambda: _m(rig, 1, "change") == 1, 10)
    rig.pulse(f"{CHAN}.basic.out.reset", 2)
    rig.step(2)
    assert _m(rig, 1, "change") == 0
    assert rig.channel.aux.state is OutputState.IDLE


# ---------------------------------------------------------------------------- PLC user alarms


def test_plc_user_alarm_follows_its_db2_bit() -> None:
    rig = _rig()
    rig.set("PLCALARMS.userArea0.out.alarm700003", 1)
    rig.step(rig.sim.plc_period + 1)
    assert 700003 in rig.alarm_numbers()
    rig.set("PLCALARMS.userArea0.out.alarm700003", 0)
    rig.step(rig.sim.plc_period + 1)
    assert 700003 not in rig.alarm_numbers()
    assert 700003 in rig.history_numbers()


def test_md14516_read_in_disabled_holds_the_program() -> None:
    rig = _rig("NC: {MD14516: [0, 2]}")
    period = rig.sim.plc_period
    rig.set("PLCALARMS.userArea0.out.alarm700001", 1)
    rig.mda("M8\nM9\nM30")
    rig.step(30 * period)
    assert _m(rig, 1, "value") == 8 and not _done(rig)
    rig.set("PLCALARMS.userArea0.out.alarm700001", 0)
    rig.run_until(lambda: _done(rig), 30 * period)
