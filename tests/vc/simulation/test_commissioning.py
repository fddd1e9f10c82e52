"""The commissioning facts of a machine: referencing, wiring, what the plant needs from the PLC,
as ``vc map`` prints them and as the link description carries them."""

from __future__ import annotations

import csv
import io
import json
from pathlib import Path

import pytest

from interfaces.catalog import load_catalog
from interfaces.commissioning import RULES, Commissioning
from interfaces.links.description import LinkDescription
from interfaces.links.modbus.codec import MAX_DESCRIPTION_BYTES, RegisterMap
from interfaces.plc import PlcEnvironment
from interfaces.signals import expand
from vc.cli.main import main
from vc.config.loader import load_machine
from vc.config.machine_files import packaged_machines
from vc.config.model import MachineConfig
from vc.located_yaml import LocatedMap, load_text
from vc.simulation.commissioning import commissioning_of

LATHE_WITH_TAILSTOCK = str(Path(__file__).resolve().parents[3] / "scenarios" / "fixed_stop" / "machines"
                           / "lathe_tailstock.yaml")
VERTICAL_AXIS = str(Path(__file__).resolve().parents[3] / "scenarios" / "drives" / "machines" / "vertical_axis.yaml")
ROTARY_TABLE = str(Path(__file__).resolve().parents[3] / "scenarios" / "indexing_axes" / "machines"
                   / "rotary_table.yaml")


def facts(machine: MachineConfig) -> Commissioning:
    return commissioning_of(machine, expand(load_catalog(), machine.layout))


def test_turn_mill_axes_as_the_machine_file_and_the_inclined_axis_rule_say() -> None:
    turn_mill = facts(load_machine("turn_mill"))
    x1, y1, sp1 = turn_mill.axis("X1"), turn_mill.axis("Y1"), turn_mill.axis("SP1")
    assert (x1.approach, x1.cam, x1.hw_limit_minus, x1.hw_limit_plus) == ("plus", (280.0, 295.0), -12.0, 312.0)
    assert (x1.sw_limits, x1.reference_position, x1.reference_cycle) == ((-5.0, 305.0), 273.0, 2)
    assert x1.before == ("Y1",) and "alarm 65820" in x1.prerequisite
    assert (y1.approach, y1.cam, y1.reference_cycle, y1.before) == ("minus", (-95.0, -80.0), 1, ())
    assert (sp1.kind, sp1.approach, sp1.gear_stages, sp1.reference_cycle) == ("spindle", "", 3, -1)
    assert turn_mill.reference_order == {"CHAN1": (("Z1", "Y1"), ("X1",))}
    assert turn_mill.order_text("CHAN1") == "Z1 and Y1 then X1 (MD34110, equal numbers together)"


def test_the_facts_follow_the_machine_data_a_scenario_overrides() -> None:
    document, problems = load_text("X1: {MD34010: 1, MD34110: 1}\nCHAN1: {MD62800: 0}", "<test>")
    assert not problems and isinstance(document, LocatedMap)
    changed = facts(load_machine("turn_mill", document, "<test>"))
    x1 = changed.axis("X1")
    assert (x1.approach, x1.before, x1.prerequisite) == ("minus", (), "")  # no inclined-axis control any more
    assert changed.reference_order == {"CHAN1": (("X1", "Z1", "Y1"),)}


