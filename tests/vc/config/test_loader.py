"""Machine files: the shipped machines, scenario overrides, and the bad-file corpus."""

from __future__ import annotations

from pathlib import Path

import pytest

from vc.config import md_dictionary as mdd
from vc.config.loader import load_machine
from vc.config.model import AxisConfig, ChuckPlant, DcLinkConfig, GearboxPlant, MachineConfig, machine_ipo_cycle_us
from vc.located_yaml import LocatedMap, SourceError, load_text

ROOT = Path(__file__).resolve().parents[3]
MACHINES = ROOT / "scenarios" / "machines"
TURN_MILL = str(MACHINES / "turn_mill.yaml")
MILL = str(MACHINES / "mill_3axis.yaml")
CORPUS = Path(__file__).resolve().parent / "bad_machines"


@pytest.fixture(scope="module")
def turn_mill() -> MachineConfig:
    return load_machine(TURN_MILL)


@pytest.fixture(scope="module")
def mill() -> MachineConfig:
    return load_machine(MILL)


# ------------------------------------------------------------------------------ shipped machines


@pytest.mark.parametrize("path", sorted(str(path) for path in MACHINES.glob("*.yaml")))
def test_every_shipped_machine_loads(path: str) -> None:
    config = load_machine(path)
    assert config.source == path
    assert machine_ipo_cycle_us(config) == 2000


def test_turn_mill_structure(turn_mill: MachineConfig) -> None:
    assert turn_mill.name == "turn_mill"
    assert turn_mill.plc_cycle_ipo == 5
    assert [(axis.name, axis.number, axis.db) for axis in turn_mill.axes] == [
        ("X1", 1, 31), ("Z1", 2, 32), ("Y1", 3, 33), ("SP1", 4, 34), ("SP2", 5, 35), ("SP3", 6, 36)]
    assert [(axis.name, axis.spindle_number) for axis in turn_mill.axes if axis.is_spindle] == [
        ("SP1", 1), ("SP2", 2), ("SP3", 3)]
    assert [axis.name for axis in turn_mill.axes if axis.is_rotary] == ["SP1", "SP2", "SP3"]
    (channel,) = turn_mill.channels
    assert (channel.name, channel.number, channel.db) == ("CHAN1", 1, 21)
    assert channel.axes == ("X1", "Z1", "Y1", "SP1", "SP2", "SP3")
    assert channel.program_names == ("X", "Z", "Y", "SP1", "SP2", "SP3")
    assert channel.geometry_names == ("X", "Y", "Z")
    assert channel.geometry_axes == ("X1", "Y1", "Z1")
    assert channel.axis_for_program_name("Y") == "Y1"
    assert channel.axis_for_program_name("Z") == "Z1"
    assert channel.axis_for_program_name("SP2") == "SP2"
    assert channel.axis_for_program_name("X1") == "X1"
    assert channel.axis_for_program_name("Q") is None
    assert channel.md.int(mdd.REFP_NC_START_LOCK) == 1
    assert channel.md.value(mdd.AXCONF_MACHAX_USED) == (1, 2, 3, 4, 5, 6) + (0,) * 14
    assert turn_mill.layout.axes == ("X1", "Z1", "Y1", "SP1", "SP2", "SP3")
    assert turn_mill.layout.channels == ("CHAN1",)


def test_machine_data_values_and_defaults(turn_mill: MachineConfig) -> None:
    x1, sp1 = turn_mill.axis("X1"), turn_mill.axis("SP1")
    assert x1.md.float(mdd.MAX_AX_VELO) == 30000.0
    assert x1.md.float(mdd.MAX_AX_ACCEL, 0) == 4.0
    # an array written from index 0: the unwritten indices keep the defaults
    assert x1.md.value(mdd.REFP_SET_POS) == (273.0, 0.0, 0.0, 0.0)
    assert sp1.md.floats(mdd.GEAR_STEP_MAX_VELO) == (800.0, 800.0, 2000.0, 4500.0, 4000.0, 8000.0)
    assert sp1.md.int(mdd.NUM_GEAR_STEPS) == 3
    # MachineData holds only what the file writes; the rest comes from the definitions
    written = dict(x1.md.items())
    assert mdd.STANDSTILL_POS_TOL.number not in written
    assert x1.md.float(mdd.STANDSTILL_POS_TOL) == mdd.STANDSTILL_POS_TOL.default
    names = turn_mill.nck.value(mdd.AXCONF_MACHAX_NAME_TAB)
    assert names[:7] == ("X1", "Z1", "Y1", "SP1", "SP2", "SP3", "AX7")  # MD10000 from the axes: section


