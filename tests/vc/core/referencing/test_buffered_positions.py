"""Power-on restore and encoder slip of the measuring systems (seed 003 §4.9, §4.10, L2025-2043).

Turn-mill X1: measuring system 1 = motor encoder, measuring system 2 = linear scale; the slide
stands where each test puts it at power-on.
"""

from __future__ import annotations

import pytest
from core_rig import Rig, machine

from vc.config import md_dictionary as MD
from vc.core.alarms import AlarmList
from vc.core.axis.axis import MachineAxis
from vc.core.nc_memory import BufferedEncoder, NcMemory
from vc.core.referencing.buffered_positions import encoder_slip, restore_at_power_on

# ------------------------------------------------------------------------------ restore at power-on


def restore(overrides: str, buffered: BufferedEncoder | None, physical: float = 200.0,
            written: dict[int, object] | None = None) -> tuple[MachineAxis, NcMemory, AlarmList]:
    """Power X1 on with ``buffered`` as what measuring system 1 left at switch-off."""
    axis = Rig(machine(overrides)).axis("X1")
    axis.physical = physical
    memory = NcMemory()
    if buffered is not None:
        memory.buffered[("X1", 0)] = buffered
    alarms = AlarmList()
    restore_at_power_on(axis, memory, alarms)
    return axis, memory, alarms


def md34210(axis: MachineAxis, memory: NcMemory, index: int = 0) -> int:
    return memory.view("X1", axis.config.md).int(MD.ENC_REFP_STATE, index)


REFERENCED_AT_REST = BufferedEncoder(actual=273.0, referenced=True, restored=False, exact_stop_fine=True)
REFERENCED_MOVING = BufferedEncoder(actual=273.0, referenced=True, restored=False, exact_stop_fine=False)
RESTORED = BufferedEncoder(actual=250.0, referenced=False, restored=True, exact_stop_fine=True)
NEVER_REFERENCED = BufferedEncoder(actual=40.0, referenced=False, restored=False, exact_stop_fine=True)


@pytest.mark.parametrize("buffered", [None, REFERENCED_AT_REST])
def test_incremental_without_restore_starts_at_zero(buffered: BufferedEncoder | None) -> None:
    axis, memory, _ = restore("", buffered)
    assert not axis.encoder.referenced and not axis.encoder.restored
    assert axis.actual == 0.0
    assert md34210(axis, memory) == 0


def test_incremental_md34210_1_is_enabled_but_not_yet_referenced() -> None:
    # L2672-2684: state 1 at activation: actual position 0, not referenced
    axis, memory, _ = restore("X1: {MD34210: [1]}", REFERENCED_AT_REST)
    assert not axis.encoder.referenced
    assert axis.actual == 0.0
    assert md34210(axis, memory) == 1


def test_incremental_md34210_2_in_exact_stop_is_referenced_with_the_buffered_value() -> None:
    # L2627-2666: referenced before switch-off, in exact stop fine: buffered position, referenced
    axis, memory, _ = restore("X1: {MD34210: [2]}", REFERENCED_AT_REST)
    assert axis.encoder.referenced and not axis.encoder.restored
    assert axis.actual == pytest.approx(273.0)
    assert axis.setpoint == pytest.approx(273.0)
    assert axis.encoder.actual(axis.physical + 1.0) == pytest.approx(274.0)
    assert md34210(axis, memory) == 2


@pytest.mark.parametrize("buffered", [None, REFERENCED_MOVING, NEVER_REFERENCED])
def test_incremental_md34210_2_without_exact_stop_loses_the_reference(buffered: BufferedEncoder | None) -> None:
    # L2644-2647: not in exact stop at switch-off: actual 0, not referenced; MD34210 back to 1
    axis, memory, _ = restore("X1: {MD34210: [2]}", buffered)
    assert not axis.encoder.referenced
    assert axis.actual == 0.0
    assert md34210(axis, memory) == 1


