"""sync_spindle: the counter-spindle handover step chain and its chuck supervision.

The PLC runs alone on the bench (plc_bench.py); the test plays the NC (SP2 follows SP1 in the
configured pair), the chucks (sensors I10.1-I10.4) and the operator.  SP1 holds the part at
power-on, SP2's chuck waits open.  A value the PLC computes shows one scan later (PUBLISH).
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import pytest
from plc_bench import PlcBench

from plc_stub.programs import REGISTRY
from plc_stub.programs.guard_door import GuardedSpindle
from plc_stub.programs.sync_spindle import HandoverStep, SyncSpindle

AXES = ("X1", "SP1", "SP2")
IO_LIST = {
    "I0.1": "MCP.mda", "I1.0": "MCP.ncStart", "I1.2": "MCP.reset",
    "I6.0": "EStop.chainOk", "I6.1": "Drives.ready",
    "I10.0": "Door.closed", "I10.1": "SP1.chuckClosed", "I10.2": "SP1.chuckOpen",
    "I10.3": "SP2.chuckClosed", "I10.4": "SP2.chuckOpen",
    "Q0.0": "Drives.on", "Q0.4": "SP1.chuckClose", "Q0.5": "SP1.chuckRelease", "Q0.6": "SP2.chuckClose",
    "Q0.7": "SP2.chuckRelease", "Q1.7": "Lamp.alarm",
}
PUBLISH = 2


def handover_plc(parameters: Mapping[str, Any] | None = None, io_list: Mapping[str, str] = IO_LIST) -> PlcBench:
    """Power-on: the part in SP1's chuck, SP2's chuck open, the door closed, a program running."""
    plc = PlcBench(SyncSpindle, io_list, AXES, parameters)
    plc.input("Door.closed", 1)
    chuck(plc, "SP1", clamped=True)
    chuck(plc, "SP2", clamped=False)
    for spindle in ("SP1", "SP2"):
        plc.nc(f"{spindle}.basic.in.spindleModeActive", 1)
    plc.nc("CHAN1.basic.in.stateActive", 1)
    plc.scan(PUBLISH)
    return plc


@pytest.fixture
def plc() -> PlcBench:
    return handover_plc()


def chuck(plc: PlcBench, spindle: str, clamped: bool | None) -> None:
    """The chuck's end-position sensors: clamped, open, or between (None)."""
    plc.input(f"{spindle}.chuckClosed", 1 if clamped is True else 0)
    plc.input(f"{spindle}.chuckOpen", 1 if clamped is False else 0)


def coupled(plc: PlcBench, fine: bool) -> None:
    """SP2 follows SP1 (DB35.DBX99.1), in fine synchronism (98.0) or not."""
    plc.nc("SP2.coupling.in.followingSpindleActive", 1)
    plc.nc("SP2.coupling.in.syncFineReached", 1 if fine else 0)
    plc.nc("SP2.coupling.in.syncCoarseReached", 1 if fine else 0)


def step(plc: PlcBench) -> HandoverStep:
    program = plc.runtime.program
    assert isinstance(program, SyncSpindle)
    return program.handover


def outputs(plc: PlcBench) -> tuple[object, object, object]:
    """Read-in disable DB21.DBX6.1 and the chuck commands of SP1 and SP2: 1 = clamp (chuckClose on,
    chuckRelease off), 0 = open (the other way round), None = neither solenoid (the chuck holds)."""
    return plc.out("CHAN1.basic.out.disableReadIn"), command(plc, "SP1"), command(plc, "SP2")


def command(plc: PlcBench, spindle: str) -> object:
    solenoids = plc.out(f"{spindle}.chuckClose"), plc.out(f"{spindle}.chuckRelease")
    return {(1, 0): 1, (0, 1): 0, (0, 0): None}[solenoids]


def test_sync_spindle_is_registered_and_has_the_guard_door() -> None:
    assert "sync_spindle" in REGISTRY
    assert issubclass(SyncSpindle, GuardedSpindle)


