"""spindle: the gear change handshake, the gear report, oscillation by the PLC, spindle keys and override.

The PLC runs alone on the bench (plc_bench.py); the test plays the NC (DB31 of SP1 = DB32)
and the gearbox (sensors I9.x) scan by scan.  SP1 has a three-stage gearbox, SP2 is a motor
spindle without one, X1 a linear axis.  A value the PLC computes shows one scan later.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import pytest
from plc_bench import SCAN, PlcBench

from interfaces.image import Value
from plc_stub.programs import REGISTRY
from plc_stub.programs.referencing import Referencing
from plc_stub.programs.spindle import GEAR_SHIFT_TIMEOUT_S, Spindle

AXES = ("X1", "SP1", "SP2")
IO_LIST = {
    "I0.2": "MCP.jog", "I0.3": "MCP.ref",
    "I1.0": "MCP.ncStart", "I1.2": "MCP.reset", "I1.5": "MCP.spindleStop", "I1.6": "MCP.spindleStart",
    "IB3": "MCP.feedOverride", "IB4": "MCP.spindleOverride",
    "I6.0": "EStop.chainOk", "I6.1": "Drives.ready",
    "I9.0": "SP1.gearEngaged1", "I9.1": "SP1.gearEngaged2", "I9.2": "SP1.gearEngaged3", "I9.3": "SP1.gearNeutral",
    "Q0.0": "Drives.on",
    "Q2.0": "SP1.gearShift1", "Q2.1": "SP1.gearShift2", "Q2.2": "SP1.gearShift3",
}
SP1 = "SP1.spindle"
PUBLISH = 2  # scans from an input to the output it causes: read and compute, then publish


def spindle_plc(parameters: Mapping[str, Any] | None = None, io_list: Mapping[str, str] = IO_LIST) -> PlcBench:
    """The machine at power-on: SP1 in gear stage 1, the NC reports SP1 and SP2 as spindles."""
    plc = PlcBench(Spindle, io_list, AXES, parameters)
    if plc.plant_io.by_name("SP1.gearEngaged1") is not None:
        gearbox(plc, 1)
    for spindle in ("SP1", "SP2"):
        plc.nc(f"{spindle}.basic.in.spindleModeActive", 1)
    plc.scan(PUBLISH)
    return plc


@pytest.fixture
def plc() -> PlcBench:
    return spindle_plc()


def gearbox(plc: PlcBench, engaged: int) -> None:
    """The gearbox's sensors for the stage in mesh (0 = neutral)."""
    for stage in (1, 2, 3):
        plc.input(f"SP1.gearEngaged{stage}", 1 if stage == engaged else 0)
    plc.input("SP1.gearNeutral", 1 if engaged == 0 else 0)


def nc_requests(plc: PlcBench, stage: int, stationary: bool) -> None:
    """The NC asks for ``stage`` (82.0-2 with 82.3), the spindle still braking or standing (61.4)."""
    plc.nc(f"{SP1}.in.requestedGearStageNumber", stage)
    plc.nc(f"{SP1}.in.gearChangeoverRequested", 1)
    plc.nc("SP1.basic.in.isStationary", 1 if stationary else 0)


def actuators(plc: PlcBench) -> tuple[Value, Value, Value]:
    return plc.out("SP1.gearShift1"), plc.out("SP1.gearShift2"), plc.out("SP1.gearShift3")


def reported(plc: PlcBench) -> tuple[Value, Value]:
    """DB32.DBX16.0-2 actual gear, DB32.DBX16.3 gear changed."""
    return plc.out(f"{SP1}.out.gearStageSelection"), plc.out(f"{SP1}.out.gearChangeoverDone")


def oscillation(plc: PlcBench) -> tuple[Value, Value, Value, Value]:
    """DB32.DBX18.4 by PLC, 18.5 enable, 18.6 CW, 18.7 CCW."""
    return (plc.out(f"{SP1}.out.oscillRequest"), plc.out(f"{SP1}.out.oscillEnable"),
            plc.out(f"{SP1}.out.oscillSetDirCw"), plc.out(f"{SP1}.out.oscillSetDirCcw"))


def test_spindle_is_registered_and_does_everything_referencing_does() -> None:
    assert "spindle" in REGISTRY
    assert issubclass(Spindle, Referencing)


# ------------------------------------------------------------------------------ gear report (reset state)


def test_outside_a_change_the_sensed_gear_is_reported_without_16_3(plc: PlcBench) -> None:
    # Seed 003 L18610-18622: 16.0-2 carries the gear; 16.3 must not be set.
    assert reported(plc) == (1, 0)
    gearbox(plc, 0)  # the gearbox disengaged (stage 0, L18753-18757)
    plc.scan(PUBLISH)
    assert reported(plc) == (0, 0)
    gearbox(plc, 3)  # shifted by hand on the machine (L18598-18600)
    plc.scan(PUBLISH)
    assert reported(plc) == (3, 0)
    plc.scan(50)
    assert reported(plc) == (3, 0)
    assert actuators(plc) == (0, 0, 0)


