"""basic_machine: the basic machine control, scan by scan, against its interface and plant images.

The PLC runs alone on the bench (plc_bench.py): the test writes its inputs and reads what it
published, one scan later.
"""

from __future__ import annotations

import pytest
from plc_bench import SCAN, PlcBench

from interfaces.image import Value
from plc_stub.programs import REGISTRY
from plc_stub.programs.basic_machine import DRIVES_OFF_DELAY_S, BasicMachine

AXES = ("X1", "Z1", "SP1")
IO_LIST = {
    "I0.0": "MCP.auto", "I0.1": "MCP.mda", "I0.2": "MCP.jog", "I0.3": "MCP.ref",
    "I1.0": "MCP.ncStart", "I1.1": "MCP.ncStop", "I1.2": "MCP.reset", "I1.3": "MCP.feedStop",
    "I1.4": "MCP.feedStart", "I1.7": "MCP.rapid",
    "I2.0": "MCP.plus.X1", "I2.1": "MCP.minus.X1", "I2.2": "MCP.plus.Z1", "I2.3": "MCP.minus.Z1",
    "IB3": "MCP.feedOverride", "IB5": "MCP.rapidOverride",
    "I6.0": "EStop.chainOk", "I6.1": "Drives.ready",
    "I7.0": "X1.refCam", "I7.1": "X1.hwLimitMinus", "I7.2": "X1.hwLimitPlus",
    "I7.4": "Z1.hwLimitMinus", "I7.5": "Z1.hwLimitPlus",  # Z1 has no cam
    "Q0.0": "Drives.on",
}


def bench(io_list: dict[str, str] | None = None) -> PlcBench:
    return PlcBench(BasicMachine, io_list or IO_LIST, AXES)


@pytest.fixture
def plc() -> PlcBench:
    started = bench()
    started.scan(2)
    return started


def test_basic_machine_is_registered_under_its_name() -> None:
    assert "basic_machine" in REGISTRY


# ------------------------------------------------------------------------------ scan timing


def test_reference_cam_reaches_db31_dbx12_7_one_scan_later(plc: PlcBench) -> None:
    plc.input("X1.refCam", 1)
    plc.scan()  # reads the cam and computes the output
    assert plc.out("X1.basic.out.refPointApproachCam") == 0
    plc.scan()  # publishes it
    assert plc.out("X1.basic.out.refPointApproachCam") == 1
    plc.input("X1.refCam", 0)
    plc.scan()
    assert plc.out("X1.basic.out.refPointApproachCam") == 1
    plc.scan()
    assert plc.out("X1.basic.out.refPointApproachCam") == 0


def test_axis_without_a_cam_keeps_its_cam_signal_0() -> None:
    plc = bench()
    plc.scan(3)
    assert plc.out("Z1.basic.out.refPointApproachCam") == 0


def test_first_scan_publishes_nothing() -> None:
    plc = bench()
    plc.scan()
    assert plc.out("X1.basic.out.enableCtrl") == 0
    plc.scan()
    assert plc.out("X1.basic.out.enableCtrl") == 1


# ------------------------------------------------------------------------------ limit switches


@pytest.mark.parametrize(("contact", "signal"), [(1, 0), (0, 1)])
def test_normally_closed_limit_switches_are_inverted_to_db31_dbx12_0_and_12_1(
        plc: PlcBench, contact: int, signal: int) -> None:
    plc.input("X1.hwLimitMinus", contact)
    plc.input("Z1.hwLimitPlus", contact)
    plc.scan(2)
    assert plc.out("X1.basic.out.hwLimitSwitchMinus") == signal  # DB31.DBX12.0
    assert plc.out("Z1.basic.out.hwLimitSwitchPlus") == signal  # DB32.DBX12.1
    assert plc.out("X1.basic.out.hwLimitSwitchPlus") == 0
    assert plc.out("Z1.basic.out.hwLimitSwitchMinus") == 0


# ------------------------------------------------------------------------------ operating modes


def modes(plc: PlcBench) -> tuple[Value, Value, Value]:
    return (plc.out("MODEGROUP.basic.out.autoMode"), plc.out("MODEGROUP.basic.out.mdaMode"),
            plc.out("MODEGROUP.basic.out.jogMode"))


def test_power_on_mode_request_is_jog(plc: PlcBench) -> None:
    assert modes(plc) == (0, 0, 1)


@pytest.mark.parametrize(("key", "expected"), [("MCP.auto", (1, 0, 0)), ("MCP.mda", (0, 1, 0)),
                                               ("MCP.jog", (0, 0, 1))])
def test_mode_keys_select_one_hot_and_the_selection_is_held(plc: PlcBench, key: str,
                                                            expected: tuple[int, int, int]) -> None:
    plc.tap("MCP.auto" if key != "MCP.auto" else "MCP.mda")
    plc.tap(key)
    assert modes(plc) == expected
    plc.scan(10)  # key released: the selection stays
    assert modes(plc) == expected