def test_at_power_on_the_valves_take_the_state_the_sensors_show(plc: PlcBench) -> None:
    assert outputs(plc) == (0, 1, 0)  # the part stays clamped in SP1
    plc.scan(300)
    assert outputs(plc) == (0, 1, 0)
    assert plc.out("Lamp.alarm") == 0


def test_a_chuck_between_its_end_positions_at_power_on_is_left_alone() -> None:
    plc = PlcBench(SyncSpindle, IO_LIST, AXES)
    chuck(plc, "SP1", clamped=True)
    chuck(plc, "SP2", clamped=None)
    plc.scan(300)
    assert outputs(plc) == (0, 1, None)
    assert plc.out("Lamp.alarm") == 0


def test_the_handover_from_fine_synchronism_to_the_cut_off(plc: PlcBench) -> None:
    coupled(plc, fine=False)  # COUPON: the counter spindle synchronises
    plc.scan(10)
    assert outputs(plc) == (0, 1, 0)
    coupled(plc, fine=True)
    plc.scan(PUBLISH)
    assert outputs(plc) == (1, 1, 1)  # the program held, the counter chuck clamps
    assert step(plc) is HandoverStep.CLAMP_COUNTER
    chuck(plc, "SP2", clamped=None)
    plc.scan(20)
    assert outputs(plc) == (1, 1, 1)
    chuck(plc, "SP2", clamped=True)
    plc.scan(PUBLISH)
    assert outputs(plc) == (1, 0, 1)  # the part is in both chucks: the main chuck lets go
    chuck(plc, "SP1", clamped=None)
    plc.scan(20)
    assert outputs(plc) == (1, 0, 1)
    chuck(plc, "SP1", clamped=False)
    plc.scan(PUBLISH)
    assert outputs(plc) == (0, 0, 1)  # the program cuts off
    assert step(plc) is HandoverStep.HANDED_OVER
    plc.nc("SP2.coupling.in.followingSpindleActive", 0)  # COUPOF
    plc.scan(PUBLISH)
    assert step(plc) is HandoverStep.IDLE
    assert outputs(plc) == (0, 0, 1)  # the part stays in the counter spindle


@pytest.mark.parametrize("situation", ["channel reset", "counter chuck clamped", "main chuck open", "door open"])
def test_no_handover_without_its_preconditions(plc: PlcBench, situation: str) -> None:
    if situation == "channel reset":
        plc.nc("CHAN1.basic.in.stateActive", 0)
    elif situation == "counter chuck clamped":
        chuck(plc, "SP2", clamped=True)
    elif situation == "main chuck open":
        chuck(plc, "SP1", clamped=False)
    else:
        plc.input("Door.closed", 0)
    plc.scan(PUBLISH)
    coupled(plc, fine=True)
    plc.scan(20)
    assert step(plc) is HandoverStep.IDLE
    assert plc.out("CHAN1.basic.out.disableReadIn") == 0


def test_the_door_opened_before_the_counter_chuck_holds_opens_it_again(plc: PlcBench) -> None:
    coupled(plc, fine=True)
    plc.scan(PUBLISH)
    chuck(plc, "SP2", clamped=None)
    plc.input("Door.closed", 0)
    plc.nc("SP1.basic.in.isStationary", 0)
    plc.scan(PUBLISH)
    assert step(plc) is HandoverStep.WAIT_SYNC
    assert outputs(plc) == (1, 1, 0)  # the program stays held; the counter chuck opens again
    chuck(plc, "SP2", clamped=False)
    plc.nc("SP1.basic.in.isStationary", 1)
    plc.scan(10)
    assert step(plc) is HandoverStep.WAIT_SYNC  # door open: no new clamping
    plc.input("Door.closed", 1)
    plc.scan(PUBLISH)
    plc.tap("MCP.ncStart")
    plc.scan(30)  # the door network judges the synchronism after resync_delay
    assert step(plc) is HandoverStep.CLAMP_COUNTER
    assert outputs(plc) == (1, 1, 1)