def test_what_the_plant_needs_from_the_plc_names_its_inputs_outputs_and_signals() -> None:
    needs = {need.name: need for need in facts(load_machine("turn_mill")).needs}
    mill = {need.name: need for need in facts(load_machine("mill_3axis")).needs}
    lathe = {need.name: need for need in facts(load_machine(LATHE_WITH_TAILSTOCK)).needs}  # no packaged one has it
    table = {need.name: need for need in facts(load_machine(ROTARY_TABLE)).needs}  # nor the clamp
    vertical = {need.name: need for need in facts(load_machine(VERTICAL_AXIS)).needs}  # nor the holding brake
    assert set(RULES) == {need.rule for need in (*needs.values(), *mill.values(), *lathe.values(), *table.values(),
                                                 *vertical.values())}
    assert "Z1.drive.out.releaseHoldingBrake" in vertical["Brake"].text and "sags at 600" in vertical["Brake"].text
    assert "Clamp.close (Q0.6)" in table["Clamp"].plant_io and "C1.basic.out.clampingInProgress" in table["Clamp"].text
    assert "Turret.unlock (Q2.2)" in needs["Turret"].plant_io and "8 stations" in needs["Turret"].text
    assert "ToolArm.toSpindle (Q0.3)" in mill["ToolChanger"].plant_io and "12 pockets" in mill["ToolChanger"].text
    assert "DB21.DBX6.1" in needs["CHAN1.auxiliaryFunctions"].interface
    assert "exactly one PLC scan" in needs["CHAN1.auxiliaryFunctions"].text
    assert (needs["X1.refCam"].plant_io, needs["X1.refCam"].interface) == (("X1.refCam (I7.0)",), ("DB31.DBX12.7",))
    assert needs["X1.hwLimitMinus"].rule == "copy_inverse" and "<= -12" in needs["X1.hwLimitMinus"].text
    gearbox = needs["SP1.gearbox"]
    assert "SP1.gearShift2 (Q0.2)" in gearbox.plant_io and "oscillation enable DB34.DBX18.5" in gearbox.text
    assert "DB10.DBX56.2 alone leaves alarm 3000 standing" in needs["EStop"].text
    assert "DB21.DBX7.7" in needs["EStop"].interface and "DB11.DBX0.7" in needs["EStop"].interface
    assert "Drives.ready (I6.1) follows after 0.1 s" in needs["Drives"].text
    assert "CHAN1.nozagc" in needs and "CHAN1.nozagc" not in {n.name for n in facts(load_machine("mill_5axis")).needs}


@pytest.mark.parametrize("name", packaged_machines())
def test_the_description_carries_the_facts_within_its_registers(name: str) -> None:
    machine = load_machine(name)
    catalog = expand(load_catalog(), machine.layout)
    commissioning = commissioning_of(machine, catalog)
    environment = PlcEnvironment(catalog, machine.plant_io, 0.01, {}, machine.name, 2000, 5, commissioning)
    text = LinkDescription.of(environment, None, RegisterMap.build(catalog, machine.plant_io.area_sizes())).to_json()
    assert len(text) <= MAX_DESCRIPTION_BYTES
    received = Commissioning.from_dict(LinkDescription.from_json(text).commissioning)
    assert received.axes == commissioning.axes and received.reference_order == commissioning.reference_order
    assert [(n.name, n.rule, n.plant_io, n.interface) for n in received.needs] == \
        [(n.name, n.rule, n.plant_io, n.interface) for n in commissioning.needs]
    assert received.devices == commissioning.devices  # the turret's stations, the magazine's pockets


def test_vc_map_prints_the_facts_in_every_format(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["map", "--machine", "turn_mill", "--format", "csv"]) == 0
    rows = {row["symbol"]: row for row in csv.DictReader(io.StringIO(capsys.readouterr().out))}
    assert rows["X1.commissioning"]["instance"] == "COMMISSIONING"
    assert "approach X1+ (MD34010 = 0)" in rows["X1.commissioning"]["meaning"]
    assert rows["wiring.X1.refCam"]["address"] == "X1.refCam (I7.0) DB31.DBX12.7"
    assert main(["map", "--machine", "turn_mill", "--format", "json"]) == 0
    entries = {entry["symbol"]: entry for entry in json.loads(capsys.readouterr().out)}
    assert entries["CHAN1.referenceOrder"]["meaning"].startswith("Z1 and Y1 then X1")
    assert main(["map", "--machine", "turn_mill", "--format", "md"]) == 0
    markdown = capsys.readouterr().out
    assert "## Commissioning" in markdown and "| Y1.commissioning | DB33 |" in markdown
