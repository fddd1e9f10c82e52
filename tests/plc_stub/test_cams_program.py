"""The PLC program cams alone (plc_stub/programs/cams.py): the test plays the NC's cam signals and Z1's
status; scenarios/software_cams/ run it against the NC."""

from __future__ import annotations

import pytest
from plc_bench import PlcBench

from plc_stub.programs import REGISTRY
from plc_stub.programs.auxiliary import AuxiliaryMachine
from plc_stub.programs.cams import Cams, LubeStep

AXES = ("X1", "Z1")
IO_LIST = {
    "I0.1": "MCP.mda", "I1.0": "MCP.ncStart", "I1.2": "MCP.reset", "I6.0": "EStop.chainOk", "I6.1": "Drives.ready",
    "Q0.0": "Drives.on", "Q2.4": "Lube.pump",
}


def _plc(parameters: dict[str, object] | None = None, io_list: dict[str, str] = IO_LIST) -> PlcBench:
    plc = PlcBench(Cams, io_list, AXES, {"cam_axis": "Z1", "lube_cam": 3, "lube_pulse": 0.1,
                                          **(parameters or {})})
    plc.scan(2)
    return plc


def _program(plc: PlcBench) -> Cams:
    program = plc.runtime.program
    assert isinstance(program, Cams)
    return program


def _activate(plc: PlcBench) -> None:
    plc.nc("Z1.basic.in.enc1Synchronized", 1)
    plc.scan(2)  # the outputs of the scan that saw it are published with the next
    assert plc.out("Z1.basic.out.swCams") == 1
    plc.nc("Z1.basic.in.swCamsActive", 1)
    plc.scan()


def test_the_program_builds_on_the_auxiliary_functions() -> None:
    assert REGISTRY["cams"] is Cams and issubclass(Cams, AuxiliaryMachine)


def test_the_cams_go_on_with_referencing_and_the_plus_cam_gives_one_pulse_per_rising_edge() -> None:
    plc = _plc()
    assert plc.out("Z1.basic.out.swCams") == 0  # not referenced: no cams
    _activate(plc)
    plc.nc("NC.basic.in.swCams[0].plus3", 1)
    plc.scan(2)
    assert (_program(plc).lube_step, plc.out("Lube.pump"), _program(plc).strokes) == (LubeStep.PULSE, 1, 1)
    plc.scan(12)  # 0.1 s at 10 ms
    assert (_program(plc).lube_step, plc.out("Lube.pump")) == (LubeStep.IDLE, 0)
    plc.scan(5)
    assert plc.out("Lube.pump") == 0  # the signal stays: no second pulse
    plc.nc("NC.basic.in.swCams[0].plus3", 0)
    plc.scan()
    plc.nc("NC.basic.in.swCams[0].plus3", 1)
    plc.scan(2)
    assert (plc.out("Lube.pump"), _program(plc).strokes) == (1, 2)


def test_cams_that_do_not_become_active_raise_700030_and_hold_the_feed_until_the_reset_key() -> None:
    plc = _plc({"cams_timeout": 0.05})
    plc.nc("Z1.basic.in.enc1Synchronized", 1)
    plc.scan(8)
    assert plc.out("PLCALARMS.userArea0.out.alarm700030") == 1 and plc.out("CHAN1.basic.out.disableFeed") == 1
    plc.nc("NC.basic.in.swCams[0].plus3", 1)
    plc.scan(2)
    assert plc.out("Lube.pump") == 0  # no lubrication on cams the NC does not run
    plc.nc("Z1.basic.in.swCamsActive", 1)
    plc.input("MCP.reset", 1)
    plc.scan(2)
    plc.input("MCP.reset", 0)
    plc.scan(2)
    assert plc.out("PLCALARMS.userArea0.out.alarm700030") == 0


def test_a_machine_without_lube_pump_has_no_lubrication() -> None:
    plc = _plc(io_list={key: value for key, value in IO_LIST.items() if value != "Lube.pump"})
    plc.nc("Z1.basic.in.enc1Synchronized", 1)
    plc.scan(20)
    assert plc.out("Z1.basic.out.swCams") == 0 and plc.out("PLCALARMS.userArea0.out.alarm700030") == 0


@pytest.mark.parametrize(("parameters", "problem"), [
    ({"cam_axis": "Q9"}, "plc: cam_axis is a machine axis of this machine (X1, Z1), got 'Q9'"),
    ({"lube_cam": 33}, "plc: lube_cam is a cam pair 1..32, got 33"),
    ({"lube_pulse": 0}, "plc: lube_pulse is a time in seconds above 0, got 0"),
])
def test_bad_parameters_are_refused_with_their_names(parameters: dict[str, object], problem: str) -> None:
    with pytest.raises(ValueError, match=problem.replace("(", r"\(").replace(")", r"\)")):
        _plc(parameters)