def test_sim_and_plant(turn_mill: MachineConfig) -> None:
    x1 = turn_mill.axis("X1")
    assert (x1.sim.start_position, x1.sim.zero_mark_offset) == (150.0, 275.0)
    assert x1.plant.ref_cam == (280.0, 295.0)
    assert (x1.plant.hw_limit_minus, x1.plant.hw_limit_plus) == (-12.0, 312.0)
    assert turn_mill.axis("SP1").plant.ref_cam is None


def test_plant_io(turn_mill: MachineConfig, mill: MachineConfig) -> None:
    assert turn_mill.plant_io.area_sizes() == {"I": 10, "Q": 3}  # Q2: the turret and the coolant pump
    assert len(turn_mill.plant_io.points) == 71  # with Lube.pump (Q2.4, the PLC program cams)
    assert str(turn_mill.plant_io.resolve("X1.refCam").address) == "I7.0"
    assert str(turn_mill.plant_io.resolve("MCP.feedOverride").address) == "IB3"
    assert mill.plant_io.area_sizes() == {"I": 11, "Q": 3}
    assert str(mill.plant_io.resolve("EStop.chainOk").address) == "I0.0"


def test_mill_structure(mill: MachineConfig) -> None:
    assert [axis.name for axis in mill.axes] == ["X1", "Y1", "Z1", "SP1"]
    (channel,) = mill.channels
    assert channel.geometry_axes == ("X1", "Y1", "Z1")
    sp1 = mill.axis("SP1")
    assert sp1.is_spindle and sp1.md.int(mdd.NUM_GEAR_STEPS) == 2
    assert mill.plc_cycle_ipo == 4


def _linear_axes() -> list[tuple[str, AxisConfig]]:
    return [(Path(path).stem, axis) for path in (TURN_MILL, MILL) for axis in load_machine(path).axes
            if not axis.is_rotary]


@pytest.mark.parametrize(("machine", "axis"), _linear_axes(), ids=lambda value: getattr(value, "name", value))
def test_shipped_linear_axes_are_physically_consistent(machine: str, axis: AxisConfig) -> None:
    """Cam near one end, start position free, software limits inside the hardware limits, the
    first zero mark a few mm beyond the cam edge, and MD34100 = where referencing ends."""
    md, plant, sim = axis.md, axis.plant, axis.sim
    assert plant.ref_cam is not None and plant.hw_limit_minus is not None and plant.hw_limit_plus is not None
    minus, plus = md.float(mdd.POS_LIMIT_MINUS), md.float(mdd.POS_LIMIT_PLUS)
    assert plant.hw_limit_minus < minus < plus < plant.hw_limit_plus
    assert minus < sim.start_position < plus
    assert not plant.ref_cam[0] <= sim.start_position <= plant.ref_cam[1]
    towards_minus = md.bool(mdd.REFP_CAM_DIR_IS_MINUS)
    assert md.bool(mdd.REFP_CAM_IS_ACTIVE)
    assert not md.bool(mdd.REFP_SEARCH_MARKER_REVERSE)  # falling-edge synchronisation
    travel = plant.hw_limit_plus - plant.hw_limit_minus
    if towards_minus:
        assert plant.ref_cam[0] - plant.hw_limit_minus < 0.1 * travel
    else:
        assert plant.hw_limit_plus - plant.ref_cam[1] < 0.1 * travel
    # phase 2 leaves the cam against the approach direction
    edge, search = (plant.ref_cam[1], 1.0) if towards_minus else (plant.ref_cam[0], -1.0)
    pitch = md.float(mdd.LEADSCREW_PITCH)
    nearest = round((edge - sim.zero_mark_offset) / pitch)
    marks = [sim.zero_mark_offset + pitch * k for k in range(nearest - 2, nearest + 3)]
    beyond_edge = [mark for mark in marks if (mark - edge) * search > 0]
    first_mark = min(beyond_edge, key=lambda mark: abs(mark - edge))
    assert 0.2 * pitch <= abs(first_mark - edge) <= 0.8 * pitch
    reference_point = first_mark + search * md.float(mdd.REFP_MOVE_DIST)
    assert md.float(mdd.REFP_SET_POS, 0) == pytest.approx(reference_point)
    distance_to_cam = abs((plant.ref_cam[1] if towards_minus else plant.ref_cam[0]) - sim.start_position)
    assert distance_to_cam < md.float(mdd.REFP_MAX_CAM_DIST)