def test_power_on_in_neutral_reports_gear_stage_0() -> None:
    plc = PlcBench(Spindle, IO_LIST, AXES)
    gearbox(plc, 0)
    plc.scan(PUBLISH)
    assert reported(plc) == (0, 0)  # L18808-18843: the PLC detects "disengaged", 16.0-2 = 0


# ------------------------------------------------------------------------------ the handshake


def test_gear_change_handshake_from_request_to_reset_of_16_3(plc: PlcBench) -> None:
    # t1: S1300 needs gear 2; the spindle still brakes
    nc_requests(plc, 2, stationary=False)
    plc.scan(20)
    assert oscillation(plc) == (0, 0, 0, 0)  # 18.5 only at standstill
    assert actuators(plc) == (0, 0, 0)
    assert reported(plc) == (1, 0)
    # t2: standstill: oscillation enable and the actuator of gear 2, the NC oscillates (no 18.4)
    plc.nc("SP1.basic.in.isStationary", 1)
    plc.scan(PUBLISH)
    assert oscillation(plc) == (0, 1, 0, 0)
    assert actuators(plc) == (0, 1, 0)
    gearbox(plc, 0)  # the sliding gear leaves stage 1 ...
    plc.scan(30)
    assert actuators(plc) == (0, 1, 0)  # held on while the teeth search their gaps
    assert reported(plc) == (1, 0)  # 16.0-2 stays until the change is done
    # t3: gear 2 is in: actuator off; 16.0-2 = 2 with 16.3 = 1 and 18.5 = 0, in one scan
    gearbox(plc, 2)
    plc.scan(1)
    assert actuators(plc) == (0, 1, 0) and reported(plc) == (1, 0)
    plc.scan(1)
    assert actuators(plc) == (0, 0, 0)
    assert reported(plc) == (2, 1)
    assert oscillation(plc) == (0, 0, 0, 0)
    plc.scan(10)
    assert reported(plc) == (2, 1)  # 16.3 stays while the NC holds 82.3
    # t4: the NC resets 82.3, the PLC resets 16.3 (L18392-18397)
    plc.nc(f"{SP1}.in.gearChangeoverRequested", 0)
    plc.scan(PUBLISH)
    assert reported(plc) == (2, 0)
    plc.scan(10)
    assert reported(plc) == (2, 0) and actuators(plc) == (0, 0, 0)


def test_a_request_at_standstill_enables_the_oscillation_at_once(plc: PlcBench) -> None:
    nc_requests(plc, 3, stationary=True)
    plc.scan(PUBLISH)
    assert oscillation(plc) == (0, 1, 0, 0)
    assert actuators(plc) == (0, 0, 1)


def test_the_gear_the_nc_asked_for_is_latched_with_its_request(plc: PlcBench) -> None:
    nc_requests(plc, 2, stationary=False)
    plc.scan(PUBLISH)
    plc.nc(f"{SP1}.in.requestedGearStageNumber", 3)  # 82.0-2 change while the request stands
    plc.nc("SP1.basic.in.isStationary", 1)
    plc.scan(PUBLISH)
    assert actuators(plc) == (0, 1, 0)


def test_the_requested_gear_already_engaged_is_reported_without_shifting(plc: PlcBench) -> None:
    nc_requests(plc, 1, stationary=True)  # e.g. after the PLC had reported gear 0 (L18764-18771)
    plc.scan(PUBLISH)
    assert reported(plc) == (1, 1)
    assert actuators(plc) == (0, 0, 0)


def test_an_nc_reset_during_the_change_releases_the_actuator(plc: PlcBench) -> None:
    nc_requests(plc, 2, stationary=True)
    plc.scan(PUBLISH)
    gearbox(plc, 0)
    plc.scan(20)
    plc.nc(f"{SP1}.in.gearChangeoverRequested", 0)  # reset: the change ends without alarm (L18694-18699)
    plc.scan(PUBLISH)
    assert actuators(plc) == (0, 0, 0)
    assert oscillation(plc) == (0, 0, 0, 0)
    assert reported(plc) == (0, 0)  # the gear report resumes: the gearbox is in neutral


# ------------------------------------------------------------------------------ watchdog


