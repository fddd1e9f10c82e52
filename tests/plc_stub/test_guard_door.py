"""The guard door network (program polygon): stop, disable, restart, resynchronise.

The PLC runs alone on the bench (plc_bench.py); the test plays the NC and the operator.  SP1 is
the leading spindle (workpiece), SP3 follows it (polygon turning: DB36.DBX99.1), SP2 stands
aside, X1 is a slide.  A value the PLC computes shows one scan later (PUBLISH).
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import pytest
from plc_bench import SCAN, PlcBench

from plc_stub.programs import REGISTRY
from plc_stub.programs.guard_door import RESYNC_DELAY_S, DoorStep, GuardDoor, GuardedSpindle
from plc_stub.programs.polygon import Polygon

AXES = ("X1", "SP1", "SP2", "SP3")
SPINDLES = ("SP1", "SP2", "SP3")
IO_LIST = {
    "I0.1": "MCP.mda", "I1.0": "MCP.ncStart", "I1.2": "MCP.reset", "I1.5": "MCP.spindleStop",
    "I1.6": "MCP.spindleStart", "IB4": "MCP.spindleOverride",
    "I6.0": "EStop.chainOk", "I6.1": "Drives.ready", "I10.0": "Door.closed",
    "Q0.0": "Drives.on", "Q1.7": "Lamp.alarm",
}
PUBLISH = 2
RESTART = round(RESYNC_DELAY_S / SCAN)  # scans from NC start until the coarse synchronism is judged


def door_plc(parameters: Mapping[str, Any] | None = None, io_list: Mapping[str, str] = IO_LIST) -> PlcBench:
    """Polygon turning at speed: SP3 follows SP1 in fine synchronism, the door closed."""
    plc = PlcBench(Polygon, io_list, AXES, {"master_spindle": "SP1", **(parameters or {})})
    if plc.plant_io.by_name("Door.closed") is not None:
        plc.input("Door.closed", 1)
    for spindle in SPINDLES:
        plc.nc(f"{spindle}.basic.in.spindleModeActive", 1)
    plc.nc("SP2.basic.in.isStationary", 1)
    plc.nc("SP1.coupling.in.leadingSpindleActive", 1)
    synchronous(plc, coarse=1, fine=1)
    plc.nc("SP3.coupling.in.followingSpindleActive", 1)
    plc.scan(PUBLISH)
    return plc


@pytest.fixture
def plc() -> PlcBench:
    return door_plc()


def door(plc: PlcBench) -> GuardDoor:
    program = plc.runtime.program
    assert isinstance(program, GuardedSpindle)
    return program.guard_door


def synchronous(plc: PlcBench, coarse: int, fine: int, resync_running: int = 0) -> None:
    plc.nc("SP3.coupling.in.syncCoarseReached", coarse)
    plc.nc("SP3.coupling.in.syncFineReached", fine)
    plc.nc("SP3.coupling.in.ProcessActive", resync_running)


def stops(plc: PlcBench) -> tuple[object, ...]:
    """DB3x.DBX4.3 of SP1, SP2, SP3 and the channel feed disable DB21.DBX6.0."""
    return (*(plc.out(f"{spindle}.basic.out.feedStopSpindleStop") for spindle in SPINDLES),
            plc.out("CHAN1.basic.out.disableFeed"))


def enables(plc: PlcBench) -> tuple[object, ...]:
    """DB3x.DBX2.1 of X1, SP1, SP2, SP3."""
    return tuple(plc.out(f"{axis}.basic.out.enableCtrl") for axis in AXES)


def open_and_stand(plc: PlcBench) -> None:
    """The door opens; the spindles brake and stand (the NC reports the leading ones stationary)."""
    plc.input("Door.closed", 0)
    plc.nc("SP1.basic.in.isStationary", 0)
    plc.scan(PUBLISH)
    plc.nc("SP1.basic.in.isStationary", 1)
    plc.scan(PUBLISH + 1)


def close_and_start(plc: PlcBench) -> None:
    plc.input("Door.closed", 1)
    plc.scan(PUBLISH)
    plc.tap("MCP.ncStart")


def test_polygon_is_registered_and_is_the_guarded_spindle_program() -> None:
    assert "polygon" in REGISTRY
    assert issubclass(Polygon, GuardedSpindle)


def test_with_the_door_closed_the_block_adds_nothing(plc: PlcBench) -> None:
    plc.scan(20)
    assert stops(plc) == (0, 0, 0, 0)
    assert enables(plc) == (1, 1, 1, 1)
    assert plc.out("SP3.coupling.out.syncSpindleResync") == 0
    assert door(plc).step is DoorStep.CLOSED


def test_opening_the_door_stops_the_spindles_together_and_holds_the_slides(plc: PlcBench) -> None:
    # seed 003 L23315-23323: 4.3 on leading and following spindle; the feed disable holds X1.
    plc.input("Door.closed", 0)
    plc.nc("SP1.basic.in.isStationary", 0)
    plc.scan(PUBLISH)
    assert stops(plc) == (1, 1, 1, 1)
    assert enables(plc) == (1, 1, 1, 1)  # no enable is taken while a spindle turns
    plc.scan(30)
    assert enables(plc) == (1, 1, 1, 1)


def test_at_standstill_the_enables_go_the_following_spindle_one_scan_later(plc: PlcBench) -> None:
    plc.input("Door.closed", 0)
    plc.nc("SP1.basic.in.isStationary", 0)
    plc.scan(PUBLISH)
    plc.nc("SP1.basic.in.isStationary", 1)  # SP3 follows SP1: its own 61.4 is not waited for
    plc.scan(PUBLISH)
    assert enables(plc) == (1, 0, 0, 1)  # SP1 and SP2 (standing aside) at once ...
    plc.scan(1)
    assert enables(plc) == (1, 0, 0, 0)  # ... SP3 when the NC sees SP1 at rest without enable
    assert stops(plc) == (1, 1, 1, 1)
    assert plc.out("X1.basic.out.enableCtrl") == 1  # the slides keep theirs, held by the feed disable


def test_closing_the_door_starts_nothing_nc_start_does(plc: PlcBench) -> None:
    open_and_stand(plc)
    plc.input("Door.closed", 1)
    plc.scan(50)
    assert enables(plc) == (1, 0, 0, 0)
    assert stops(plc) == (1, 1, 1, 1)
    plc.tap("MCP.ncStart")
    assert enables(plc) == (1, 1, 1, 1)
    assert stops(plc) == (0, 0, 0, 1)  # the spindles run up; the slides wait
    plc.scan(RESTART)
    assert stops(plc) == (0, 0, 0, 0)


def test_the_slides_wait_until_the_spindles_are_at_speed_again(plc: PlcBench) -> None:
    # L20840-20858: 83.5 "spindle in set range"; SP1 was at speed when the door opened, SP2 stood.
    plc.nc("SP1.spindle.in.speedSetpointReached", 1)
    plc.scan(PUBLISH)
    open_and_stand(plc)
    plc.nc("SP1.spindle.in.speedSetpointReached", 0)
    close_and_start(plc)
    plc.scan(RESTART + 20)
    assert door(plc).step is DoorStep.RUNNING_UP
    assert stops(plc) == (0, 0, 0, 1)
    assert not door(plc).running
    plc.nc("SP1.spindle.in.speedSetpointReached", 1)
    plc.scan(PUBLISH)
    assert stops(plc) == (0, 0, 0, 0)
    assert door(plc).running


def test_nc_start_with_the_door_open_starts_nothing(plc: PlcBench) -> None:
    open_and_stand(plc)
    plc.tap("MCP.ncStart")
    plc.scan(10)
    assert enables(plc) == (1, 0, 0, 0)
    plc.input("Door.closed", 1)
    plc.scan(10)
    assert enables(plc) == (1, 0, 0, 0)  # the start key must come after the door closed


def test_synchronism_kept_no_resynchronisation(plc: PlcBench) -> None:
    open_and_stand(plc)
    close_and_start(plc)
    plc.scan(RESTART + 10)
    assert door(plc).step is DoorStep.CLOSED
    assert plc.out("SP3.coupling.out.syncSpindleResync") == 0


def test_relation_lost_31_4_for_one_scan_then_wait_for_the_nc(plc: PlcBench) -> None:
    open_and_stand(plc)
    synchronous(plc, coarse=0, fine=0, resync_running=1)  # SP3 turned by hand in follow-up
    close_and_start(plc)
    pulses = []
    for _ in range(RESTART + 5):
        plc.scan()
        pulses.append(plc.out("SP3.coupling.out.syncSpindleResync"))
    assert pulses.count(1) == 1  # the NC starts the resynchronisation on the rising edge (L23134)
    assert plc.out("SP1.coupling.out.syncSpindleResync") == 0
    assert door(plc).step is DoorStep.WAIT_SYNC
    assert not door(plc).running
    synchronous(plc, coarse=1, fine=0, resync_running=0)  # coarse, not fine yet
    plc.scan(5)
    assert door(plc).step is DoorStep.WAIT_SYNC
    synchronous(plc, coarse=1, fine=1)
    plc.scan(PUBLISH)
    assert door(plc).running
    assert plc.out("Lamp.alarm") == 0


def test_a_resynchronisation_that_does_not_finish_lights_the_alarm_lamp_until_reset() -> None:
    plc = door_plc({"resync_timeout": 0.5})
    open_and_stand(plc)
    synchronous(plc, coarse=0, fine=0, resync_running=1)
    close_and_start(plc)
    while door(plc).step is not DoorStep.WAIT_SYNC:
        plc.scan()
    plc.scan(48)
    assert plc.out("Lamp.alarm") == 0
    plc.scan(4)  # 0.5 s in WAIT_SYNC, and published
    assert plc.out("Lamp.alarm") == 1
    assert door(plc).running  # the machine runs on; the operator sees the lamp
    plc.tap("MCP.reset")
    assert plc.out("Lamp.alarm") == 0


def test_the_door_opened_again_during_the_restart_stops_again(plc: PlcBench) -> None:
    open_and_stand(plc)
    synchronous(plc, coarse=0, fine=0, resync_running=1)
    close_and_start(plc)
    plc.scan(RESTART + 1)
    assert door(plc).step is DoorStep.WAIT_SYNC
    plc.nc("SP1.basic.in.isStationary", 0)
    plc.input("Door.closed", 0)
    plc.scan(PUBLISH)
    assert stops(plc) == (1, 1, 1, 1)
    assert plc.out("SP3.coupling.out.syncSpindleResync") == 0


def test_the_spindle_stop_key_still_stops_the_master_spindle(plc: PlcBench) -> None:
    plc.tap("MCP.spindleStop")
    assert stops(plc) == (1, 0, 0, 0)
    open_and_stand(plc)
    close_and_start(plc)
    plc.scan(RESTART)
    assert stops(plc) == (1, 0, 0, 0)  # the door's stop is gone, the key's latch is not
    plc.tap("MCP.spindleStart")
    assert stops(plc) == (0, 0, 0, 0)


def test_a_machine_without_a_door_switch_has_no_door_network() -> None:
    plc = door_plc(io_list={key: name for key, name in IO_LIST.items() if name != "Door.closed"})
    plc.nc("SP1.basic.in.isStationary", 1)
    plc.scan(20)
    assert stops(plc) == (0, 0, 0, 0)
    assert enables(plc) == (1, 1, 1, 1)


def test_door_parameters_are_checked() -> None:
    with pytest.raises(ValueError) as error:
        door_plc({"resync_delay": 0, "resync_timeout": "5s"})
    assert str(error.value).splitlines() == [
        "plc: resync_delay is a time in seconds above 0, got 0",
        "plc: resync_timeout is a time in seconds above 0, got '5s'",
    ]