# ------------------------------------------------------------------------------ overrides


def _overrides(text: str) -> LocatedMap:
    document, problems = load_text(text, "scenario.yaml")
    assert problems == []
    overrides = document["machine_data"]
    assert isinstance(overrides, LocatedMap)
    return overrides


def test_valid_overrides_replace_the_file_values_index_by_index() -> None:
    overrides = _overrides(
        "machine_data:\n"
        "  X1:\n"
        "    MD34050: 1\n"
        "    REFP_SET_POS[2]: 7.5\n"
        "  SP1:\n"
        "    MD35110 GEAR_STEP_MAX_VELO[2]: 2500\n"
        "  CHAN1: {$MC_REFP_NC_START_LOCK: 0}\n"
        "  NC: {MD10192: 5.0}\n"
    )
    config = load_machine(TURN_MILL, overrides, "scenario.yaml")
    x1 = config.axis("X1")
    assert x1.md.bool(mdd.REFP_SEARCH_MARKER_REVERSE)
    assert x1.md.value(mdd.REFP_SET_POS) == (273.0, 0.0, 7.5, 0.0)
    assert config.axis("SP1").md.floats(mdd.GEAR_STEP_MAX_VELO)[:4] == (800.0, 800.0, 2500.0, 4500.0)
    assert config.channel("CHAN1").md.int(mdd.REFP_NC_START_LOCK) == 0
    assert config.nck.float(mdd.GEAR_CHANGE_WAIT_TIME) == 5.0


def test_the_limits_of_a_modulo_rotary_axis_may_leave_a_gap_across_the_range_end() -> None:
    # seed 003 L12900-12905: MD36110 = 340, MD36100 = 350 forbid 340 .. 350 on a modulo axis only
    gap = "machine_data:\n  Z1: {MD30300: 1, MD30310: 1, MD36100: 350, MD36110: 340}\n"
    config = load_machine(TURN_MILL, _overrides(gap), "scenario.yaml")
    assert config.axis("Z1").md.float(mdd.POS_LIMIT_MINUS) == 350.0
    with pytest.raises(SourceError) as error:
        load_machine(TURN_MILL, _overrides(gap.replace("MD30310: 1", "MD30310: 0")), "scenario.yaml")
    assert "must be below" in str(error.value.problems[0])


def test_overrides_that_change_the_structure_are_rechecked() -> None:
    overrides = _overrides("machine_data:\n  SP2: {MD35000: 1}\n  CHAN1: {MD20050: [1, 4, 2]}\n")
    with pytest.raises(SourceError) as error:
        load_machine(TURN_MILL, overrides, "scenario.yaml")
    assert [str(problem) for problem in error.value.problems] == [
        "scenario.yaml:2:18: SP2: spindle number 1 (MD35000 SPIND_ASSIGN_TO_MACHAX) is already the number"
        " of SP1",
        "scenario.yaml:3:24: MD20050 AXCONF_GEOAX_ASSIGN_TAB[1] = 4: geometry axis Y is channel axis 4 (SP1),"
        " but MD20080 gives the name Y to channel axis 3",
        "scenario.yaml:3:24: MD20050 AXCONF_GEOAX_ASSIGN_TAB[1] = 4: geometry axis Y would be the"
        " spindle SP1",
    ]


