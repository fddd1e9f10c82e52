"""The co-simulation unit the FMU wraps, without FMI: variables, parameters, the step."""

from __future__ import annotations

import subprocess
import sys

import pytest
from fmu_machines import REPOSITORY, TURN_MILL

from fmu.unit import IPO_CYCLE, PLC_SIGN_OF_LIFE, Causality, Kind, NcUnit, UnitError, Variability
from vc.simulation.lockstep import Simulation


@pytest.fixture
def unit() -> NcUnit:
    unit = NcUnit(TURN_MILL)
    unit.setup(0.0)
    return unit


def index_of(unit: NcUnit, name: str) -> int:
    return next(position for position, variable in enumerate(unit.variables) if variable.name == name)


def value(unit: NcUnit, name: str) -> float | int | bool:
    return unit.get(index_of(unit, name))


def test_names_are_unique_and_kinds_follow_the_signal_types(unit: NcUnit) -> None:
    names = [variable.name for variable in unit.variables]
    assert len(names) == len(set(names))
    kinds = {variable.name: (variable.kind, variable.causality, variable.variability) for variable in unit.variables}
    assert kinds["X1.basic.out.enableCtrl"] == (Kind.BOOLEAN, Causality.INPUT, Variability.DISCRETE)
    assert kinds["SP1.spindle.out.gearStageSelection"] == (Kind.INTEGER, Causality.INPUT, Variability.DISCRETE)
    assert kinds["SP1.spindle.in.sFuncValue"] == (Kind.REAL, Causality.OUTPUT, Variability.DISCRETE)
    assert kinds["SP1.gearShift2"] == (Kind.BOOLEAN, Causality.INPUT, Variability.DISCRETE)  # plant output Q
    assert kinds["SP1.gearEngaged2"] == (Kind.BOOLEAN, Causality.OUTPUT, Variability.DISCRETE)  # plant input I
    assert kinds["MCP.feedOverride"] == (Kind.INTEGER, Causality.OUTPUT, Variability.DISCRETE)
    assert kinds["SP1.velocity"] == (Kind.REAL, Causality.OUTPUT, Variability.CONTINUOUS)
    assert kinds["Z1.startPosition"] == (Kind.REAL, Causality.PARAMETER, Variability.FIXED)
    descriptions = {variable.name: variable.description for variable in unit.variables}
    assert descriptions["X1.basic.in.enc1Synchronized"].startswith("DB31.DBX60.4 ")
    assert descriptions["SP1.basic.in.enc1Synchronized"].startswith("DB34.DBX60.4 ")
    assert descriptions["X1.refCam"].startswith("I7.0 ")
    assert descriptions["SP1.velocity"].endswith(", rev/min") and descriptions["X1.velocity"].endswith(", mm/min")


def test_inputs_reach_the_nc_at_the_next_step_and_outputs_show_the_last_cycle(unit: NcUnit) -> None:
    select, active = index_of(unit, "MODEGROUP.basic.out.mdaMode"), index_of(unit, "MODEGROUP.basic.in.mdaModeActive")
    unit.initialize()
    unit.set(select, True)
    assert unit.get(select) is True and unit.get(active) is False  # set, not yet seen by the NC
    unit.step(0.0, 0.002)
    assert unit.get(active) is True
    assert unit.time == pytest.approx(0.002)


def test_outputs_cannot_be_set_and_bad_values_are_not_taken(unit: NcUnit) -> None:
    with pytest.raises(UnitError, match=r"^X1\.basic\.in\.enc1Synchronized is an output; only inputs and parameters"):
        unit.set(index_of(unit, "X1.basic.in.enc1Synchronized"), True)
    override = index_of(unit, "X1.basic.out.feedrateOvrFactor")
    unit.set(override, 80)
    with pytest.raises(UnitError, match=r"is a byte; 300 is outside 0\.\.255; the value was not taken"):
        unit.set(override, 300)
    with pytest.raises(UnitError, match=r"2\.5 is not a whole number"):
        unit.set(override, 2.5)
    assert unit.get(override) == 80
    start = index_of(unit, "CHAN1.basic.out.ncStart")
    with pytest.raises(UnitError, match=r"is a bool; 2 is outside 0\.\.1; the value was not taken"):
        unit.set(start, 2)
    assert unit.get(start) is False


@pytest.mark.parametrize(("step", "reason"), [
    (0.003, "the communication step 0.003 s is not a whole number of IPO cycles of 2 ms;"
            " use a multiple such as 0.004 s"),
    (0.0, "the communication step 0 s is not a whole number of IPO cycles of 2 ms; use a multiple such as 0.002 s"),
    (-0.01, "the communication step -0.01 s is not a whole number"),
])
def test_a_step_must_be_whole_ipo_cycles(unit: NcUnit, step: float, reason: str) -> None:
    unit.initialize()
    with pytest.raises(UnitError) as raised:
        unit.step(0.0, step)
    assert str(raised.value).startswith(reason)
    assert unit.simulation.cycle == 0  # nothing happened


def test_floating_point_steps_are_whole_cycles_and_time_follows_the_start_time(unit: NcUnit) -> None:
    unit.setup(1.5)
    unit.initialize()
    time = 1.5
    for _ in range(30):
        unit.step(time, 0.1 / 10)  # 0.01 as a host computes it
        time += 0.1 / 10
    assert unit.simulation.cycle == 150 and unit.time == pytest.approx(1.8)
    with pytest.raises(UnitError, match=r"t = 1.7 s is not where the NC stands \(t = 1.8 s\)"):
        unit.step(1.7, 0.01)


