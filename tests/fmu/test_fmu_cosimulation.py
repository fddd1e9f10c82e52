"""examples/fmu_cosimulation.py: plc_stub drives the NC FMU step by step, in the harness's lockstep.

Each case runs the example's master against the exported FMU once, and the same operator and
plant model against ``Simulation(machine, "referencing")`` in process: the two timelines must
be the same to the last bit, since both are the same deterministic NC, plant and PLC, scanned
at the same instants.
"""

from __future__ import annotations

import importlib.util
import itertools
import sys
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from types import ModuleType
from typing import Any

import pytest
from fmu_machines import REPOSITORY, TURN_MILL

from interfaces.signals import SignalRef, UnknownSignalError
from vc.config.loader import load_machine
from vc.config.md_dictionary import REFP_CYCLE_NR, REFP_SET_POS
from vc.config.model import MachineConfig
from vc.simulation.lockstep import Simulation
from vc.simulation.observables import AXIS_QUANTITIES


def _load_example() -> ModuleType:
    path = REPOSITORY / "examples" / "fmu_cosimulation.py"
    spec = importlib.util.spec_from_file_location("fmu_cosimulation", path)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module  # dataclasses look their module up while the class is built
    spec.loader.exec_module(module)
    return module


example = _load_example()

# the PLC's own order, as scenarios/referencing/order_plc_sequence.yaml gives it (Y1 references in Y-, MD34010 = 1)
PLC_ORDER = {"referencing_order": [["Y1", "Z1"], ["X1"]], "referencing_direction": {"Y1": "minus"}}


@dataclass(frozen=True, slots=True)
class Runs:
    machine: MachineConfig  # with the case's PLC parameters
    fmu: Any  # example.Timeline of the co-simulation with the FMU
    in_process: Any  # example.Timeline of the same sequence against the harness's own lockstep


def _reader(simulation: Simulation) -> Any:
    """The harness's machine read the way the FMU's outputs are named."""
    axes = {axis.name for axis in simulation.machine.axes}
    refs: dict[str, SignalRef] = {}

    def read(name: str) -> float:
        axis, _, quantity = name.rpartition(".")
        if axis in axes and quantity in AXIS_QUANTITIES:
            return simulation.axis_quantity(axis, quantity)
        if name not in refs:
            try:
                refs[name] = simulation.catalog.resolve(name)
            except UnknownSignalError:
                refs[name] = simulation.plant_io.resolve(name)
        return simulation.read(refs[name])

    return read


def _run_in_process(machine: MachineConfig) -> Any:
    """The example's surroundings against the harness: they look and act after the scan of each
    PLC cycle, and the harness's next scan reads what they set, as the master does."""
    simulation = Simulation(machine, example.PLC_PROGRAM)  # the power-on scan at t = 0 happens here
    read = _reader(simulation)
    surroundings = example.Surroundings(machine, read)
    step_s = example.communication_step_s(machine)
    for step in range(round(example.TIME_LIMIT_S / step_s) + 1):
        surroundings.look_and_act(step * step_s, read)
        if surroundings.finished:
            break
        for name, value in surroundings.plant_inputs().items():
            simulation.write(simulation.plant_io.resolve(name), value)
        simulation.step(machine.plc_cycle_ipo)
    return surroundings.timeline


@pytest.fixture(scope="module", params=[None, PLC_ORDER], ids=["nc_order", "plc_order"])
def runs(request: pytest.FixtureRequest, turn_mill_fmu: Path) -> Runs:
    parameters: Mapping[str, Any] | None = request.param
    machine = example.with_plc_parameters(load_machine(TURN_MILL), parameters)
    return Runs(machine, example.run(turn_mill_fmu, parameters), _run_in_process(machine))


def _expected_groups(machine: MachineConfig) -> list[list[str]]:
    """Who references together, group after group: the PLC's ``referencing_order``, or without
    one (the PLC then requests channel referencing) the NC's MD34110, equal numbers together."""
    order = machine.plc_parameters.get("referencing_order")
    if order:
        return [list(group) for group in order]
    numbers = {axis.name: axis.md.int(REFP_CYCLE_NR) for axis in machine.axes}
    taking_part = sorted({number for number in numbers.values() if number > 0})  # -1, 0: not referenced here
    return [[name for name, number in numbers.items() if number == wanted] for wanted in taking_part]


def test_the_sequence_finishes_with_every_event(runs: Runs) -> None:
    timeline = runs.fmu
    assert timeline.all_referenced_s is not None
    assert timeline.zone_entered_s is not None and timeline.emergency_stop_s is not None
    assert timeline.stopped_s is not None
    assert timeline.stopped_s < 12.0  # about 10.8 s: the run stays short


def test_the_axes_stand_at_their_reference_point_values(runs: Runs) -> None:
    # the machine file chooses MD34100 so that the position after referencing is the physical one
    expected = {axis.name: axis.md.float(REFP_SET_POS, 0) for axis in runs.machine.axes if not axis.is_rotary}
    assert runs.fmu.reference_positions == pytest.approx(expected, abs=1e-9)
    assert expected == {"X1": 273.0, "Z1": 568.0, "Y1": -73.0}


def test_the_axes_reference_group_after_group_in_the_configured_order(runs: Runs) -> None:
    timeline = runs.fmu
    groups = _expected_groups(runs.machine)
    assert sorted(name for group in groups for name in group) == sorted(timeline.referenced_s)
    for group in groups:
        assert len({timeline.referencing_started_s[axis] for axis in group}) == 1  # a group starts together
    for earlier, later in itertools.pairwise(groups):
        last_done = max(timeline.referenced_s[axis] for axis in earlier)
        next_start = min(timeline.referencing_started_s[axis] for axis in later)
        assert last_done <= next_start, (earlier, later)
    assert timeline.all_referenced_s == max(timeline.referenced_s.values())


def test_the_fmu_run_is_the_harness_lockstep_to_the_last_bit(runs: Runs) -> None:
    assert runs.fmu.events == runs.in_process.events
    assert runs.fmu == runs.in_process  # every time, every position, exactly


def test_the_plant_model_trips_and_the_nc_stops_before_the_chuck(runs: Runs) -> None:
    timeline = runs.fmu
    step_s = example.communication_step_s(runs.machine)
    assert timeline.all_referenced_s < timeline.zone_entered_s
    # the model opens the chain at t_k; the scan at t_k+1 reads it, the one at t_k+2 publishes
    # DB10.DBX56.1, the NC answers with DB10.DBX106.1 in its next IPO cycle, seen at t_k+3
    assert timeline.emergency_stop_s - timeline.zone_entered_s == pytest.approx(3 * step_s)
    margin = example.ChuckProtection().margin_mm
    assert 0.0 < timeline.clearance_at_rest_mm < margin  # braked inside the zone, short of the chuck
