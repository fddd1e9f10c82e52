"""DB100, the NC's alarm list for the PLC: what the NC writes for the alarms present."""

from __future__ import annotations

from core_rig import Rig, machine

from interfaces.alarm_block import CLEARED_BY, REACTION_BITS
from vc.core.alarms import Clear, Reaction

ENTRIES = 8


def entry(rig: Rig, number: int) -> tuple[object, ...]:
    prefix = f"ALARMS.entry[{number}].in."
    return tuple(rig.get(prefix + name) for name in ("number", "channel", "axis", "reaction", "clearedBy"))


def test_an_emergency_stop_shows_alarm_3000_with_its_reaction_and_how_it_is_cleared() -> None:
    rig = Rig(machine())
    rig.step(2)
    assert (rig.get("ALARMS.list.in.count"), entry(rig, 1)) == (0, (0, 0, 0, 0, 0))
    rig.set("NC.basic.out.emergencyStop", 1)
    rig.step(2)
    reaction = (Reaction.STOP_AXES | Reaction.NC_START_DISABLED | Reaction.CHANNEL_INTERRUPT | Reaction.RAPID_STOP
                | Reaction.MODE_GROUP).value
    assert rig.get("ALARMS.list.in.count") == 1
    assert entry(rig, 1) == (3000, 0, 0, reaction, 5)  # an NCK alarm; cleared by e-stop ack and reset
    assert rig.nck.image.area("DB100")[4:8] == (3000).to_bytes(4, "big")  # DBD4, S7 byte order


def test_channel_and_axis_are_the_numbers_of_their_data_blocks_in_the_order_raised() -> None:
    rig = Rig(machine())  # turn_mill: CHAN1 = DB21, X1 = DB31 .. SP3 = DB36
    alarms = rig.nck.alarms
    changes = rig.get("ALARMS.list.in.changes")
    alarms.raise_alarm(21614, rig.nck.cycle, "CHAN1", "Y1", "+", channel="CHAN1", axis="Y1")
    alarms.raise_alarm(25022, rig.nck.cycle, "SP3", 1, 0, channel="CHAN1", axis="SP3")
    rig.step(1)
    assert rig.get("ALARMS.list.in.count") == 2
    assert rig.get("ALARMS.list.in.changes") == (changes + 2) & 0xFFFF
    assert entry(rig, 1)[:3] == (21614, 1, 3) and entry(rig, 1)[4] == 1  # Y1 is DB33; cleared by reset
    assert entry(rig, 2) == (25022, 1, 6, 0, 2)  # SP3 is DB36; a warning without reaction, cancel key


def test_more_alarms_than_entries_count_all_and_show_the_first_and_clearing_empties_the_entries() -> None:
    rig = Rig(machine())
    alarms = rig.nck.alarms
    axes = ("X1", "Z1", "Y1", "SP1", "SP2", "SP3")
    for number in (21614, 25040):
        for axis in axes:
            alarms.raise_alarm(number, rig.nck.cycle, "CHAN1", axis, "+", channel="CHAN1", axis=axis)
    rig.step(1)
    assert rig.get("ALARMS.list.in.count") == 12
    assert [entry(rig, k)[:3] for k in range(1, ENTRIES + 1)] == \
        [(21614, 1, n) for n in range(1, 7)] + [(25040, 1, 1), (25040, 1, 2)]
    alarms.clear(21614)
    rig.step(1)
    assert rig.get("ALARMS.list.in.count") == 6
    assert [entry(rig, k)[2] for k in range(1, ENTRIES + 1)] == [1, 2, 3, 4, 5, 6, 0, 0]
    assert entry(rig, 7) == entry(rig, 8) == (0, 0, 0, 0, 0)


def test_the_codes_are_those_the_interface_documents() -> None:
    bits = [Reaction.STOP_AXES, Reaction.NC_START_DISABLED, Reaction.READ_IN_DISABLED, Reaction.CHANNEL_INTERRUPT,
            Reaction.RAPID_STOP, Reaction.MODE_GROUP]
    assert [reaction.value for reaction in bits] == [1 << bit for bit in range(len(REACTION_BITS))]
    assert {clear.value for clear in Clear} == set(CLEARED_BY)