@pytest.mark.parametrize("buffered", [REFERENCED_AT_REST, REFERENCED_MOVING, RESTORED])
def test_incremental_md34210_3_restores_the_buffered_position_without_referencing(buffered: BufferedEncoder) -> None:
    # L2698-2763: restored (71.4 = 1), not referenced (60.4 = 0); MD34210 stays 3
    axis, memory, _ = restore("X1: {MD34210: [3]}", buffered)
    assert axis.encoder.restored and not axis.encoder.referenced
    assert axis.actual == pytest.approx(buffered.actual)
    assert md34210(axis, memory) == 3


def test_incremental_md34210_3_needs_a_first_referencing() -> None:
    # L2742-2745: the measuring system must have been referenced before switch-off
    axis, _, _ = restore("X1: {MD34210: [3]}", NEVER_REFERENCED)
    assert not axis.encoder.restored and not axis.encoder.referenced
    assert axis.actual == 0.0


@pytest.mark.parametrize(("state", "referenced"), [(0, False), (1, False), (2, True)])
def test_absolute_encoder_is_referenced_only_when_calibrated(state: int, referenced: bool) -> None:
    # L1970-1978, L2584-2586: actual = encoder value (physical in the simulation) + MD34090
    axis, memory, alarms = restore(f"X1: {{MD30240: [4], MD34210: [{state}], MD34090: [-26.6, -20.0]}}", None)
    assert axis.encoder.referenced is referenced
    assert axis.actual == pytest.approx(200.0 - 26.6)
    assert md34210(axis, memory) == state
    assert not list(alarms.present)


def test_absolute_encoder_with_a_new_serial_number_loses_its_calibration() -> None:
    # L2028-2040: new serial number: MD34210 := 0, alarm 25022; MD34230 takes the new number
    axis, memory, alarms = restore("X1: {MD30240: [4], MD34210: [2], MD34230: [4711]}", None)
    assert not axis.encoder.referenced
    assert md34210(axis, memory) == 0
    assert memory.view("X1", axis.config.md).int(MD.ENC_SERIAL_NUMBER, 0) == 0  # sim serial
    assert [(a.number, a.axis) for a in alarms.present] == [(25022, "X1")]


def test_absolute_encoder_with_the_same_serial_number_keeps_its_calibration() -> None:
    axis, memory, alarms = restore("X1: {MD30240: [4], MD34210: [2], MD34230: [0]}", None)
    assert axis.encoder.referenced
    assert md34210(axis, memory) == 2
    assert not list(alarms.present)


# ------------------------------------------------------------------------------ encoder slip


def test_slip_of_a_referenced_incremental_encoder_drops_the_reference() -> None:
    rig = Rig(machine())
    axis = rig.axis("X1")
    axis.synchronise(axis.encoder, 150.0, 150.0)
    alarms = AlarmList()
    memory = NcMemory()
    encoder_slip(axis, 0, 0.5, memory, alarms)
    assert not axis.encoder.referenced
    assert axis.actual == pytest.approx(150.5)  # the miscount shows in the actual value
    assert [a.number for a in alarms.present] == [25020]
    assert memory.written == {}  # MD34210 of an incremental encoder is not touched


def test_slip_of_a_calibrated_absolute_encoder_takes_the_calibration_away() -> None:
    # L2028-2043: zero-mark monitoring: MD34210 := 0, alarms 25020 and 25022
    rig = Rig(machine("X1: {MD30240: [4], MD34210: [2]}"))
    axis = rig.axis("X1")
    assert axis.encoder.referenced
    alarms = AlarmList()
    encoder_slip(axis, 0, -0.25, rig.nck.memory, alarms)
    assert not axis.encoder.referenced
    assert md34210(axis, rig.nck.memory) == 0
    assert sorted(a.number for a in alarms.present) == [25020, 25022]
    assert all(a.axis == "X1" for a in alarms.present)


def test_slip_of_the_passive_measuring_system_leaves_the_actual_value() -> None:
    rig = Rig(machine())
    axis = rig.axis("X1")
    before = axis.actual
    encoder_slip(axis, 1, 0.5, NcMemory(), AlarmList())
    assert axis.actual == before
    assert axis.encoders[1].actual(axis.physical) == pytest.approx(axis.encoders[0].actual(axis.physical) + 0.5)
