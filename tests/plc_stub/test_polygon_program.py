"""Network 11 of the program polygon: no NC start with the door open, the slides held until the
tool spindle is in fine synchronism, a loss of synchronism holds them until the reset key.

The PLC runs alone on the bench (plc_bench.py); the test plays the NC and the operator.  SP3
follows SP1 (polygon turning: DB36.DBX99.1).  A value the PLC computes shows one scan later
(PUBLISH).
"""

from __future__ import annotations

from plc_bench import PlcBench
from test_guard_door import PUBLISH, SPINDLES, door_plc, open_and_stand, synchronous

from plc_stub.programs.polygon import Polygon, PolygonStep


def coupled_plc(fine: int) -> PlcBench:
    """SP3 just coupled to SP1 (99.1), in fine synchronism or not yet, the door closed."""
    plc = door_plc()
    plc.nc("SP3.coupling.in.followingSpindleActive", 0)
    plc.scan(PUBLISH)
    synchronous(plc, coarse=fine, fine=fine)
    plc.nc("SP3.coupling.in.followingSpindleActive", 1)
    plc.scan(PUBLISH)
    return plc


def step(plc: PlcBench) -> PolygonStep:
    program = plc.runtime.program
    assert isinstance(program, Polygon)
    return program.polygon


def held(plc: PlcBench) -> tuple[object, object]:
    """The channel feed disable DB21.DBX6.0 and Lamp.alarm."""
    return plc.out("CHAN1.basic.out.disableFeed"), plc.out("Lamp.alarm")


def test_nc_start_is_disabled_while_the_door_is_open() -> None:
    plc = door_plc()
    assert plc.out("CHAN1.basic.out.disableNcStart") == 0
    plc.input("Door.closed", 0)
    plc.scan(PUBLISH)
    assert plc.out("CHAN1.basic.out.disableNcStart") == 1
    plc.input("Door.closed", 1)
    plc.scan(PUBLISH)
    assert plc.out("CHAN1.basic.out.disableNcStart") == 0


def test_the_slides_wait_for_fine_synchronism_of_the_tool_spindle() -> None:
    plc = coupled_plc(fine=0)
    assert step(plc) is PolygonStep.WAIT_FINE and held(plc) == (1, 0)
    synchronous(plc, coarse=1, fine=0)
    plc.scan(PUBLISH)
    assert held(plc) == (1, 0)  # coarse is not enough
    synchronous(plc, coarse=1, fine=1)
    plc.scan(PUBLISH)
    assert step(plc) is PolygonStep.SYNCHRONOUS and held(plc) == (0, 0)
    plc.nc("SP3.coupling.in.followingSpindleActive", 0)  # G50.2
    synchronous(plc, coarse=0, fine=0)
    plc.scan(PUBLISH)
    assert step(plc) is PolygonStep.IDLE and held(plc) == (0, 0)


def test_a_loss_of_synchronism_holds_the_slides_until_the_reset_key() -> None:
    plc = coupled_plc(fine=1)
    assert step(plc) is PolygonStep.SYNCHRONOUS and held(plc) == (0, 0)
    synchronous(plc, coarse=1, fine=0)
    plc.scan(PUBLISH)
    assert step(plc) is PolygonStep.LOST and held(plc) == (1, 1)
    synchronous(plc, coarse=1, fine=1)  # back in synchronism: still held, the operator decides
    plc.scan(10)
    assert step(plc) is PolygonStep.LOST and held(plc) == (1, 1)
    plc.tap("MCP.reset")
    assert step(plc) is PolygonStep.SYNCHRONOUS and held(plc) == (0, 0)


def test_synchronism_lost_behind_the_open_door_is_the_door_networks_business() -> None:
    plc = coupled_plc(fine=1)
    open_and_stand(plc)
    synchronous(plc, coarse=0, fine=0)  # the tool spindle turned by hand without enable
    plc.scan(PUBLISH)
    assert step(plc) is PolygonStep.WAIT_FINE and plc.out("Lamp.alarm") == 0
    assert all(plc.out(f"{spindle}.basic.out.enableCtrl") == 0 for spindle in SPINDLES if spindle != "SP2")
