"""The DB31 signal groups of an axis (vc/core/axis/signals.py) compiled against the catalogue: the
PLC's outputs decoded into AxisInputs, the AxisStatus bits written where the catalogue puts them."""

from __future__ import annotations

import pytest

from interfaces.group_codec import declared_signals
from interfaces.signal_groups import AxisStatus
from interfaces.signals import InstanceKind
from vc.core.axis.signals import AxisInputs
from vc.core.interface_map import SignalTable
from vc.scenario.language.loader import default_catalog


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


# the status bits of DB31 the axis writes, by attribute (AxisStatus is built by keyword)
STATUS_SIGNALS = {
    "exact_coarse": "basic.in.posCoarseReached", "exact_fine": "basic.in.posFineReached",
    "stationary": "basic.in.isStationary", "position_control": "basic.in.posCtrlActive",
    "follow_up_active": "basic.in.followUpModeActive", "referenced_1": "basic.in.enc1Synchronized",
    "referenced_2": "basic.in.enc2Synchronized", "restored_1": "basic.in.enc1Restored",
    "restored_2": "basic.in.enc2Restored", "frequency_exceeded_1": "basic.in.enc1FreqLimitExceeded",
    "frequency_exceeded_2": "basic.in.enc2FreqLimitExceeded", "disabled": "basic.in.disabled",
    "command_plus": "basic.in.traversPlusCommandActive", "command_minus": "basic.in.traversMinusCommandActive",
    "drive_enabled": "drive.in.enabled", "modulo_limit_active": "basic.in.moduloLimitSwitchActive",
    "index_in_position": "basic.in.indexAxisInPos",
}


def test_the_status_group_declares_these_signals() -> None:
    assert dict(declared_signals(AxisStatus)) == STATUS_SIGNALS


@pytest.mark.parametrize("attribute", STATUS_SIGNALS)
def test_each_status_bit_is_written_to_its_signal_alone(table: SignalTable, attribute: str) -> None:
    area = bytearray(table.size)
    table.codec(AxisStatus).encode(area, AxisStatus(**{attribute: True}))
    assert [name for name, symbol in STATUS_SIGNALS.items() if table.bit(symbol).get(area)] == [attribute]
    assert sum(bin(byte).count("1") for byte in area) == 1


def test_status_bits_are_cleared_again(table: SignalTable) -> None:
    encode = table.codec(AxisStatus).encode
    area = bytearray(table.size)
    encode(area, AxisStatus(**dict.fromkeys(STATUS_SIGNALS, True)))
    encode(area, AxisStatus())
    assert not any(area)