def test_ref_key_switches_on_the_machine_function_and_a_mode_key_off(plc: PlcBench) -> None:
    plc.tap("MCP.ref")
    assert plc.out("MODEGROUP.basic.out.refPoint") == 1
    assert modes(plc) == (0, 0, 1)
    plc.tap("MCP.mda")
    assert plc.out("MODEGROUP.basic.out.refPoint") == 0
    assert modes(plc) == (0, 1, 0)


def test_ref_key_in_auto_selects_jog(plc: PlcBench) -> None:
    plc.tap("MCP.auto")
    plc.tap("MCP.ref")
    assert modes(plc) == (0, 0, 1)
    assert plc.out("MODEGROUP.basic.out.refPoint") == 1


# ------------------------------------------------------------------------------ channel keys


def test_program_keys_reach_the_channel_while_pressed(plc: PlcBench) -> None:
    for key, signal in (("MCP.ncStart", "ncStart"), ("MCP.ncStop", "ncStop"), ("MCP.reset", "reset")):
        plc.input(key, 1)
        plc.scan(2)
        assert plc.out(f"CHAN1.basic.out.{signal}") == 1, key
        plc.input(key, 0)
        plc.scan(2)
        assert plc.out(f"CHAN1.basic.out.{signal}") == 0, key


def test_feed_stop_and_feed_start_keys_latch_the_channel_feed_disable(plc: PlcBench) -> None:
    plc.tap("MCP.feedStop")
    assert plc.out("CHAN1.basic.out.disableFeed") == 1  # DB21.DBX6.0
    plc.scan(10)
    assert plc.out("CHAN1.basic.out.disableFeed") == 1  # latched after the key is released
    plc.tap("MCP.feedStart")
    assert plc.out("CHAN1.basic.out.disableFeed") == 0
    plc.scan(10)
    assert plc.out("CHAN1.basic.out.disableFeed") == 0


def test_feed_stop_wins_while_feed_stop_and_feed_start_are_both_pressed(plc: PlcBench) -> None:
    plc.input("MCP.feedStart", 1)
    plc.input("MCP.feedStop", 1)
    plc.scan(2)
    assert plc.out("CHAN1.basic.out.disableFeed") == 1
    plc.input("MCP.feedStop", 0)
    plc.scan(2)
    assert plc.out("CHAN1.basic.out.disableFeed") == 0  # the start key, still held, releases it


def test_override_switches_are_copied_with_their_enables(plc: PlcBench) -> None:
    plc.input("MCP.feedOverride", 73)
    plc.input("MCP.rapidOverride", 25)
    plc.scan(2)
    assert plc.out("CHAN1.basic.out.pathFeedrateOvrFactor") == 73  # DB21.DBB4
    assert plc.out("CHAN1.basic.out.pathFeedrateOvr") == 1  # DB21.DBX6.7
    assert plc.out("CHAN1.basic.out.pathRapidTraversOvrFactor") == 25  # DB21.DBB5
    assert plc.out("CHAN1.basic.out.pathRapidTraversOvr") == 1  # DB21.DBX6.6
    for axis in ("X1", "Z1"):
        assert plc.out(f"{axis}.basic.out.feedrateOvrFactor") == 73  # DB31.DBB0
        assert plc.out(f"{axis}.basic.out.enableOvr") == 1  # DB31.DBX1.7


def test_without_a_rapid_override_switch_the_feed_override_acts_on_rapid() -> None:
    # Seed 003 (§7.4.2): without a separate rapid override switch DB21.DBB5 = DB21.DBB4.
    io_list = {key: value for key, value in IO_LIST.items() if value != "MCP.rapidOverride"}
    plc = bench(io_list)
    plc.input("MCP.feedOverride", 40)
    plc.scan(2)
    assert plc.out("CHAN1.basic.out.pathRapidTraversOvrFactor") == 40


# ------------------------------------------------------------------------------ axes


def test_traverse_keys_and_rapid_key_reach_the_axis(plc: PlcBench) -> None:
    plc.input("MCP.plus.X1", 1)
    plc.input("MCP.rapid", 1)
    plc.scan(2)
    assert plc.out("X1.basic.out.traversKeyPlus") == 1  # DB31.DBX4.7
    assert plc.out("X1.basic.out.traversKeyMinus") == 0
    assert plc.out("X1.basic.out.enableRapidTravers") == 1  # DB31.DBX4.5
    assert plc.out("Z1.basic.out.traversKeyPlus") == 0
    plc.input("MCP.plus.X1", 0)
    plc.input("MCP.minus.Z1", 1)
    plc.scan(2)
    assert plc.out("X1.basic.out.traversKeyPlus") == 0
    assert plc.out("Z1.basic.out.traversKeyMinus") == 1  # DB32.DBX4.6


