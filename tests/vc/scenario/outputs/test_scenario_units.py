"""Units follow the axis: mm and mm/min on a linear axis, degrees and rev/min on a rotary axis or spindle, in
the timing diagram's lanes, the CSV trace and the failure messages (declared once in
vc.simulation.observables.quantity_unit, from AxisConfig.position_unit and velocity_unit)."""

from __future__ import annotations

import csv
from pathlib import Path

import pytest

from interfaces.links.inprocess import plc_programs
from vc.harness.targets import simulation_for
from vc.scenario.language.loader import load_scenario
from vc.scenario.outputs.report import failure_text
from vc.scenario.outputs.timing import timing_diagram
from vc.scenario.run.runner import run_one
from vc.simulation.observables import quantity_unit

ROOT = Path(__file__).resolve().parents[4]
SPINDLE = "scenarios/spindle/chuck_speed_22100_axis_mode.yaml"  # names SP1.velocity; SP1 turns 20 times


@pytest.fixture(autouse=True)
def _in_repository(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(ROOT)


def test_the_units_are_the_axis_own() -> None:
    machine = load_scenario(SPINDLE, plc_programs().keys()).machine
    assert [quantity_unit(machine, axis, quantity) for axis, quantity in (
        ("X1", "position"), ("X1", "velocity"), ("SP1", "position"), ("SP1", "velocity"), ("SP1", "followingError"),
        ("SP2", "couplingRelationError"), ("SP2", "syncDeviation"), ("CHAN1", "toolTipX"), ("CHAN1", "tcpActive"),
        ("NC", "dcLinkVoltage"))] == ["mm", "mm/min", "deg", "rev/min", "deg", "deg", "", "mm", "", "V"]


def test_a_spindle_lane_and_its_trace_rows_are_in_degrees_and_rev_per_min(tmp_path: Path) -> None:
    scenario = load_scenario(SPINDLE, plc_programs().keys())
    result = run_one(scenario, simulation_for, trace_dir=tmp_path, trace_name="chuck")
    assert result.passed, failure_text(result)
    diagram = timing_diagram(result)
    assert diagram is not None
    units = {lane.name: lane.unit for lane in diagram.lanes}
    assert units["SP1.velocity"] == "rev/min" and units["SP1.position"] == "deg"
    with (tmp_path / "chuck.csv").open(newline="") as handle:
        rows = list(csv.DictReader(handle))
    unit_of = {row["name"]: row["unit"] for row in rows}
    assert (unit_of["SP1.velocity"], unit_of["SP1.position"]) == ("rev/min", "deg")
    assert (unit_of["X1.velocity"], unit_of["X1.position"]) == ("mm/min", "mm")
    assert unit_of["SP1.spindle.in.speedLimitationExceeded"] == ""


def test_a_failure_shows_a_spindle_speed_in_rev_per_min(tmp_path: Path) -> None:
    path = tmp_path / "s.yaml"
    path.write_text("name: s\nmachine: turn_mill\nplc: spindle\nsteps:\n  - wait: 20ms\n"
                    "  - expect: {SP1.velocity: 5}\n  - expect: \"X1.position > 5\"\n")
    result = run_one(load_scenario(str(path), plc_programs().keys()), simulation_for)
    assert result.failure is not None
    assert result.failure.message == "expected SP1.velocity = 5, found 0.0 rev/min"
    assert "SP1.velocity: 0.000 s = 0.0 rev/min" in failure_text(result)