@pytest.mark.parametrize(("sensed", "report"), [(0, 0), (3, 3)])
def test_watchdog_reports_the_sensed_gear_when_the_gear_does_not_engage(sensed: int, report: int) -> None:
    plc = spindle_plc({"gear_shift_timeout": 0.5})
    nc_requests(plc, 2, stationary=True)
    plc.scan(1)  # the scan that switches the actuator on starts the watchdog
    gearbox(plc, sensed)  # stuck in neutral, or a wrong stage sensed
    plc.scan(round(0.5 / SCAN))  # 50 scans later the TON's elapsed time reaches 0.5 s ...
    assert actuators(plc) == (0, 1, 0)
    assert reported(plc) == (1, 0)
    plc.scan(1)  # ... and the next scan publishes the outcome
    assert reported(plc) == (report, 1)  # the NC compares with the set gear: alarm 22010
    assert actuators(plc) == (0, 0, 0)
    assert oscillation(plc) == (0, 0, 0, 0)
    plc.nc(f"{SP1}.in.gearChangeoverRequested", 0)
    plc.scan(PUBLISH)
    assert reported(plc) == (report, 0)


def test_watchdog_default_is_five_seconds(plc: PlcBench) -> None:
    assert GEAR_SHIFT_TIMEOUT_S == 5.0
    nc_requests(plc, 2, stationary=True)
    plc.scan(1)
    gearbox(plc, 0)
    plc.scan(round(GEAR_SHIFT_TIMEOUT_S / SCAN))
    assert reported(plc) == (1, 0)
    plc.scan(1)
    assert reported(plc) == (0, 1)


def test_a_gear_the_gearbox_lacks_ends_with_the_watchdog(plc: PlcBench) -> None:
    nc_requests(plc, 4, stationary=True)
    plc.scan(PUBLISH)
    assert actuators(plc) == (0, 0, 0)  # no actuator for gear 4
    assert oscillation(plc) == (0, 1, 0, 0)
    plc.scan(round(GEAR_SHIFT_TIMEOUT_S / SCAN))
    assert reported(plc) == (1, 1)


# ------------------------------------------------------------------------------ oscillation by the PLC


def test_oscillation_by_plc_alternates_cw_and_ccw_until_the_gear_is_engaged() -> None:
    plc = spindle_plc({"oscillation_by_plc": ["SP1"], "oscillation_time_cw": 0.2, "oscillation_time_ccw": 0.15})
    nc_requests(plc, 3, stationary=True)
    plc.scan(1)
    gearbox(plc, 0)
    directions = []
    for _ in range(75):
        plc.scan()
        request, enable, cw, ccw = oscillation(plc)
        assert (request, enable) == (1, 1)  # 18.4 with 18.5 (L19332-19334)
        assert cw + ccw == 1
        directions.append("CW" if cw else "CCW")
    # 0.2 s CW, 0.15 s CCW, 0.2 s CW, ... at a 10 ms scan, starting clockwise
    assert directions == ["CW"] * 20 + ["CCW"] * 15 + ["CW"] * 20 + ["CCW"] * 15 + ["CW"] * 5
    gearbox(plc, 3)
    plc.scan(PUBLISH)
    assert oscillation(plc) == (0, 0, 0, 0)
    assert reported(plc) == (3, 1)


def test_the_next_oscillation_by_plc_starts_clockwise_again() -> None:
    plc = spindle_plc({"oscillation_by_plc": ["SP1"]})
    nc_requests(plc, 2, stationary=True)
    plc.scan(1)
    gearbox(plc, 0)
    plc.scan(25)  # in the CCW phase
    assert oscillation(plc)[2:] == (0, 1)
    gearbox(plc, 2)
    plc.scan(PUBLISH)
    plc.nc(f"{SP1}.in.gearChangeoverRequested", 0)
    plc.scan(PUBLISH)
    nc_requests(plc, 3, stationary=True)
    plc.scan(PUBLISH)
    assert oscillation(plc) == (1, 1, 1, 0)


# ------------------------------------------------------------------------------ spindle keys and override


def test_spindle_keys_latch_the_spindle_stop_of_the_master_spindle(plc: PlcBench) -> None:
    plc.tap("MCP.spindleStop")
    assert plc.out("SP1.basic.out.feedStopSpindleStop") == 1  # DB32.DBX4.3
    plc.scan(10)
    assert plc.out("SP1.basic.out.feedStopSpindleStop") == 1  # latched
    assert plc.out("SP2.basic.out.feedStopSpindleStop") == 0
    assert plc.out("X1.basic.out.feedStopSpindleStop") == 0
    plc.tap("MCP.spindleStart")
    assert plc.out("SP1.basic.out.feedStopSpindleStop") == 0


def test_spindle_stop_wins_while_both_keys_are_pressed(plc: PlcBench) -> None:
    plc.input("MCP.spindleStart", 1)
    plc.input("MCP.spindleStop", 1)
    plc.scan(PUBLISH)
    assert plc.out("SP1.basic.out.feedStopSpindleStop") == 1


