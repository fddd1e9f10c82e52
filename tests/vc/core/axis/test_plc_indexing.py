"""Indexing by the PLC (seed 003 §11.2.3, L13522-13530): FC18 with Funct 4 indexes an indexing axis as
a concurrent positioning axis, Pos the number of an index position and Mode the coded way of the
program (CAC, CIC, CDC, CACP, CACN); its errors.  mill_5axis's table C1 with the seed's turret of
example 1 (8 positions 45 degrees apart, L14131-14155) and an absolute encoder: it stands at 295
degrees, between positions 7 (270) and 8 (315); the test is the PLC."""

from __future__ import annotations

import pytest
from core_rig import FIVE_AXIS, Rig, machine

from vc.core.axis.plc_axis import Job

TURRET = ("NC: {MD10900: 8, MD10910: [0, 45, 90, 135, 180, 225, 270, 315]}\n"
          "CHAN1: {MD20700: 0}\nC1: {MD30240: [4], MD34210: [2], MD30500: 1}")
INDEXING, POSITIONING = 4, 5  # FC18 Funct
CAC, CIC, CDC, CACP, CACN = range(5)  # FC18 Mode of an indexing axis


def _rig(overrides: str = TURRET) -> Rig:
    rig = Rig(machine(overrides, FIVE_AXIS))
    rig.ready_mda()
    return rig


def _index(rig: Rig, function: int, mode: int, number: float, feed: float = 7200.0) -> None:
    """What FC18 hands the NC: Funct, Mode, Pos, FRate, then the Start edge."""
    rig.set("C1.plcAxis.out.function", function)
    rig.set("C1.plcAxis.out.mode", mode)
    rig.set("C1.plcAxis.out.position", number)
    rig.set("C1.plcAxis.out.feedrate", feed)
    rig.set("C1.plcAxis.out.start", 1)
    rig.step(2)
    rig.set("C1.plcAxis.out.start", 0)


def _done(rig: Rig) -> Job:
    plc = rig.channel.plc_axes.by_name["C1"]
    rig.run_until(lambda: plc.job in (Job.IN_POSITION, Job.FAILED), 3000)
    rig.step(2)
    return plc.job


def test_the_plc_indexes_the_table_to_an_index_position_and_it_reports_in_position() -> None:
    rig = _rig()
    c1 = rig.axis("C1")
    _index(rig, INDEXING, CAC, 3)
    rig.step(20)
    assert rig.get("C1.plcAxis.in.active") == 1 and rig.get("C1.plcCtrl.in.assignedToPlc") == 1
    assert c1.command_velocity < 0.0  # as AC: 90 lies below 295
    assert _done(rig) is Job.IN_POSITION and c1.setpoint == 90.0  # index position 3 of the table
    assert rig.get("C1.plcAxis.in.inPosition") == 1 and rig.get("C1.basic.in.indexAxisInPos") == 1
    assert rig.get("C1.plcCtrl.in.assignedToPlc") == 0  # back to its channel


@pytest.mark.parametrize(("mode", "number", "end", "way"), [
    (CIC, -1, 270.0, -1),  # between two positions: the next lower (L13896-13902)
    (CIC, 2, 360.0, +1),  # 7 + 2 round the turn: position 1 (L13888-13893)
    (CDC, 1, 360.0, +1), (CDC, 7, 270.0, -1),  # the shorter way
    (CACP, 7, 630.0, +1), (CACN, 3, 90.0, -1),
])
def test_mode_is_the_coded_way_of_the_program(mode: int, number: int, end: float, way: int) -> None:
    rig = _rig()
    c1 = rig.axis("C1")
    _index(rig, INDEXING, mode, number)
    rig.step(20)
    assert c1.command_velocity * way > 0.0
    assert _done(rig) is Job.IN_POSITION and c1.setpoint == pytest.approx(end)
    assert rig.get("C1.basic.in.indexAxisInPos") == 1


def test_cic_between_two_positions_goes_to_the_next_one() -> None:
    rig = _rig()
    c1 = rig.axis("C1")
    _index(rig, POSITIONING, 0, 100.0)  # Funct 5: degrees, off the index positions
    assert _done(rig) is Job.IN_POSITION and rig.get("C1.basic.in.indexAxisInPos") == 0
    _index(rig, INDEXING, CIC, 1)
    assert _done(rig) is Job.IN_POSITION and c1.setpoint == 135.0  # the next higher (L13896-13902)


@pytest.mark.parametrize(("overrides", "function", "mode", "number", "state"), [
    (TURRET, INDEXING, CAC, 9, 100),  # no index position 9: "number of index positions too high"
    (TURRET, INDEXING, CAC, 0, 100),
    (TURRET, INDEXING, CAC, 2.5, 100),  # no whole number
    (TURRET, INDEXING, 5, 2, 1),  # no such Mode
    (TURRET, 3, CAC, 2, 1),  # a spindle's function (oscillation) on an axis
    ("CHAN1: {MD20700: 0}\nC1: {MD30240: [4], MD34210: [2]}", INDEXING, CAC, 2, 1),  # no indexing axis
])
def test_a_refused_indexing_start_reports_its_error(overrides: str, function: int, mode: int, number: float,
                                                    state: int) -> None:
    rig = _rig(overrides)
    _index(rig, function, mode, number)
    assert _done(rig) is Job.FAILED
    assert rig.get("C1.plcAxis.in.error") == 1 and rig.get("C1.plcAxis.in.errorNumber") == state
    assert rig.axis("C1").command_velocity == 0.0 and rig.get("C1.plcCtrl.in.assignedToPlc") == 0


def test_funct_0_is_the_positioning_axis_of_a_plc_that_leaves_the_byte_alone() -> None:
    rig = _rig()
    _index(rig, 0, 0, 100.0)
    assert _done(rig) is Job.IN_POSITION and rig.axis("C1").setpoint == 100.0


def test_the_channel_reset_aborts_the_indexing_between_two_positions() -> None:
    rig = _rig()
    c1 = rig.axis("C1")
    _index(rig, INDEXING, CAC, 5, feed=3600.0)  # to 180 degrees
    rig.step(100)
    rig.set("CHAN1.basic.out.reset", 1)
    assert _done(rig) is Job.FAILED and rig.get("C1.plcAxis.in.errorNumber") == 30
    rig.set("CHAN1.basic.out.reset", 0)
    rig.step(100)
    assert 180.0 < c1.setpoint < 290.0 and rig.get("C1.basic.in.indexAxisInPos") == 0