def test_invalid_overrides_are_reported_with_the_scenario_marks() -> None:
    overrides = _overrides(
        "machine_data:\n"
        "  Q9: {MD32000: 100}\n"
        "  X1:\n"
        "    MD32000: fast\n"
        "    MD20700: 0\n"
        "    MD34100[9]: 1.0\n"
        "    MD34093: 2.0\n"
        "  CHAN1: 3\n"
        "  NC: {MD10000: [A, B]}\n"
    )
    with pytest.raises(SourceError) as error:
        load_machine(TURN_MILL, overrides, "scenario.yaml")
    assert [str(problem) for problem in error.value.problems] == [
        "scenario.yaml:2:3: machine_data: turn_mill has no axis or channel 'Q9'"
        " (it has X1, Z1, Y1, SP1, SP2, SP3, CHAN1, NC)",
        "scenario.yaml:4:14: MD32000 MAX_AX_VELO: expected a number, got 'fast'",
        "scenario.yaml:5:5: MD20700 REFP_NC_START_LOCK is channel data ($MC_); set it for a channel",
        "scenario.yaml:6:5: MD34100 REFP_SET_POS has 4 values; index 9 is out of range",
        "scenario.yaml:7:5: MD34093 REFP_CAM_MARKER_DIST is read-only: the control writes it",
        "scenario.yaml:8:10: machine_data.CHAN1: expected a mapping of machine data, got 3",
        "scenario.yaml:9:8: MD10000 AXCONF_MACHAX_NAME_TAB is not written as machine data:"
        " it comes from the names under axes:, in order",
    ]


def test_overrides_built_in_code_use_the_scenario_file_name() -> None:
    overrides = LocatedMap({"X1": {"MD32000": -1}})
    with pytest.raises(SourceError) as error:
        load_machine(TURN_MILL, overrides, "built.yaml")
    assert [str(problem) for problem in error.value.problems] == [
        "built.yaml:1:1: MD32000 MAX_AX_VELO = -1: below the minimum 0.0 mm/min"]


def test_axis_overrides_may_move_the_slide_and_the_switches(turn_mill: MachineConfig) -> None:
    overrides = _overrides(
        "machine_data:\n"
        "  X1:\n"
        "    MD34320: [false, true]\n"
        "    sim: {zero_mark_offset_2: 320.0, start_position: 100}\n"
        "    plant: {ref_cam: [250.0, 260.0]}\n"
    )
    x1 = load_machine(TURN_MILL, overrides, "scenario.yaml").axis("X1")
    shipped = turn_mill.axis("X1")
    assert (x1.sim.zero_mark_offset_2, x1.sim.start_position) == (320.0, 100.0)
    assert x1.sim.zero_mark_offset == shipped.sim.zero_mark_offset  # not written: kept
    assert x1.plant.ref_cam == (250.0, 260.0)
    assert (x1.plant.hw_limit_minus, x1.plant.hw_limit_plus) == (shipped.plant.hw_limit_minus,
                                                                 shipped.plant.hw_limit_plus)
    assert turn_mill.axis("X1").sim == shipped.sim  # the shipped machine is not touched


def test_bad_sim_and_plant_overrides_are_reported_with_the_scenario_marks() -> None:
    overrides = _overrides(
        "machine_data:\n"
        "  X1:\n"
        "    sim: {start_position: far, encoder_serial: -3, height: 2}\n"
        "    plant: {ref_cam: [260.0, 250.0], door: 1}\n"
        "  CHAN1: {sim: {start_position: 1}}\n"
    )
    with pytest.raises(SourceError) as error:
        load_machine(TURN_MILL, overrides, "scenario.yaml")
    messages = [str(problem) for problem in error.value.problems]
    assert messages == [
        "scenario.yaml:3:27: sim.start_position: expected a number, got 'far'",
        "scenario.yaml:3:48: sim.encoder_serial is a serial number: a whole number >= 0, got -3",
        "scenario.yaml:3:52: unknown key 'height' in sim; allowed: start_position, zero_mark_offset,"
        " zero_mark_offset_2, encoder_serial, encoder_serial_2",
        "scenario.yaml:4:22: plant.ref_cam [260.0, 250.0]: the start of the cam must be below its end",
        "scenario.yaml:4:38: unknown key 'door' in plant; allowed: ref_cam, hw_limits, gearbox, chuck",
        "scenario.yaml:5:11: unknown key 'sim'; CHAN1 takes machine data",  # sim and plant are axis keys
    ]


# ------------------------------------------------------------------------------ spindle gearboxes


