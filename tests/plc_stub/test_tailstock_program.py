"""The PLC program tailstock alone (plc_stub/programs/tailstock.py): the test plays the NC's
travel to fixed stop of the quill W1 (DB34) and the sleeve sensors; the scenarios under
scenarios/fixed_stop/ run it against the NC and the plant."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import pytest
from plc_bench import PlcBench

from interfaces.commissioning import AxisFacts, Commissioning
from plc_stub.programs import REGISTRY
from plc_stub.programs.tailstock import Tailstock, TailstockStep
from plc_stub.programs.turret import Turret

AXES = ("X1", "SP1", "W1")
IO_LIST = {
    "I0.1": "MCP.mda", "I1.0": "MCP.ncStart", "I1.2": "MCP.reset", "I6.0": "EStop.chainOk", "I6.1": "Drives.ready",
    "I9.4": "SP1.chuckClosed", "I9.5": "SP1.chuckOpen", "I10.0": "Tailstock.retracted", "I10.1": "Tailstock.atPart",
    "Q0.0": "Drives.on", "Q0.4": "SP1.chuckClose", "Q0.5": "SP1.chuckRelease",
}
FACTS = Commissioning(
    (AxisFacts("X1", 31, "linear axis", "mm", "", "plus", -1), AxisFacts("SP1", 32, "spindle", "deg", "", "", -1),
     AxisFacts("W1", 33, "linear axis", "mm", "", "", -1)),
    devices={"tailstock": {"axis_db": 33}})


def _plc(parameters: Mapping[str, Any] | None = None) -> PlcBench:
    plc = PlcBench(Tailstock, IO_LIST, AXES, {"master_spindle": "SP1", **(parameters or {})}, FACTS)
    plc.input("SP1.chuckClosed", 1)
    plc.input("Tailstock.retracted", 1)
    plc.scan(2)
    return plc


def _step(plc: PlcBench) -> TailstockStep:
    program = plc.runtime.program
    assert isinstance(program, Tailstock)
    return program.tailstock_step


def test_the_program_builds_on_turret() -> None:
    assert REGISTRY["tailstock"] is Tailstock and issubclass(Tailstock, Turret)


def test_the_handshake_enables_acknowledges_and_releases() -> None:
    plc = _plc()
    plc.nc("W1.basic.in.fixedStopRequest", 1)
    plc.scan(2)
    assert _step(plc) is TailstockStep.ADVANCE and plc.out("W1.basic.out.fixedStopEnable") == 1
    plc.nc("W1.basic.in.fixedStopReached", 1)
    plc.scan(2)
    assert plc.out("W1.basic.out.fixedStopAckReached") == 0  # the sleeve is not at the part yet
    plc.input("Tailstock.atPart", 1)
    plc.scan(2)
    assert _step(plc) is TailstockStep.CLAMPED and plc.out("W1.basic.out.fixedStopAckReached") == 1
    assert plc.out("W1.basic.out.fixedStopSensor") == 1  # the sleeve sensor for MD37040 = 1 / 2
    plc.nc("W1.basic.in.fixedStopRequest", 0)
    plc.nc("W1.basic.in.fixedStopReached", 0)
    plc.scan(2)
    assert _step(plc) is TailstockStep.IDLE
    assert plc.out("W1.basic.out.fixedStopEnable") == plc.out("W1.basic.out.fixedStopAckReached") == 0


def test_no_enable_with_the_chuck_open_and_a_lost_part_holds_the_slides() -> None:
    plc = _plc()
    plc.input("SP1.chuckClosed", 0)
    plc.nc("W1.basic.in.fixedStopRequest", 1)
    plc.scan(2)
    assert _step(plc) is TailstockStep.FAULT and plc.out("W1.basic.out.fixedStopEnable") == 0
    assert plc.out("PLCALARMS.userArea0.out.alarm700032") == 1
    plc.input("SP1.chuckClosed", 1)
    plc.nc("W1.basic.in.fixedStopRequest", 0)
    plc.tap("MCP.reset")
    assert _step(plc) is TailstockStep.IDLE and plc.out("PLCALARMS.userArea0.out.alarm700032") == 0
    plc.nc("W1.basic.in.fixedStopRequest", 1)
    plc.nc("W1.basic.in.fixedStopReached", 1)
    plc.input("Tailstock.atPart", 1)
    plc.scan(3)
    assert _step(plc) is TailstockStep.CLAMPED
    plc.input("Tailstock.atPart", 0)  # the part slipped
    plc.scan(2)
    assert _step(plc) is TailstockStep.FAULT and plc.out("PLCALARMS.userArea0.out.alarm700030") == 1
    assert plc.out("W1.basic.out.fixedStopEnable") == 0 and plc.out("CHAN1.basic.out.disableFeed") == 1


def test_the_approach_watchdog_takes_the_enable_away() -> None:
    plc = _plc({"approach_timeout": 0.05})
    plc.nc("W1.basic.in.fixedStopRequest", 1)
    plc.scan(4)
    assert _step(plc) is TailstockStep.ADVANCE
    plc.scan(4)
    assert _step(plc) is TailstockStep.FAULT and plc.out("PLCALARMS.userArea0.out.alarm700031") == 1
    assert plc.out("W1.basic.out.fixedStopEnable") == 0


def test_a_wrong_timeout_is_refused() -> None:
    with pytest.raises(ValueError, match="plc: approach_timeout is a time in seconds above 0, got '5s'"):
        _plc({"approach_timeout": "5s"})


def test_without_a_tailstock_the_network_does_nothing() -> None:
    plc = PlcBench(Tailstock, IO_LIST, AXES, {"master_spindle": "SP1"})
    plc.nc("W1.basic.in.fixedStopRequest", 1)
    plc.scan(3)
    assert plc.out("W1.basic.out.fixedStopEnable") == 0


def _at_the_stop(plc: PlcBench) -> None:
    plc.nc("W1.basic.in.fixedStopRequest", 1)
    plc.scan(2)
    plc.nc("W1.drive.in.torqueBelowThreshold", 1)
    plc.nc("W1.basic.in.fixedStopReached", 1)
    plc.input("Tailstock.atPart", 1)
    plc.scan(2)


def test_with_the_torque_check_the_acknowledgement_waits_for_the_clamping_torque() -> None:
    plc = _plc({"clamp_torque_timeout": 0.5})
    _at_the_stop(plc)
    assert _step(plc) is TailstockStep.ADVANCE and plc.out("W1.basic.out.fixedStopAckReached") == 0
    plc.nc("W1.drive.in.torqueBelowThreshold", 0)  # |Md| >= Mdx: the clamping torque is there
    plc.scan(2)
    assert _step(plc) is TailstockStep.CLAMPED and plc.out("W1.basic.out.fixedStopAckReached") == 1


def test_a_clamping_torque_that_never_comes_raises_700033_and_takes_the_enable_away() -> None:
    plc = _plc({"clamp_torque_timeout": 0.05})
    _at_the_stop(plc)
    plc.scan(6)
    assert _step(plc) is TailstockStep.FAULT and plc.out("PLCALARMS.userArea0.out.alarm700033") == 1
    assert plc.out("W1.basic.out.fixedStopEnable") == 0 and plc.out("W1.basic.out.fixedStopAckReached") == 0


def test_without_the_torque_check_the_drives_message_is_not_read() -> None:
    plc = _plc()
    _at_the_stop(plc)
    assert _step(plc) is TailstockStep.CLAMPED  # |Md| < Mdx still 1: not asked for
