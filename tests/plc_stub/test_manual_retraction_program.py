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
