"""The PLC program drive_lineup alone (plc_stub/programs/drive_lineup.py): the test plays the drive of
the braked axis Z1 (DB33: its ready DBX92.7 and the brake's feedback DBX92.5); the scenarios
scenarios/drives/drive_lineup_*.yaml run it against the NC and the plant's brake."""

from __future__ import annotations

import pytest
from plc_bench import PlcBench

from interfaces.commissioning import AxisFacts, Commissioning
from plc_stub.programs import REGISTRY
from plc_stub.programs.drive_lineup import DriveLineup, LineUpStep
from plc_stub.programs.tool_change import ToolChange

AXES = ("X1", "Y1", "Z1")
IO_LIST = {"I1.2": "MCP.reset", "I6.0": "EStop.chainOk", "I6.1": "Drives.ready", "Q0.0": "Drives.on"}
FACTS = Commissioning(tuple(AxisFacts(axis, 31 + index, "linear axis", "mm", "", "plus", -1)
                            for index, axis in enumerate(AXES)),
                      devices={"holding_brake": {"axis_db": 33, "switch_time": 0.05}})
RELEASED, READY = "Z1.drive.in.holdingBrakeReleased", "Z1.drive.in.enabled"


def _plc() -> PlcBench:
    return PlcBench(DriveLineup, IO_LIST, AXES, {}, FACTS)


def _step(plc: PlcBench) -> LineUpStep:
    program = plc.runtime.program
    assert isinstance(program, DriveLineup)
    return program.line_up_step


def _outputs(plc: PlcBench) -> tuple[int, int, int, int]:
    """What the program wrote in its last scan (the runtime publishes it at the start of the next)."""
    image = plc.runtime.io.image
    return tuple(int(image.read(plc.catalog.resolve(name))) for name in (  # type: ignore[return-value]
        "Z1.drive.out.enablePulses", "Z1.basic.out.enableCtrl", "Z1.drive.out.releaseHoldingBrake",
        "Z1.basic.out.feedStopSpindleStop"))


def _published(plc: PlcBench) -> tuple[int, int, int, int]:
    return (int(plc.out("Z1.drive.out.enablePulses")), int(plc.out("Z1.basic.out.enableCtrl")),
            int(plc.out("Z1.drive.out.releaseHoldingBrake")), int(plc.out("Z1.basic.out.feedStopSpindleStop")))


def _ready(plc: PlcBench) -> None:
    plc.scan(3)
    plc.nc(READY, 1)
    plc.scan(1)
    plc.nc(RELEASED, 1)
    plc.scan(1)
    assert _step(plc) is LineUpStep.READY


def test_the_program_builds_on_tool_change() -> None:
    assert REGISTRY["drive_lineup"] is DriveLineup and issubclass(DriveLineup, ToolChange)


def test_pulses_then_controller_enable_then_the_brake_then_the_axis_may_move() -> None:
    plc = _plc()
    seen = []
    for _ in range(3):
        plc.scan()
        seen.append((_step(plc), _outputs(plc)))
    assert seen == [(LineUpStep.PULSES, (1, 0, 0, 1)), (LineUpStep.ENABLE, (1, 1, 0, 1)),
                    (LineUpStep.ENABLE, (1, 1, 0, 1))]  # waiting for the drive ready
    plc.nc(READY, 1)
    plc.scan()
    assert (_step(plc), _outputs(plc)) == (LineUpStep.RELEASE, (1, 1, 1, 1))
    plc.nc(RELEASED, 1)
    plc.scan()
    assert (_step(plc), _outputs(plc)) == (LineUpStep.READY, (1, 1, 1, 0))
    plc.scan()
    assert _published(plc) == (1, 1, 1, 0)
    assert plc.out("X1.basic.out.enableCtrl") == 1 and plc.out("X1.basic.out.feedStopSpindleStop") == 0


def test_the_brake_engages_before_the_enables_drop() -> None:
    plc = _plc()
    _ready(plc)
    plc.input("EStop.chainOk", 0)
    plc.scan(3)
    assert (_step(plc), _outputs(plc)) == (LineUpStep.ENGAGE, (1, 1, 0, 1))  # the drive holds the axis
    plc.nc(RELEASED, 0)
    plc.scan()
    assert (_step(plc), _outputs(plc)) == (LineUpStep.OFF, (0, 0, 0, 1))


@pytest.mark.parametrize(("released", "alarm", "outputs"),
                         [(False, 700050, (0, 0, 0, 1)), (True, 700051, (1, 1, 0, 1))])
def test_a_brake_that_does_not_follow_raises_its_alarm_until_the_reset_key(
        released: bool, alarm: int, outputs: tuple[int, int, int, int]) -> None:
    plc = _plc()
    if released:
        _ready(plc)
        plc.input("EStop.chainOk", 0)  # the brake should engage, its contact stays 1
    else:
        plc.scan(3)
        plc.nc(READY, 1)  # the brake should release, its contact stays 0
    plc.scan(35)  # brake_timeout 0.3 s of 10 ms scans
    assert _step(plc) is LineUpStep.FAULT and plc.out(f"PLCALARMS.userArea0.out.alarm{alarm}") == 1
    assert _outputs(plc) == outputs  # not engaged: the enables stay, the drive holds the axis
    plc.nc(RELEASED, 0)
    plc.input("EStop.chainOk", 1)
    plc.tap("MCP.reset")
    assert plc.out(f"PLCALARMS.userArea0.out.alarm{alarm}") == 0 and _step(plc) is not LineUpStep.FAULT


def test_no_drive_ready_within_ready_timeout_raises_700052() -> None:
    plc = _plc()
    plc.scan(14)
    assert _step(plc) is LineUpStep.FAULT and plc.out("PLCALARMS.userArea0.out.alarm700052") == 1
    assert _outputs(plc) == (0, 0, 0, 1)


def test_a_machine_without_a_brake_runs_as_tool_change() -> None:
    plc = PlcBench(DriveLineup, IO_LIST, AXES, {}, Commissioning(FACTS.axes))
    plc.scan(3)
    assert _published(plc)[1:] == (1, 0, 0)
    program = plc.runtime.program
    assert isinstance(program, DriveLineup) and program.braked_axis is None


def test_wrong_parameters_are_refused() -> None:
    with pytest.raises(ValueError, match="brake_timeout"):
        PlcBench(DriveLineup, IO_LIST, AXES, {"brake_timeout": -1}, FACTS)