def test_gearboxes_of_the_shipped_machines_and_their_io(turn_mill: MachineConfig, mill: MachineConfig) -> None:
    assert turn_mill.axis("SP1").plant.gearbox == GearboxPlant(stages=3, shift_time_s=0.4, engaged_at_power_on=1)
    assert mill.axis("SP1").plant.gearbox == GearboxPlant(stages=2, shift_time_s=0.4, engaged_at_power_on=1)
    assert [axis.name for axis in turn_mill.axes if axis.plant.gearbox] == ["SP1"]  # SP2, SP3: motor spindles
    wired = {name: str(turn_mill.plant_io.resolve(name).address) for name in (
        "SP1.gearEngaged1", "SP1.gearEngaged2", "SP1.gearEngaged3", "SP1.gearNeutral",
        "SP1.gearShift1", "SP1.gearShift2", "SP1.gearShift3")}
    assert wired == {"SP1.gearEngaged1": "I9.0", "SP1.gearEngaged2": "I9.1", "SP1.gearEngaged3": "I9.2",
                     "SP1.gearNeutral": "I9.3",
                     "SP1.gearShift1": "Q0.1", "SP1.gearShift2": "Q0.2", "SP1.gearShift3": "Q0.3"}
    assert str(mill.plant_io.resolve("SP1.gearShift2").address) == "Q1.1"


def test_gearbox_overrides_replace_the_file_values_key_by_key(turn_mill: MachineConfig) -> None:
    overrides = _overrides("machine_data:\n  SP1:\n    plant: {gearbox: {engaged: 0, shift_time: 1.5}}\n")
    gearbox = load_machine(TURN_MILL, overrides, "scenario.yaml").axis("SP1").plant.gearbox
    assert gearbox == GearboxPlant(stages=3, shift_time_s=1.5, engaged_at_power_on=0)
    assert turn_mill.axis("SP1").plant.gearbox == GearboxPlant(3, 0.4, 1)  # the shipped machine is not touched


def test_a_gearbox_without_engaged_is_in_stage_1_at_power_on() -> None:
    overrides = _overrides("machine_data:\n  SP1:\n    plant: {ref_cam: [10.0, 20.0]}\n")
    config = load_machine(TURN_MILL, overrides, "scenario.yaml")
    gearbox = config.axis("SP1").plant.gearbox
    assert gearbox is not None and gearbox.engaged_at_power_on == 1  # other plant keys leave the gearbox alone


def test_bad_gearbox_overrides_are_reported_with_the_scenario_marks() -> None:
    overrides = _overrides(
        "machine_data:\n"
        "  SP1:\n"
        "    MD35090 NUM_GEAR_STEPS: 2\n"
        "    plant: {gearbox: {engaged: 4}}\n"
        "  SP2:\n"
        "    plant: {gearbox: 3}\n"
        "  X1:\n"
        "    plant: {gearbox: {stages: 1, shift_time: 0.2}}\n"
    )
    with pytest.raises(SourceError) as error:
        load_machine(TURN_MILL, overrides, "scenario.yaml")
    assert [str(problem) for problem in error.value.problems] == [
        "scenario.yaml:3:29: SP1: plant.gearbox.stages = 3, but MD35090 NUM_GEAR_STEPS = 2",
        "scenario.yaml:4:32: SP1: plant.gearbox.engaged = 4: the gearbox has 3 stages (0 = neutral)",
        "scenario.yaml:6:22: machine_data.SP2.plant.gearbox: expected a mapping, got 3",
        "scenario.yaml:8:22: X1: plant.gearbox on an axis that is not a spindle (MD35000 SPIND_ASSIGN_TO_MACHAX"
        " = 0); only a spindle changes gear stages",
        "scenario.yaml:8:22: X1: the gearbox's I/O is not wired in plant_io: X1.gearShift1, X1.gearEngaged1",
    ]


# ------------------------------------------------------------------------------ spindle chucks


def test_chuck_overrides_replace_the_file_values_key_by_key(turn_mill: MachineConfig) -> None:
    overrides = _overrides("machine_data:\n  SP2:\n    plant: {chuck: {closed: true}}\n")
    config = load_machine(TURN_MILL, overrides, "scenario.yaml")
    assert config.axis("SP2").plant.chuck == ChuckPlant(travel_time_s=0.3, closed_at_power_on=True)
    assert turn_mill.axis("SP2").plant.chuck == ChuckPlant(0.3, False)  # the shipped machine is not touched
    assert [str(config.plant_io.resolve(name).address) for name in (
        "Door.closed", "SP2.chuckClosed", "SP2.chuckOpen", "SP2.chuckClose", "SP2.chuckRelease")] == [
        "I6.2", "I9.6", "I9.7", "Q0.6", "Q0.7"]