def test_master_spindle_parameter_chooses_the_spindle_of_the_keys() -> None:
    plc = spindle_plc({"master_spindle": "SP2"})
    plc.tap("MCP.spindleStop")
    assert plc.out("SP2.basic.out.feedStopSpindleStop") == 1
    assert plc.out("SP1.basic.out.feedStopSpindleStop") == 0


def test_spindle_override_switch_reaches_every_spindle_with_its_enable(plc: PlcBench) -> None:
    assert plc.out("SP1.spindle.out.ovrFactor") == 100
    plc.input("MCP.spindleOverride", 55)
    plc.input("MCP.feedOverride", 80)
    plc.scan(PUBLISH)
    for spindle in ("SP1", "SP2"):
        assert plc.out(f"{spindle}.spindle.out.ovrFactor") == 55  # DB3x.DBB19
        assert plc.out(f"{spindle}.basic.out.enableOvr") == 1  # DB3x.DBX1.7 (basic machine, every axis)
    assert plc.out("X1.spindle.out.ovrFactor") == 0  # the NC does not report X1 as a spindle
    assert plc.out("X1.basic.out.feedrateOvrFactor") == 80


def test_without_a_spindle_override_switch_the_spindles_run_at_100_percent() -> None:
    plc = spindle_plc(io_list={key: name for key, name in IO_LIST.items() if name != "MCP.spindleOverride"})
    assert plc.out("SP1.spindle.out.ovrFactor") == 100
    assert plc.out("SP2.spindle.out.ovrFactor") == 100


def test_a_spindle_without_a_gearbox_has_no_gear_networks(plc: PlcBench) -> None:
    plc.nc("SP2.spindle.in.requestedGearStageNumber", 2)
    plc.nc("SP2.spindle.in.gearChangeoverRequested", 1)
    plc.nc("SP2.basic.in.isStationary", 1)
    plc.scan(20)
    assert plc.out("SP2.spindle.out.oscillEnable") == 0
    assert plc.out("SP2.spindle.out.gearChangeoverDone") == 0
    assert plc.out("SP2.spindle.out.gearStageSelection") == 0


# ------------------------------------------------------------------------------ parameters


def test_unknown_parameters_and_wrong_values_are_reported_together() -> None:
    with pytest.raises(ValueError) as error:
        spindle_plc({"gear_shift_timout": 5.0, "gear_shift_timeout": "5s", "oscillation_by_plc": ["SP2", "Q9"],
                     "oscillation_time_cw": 0, "oscillation_time_ccw": True, "master_spindle": ["SP1"]})
    assert str(error.value).splitlines() == [
        "plc: unknown parameter 'gear_shift_timout'; the program spindle takes referencing_order,"
        " referencing_direction, gear_shift_timeout, oscillation_by_plc, oscillation_time_cw,"
        " oscillation_time_ccw, master_spindle",
        "plc: gear_shift_timeout is a time in seconds above 0, got '5s'",
        "plc: oscillation_by_plc names SP2, which has no gearbox wired (SP2.gearShift1, SP2.gearEngaged1 ...)",
        "plc: oscillation_by_plc names Q9, which the machine lacks",
        "plc: oscillation_time_cw is a time in seconds above 0, got 0",
        "plc: oscillation_time_ccw is a time in seconds above 0, got True",
        "plc: master_spindle is the name of a spindle, e.g. SP1, got ['SP1']",
    ]


@pytest.mark.parametrize(("parameters", "message"), [
    ({"oscillation_by_plc": "SP1"}, "plc: oscillation_by_plc is a list of spindles, e.g. [SP1], got 'SP1'"),
    ({"master_spindle": "SP9"}, "plc: master_spindle names SP9, which the machine lacks"),
])
def test_parameter_problems(parameters: dict[str, Any], message: str) -> None:
    with pytest.raises(ValueError) as error:
        spindle_plc(parameters)
    assert str(error.value) == message


def test_without_a_gearbox_the_spindle_keys_need_a_master_spindle() -> None:
    without_gearbox = {key: name for key, name in IO_LIST.items() if ".gear" not in name}
    with pytest.raises(ValueError) as error:
        spindle_plc(io_list=without_gearbox)
    assert str(error.value) == ("plc: master_spindle: no spindle has a gearbox wired; name the spindle the"
                                " panel's spindle keys act on")
    plc = spindle_plc({"master_spindle": "SP2"}, io_list=without_gearbox)
    plc.tap("MCP.spindleStop")
    assert plc.out("SP2.basic.out.feedStopSpindleStop") == 1


def test_referencing_parameters_are_still_checked_by_referencing() -> None:
    with pytest.raises(ValueError, match="referencing_order names Y1, which the machine lacks"):
        spindle_plc({"referencing_order": [["Y1"]]})
    spindle_plc({"referencing_order": [["X1"]], "gear_shift_timeout": 2})
