"""The PLC program rotary_table alone (plc_stub/programs/rotary_table.py): the test plays the NC's
M functions and C1's status (DB32) and the clamp's sensors; scenarios/indexing_axes/rotary_table_cycle
runs it against the NC and the plant."""

from __future__ import annotations

from plc_bench import PlcBench

from interfaces.commissioning import AxisFacts, Commissioning
from plc_stub.programs import REGISTRY
from plc_stub.programs.auxiliary import AuxiliaryMachine
from plc_stub.programs.rotary_table import RotaryTable, TableStep

AXES = ("X1", "C1")
IO_LIST = {
    "I0.1": "MCP.mda", "I1.0": "MCP.ncStart", "I1.2": "MCP.reset", "I6.0": "EStop.chainOk", "I6.1": "Drives.ready",
    "I10.0": "Clamp.closed", "I10.1": "Clamp.opened", "Q0.0": "Drives.on", "Q0.6": "Clamp.close",
}
FACTS = Commissioning(
    (AxisFacts("X1", 31, "linear axis", "mm", "", "plus", -1), AxisFacts("C1", 32, "rotary axis", "deg", "", "", -1)),
    devices={"clamp": {"axis_db": 32, "travel_time": 0.2}})


def _plc() -> PlcBench:
    plc = PlcBench(RotaryTable, IO_LIST, AXES, {}, FACTS)
    plc.input("Clamp.opened", 1)
    plc.nc("C1.basic.in.posCtrlActive", 1)
    plc.nc("C1.basic.in.indexAxisInPos", 1)
    plc.scan(2)
    return plc


def _step(plc: PlcBench) -> TableStep:
    program = plc.runtime.program
    assert isinstance(program, RotaryTable)
    assert program.table_step is not None
    return program.table_step


def _m(plc: PlcBench, value: int) -> None:
    """The NC outputs M<value> for one PLC cycle (DB21 M slot 1)."""
    plc.nc("CHAN1.auxMFuncs[1].in.value", value)
    plc.nc("CHAN1.auxMFuncs[1].in.change", 1)
    plc.scan()
    plc.nc("CHAN1.auxMFuncs[1].in.change", 0)
    plc.scan()  # the outputs of the scan that saw it are published


def _clamp(plc: PlcBench, closed: bool) -> None:
    plc.input("Clamp.closed", int(closed))
    plc.input("Clamp.opened", int(not closed))
    plc.scan(2)


def test_the_program_builds_on_the_auxiliary_functions() -> None:
    assert REGISTRY["rotary_table"] is RotaryTable and issubclass(RotaryTable, AuxiliaryMachine)


def test_m10_clamps_on_an_index_position_and_m11_unclamps_holding_the_program_meanwhile() -> None:
    plc = _plc()
    assert _step(plc) is TableStep.FREE and plc.out("Clamp.close") == 0
    _m(plc, 10)
    assert _step(plc) is TableStep.CLAMPING and plc.out("Clamp.close") == 1
    assert plc.out("C1.basic.out.clampingInProgress") == 1 and plc.out("CHAN1.basic.out.disableReadIn") == 1
    _clamp(plc, True)
    assert _step(plc) is TableStep.CLAMPED and plc.out("CHAN1.basic.out.disableReadIn") == 0
    _m(plc, 11)
    assert _step(plc) is TableStep.UNCLAMPING and plc.out("Clamp.close") == 0
    assert plc.out("C1.basic.out.clampingInProgress") == 0 and plc.out("CHAN1.basic.out.disableReadIn") == 1
    _clamp(plc, False)
    assert _step(plc) is TableStep.FREE and plc.out("CHAN1.basic.out.disableReadIn") == 0


def test_refusals_and_faults_raise_their_plc_alarms_until_the_reset_key() -> None:
    plc = _plc()
    plc.nc("C1.basic.in.indexAxisInPos", 0)
    _m(plc, 10)  # between two positions: never clamp
    assert _step(plc) is TableStep.FAULT and plc.out("PLCALARMS.userArea0.out.alarm700043") == 1
    assert plc.out("Clamp.close") == 0 and plc.out("CHAN1.basic.out.disableReadIn") == 1
    plc.nc("C1.basic.in.indexAxisInPos", 1)
    plc.tap("MCP.reset")
    assert _step(plc) is TableStep.FREE and plc.out("PLCALARMS.userArea0.out.alarm700043") == 0
    _m(plc, 10)
    plc.scan(101)  # the clamp does not close within clamp_timeout (1 s)
    assert _step(plc) is TableStep.FAULT and plc.out("PLCALARMS.userArea0.out.alarm700040") == 1
    plc.tap("MCP.reset")
    _m(plc, 10)
    _clamp(plc, True)
    plc.nc("C1.basic.in.posCtrlActive", 0)
    _m(plc, 11)  # the table's drive is not ready: the clamp stays closed
    assert plc.out("PLCALARMS.userArea0.out.alarm700042") == 1 and plc.out("Clamp.close") == 1
    plc.nc("C1.basic.in.posCtrlActive", 1)
    plc.tap("MCP.reset")
    assert _step(plc) is TableStep.CLAMPED
    plc.input("Clamp.closed", 0)  # the clamp gives way under the load
    plc.scan(2)
    assert plc.out("PLCALARMS.userArea0.out.alarm700044") == 1 and plc.out("CHAN1.basic.out.disableFeed") == 1
    assert plc.out("Clamp.close") == 1 and plc.out("C1.basic.out.clampingInProgress") == 1
    plc.tap("MCP.reset")
    assert _step(plc) is TableStep.FREE and plc.out("Clamp.close") == 0  # the reset opens it