def test_bad_chuck_overrides_are_reported_with_the_scenario_marks() -> None:
    overrides = _overrides(
        "machine_data:\n"
        "  SP1:\n"
        "    plant: {chuck: {travel_time: 0, closed: 1, jaws: 3}}\n"
        "  SP3:\n"
        "    plant: {chuck: {closed: false}}\n"
        "  X1:\n"
        "    plant: {chuck: {travel_time: 0.3}}\n"
    )
    with pytest.raises(SourceError) as error:
        load_machine(TURN_MILL, overrides, "scenario.yaml")
    assert [str(problem) for problem in error.value.problems] == [
        "scenario.yaml:3:34: plant.chuck.travel_time: the seconds of the chuck's stroke, above 0, got 0",
        "scenario.yaml:3:45: plant.chuck.closed: true (clamped at power-on) or false, got 1",
        "scenario.yaml:3:48: unknown key 'jaws' in plant.chuck; allowed: travel_time, closed",
        "scenario.yaml:5:20: SP3: plant.chuck lacks travel_time (the seconds of the chuck's stroke)",
        "scenario.yaml:5:20: SP3: the chuck's I/O is not wired in plant_io: SP3.chuckClose, SP3.chuckRelease,"
        " SP3.chuckClosed",
        "scenario.yaml:7:20: X1: plant.chuck on an axis that is not a spindle (MD35000 SPIND_ASSIGN_TO_MACHAX = 0)",
        "scenario.yaml:7:20: X1: the chuck's I/O is not wired in plant_io: X1.chuckClose, X1.chuckRelease,"
        " X1.chuckClosed",
    ]


def test_chuck_io_without_a_chuck_is_a_mistake(tmp_path: Path) -> None:
    text = Path(TURN_MILL).read_text().replace("plant: {chuck: {travel_time: 0.3, closed: false}}", "")
    path = tmp_path / "machine.yaml"
    path.write_text(text)
    with pytest.raises(SourceError) as error:
        load_machine(str(path))
    assert [problem.message for problem in error.value.problems] == [
        f"plant_io {address}: SP2.{function} needs a chuck on SP2 (plant: {{chuck: {{travel_time: s}}}})"
        for address, function in (("I9.6", "chuckClosed"), ("I9.7", "chuckOpen"), ("Q0.6", "chuckClose"),
                                  ("Q0.7", "chuckRelease"))]


def test_a_missing_file_is_a_problem() -> None:
    with pytest.raises(SourceError) as error:
        load_machine(str(CORPUS / "no_such_machine.yaml"))
    (problem,) = error.value.problems
    assert problem.message.startswith("cannot read the file")


# ------------------------------------------------------------------------------ bad-file corpus


@pytest.mark.parametrize("name", sorted(path.name for path in CORPUS.glob("*.yaml")))
def test_bad_machine_corpus(name: str, monkeypatch: pytest.MonkeyPatch) -> None:
    """Each bad file reports exactly the problems of its ``.expected`` file, sorted by line."""
    monkeypatch.chdir(CORPUS)
    assert Path(name).read_text(encoding="utf-8").startswith("#"), "every corpus file explains itself"
    expected = Path(name).with_suffix(".expected").read_text(encoding="utf-8").splitlines()
    with pytest.raises(SourceError) as error:
        load_machine(name)
    assert [str(problem) for problem in error.value.problems] == expected


def test_corpus_is_complete() -> None:
    names = {path.stem for path in CORPUS.glob("*.yaml")}
    assert len(names) >= 15
    assert names == {path.stem for path in CORPUS.glob("*.expected")}


# ------------------------------------------------------------------------------ drive line-up


def test_the_turn_mill_buffers_its_dc_link_with_the_main_spindle(turn_mill: MachineConfig) -> None:
    assert turn_mill.dc_link is not None and turn_mill.dc_link.supply_voltage == 400.0
    drive = turn_mill.axis("SP1").drive
    assert drive.generator and (drive.p1248, drive.p2161) == (450.0, 1000.0)
    assert not turn_mill.axis("SP2").drive.generator