def test_enables_follow_drives_ready_and_follow_up_is_requested_without_them(plc: PlcBench) -> None:
    assert plc.out("X1.basic.out.enableCtrl") == 1  # DB31.DBX2.1
    assert plc.out("X1.drive.out.enablePulses") == 1  # DB31.DBX21.7
    assert plc.out("X1.basic.out.followUpMode") == 0  # DB31.DBX1.4
    plc.input("Drives.ready", 0)
    plc.scan(2)
    assert plc.out("X1.basic.out.enableCtrl") == 0
    assert plc.out("X1.drive.out.enablePulses") == 0
    assert plc.out("X1.basic.out.followUpMode") == 1


# ------------------------------------------------------------------------------ emergency stop and drives


def test_open_emergency_stop_chain_sets_db10_dbx56_1(plc: PlcBench) -> None:
    assert plc.out("NC.basic.out.emergencyStop") == 0
    plc.input("EStop.chainOk", 0)
    plc.scan(2)
    assert plc.out("NC.basic.out.emergencyStop") == 1
    plc.input("EStop.chainOk", 1)
    plc.scan(2)
    assert plc.out("NC.basic.out.emergencyStop") == 0


def test_reset_key_acknowledges_the_emergency_stop_only_with_the_chain_closed(plc: PlcBench) -> None:
    plc.input("EStop.chainOk", 0)
    plc.input("MCP.reset", 1)
    plc.scan(2)
    assert plc.out("NC.basic.out.emergencyStopAck") == 0  # DB10.DBX56.2
    plc.input("EStop.chainOk", 1)
    plc.scan(2)
    assert plc.out("NC.basic.out.emergencyStopAck") == 1
    assert plc.out("CHAN1.basic.out.reset") == 1  # together with the channel reset


def test_drives_stay_on_for_the_off_delay_after_an_emergency_stop(plc: PlcBench) -> None:
    # Stop category 1: the infeed stays on DRIVES_OFF_DELAY_S = 0.5 s = 50 scans so that the NC
    # can brake the axes with powered drives.
    assert plc.out("Drives.on") == 1
    plc.input("EStop.chainOk", 0)
    plc.scan(2)
    assert plc.out("Drives.on") == 1
    plc.scan(round(DRIVES_OFF_DELAY_S / SCAN) - 5)
    assert plc.out("Drives.on") == 1
    plc.scan(10)
    assert plc.out("Drives.on") == 0
    plc.input("EStop.chainOk", 1)
    plc.scan(2)
    assert plc.out("Drives.on") == 1


# ------------------------------------------------------------------ network 5: JOG to a fixed point
FIXED_POINT_IO = {**IO_LIST, "I8.0": "MCP.fixedPoint1", "I8.1": "MCP.fixedPoint2",
                  "Q1.0": "Lamp.fixedPoint1", "Q1.1": "Lamp.fixedPoint2"}


def test_a_fixed_point_key_selects_it_on_every_axis_again_withdraws_it_and_jog_left_too() -> None:
    plc = bench(FIXED_POINT_IO)
    plc.scan(2)
    plc.tap("MCP.fixedPoint2")
    assert [plc.out(f"{axis}.basic.out.jogFixedPointSelection") for axis in AXES] == [2, 2, 2]
    plc.tap("MCP.fixedPoint1")
    assert plc.out("X1.basic.out.jogFixedPointSelection") == 1
    plc.tap("MCP.fixedPoint1")
    assert plc.out("X1.basic.out.jogFixedPointSelection") == 0
    plc.tap("MCP.fixedPoint2")
    plc.tap("MCP.mda")
    assert plc.out("X1.basic.out.jogFixedPointSelection") == 0
    plc.tap("MCP.jog")
    assert plc.out("X1.basic.out.jogFixedPointSelection") == 0  # a new press selects it again


def test_the_lamp_flashes_while_an_axis_travels_to_the_fixed_point_and_lights_once_all_stand_on_it() -> None:
    plc = bench(FIXED_POINT_IO)
    plc.scan(2)
    plc.tap("MCP.fixedPoint2")
    assert plc.out("Lamp.fixedPoint2") == 0  # not acknowledged yet
    plc.nc("X1.basic.in.jogFixedPointSelectedNumber", 2)
    plc.nc("Z1.basic.in.jogFixedPointSelectedNumber", 2)
    plc.nc("X1.basic.in.jogFixedPointReachedNumber", 2)
    seen = set()
    for _ in range(100):
        plc.scan()
        seen.add(plc.out("Lamp.fixedPoint2"))
    assert seen == {0, 1}  # Z1 still travels: flashing
    plc.nc("Z1.basic.in.jogFixedPointReachedNumber", 2)
    plc.scan()
    assert all(plc.scan() is None and plc.out("Lamp.fixedPoint2") == 1 for _ in range(100))
    assert plc.out("Lamp.fixedPoint1") == 0
