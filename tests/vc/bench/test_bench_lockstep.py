"""The workloads of ``vc bench`` and ``vc bench --scaling``: they move what they say, and the
scaling table has every row.

No speed targets (the figures of short runs on a shared machine say nothing): only that the
motion happened and the figures are positive and finite.
"""

from __future__ import annotations

import math
from pathlib import Path

import pytest

from vc.bench.lockstep import (
    HEAVY_PLC,
    LIGHT_PLC,
    BenchmarkError,
    Workload,
    _press,
    benchmark_machine,
    run_benchmark,
)
from vc.bench.scaling import SCALING_MACHINES, row_figures, run_scaling, scaling_table
from vc.bench.workloads import Load, motion_plan
from vc.simulation.lockstep import Simulation

ROOT = Path(__file__).resolve().parents[3]
TURN_MILL = str(ROOT / "scenarios" / "machines" / "turn_mill.yaml")
MILL_3AXIS = str(ROOT / "scenarios" / "machines" / "mill_3axis.yaml")
TURN_MILL_AXES = ("X1", "Z1", "Y1", "SP1", "SP2", "SP3")


def test_the_heavy_program_turns_every_spindle_and_couples_sp2_to_sp1_on_turn_mill() -> None:
    plan = motion_plan(benchmark_machine(TURN_MILL, HEAVY_PLC), Load.EVERYTHING)
    lines = plan.program.splitlines()
    assert "M1=3 S1=400 M3=3 S3=5000" in lines  # SP2 turns only as SP1's following spindle
    assert lines.index('COUPDEF(S2,S1,1,1,"NOC","DV")') + 1 == lines.index("COUPON(S2,S1)")
    assert "X20 Z20 Y20" in lines and "G0 X-20 Z-20 Y-20" in lines and lines[-1] == "M30"
    assert plan.setup.splitlines() == ["SPOS[1]=0 SPOS[2]=0 SPOS[3]=0", "M30"]
    assert plan.moving == TURN_MILL_AXES
    assert plan.pair is not None and (plan.pair.following, plan.pair.leading) == ("SP2", "SP1")
    # a machine without a configured pair: no coupling
    mill = motion_plan(benchmark_machine(MILL_3AXIS, HEAVY_PLC), Load.EVERYTHING)
    assert mill.pair is None and "COUP" not in mill.program and "M1=3 S1=1000" in mill.program


def test_the_heavy_workload_moves_every_axis_and_spindle_of_turn_mill_with_sp2_coupled() -> None:
    machine = benchmark_machine(TURN_MILL, HEAVY_PLC)
    simulation = Simulation(machine, HEAVY_PLC)
    workload = Workload(simulation, Load.EVERYTHING)
    following = simulation.catalog.resolve("SP2.coupling.in.followingSpindleActive")
    fastest = dict.fromkeys(TURN_MILL_AXES, 0.0)
    coupled_at_speed = False
    for _ in range(30):  # 3 s: the program runs about 1 s, NC start again after each end
        workload.run(50)
        for axis in TURN_MILL_AXES:
            fastest[axis] = max(fastest[axis], abs(simulation.axis_quantity(axis, "velocity")))
        if simulation.read(following) == 1 and simulation.axis_quantity("SP2", "velocity") == pytest.approx(400):
            coupled_at_speed = simulation.axis_quantity("SP1", "velocity") == pytest.approx(400)
    assert all(speed > 0 for speed in fastest.values()), fastest
    assert fastest["SP3"] == pytest.approx(5000) and fastest["SP1"] == pytest.approx(400)
    assert coupled_at_speed
    assert workload.moved == set(TURN_MILL_AXES) and workload.coupled
    assert workload.problems() == []
    assert simulation.alarm_history() == []  # SPOS before: no 22040 at COUPON


def test_the_light_workload_moves_the_first_two_geometry_axes_only() -> None:
    result = run_benchmark(TURN_MILL, 2.0, Load.TWO_AXES, LIGHT_PLC)
    # turn_mill's geometry axes are X = X1, Y = Y1 (inclined), Z = Z1 (MD20050)
    assert result.plan.moving == ("X1", "Y1") and result.plan.pair is None
    assert result.cycles >= 1000 and math.isfinite(result.us_per_cycle) and result.us_per_cycle > 0


def test_the_heavy_workload_does_not_run_under_basic_machine() -> None:
    """basic_machine reports no gear stage (DB31.DBX16.0-2 stays 0): the NC asks for a gear change
    on SP1 (82.3) that no network answers, and the first spindle block waits (alarm 65830 after
    MD10192 = 10 s); the untimed setup does not end, and no figure comes out."""
    with pytest.raises(BenchmarkError, match=r"setup program did not end within 30 s"):
        run_benchmark(TURN_MILL, 1.0, Load.EVERYTHING, LIGHT_PLC)
    simulation = Simulation(benchmark_machine(TURN_MILL, LIGHT_PLC), LIGHT_PLC)
    simulation.load_mda("CHAN1", "M1=3 S1=400\nG91 G1 X20 F6000\nM30\n")
    for key in ("MCP.mda", "MCP.ncStart"):
        _press(simulation, key)
    simulation.step(500)
    assert simulation.read(simulation.catalog.resolve("SP1.spindle.in.gearChangeoverRequested")) == 1
    assert simulation.axis_quantity("SP1", "velocity") == 0 and simulation.axis_quantity("X1", "velocity") == 0


def test_a_workload_that_stands_still_gives_no_figure() -> None:
    simulation = Simulation(benchmark_machine(TURN_MILL), LIGHT_PLC)
    _press(simulation, "MCP.feedStop")  # basic_machine latches the channel's feed disable
    workload = Workload(simulation, Load.TWO_AXES)
    workload.run(1000)
    assert workload.moved == set()
    assert workload.problems() == ["X1, Y1 never moved"]


def test_the_scaling_table_has_every_machine_under_every_load() -> None:
    rows = run_scaling(list(SCALING_MACHINES), 0.5)  # by name: the packaged machines
    assert [(row.machine, row.plan.load) for row in rows] == [
        (machine, load) for machine in ("mill_3axis", "turn_mill", "mill_5axis") for load in Load]
    for row in rows:
        figures = row_figures(row)
        assert math.isfinite(row.us_per_cycle) and row.us_per_cycle > 0
        assert math.isfinite(row.realtime_factor) and row.realtime_factor > 0
        expected = {Load.IDLE: 0, Load.TWO_AXES: 2, Load.EVERYTHING: figures["axes"]}[row.plan.load]
        assert figures["moving"] == expected
    assert [row_figures(row)["axes"] for row in rows[::3]] == [4, 6, 6]
    table = scaling_table(rows).splitlines()
    assert len(table) == 2 + len(rows)
    assert table[-1].startswith("| mill_5axis | everything | 6 / 6 | ")
