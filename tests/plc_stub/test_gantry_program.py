"""The PLC program gantry alone (plc_stub/programs/gantry.py): the test plays the NC's gantry signals of
X1 (leading) and X2 (following); scenarios/gantry/ run it against the NC."""

from __future__ import annotations

import pytest
from plc_bench import PlcBench

from plc_stub.programs import REGISTRY
from plc_stub.programs.basic_machine import BasicMachine
from plc_stub.programs.gantry import Gantry, ReferenceStep

AXES = ("X1", "X2", "Y1")
IO_LIST = {
    "I0.0": "MCP.jog", "I0.1": "MCP.ref", "I1.0": "MCP.ncStart", "I1.2": "MCP.reset", "I1.3": "MCP.gantrySync",
    "I6.0": "EStop.chainOk", "I6.1": "Drives.ready", "Q0.0": "Drives.on", "Q2.4": "Lamp.gantrySync",
}
WARNING, TRIP = "PLCALARMS.userArea0.out.alarm700060", "PLCALARMS.userArea0.out.alarm700061"


def _plc(parameters: dict[str, object] | None = None) -> PlcBench:
    plc = PlcBench(Gantry, IO_LIST, AXES, parameters or {})
    for axis, leading in (("X1", 1), ("X2", 0)):
        plc.nc(f"{axis}.coupling.in.gantryActive", 1)
        plc.nc(f"{axis}.coupling.in.gantryLeadingActive", leading)
    plc.scan(2)
    return plc


def _program(plc: PlcBench) -> Gantry:
    program = plc.runtime.program
    assert isinstance(program, Gantry)
    return program


def _in_ref(plc: PlcBench) -> None:
    plc.nc("MODEGROUP.basic.in.refPointActive", 1)
    plc.scan()


def _tap(plc: PlcBench, key: str) -> None:
    plc.input(key, 1)
    plc.scan(2)
    plc.input(key, 0)
    plc.scan()


def test_the_program_builds_on_basic_machine_and_finds_the_grouping_from_the_nc() -> None:
    assert REGISTRY["gantry"] is Gantry and issubclass(Gantry, BasicMachine)
    groupings = _program(_plc()).groupings
    assert [grouping.leader for grouping in groupings] == ["X1"] and len(groupings[0].warnings) == 1


def test_nc_start_in_ref_holds_the_leading_axis_key_until_it_is_referenced_never_the_followers() -> None:
    plc = _plc()
    _tap(plc, "MCP.ncStart")
    assert plc.out("X1.basic.out.traversKeyPlus") == 0  # not in REF
    _in_ref(plc)
    _tap(plc, "MCP.ncStart")
    assert _program(plc).groupings[0].step is ReferenceStep.LEADER
    assert plc.out("X1.basic.out.traversKeyPlus") == 1 and plc.out("X2.basic.out.traversKeyPlus") == 0
    plc.nc("X1.basic.in.enc1Synchronized", 1)
    plc.scan(2)
    assert plc.out("X1.basic.out.traversKeyPlus") == 0 and _program(plc).groupings[0].step is ReferenceStep.IDLE


def test_the_sync_key_gives_dbx29_4_while_the_nc_waits_in_ref_and_the_lamp_shows_dbx101_5() -> None:
    plc = _plc()
    plc.nc("X1.coupling.in.gantrySyncRunReady", 1)
    _tap(plc, "MCP.gantrySync")
    assert plc.out("X1.coupling.out.gantryStartSyncRun") == 0  # not in REF
    _in_ref(plc)
    plc.input("MCP.gantrySync", 1)
    plc.scan(2)
    assert plc.out("X1.coupling.out.gantryStartSyncRun") == 1
    plc.input("MCP.gantrySync", 0)
    plc.nc("X1.coupling.in.gantrySyncRunReady", 0)  # the NC started the run
    plc.scan(2)
    assert plc.out("X1.coupling.out.gantryStartSyncRun") == 0 and plc.out("Lamp.gantrySync") == 0
    plc.nc("X1.coupling.in.gantrySyncOk", 1)
    plc.scan(2)
    assert plc.out("Lamp.gantrySync") == 1


def test_auto_sync_starts_the_run_by_itself_and_at_most_for_the_start_time() -> None:
    plc = _plc({"gantry_auto_sync": True, "gantry_disable_auto_sync": True})
    assert plc.out("X1.coupling.out.gantryDisableSync") == 1
    _in_ref(plc)
    plc.nc("X1.coupling.in.gantrySyncRunReady", 1)  # the NC does not take it
    plc.scan(2)
    assert plc.out("X1.coupling.out.gantryStartSyncRun") == 1
    plc.scan(60)  # 0.5 s
    assert plc.out("X1.coupling.out.gantryStartSyncRun") == 0


def test_the_warning_holds_the_feed_with_700060_and_the_trip_raises_700061_until_the_reset_key() -> None:
    plc = _plc()
    plc.nc("X2.coupling.in.gantryWarningLimitExceeded", 1)
    plc.scan(2)
    assert plc.out(WARNING) == 1 and plc.out("CHAN1.basic.out.disableFeed") == 1
    plc.nc("X2.coupling.in.gantryWarningLimitExceeded", 0)
    plc.scan(2)
    assert plc.out(WARNING) == 0 and plc.out("CHAN1.basic.out.disableFeed") == 0
    plc.nc("X2.coupling.in.gantryCutOffLimitExceeded", 1)
    plc.scan(2)
    plc.nc("X2.coupling.in.gantryCutOffLimitExceeded", 0)
    plc.scan(2)
    assert plc.out(TRIP) == 1
    _tap(plc, "MCP.reset")
    assert plc.out(TRIP) == 0


@pytest.mark.parametrize("parameters", [{"gantry_auto_sync": 1}, {"referencing_direction": {"X1": "up"}}])
def test_wrong_parameters_are_reported_when_the_plc_starts(parameters: dict[str, object]) -> None:
    with pytest.raises(ValueError, match="plc: "):
        PlcBench(Gantry, IO_LIST, AXES, parameters)