def test_the_precharge_time_has_a_default_and_a_scenario_may_override_it(turn_mill: MachineConfig) -> None:
    assert turn_mill.dc_link is not None and turn_mill.dc_link.precharge_time == 0.1
    slow = load_machine(TURN_MILL, _overrides("machine_data:\n  NC: {dc_link: {precharge_time: 1.5}}\n"),
                        "scenario.yaml")
    assert slow.dc_link is not None and (slow.dc_link.precharge_time, slow.dc_link.load_power) == (1.5, 3000.0)
    assert DcLinkConfig(supply_voltage=400.0, capacitance_uf=4000.0, load_power=0.0).precharge_time == 1.0


def test_bad_dc_link_overrides_are_reported_with_the_scenario_marks() -> None:
    with pytest.raises(SourceError) as error:
        load_machine(TURN_MILL, _overrides("machine_data:\n  NC: {dc_link: {precharge_time: 61, volts: 1}}\n"),
                     "scenario.yaml")
    assert [str(problem) for problem in error.value.problems] == [
        "scenario.yaml:2:34: machine_data.NC.dc_link.precharge_time (s, empty link to charged through the"
        " precharge resistors): a number from 0 to 60, got 61",
        "scenario.yaml:2:38: unknown key 'volts' in machine_data.NC.dc_link; allowed: supply_voltage,"
        " capacitance_uf, load_power, precharge_time",
    ]
    with pytest.raises(SourceError) as error:
        load_machine(MILL,
                     _overrides("machine_data:\n  NC: {dc_link: {precharge_time: 1}}\n"), "scenario.yaml")
    assert [str(problem) for problem in error.value.problems] == [
        "scenario.yaml:2:17: machine_data.NC.dc_link: mill_3axis has no dc_link: section"]


def test_a_generator_threshold_outside_the_link_s_range_is_refused() -> None:
    for threshold in (350, 545):
        overrides = _overrides(f"machine_data:\n  SP1:\n    drive: {{p1248: {threshold}}}\n")
        with pytest.raises(SourceError) as error:
            load_machine(TURN_MILL, overrides, "scenario.yaml")
        assert [str(problem) for problem in error.value.problems] == [
            f"scenario.yaml:3:12: SP1: drive p0888 = 3 (generator operation): p1248 = {threshold} V must lie"
            " between the pulse cancellation at 360 V and the link's 540 V on the supply"]


def test_an_override_may_switch_generator_operation_off_but_not_give_its_parameters_without_it() -> None:
    off = load_machine(TURN_MILL, _overrides("machine_data:\n  SP1:\n    drive: {p0888: 0}\n"), "scenario.yaml")
    assert not off.axis("SP1").drive.generator
    with pytest.raises(SourceError) as error:
        load_machine(TURN_MILL, _overrides("machine_data:\n  SP2:\n    drive: {p2161: 500}\n"), "scenario.yaml")
    assert [str(problem) for problem in error.value.problems] == [
        "scenario.yaml:3:12: machine_data.SP2.drive: p2161 belong to generator operation: without p0888 = 3"
        " the drive would ignore them"]


# ------------------------------------------------------------------------------ values the control cannot work with


