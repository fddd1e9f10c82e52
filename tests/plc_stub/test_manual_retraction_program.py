"""manual_retraction: the power-on mode and the selection of the retraction (PI service RETRAC).

The PLC runs alone on the bench (plc_bench.py); the test plays the NC and the operator.  A value
the PLC computes shows one scan later (PUBLISH).
"""

from __future__ import annotations

from plc_bench import PlcBench

from plc_stub.programs import REGISTRY
from plc_stub.programs.manual_retraction import ManualRetraction

IO_LIST = {"I0.0": "MCP.auto", "I0.1": "MCP.mda", "I0.2": "MCP.jog", "I1.0": "MCP.ncStart", "I1.2": "MCP.reset",
           "I6.0": "EStop.chainOk", "I6.1": "Drives.ready"}
PUBLISH = 2


def bench(mode_active: str = "autoModeActive") -> PlcBench:
    plc = PlcBench(ManualRetraction, IO_LIST, ("X1", "Z1"))
    plc.nc(f"MODEGROUP.basic.in.{mode_active}", 1)
    plc.nc("CHAN1.basic.in.stateReset", 1)
    return plc


def test_it_is_registered() -> None:
    assert "manual_retraction" in REGISTRY


def test_at_power_on_the_plc_keeps_the_mode_the_nc_chose() -> None:
    plc = bench("autoModeActive")
    plc.scan(PUBLISH)
    assert (plc.out("MODEGROUP.basic.out.autoMode"), plc.out("MODEGROUP.basic.out.jogMode")) == (1, 0)


def test_retract_data_select_jog_and_then_request_the_retraction_once() -> None:
    plc = bench("autoModeActive")
    plc.scan(PUBLISH)
    plc.nc("CHAN1.basic.in.jogRetractDataAvailable", 1)
    plc.scan(PUBLISH)
    assert plc.out("MODEGROUP.basic.out.jogMode") == 1
    assert plc.out("CHAN1.piService.out.retracRequest") == 0  # the NC does not show JOG yet
    plc.nc("MODEGROUP.basic.in.autoModeActive", 0)
    plc.nc("MODEGROUP.basic.in.jogModeActive", 1)
    plc.scan(PUBLISH)
    assert plc.out("CHAN1.piService.out.retracRequest") == 1
    plc.nc("CHAN1.piService.in.retracError", 1)  # refused: the request goes, and is not repeated
    plc.scan(PUBLISH)
    plc.nc("CHAN1.piService.in.retracError", 0)
    plc.scan(5)
    assert plc.out("CHAN1.piService.out.retracRequest") == 0


def test_the_nc_start_key_selects_it_again_after_a_cancel() -> None:
    plc = bench("jogModeActive")
    plc.nc("CHAN1.basic.in.jogRetractDataAvailable", 1)
    plc.scan(PUBLISH)
    assert plc.out("CHAN1.piService.out.retracRequest") == 1
    plc.nc("CHAN1.piService.in.retracDone", 1)
    plc.nc("CHAN1.basic.in.jogRetractActive", 1)
    plc.scan(PUBLISH)
    assert plc.out("CHAN1.piService.out.retracRequest") == 0
    plc.nc("CHAN1.piService.in.retracDone", 0)
    plc.nc("CHAN1.basic.in.jogRetractActive", 0)  # RESET cancelled it
    plc.scan(5)
    assert plc.out("CHAN1.piService.out.retracRequest") == 0
    plc.input("MCP.ncStart", 1)
    plc.scan(PUBLISH)
    assert plc.out("CHAN1.piService.out.retracRequest") == 1


def test_the_selection_shows_the_wcs_and_the_softkey_toggles_it() -> None:
    plc = bench("jogModeActive")
    plc.scan(PUBLISH)
    assert plc.out("HMI.basic.out.displayWcsValues") == 0
    plc.nc("HMI.basic.in.mcsWcsSwitched", 1)  # the MCS/WCS softkey
    plc.scan(PUBLISH)
    assert plc.out("HMI.basic.out.displayWcsValues") == 1
    plc.scan(5)
    assert plc.out("HMI.basic.out.displayWcsValues") == 1  # once per press
    plc.nc("HMI.basic.in.mcsWcsSwitched", 0)
    plc.scan(1)
    plc.nc("HMI.basic.in.mcsWcsSwitched", 1)
    plc.scan(PUBLISH)
    assert plc.out("HMI.basic.out.displayWcsValues") == 0
    plc.nc("CHAN1.basic.in.jogRetractActive", 1)  # SEQ-MR step 7: the PLC selects the WCS
    plc.scan(PUBLISH)
    assert plc.out("HMI.basic.out.displayWcsValues") == 1


PANEL_HANDWHEELS = {**IO_LIST, "IB2": "MCP.handwheel1", "IB3": "MCP.handwheel2", "IB4": "MCP.handwheel3",
                    "I5.0": "MCP.inc1", "I5.1": "MCP.inc10", "I5.2": "MCP.inc100", "I5.3": "MCP.inc1000",
                    "I5.4": "MCP.inc10000"}


def test_network_12_assigns_the_handwheels_from_the_panel_selectors() -> None:
    plc = PlcBench(ManualRetraction, PANEL_HANDWHEELS, ("X1", "Z1", "SP1"))
    plc.input("MCP.handwheel1", 2)  # geometry axis 2 of channel 1
    plc.input("MCP.handwheel2", 0x80 | 2)  # machine axis 2: Z1
    plc.input("MCP.handwheel3", 0x80 | 2)  # the same axis: both bits
    plc.scan(PUBLISH)
    assert plc.out("CHAN1.geoAxis2.out.handwheelSelection") == 1
    assert plc.out("Z1.basic.out.handwheelSelection") == 0b110
    assert plc.out("X1.basic.out.handwheelSelection") == 0 and plc.out("CHAN1.geoAxis1.out.handwheelSelection") == 0
    assert plc.out("Z1.basic.out.inc100") == 0  # no increment key pressed since power-on
    plc.tap("MCP.inc100")
    assert (plc.out("Z1.basic.out.inc100"), plc.out("CHAN1.geoAxis2.out.inc100")) == (1, 1)
    assert plc.out("X1.basic.out.inc100") == 0  # no handwheel: its traverse keys stay continuous
    plc.tap("MCP.inc10")  # the increment last pressed counts
    assert (plc.out("Z1.basic.out.inc100"), plc.out("Z1.basic.out.inc10")) == (0, 1)
    plc.input("MCP.handwheel2", 0)
    plc.input("MCP.handwheel3", 0x80 | 9)  # no machine axis 9: no assignment
    plc.scan(PUBLISH)
    assert (plc.out("Z1.basic.out.handwheelSelection"), plc.out("Z1.basic.out.inc10")) == (0, 0)

