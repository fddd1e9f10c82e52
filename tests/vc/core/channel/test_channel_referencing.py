"""Channel-specific referencing: the groups of MD34110 (seed 003 L667-683)."""

from __future__ import annotations

from core_rig import Rig, machine

from vc.core.channel.channel_referencing import ChannelReferencing


def referencing(overrides: str) -> ChannelReferencing:
    rig = Rig(machine(overrides))
    channel = rig.channel
    return ChannelReferencing(channel.name, channel.axes, rig.nck.referencing, rig.nck.alarms)


def test_groups_in_ascending_md34110_with_equal_numbers_together() -> None:
    control = referencing("X1: {MD34110: 2}\nZ1: {MD34110: 1}\nY1: {MD34110: 2}")
    assert not control.active
    control.start()
    assert control.active
    assert control.groups == [["Z1"], ["X1", "Y1"]]


def test_axes_with_md34110_0_or_minus_1_take_no_part() -> None:
    control = referencing("X1: {MD34110: 0}\nZ1: {MD34110: -1}\nY1: {MD34110: 3}")
    control.start()
    assert control.groups == [["Y1"]]


def test_a_second_start_while_running_changes_nothing_and_cancel_ends_it() -> None:
    control = referencing("X1: {MD34110: 2}\nZ1: {MD34110: 1}\nY1: {MD34110: 2}")
    control.start()
    control.groups.pop(0)
    control.start()
    assert control.groups == [["X1", "Y1"]]
    control.cancel()
    assert not control.active