def test_zero_where_the_control_needs_a_value_is_refused() -> None:
    """MD32000 = 0 and MD10100 = 1e-320 were accepted; MD31060 = 0 and SD42300 = 0 divided by zero when the
    axis moved, MD20090 = 0 with spindles in the channel ended M3 in a KeyError."""
    overrides = _overrides(
        "machine_data:\n"
        "  X1: {MD32000: 0, MD31060: [1, 0], MD34300: [0]}\n"
        "  NC: {MD10100: 1.0e-320, MD10120: 0}\n"
        "  CHAN1: {MD20090: 0, MD42300: [0, 1]}\n"
        "  Z1: {'MD31050[0]': '0', MD32000: '1e-13'}\n"
    )
    with pytest.raises(SourceError) as error:
        load_machine(TURN_MILL, overrides, "scenario.yaml")
    assert [str(problem) for problem in error.value.problems] == [
        "scenario.yaml:2:17: MD32000 MAX_AX_VELO = 0: 0 cannot be entered (the axis could never move, and its"
        " rapid-stop ramp is scaled by it)",
        "scenario.yaml:2:33: MD31060 DRIVE_AX_RATIO_NUMERA[1] = 0: 0 cannot be entered (the seed says 0 cannot be"
        " entered, L19032)",
        "scenario.yaml:2:47: MD34300 ENC_REFP_MARKER_DIST[0] = 0: 0 cannot be entered (marks 0 mm apart are no"
        " scale; the mark layout divides by it)",
        "scenario.yaml:3:17: MD10100 PLC_CYCLIC_TIMEOUT = 1e-320: closer to 0 than 1e-12, too fine for the control"
        " to compute with",
        "scenario.yaml:3:36: MD10120 PLC_RUNNINGUP_TIMEOUT = 0: 0 cannot be entered (no PLC starts within 0 s:"
        " alarm 2001 would come at every power-on)",
        "scenario.yaml:4:20: MD20090 SPIND_DEF_MASTER_SPIND = 0: CHAN1 has spindles (1, 2, 3); S, M3, M4 and M5"
        " without a spindle number address the master spindle, so it needs one",
        "scenario.yaml:4:33: MD42300 COUPLE_RATIO_1[0] = 0: 0 cannot be entered (a ratio of 0 couples nothing, a"
        " denominator of 0 divides by 0 [control])",
        "scenario.yaml:5:22: MD31050 DRIVE_AX_RATIO_DENOM[0] = '0': 0 cannot be entered (the seed says 0 cannot be"
        " entered, L19032)",
        "scenario.yaml:5:36: MD32000 MAX_AX_VELO = '1e-13': closer to 0 than 1e-12, too fine for the control to"
        " compute with",
    ]


@pytest.mark.parametrize(("written", "message"), [
    ("MD32000: '1e400'", "MD32000 MAX_AX_VELO: expected a number, got '1e400' (beyond 1e+15)"),
    ("MD36100: '-1e400'", "MD36100 POS_LIMIT_MINUS: expected a number, got '-1e400' (beyond 1e+15)"),
    ("sim: {start_position: 1.0e+300}", "sim.start_position: expected a number, got 1e+300 (beyond 1e+15)"),
    ("plant: {ref_cam: ['-1e400', 0]}", "plant.ref_cam: expected a number, got '-1e400' (beyond 1e+15)"),
])
def test_numbers_beyond_any_machine_are_refused(written: str, message: str) -> None:
    """'1e400' is text to YAML and infinity to float()."""
    with pytest.raises(SourceError) as error:
        load_machine(TURN_MILL, _overrides(f"machine_data:\n  X1: {{{written}}}\n"), "scenario.yaml")
    assert [problem.message for problem in error.value.problems] == [message]


def test_an_alias_bomb_in_a_machine_file_is_a_problem(tmp_path: Path) -> None:
    """It grew past a gigabyte while the machine loaded."""
    lines = ["machine: bomb", "a0: &a0 [lol]"]
    lines += [f"a{i}: &a{i} [{', '.join([f'*a{i - 1}'] * 9)}]" for i in range(1, 10)]
    path = tmp_path / "bomb.yaml"
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")
    with pytest.raises(SourceError) as error:
        load_machine(str(path))
    (problem,) = error.value.problems
    assert problem.mark.line == 7 and "values with its aliases expanded" in problem.message


def test_the_drives_messages_take_their_thresholds_and_p2161() -> None:
    overrides = _overrides("machine_data:\n  Z1:\n    drive: {messages: 1, p2161: 8, p2174: 40}\n")
    config = load_machine(TURN_MILL, overrides, "scenario.yaml")
    drive = config.axis("Z1").drive
    assert drive.messages is True and (drive.p2161, drive.p2174, drive.p2155) == (8.0, 40.0, 900.0)


def test_a_message_threshold_without_the_messages_is_reported() -> None:
    with pytest.raises(SourceError) as error:
        load_machine(TURN_MILL, _overrides("machine_data:\n  Z1:\n    drive: {p2174: 40}\n"), "scenario.yaml")
    assert [str(problem) for problem in error.value.problems] == [
        "scenario.yaml:3:12: machine_data.Z1.drive: p2174 belong to the drive's messages: without messages: 1 the"
        " drive reports none"]
