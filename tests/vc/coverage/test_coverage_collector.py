"""What the coverage collector sees of scenario runs: signals with their values and edges, the
states and transitions of the NC's state machines per variant, alarms raised and cleared by what,
the plant I/O; and data collected in parts merges into the data of the whole."""

from __future__ import annotations

from pathlib import Path

import pytest

from interfaces.links.inprocess import plc_programs
from vc.coverage.collector import CoverageCollector
from vc.coverage.data import FALLS, RISES, CoverageData
from vc.harness.targets import simulation_for
from vc.scenario.language.loader import load_scenarios
from vc.scenario.run.runner import run_scenarios

ROOT = Path(__file__).resolve().parents[3]
REFERENCING = ROOT / "scenarios" / "referencing" / "incremental_jog_ref_falling_edge.yaml"
EMERGENCY_STOP = ROOT / "scenarios" / "foundation" / "emergency_stop.yaml"
NC_START_WITHOUT_REFERENCE = ROOT / "scenarios" / "foundation" / "nc_start_without_reference.yaml"


def collect(*paths: Path) -> CoverageData:
    collector = CoverageCollector()
    scenarios = load_scenarios([str(path) for path in paths], plc_programs().keys())
    results = run_scenarios(scenarios, collector.observe(simulation_for))
    assert all(result.passed for result in results), [result.failure for result in results]
    return collector.data


@pytest.fixture(scope="module")
def referencing() -> CoverageData:
    return collect(REFERENCING)


def test_signals_keep_their_values_and_edges(referencing: CoverageData) -> None:
    machine = referencing.machines["turn_mill"]
    synchronized = machine.signals["X1.basic.in.enc1Synchronized"]
    assert synchronized.values == {0, 1} and synchronized.edges == RISES  # referenced once, never lost
    assert machine.types["X1.basic.in.enc1Synchronized"] == "bool"
    assert machine.signals["Z1.basic.in.enc1Synchronized"].values == {0}  # Z1 was not referenced
    override = machine.signals["X1.basic.out.feedrateOvrFactor"]  # a byte the PLC sets to 100 %
    assert (override.low, override.high, override.distinct) == (0, 100, 2)
    cam = machine.plant["X1.refCam"]
    assert cam.edges == RISES | FALLS  # the slide crossed the cam
    assert machine.instances["X1"] == 31 and machine.instances["CHAN1"] == 21


def test_signals_that_mean_nothing_on_their_instance_are_set_apart(referencing: CoverageData) -> None:
    machine = referencing.machines["turn_mill"]
    spindle_signals = [symbol for symbol in machine.signals if ".spindle." in symbol or ".coupling." in symbol]
    assert spindle_signals
    for symbol in spindle_signals:
        assert (symbol in machine.not_applicable) == (symbol.split(".")[0] in ("X1", "Z1", "Y1")), symbol
    assert "CHAN1.inclinedAxis.out.noOrthogonalCompensation" not in machine.not_applicable  # turn_mill's Y1
    assert any(symbol.startswith("CHAN1.orientationAxis1.") for symbol in machine.not_applicable)  # no five axes


def test_state_machines_per_variant(referencing: CoverageData) -> None:
    incremental = referencing.functions["referencing.incremental_cam"]
    assert {"IDLE", "P1_TO_CAM", "P1_BRAKE", "P2_LEAVE_CAM", "P2_ZERO_MARK", "P3_TO_POINT", "SETTLE",
            "DONE"} <= set(incremental.states)
    assert {("IDLE", "P1_TO_CAM"), ("P1_TO_CAM", "P1_BRAKE"), ("P1_BRAKE", "P2_LEAVE_CAM"),
            ("P2_LEAVE_CAM", "P2_ZERO_MARK"), ("SETTLE", "DONE")} <= set(incremental.transitions)
    assert {"turn_mill/X1", "turn_mill/Y1"} <= incremental.instances
    assert "P2_BRAKE_OFF_CAM" not in incremental.states  # MD34050 = 0: the falling cam edge
    # X1's measuring system 1 is incremental: nothing ran as distance-coded
    assert "referencing.distance_coded" not in referencing.functions
    mode_group = referencing.functions["mode_group"]
    assert ("JOG", "JOG REF") in mode_group.transitions and mode_group.instances == {"turn_mill/MODEGROUP"}
    assert set(referencing.functions["spindle_mode"].states) == {"CONTROL"}
    assert referencing.scenarios == 1 and referencing.cycles == 3353


def test_alarms_raised_and_cleared_by_what() -> None:
    data = collect(EMERGENCY_STOP, NC_START_WITHOUT_REFERENCE)
    assert data.alarms[3000].raised == 1 and data.alarms[3000].cleared == {"emergency_stop_ack": 1}
    assert data.alarms[10203].raised == 1 and data.alarms[10203].cleared == {"reset": 1}


def test_alarms_present_at_a_power_cycle_are_cleared_by_power_on(tmp_path: Path) -> None:
    scenario = tmp_path / "power_cycle.yaml"
    scenario.write_text(f"""name: NC start refused, then the machine is switched off
machine: {ROOT / "scenarios" / "machines" / "turn_mill.yaml"}
plc: basic_machine
steps:
  - press: MCP.mda
  - mda: "G1 X10 F1000"
  - press: MCP.ncStart
  - expect_alarm: 10203
  - power_cycle: 1s
  - wait: 100ms
  - expect_no_alarm: all
""", encoding="utf-8")
    data = collect(scenario)
    assert data.alarms[10203].cleared == {"power_on": 1}
    assert data.functions["channel"].instances == {"turn_mill/CHAN1"}


def test_parts_merge_into_the_whole(referencing: CoverageData) -> None:
    other = collect(EMERGENCY_STOP)
    merged = CoverageData().merge(CoverageData.merged([referencing])).merge(other)
    whole = collect(REFERENCING, EMERGENCY_STOP)
    assert merged.to_json() == whole.to_json()
    assert merged.scenarios == 2 and merged.cycles == referencing.cycles + other.cycles