def test_start_positions_and_the_ipo_cycle_take_effect_when_initialisation_ends(unit: NcUnit) -> None:
    enable = index_of(unit, "X1.basic.out.enableCtrl")
    unit.set(enable, True)  # set during initialisation: kept over the new power-on
    unit.set(index_of(unit, "X1.startPosition"), 200.0)
    unit.set(index_of(unit, IPO_CYCLE), 0.004)
    assert value(unit, "X1.physical") == 150.0
    unit.initialize()
    assert value(unit, "X1.physical") == 200.0
    assert unit.ipo_cycle_s == 0.004 and unit.get(enable) is True
    with pytest.raises(UnitError, match="IPO cycles of 4 ms"):
        unit.step(0.0, 0.002)
    unit.step(0.0, 0.02)
    assert unit.simulation.cycle == 5


def test_parameters_that_do_not_fit_the_machine_are_refused_with_their_location(unit: NcUnit) -> None:
    unit.set(index_of(unit, IPO_CYCLE), 5.0)
    with pytest.raises(UnitError) as raised:
        unit.initialize()
    assert "the machine does not load" in str(raised.value)
    assert "<FMU parameters>:1:" in str(raised.value) and "MD10050" in str(raised.value)


def test_a_machine_file_that_cannot_be_read_does_not_make_a_unit() -> None:
    reason = r"the machine does not load:\n.*no_such_machine\.yaml:1:1: cannot read the file"
    with pytest.raises(UnitError, match=reason):
        NcUnit(str(REPOSITORY / "scenarios" / "machines" / "no_such_machine.yaml"))


def test_the_unit_steps_like_the_simulation_without_plc(unit: NcUnit) -> None:
    reference = Simulation(unit.machine, plc=None)
    unit.initialize()
    for name in ("MODEGROUP.basic.out.jogMode", "X1.basic.out.enc1Activation", "X1.drive.out.enablePulses",
                 "Drives.on", "X1.basic.out.enableOvr"):
        unit.set(index_of(unit, name), True)
        ref = reference.catalog.resolve(name) if not name.startswith("Drives") else reference.plant_io.resolve(name)
        reference.write(ref, 1)
    unit.set(index_of(unit, "X1.basic.out.feedrateOvrFactor"), 100)
    reference.write(reference.catalog.resolve("X1.basic.out.feedrateOvrFactor"), 100)
    for step in range(20):
        unit.step(step * 0.01, 0.01)
        reference.step(5)
    for variable_index, variable in enumerate(unit.variables):
        if variable.causality is Causality.OUTPUT and variable.variability is Variability.DISCRETE:
            assert unit.get(variable_index) == reference.read(_ref(reference, variable.name)), variable.name


def _ref(simulation: Simulation, name: str):  # type: ignore[no-untyped-def]
    point = simulation.plant_io.by_name(name)
    return point.ref() if point is not None else simulation.catalog.resolve(name)


def test_the_nc_watches_a_plc_sign_of_life_once_it_is_written(unit: NcUnit) -> None:
    life, alarm = index_of(unit, PLC_SIGN_OF_LIFE), index_of(unit, "NC.basic.in.alarmActive")
    unit.initialize()
    for step in range(50):  # no sign of life written: nothing is watched
        unit.step(step * 0.01, 0.01)
    assert unit.get(alarm) is False
    for step in range(50, 80):  # a PLC that counts every scan
        unit.set(life, step)
        unit.step(step * 0.01, 0.01)
    assert unit.get(alarm) is False and unit.get(life) == 79
    for step in range(80, 92):  # ... and stops: MD10100 = 0.1 s later alarm 2000
        unit.step(step * 0.01, 0.01)
    assert unit.get(alarm) is True
    assert [a.number for a in unit.simulation.alarms()] == [2000]


def test_the_operators_plant_points_say_that_they_stand_at_their_power_on_position(unit: NcUnit) -> None:
    descriptions = {variable.name: variable.description for variable in unit.variables}
    assert descriptions["MCP.ncStart"].startswith("I1.0 ") and "the operator's" in descriptions["MCP.ncStart"]
    assert "the operator's" in descriptions["EStop.chainOk"]
    assert "the operator's" not in descriptions["X1.refCam"]


def test_spindles_export_their_coupling_and_the_machine_its_dc_link(unit: NcUnit) -> None:
    names = {variable.name for variable in unit.variables}
    assert {"SP2.syncDeviation", "SP2.couplingOffset", "SP3.couplingOffsetActual", "NC.dcLinkVoltage"} <= names
    assert "X1.syncDeviation" not in names  # an axis follows no spindle
    voltage = next(variable for variable in unit.variables if variable.name == "NC.dcLinkVoltage")
    assert voltage.variability is Variability.CONTINUOUS
    assert value(unit, "NC.dcLinkVoltage") == 0.0  # empty at power-on: the precharge charges it
    unit.step(0.0, 0.2)  # turn_mill's precharge_time is 0.1 s
    assert value(unit, "NC.dcLinkVoltage") == pytest.approx(540.0)  # 1.35 x the 400 V supply
    assert value(unit, "SP2.syncDeviation") == 0.0


def test_the_unit_loads_without_python_can() -> None:
    """The FMU bundles vc and interfaces but not the bus adapters: a host without python-can loads it."""
    code = "import sys; sys.modules['can'] = None; import fmu.unit"
    result = subprocess.run([sys.executable, "-c", code], cwd=REPOSITORY, capture_output=True, text=True, timeout=60)
    assert result.returncode == 0, result.stderr