def _h(plc: PlcBench, value: float) -> None:
    """The NC outputs H<value> for one PLC cycle (DB21 H slot 1)."""
    plc.nc("CHAN1.auxHFuncs[1].in.value", value)
    plc.nc("CHAN1.auxHFuncs[1].in.change", 1)
    plc.scan()
    plc.nc("CHAN1.auxHFuncs[1].in.change", 0)
    plc.scan()


def _fc18_answers(plc: PlcBench, **status: int) -> None:
    """The NC takes FC18's Start (DBX104.3) and answers with ``status`` (active, inPosition, error ...)."""
    for name, value in status.items():
        plc.nc(f"C1.plcAxis.in.{name}", value)
    plc.nc("C1.plcAxis.in.startAcknowledged", 1)
    plc.scan()
    plc.nc("C1.plcAxis.in.startAcknowledged", 0)
    plc.scan(2)


def test_h_n_unclamps_indexes_the_table_with_fc18_funct_4_and_clamps_it() -> None:
    plc = _plc()
    _m(plc, 10)
    _clamp(plc, True)
    _h(plc, 3)
    assert _step(plc) is TableStep.UNCLAMPING and plc.out("Clamp.close") == 0
    _clamp(plc, False)
    assert _step(plc) is TableStep.INDEXING and plc.out("CHAN1.basic.out.disableReadIn") == 1
    assert plc.out("C1.plcAxis.out.start") == 1 and plc.out("C1.plcAxis.out.function") == 4
    assert plc.out("C1.plcAxis.out.mode") == 2 and plc.out("C1.plcAxis.out.position") == 3.0
    assert plc.out("C1.plcAxis.out.feedrate") == 0.0  # MD32060
    _fc18_answers(plc, active=1)
    assert plc.out("C1.plcAxis.out.start") == 0 and _step(plc) is TableStep.INDEXING
    plc.nc("C1.plcAxis.in.active", 0)
    plc.nc("C1.plcAxis.in.inPosition", 1)  # in position, DBX76.6 still 1 from _plc()
    plc.scan(2)
    assert _step(plc) is TableStep.CLAMPING and plc.out("Clamp.close") == 1
    _clamp(plc, True)
    assert _step(plc) is TableStep.CLAMPED and plc.out("CHAN1.basic.out.disableReadIn") == 0


def test_fc18_errors_raise_700045_or_700043_and_the_reset_key_drops_the_h_function() -> None:
    plc = _plc()
    _h(plc, 9)  # the clamp open: FC18 at once
    assert _step(plc) is TableStep.INDEXING
    _fc18_answers(plc, error=1, errorNumber=100)
    assert _step(plc) is TableStep.FAULT and plc.out("PLCALARMS.userArea0.out.alarm700045") == 1
    plc.tap("MCP.reset")
    assert _step(plc) is TableStep.FREE and plc.out("PLCALARMS.userArea0.out.alarm700045") == 0
    _h(plc, 2)
    _fc18_answers(plc, error=1, errorNumber=30)  # the NC aborted the motion
    assert _step(plc) is TableStep.FAULT and plc.out("PLCALARMS.userArea0.out.alarm700043") == 1
    plc.tap("MCP.reset")
    _h(plc, 2)
    _fc18_answers(plc, error=0, errorNumber=0, active=1)
    assert _step(plc) is TableStep.INDEXING
    plc.tap("MCP.reset")  # the NC's reset aborts the motion; the PLC drops the H function
    assert _step(plc) is TableStep.FREE and plc.out("CHAN1.basic.out.disableReadIn") == 0
    assert all(plc.out(f"PLCALARMS.userArea0.out.alarm{n}") == 0 for n in range(700040, 700046))


def test_no_in_position_within_index_timeout_is_700043_with_fc18_stop() -> None:
    plc = _plc()
    _h(plc, 2)
    _fc18_answers(plc, active=1)
    scans = 0
    while _step(plc) is TableStep.INDEXING:
        plc.scan()
        scans += 1
    assert scans == 496  # index_timeout 5 s
    stops = []
    for _ in range(4):
        plc.scan()
        stops.append(plc.out("C1.plcAxis.out.stop"))
    assert plc.out("PLCALARMS.userArea0.out.alarm700043") == 1
    assert sorted(stops) == [0, 0, 0, 1]  # FC18 Stop: one scan's pulse