def test_synchronism_lost_while_clamping_opens_the_counter_chuck_again(plc: PlcBench) -> None:
    coupled(plc, fine=True)
    plc.scan(PUBLISH)
    chuck(plc, "SP2", clamped=None)
    coupled(plc, fine=False)
    plc.scan(PUBLISH)
    assert outputs(plc) == (1, 1, 0)
    plc.nc("SP2.coupling.in.followingSpindleActive", 0)  # the coupling ended (reset)
    plc.scan(PUBLISH)
    assert step(plc) is HandoverStep.IDLE
    assert outputs(plc) == (0, 1, 0)


def test_a_counter_chuck_that_does_not_clamp_is_a_fault_until_reset() -> None:
    plc = handover_plc({"chuck_timeout": 0.5})
    coupled(plc, fine=True)
    plc.scan(PUBLISH)
    chuck(plc, "SP2", clamped=None)  # no pressure, a sensor broken, no part ...
    plc.scan(48)
    assert plc.out("Lamp.alarm") == 0
    plc.scan(4)
    assert step(plc) is HandoverStep.FAULT
    assert plc.out("Lamp.alarm") == 1
    assert outputs(plc) == (1, 1, 1)  # the program stays held, the valves as they are
    plc.tap("MCP.reset")
    assert step(plc) is HandoverStep.IDLE
    assert plc.out("Lamp.alarm") == 0
    assert outputs(plc) == (0, 1, 1)


def test_a_main_chuck_that_does_not_open_is_a_fault() -> None:
    plc = handover_plc({"chuck_timeout": 0.5})
    coupled(plc, fine=True)
    plc.scan(PUBLISH)
    chuck(plc, "SP2", clamped=True)
    plc.scan(PUBLISH)
    assert outputs(plc) == (1, 0, 1)
    plc.scan(60)
    assert step(plc) is HandoverStep.FAULT
    assert plc.out("Lamp.alarm") == 1


def test_main_and_counter_spindle_by_parameter() -> None:
    plc = handover_plc({"main_spindle": "SP2", "counter_spindle": "SP1"})
    plc.nc("SP1.coupling.in.followingSpindleActive", 1)
    plc.nc("SP1.coupling.in.syncFineReached", 1)
    chuck(plc, "SP1", clamped=False)
    chuck(plc, "SP2", clamped=True)
    plc.scan(PUBLISH)
    assert step(plc) is HandoverStep.CLAMP_COUNTER
    assert plc.out("SP1.chuckClose") == 1


def test_parameter_mistakes_are_reported_together() -> None:
    with pytest.raises(ValueError) as error:
        handover_plc({"main_spindle": "SP9", "counter_spindle": "X1", "chuck_timeout": -1})
    assert str(error.value).splitlines() == [
        "plc: main_spindle names 'SP9', which the machine lacks",
        "plc: counter_spindle X1 needs its chuck wired: X1.chuckClose, X1.chuckRelease, X1.chuckClosed,"
        " X1.chuckOpen",
        "plc: chuck_timeout is a time in seconds above 0, got -1",
    ]


def test_unknown_parameters_name_the_program() -> None:
    with pytest.raises(ValueError, match="unknown parameter 'chuck_time'; the program sync_spindle takes"):
        handover_plc({"chuck_time": 1.0})


def test_a_machine_with_one_chuck_must_name_the_counter_spindle() -> None:
    io_list = {key: name for key, name in IO_LIST.items() if not name.startswith("SP2.chuck")}
    with pytest.raises(ValueError) as error:
        PlcBench(SyncSpindle, io_list, AXES)
    assert str(error.value).splitlines() == [
        "plc: counter_spindle: the machine has no second spindle with a chuck wired (<spindle>.chuckClose);"
        " name the spindle",
    ]
