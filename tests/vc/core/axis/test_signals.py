"""The DB31 signal groups of an axis (vc/core/axis/signals.py) compiled against the catalogue: the
PLC's outputs decoded into AxisInputs, the AxisStatus bits written where the catalogue puts them."""

from __future__ import annotations

import pytest

from interfaces.signal_groups import AxisStatus
from interfaces.signals import InstanceKind
from vc.core.axis.signals import AxisInputs
from vc.core.interface_map import SignalTable
from vc.scenario.loader import default_catalog


@pytest.fixture(scope="module")
def table() -> SignalTable:
    return SignalTable(default_catalog(), InstanceKind.AXIS)


def area_with(table: SignalTable, *bits: str) -> bytearray:
    area = bytearray(table.size)
    for name in bits:
        table.bit(name).put(area, True)
    return area


def test_an_empty_area_reads_as_no_enable_and_parked(table: SignalTable) -> None:
    inputs = AxisInputs(controller_enable=True, encoder_selected=0)
    table.codec(AxisInputs).decode(bytearray(table.size), inputs)
    inputs.select_encoder(2)
    assert inputs == AxisInputs()  # every signal 0: nothing enabled, no measuring system selected


def test_each_bit_reaches_its_input(table: SignalTable) -> None:
    area = area_with(table, "basic.out.enableCtrl", "drive.out.enablePulses", "basic.out.traversKeyMinus",
                     "basic.out.hwLimitSwitchPlus", "basic.out.refPointApproachCam")
    table.field("basic.out.feedrateOvrFactor").put(area, 37)
    inputs = table.codec(AxisInputs).read(area)
    assert (inputs.controller_enable, inputs.pulse_enable, inputs.key_minus, inputs.hw_limit_plus,
            inputs.ref_cam) == (True, True, True, True, True)
    assert (inputs.key_plus, inputs.hw_limit_minus, inputs.disable, inputs.feed_stop) == (False, False, False, False)
    assert inputs.override_raw == 37


@pytest.mark.parametrize(("selected", "encoders", "expected"), [
    (("basic.out.enc1Activation",), 1, 0),
    (("basic.out.enc1Activation", "basic.out.enc2Activation"), 2, 0),  # measuring system 1 wins
    (("basic.out.enc2Activation",), 2, 1),
    (("basic.out.enc2Activation",), 1, None),  # an axis without a second measuring system stays parked
    ((), 2, None),
])
def test_the_measuring_system_selection(table: SignalTable, selected: tuple[str, ...], encoders: int,
                                        expected: int | None) -> None:
    inputs = table.codec(AxisInputs).read(area_with(table, *selected))
    inputs.select_encoder(encoders)
    assert inputs.encoder_selected == expected


STATUS_ORDER = ("basic.in.posCoarseReached", "basic.in.posFineReached", "basic.in.isStationary",
                "basic.in.posCtrlActive", "basic.in.followUpModeActive", "basic.in.enc1Synchronized",
                "basic.in.enc2Synchronized", "basic.in.enc1Restored", "basic.in.enc2Restored",
                "basic.in.enc1FreqLimitExceeded", "basic.in.enc2FreqLimitExceeded", "basic.in.disabled",
                "basic.in.traversPlusCommandActive", "basic.in.traversMinusCommandActive", "drive.in.enabled")


@pytest.mark.parametrize("position", range(len(STATUS_ORDER)))
def test_each_status_bit_is_written_to_its_signal_alone(table: SignalTable, position: int) -> None:
    area = bytearray(table.size)
    status = tuple(index == position for index in range(len(STATUS_ORDER)))
    table.codec(AxisStatus).encode(area, AxisStatus(*status))
    assert [table.bit(name).get(area) for name in STATUS_ORDER] == list(status)
    assert sum(bin(byte).count("1") for byte in area) == 1


def test_status_bits_are_cleared_again(table: SignalTable) -> None:
    encode = table.codec(AxisStatus).encode
    area = bytearray(table.size)
    encode(area, AxisStatus(*(True,) * len(STATUS_ORDER)))
    encode(area, AxisStatus())
    assert not any(area)
