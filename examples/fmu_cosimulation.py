"""A co-simulation master: the NC FMU, the built-in PLC and a plant model in lockstep.

    .venv/bin/python examples/fmu_cosimulation.py [--fmu turn_mill.fmu]

Without ``--fmu`` the script first exports ``scenarios/machines/turn_mill.yaml`` into a
temporary directory, as ``vc fmu export`` would.  Three parts meet at every communication
point, one PLC cycle apart (10 ms = 5 IPO cycles of 2 ms on turn_mill):

* :class:`NcFmu`: the NC and its machine plant (cams, limit switches, drives, gearboxes) as
  the FMU, through FMPy's low-level API: value references from the model description, one
  batch ``get``/``set`` call per type;
* :class:`BuiltInPlc`: the soft PLC program ``referencing`` of ``plc_stub`` with the two
  process images a link hands it at every scan (interface DBs, plant I/O);
* :class:`Surroundings`: what stands around the machine: the :class:`Operator` at the panel,
  a model of the tool turret and the chuck (:class:`ChuckProtection`), the part a 3D or line
  model (SIMIT, NX MCD) plays, and the recorder of the :class:`Timeline`.

The operator selects JOG and REF and presses NC start: the axes reference (in the NC's
order of MD34110, or in the PLC's ``referencing_order`` when the machine's ``plc:`` section
has one).  Then he selects JOG, holds the rapid key and Z- and drives the turning tool
towards the chuck; the plant model sees the tool tip enter the chuck's protection zone and
opens its contact in the emergency-stop chain; the PLC sets DB10.DBX56.1 and the NC brakes.

The order at communication point t_k (k PLC cycles after power-on) is the harness's
lockstep (``vc/simulation/lockstep.py``: NC step, plant step, every fifth IPO cycle a scan):

1. get the FMU's outputs: NC->PLC signals and plant inputs as the IPO cycle ending at t_k
   left them (the FMU's plant updates its sensors with every IPO cycle);
2. copy them into the PLC's images: the interface DBs, and the inputs the FMU's plant
   drives.  The operator's points (panel keys, the emergency-stop chain) are FMU outputs
   too, frozen at power-on, because the operator acts at the PLC: they come from the
   surroundings, and copying the FMU's would undo every key the operator pressed;
3. one PLC scan (``interfaces.plc``): publish the previous scan's outputs into the images,
   read the inputs, run OB1;
4. set the FMU's inputs from the images (PLC->NC signals, plant outputs Q); the NC reads
   them from its next IPO cycle on;
5. the surroundings look at the machine of t_k and act; the PLC reads what they set at its
   next scan, just as it reads a scenario's key presses in the harness;
6. doStep(t_k, one PLC cycle).

Each of these is where it is for a reason; moved, the run no longer matches the harness: a
doStep before the first scan makes every event a PLC cycle late (the harness scans once at
power-on, before any IPO cycle); outputs taken from the PLC program's own image instead of the
images the scan published to reach the NC a scan early; the FMU's outputs read before the
doStep instead of after it show the PLC every cam and every NC answer a cycle late.  The last
two change what the axes do (on a cam a scan earlier or later they brake elsewhere), so every
later event moves by more than a cycle.
"""

from __future__ import annotations

import argparse
import json
import math
import shutil
import tempfile
import time as wallclock
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

from fmpy import extract, read_model_description
from fmpy.fmi2 import FMU2Slave

from fmu.export import export_fmu
from fmu.instance import MANIFEST
from fmu.unit import PLC_SIGN_OF_LIFE
from interfaces.catalog import load_catalog
from interfaces.image import ProcessImage
from interfaces.links.inprocess import InProcessConnector
from interfaces.plant_io import PointOwner
from interfaces.plc import PlcEnvironment
from interfaces.signals import Direction, SignalRef, expand
from vc.config.loader import load_machine
from vc.config.model import MachineConfig, machine_ipo_cycle_us

REPOSITORY = Path(__file__).resolve().parents[1]
TURN_MILL = REPOSITORY / "scenarios" / "machines" / "turn_mill.yaml"
PLC_PROGRAM = "referencing"
EMERGENCY_STOP_CHAIN = "EStop.chainOk"
EMERGENCY_STOP_ACTIVE = "NC.basic.in.emergencyStopActive"
RADIAL_AXIS, AXIAL_AXIS = "X1", "Z1"  # turn_mill: X1 moves the turret across the spindle axis, Z1 along it
KEY_PRESS_S = 0.1  # how long a finger stays on a key (a scenario's ``press``)
TIME_LIMIT_S = 30.0  # simulated; the whole sequence takes about 11 s on turn_mill
_SAME_TIME_S = 1e-9  # communication points are multiples of the step: compare times with this slack

Value = bool | int | float
Read = Callable[[str], Value]  # the machine at one communication point: a value by FMU variable name


def communication_step_s(machine: MachineConfig) -> float:
    """One PLC cycle: the PLC scans at every communication point, the FMU steps whole IPO cycles."""
    return machine.plc_cycle_ipo * machine_ipo_cycle_us(machine) / 1_000_000


def with_plc_parameters(machine: MachineConfig, parameters: Mapping[str, Any] | None) -> MachineConfig:
    """The machine with ``parameters`` over its ``plc:`` section, as a scenario's ``plc_parameters``."""
    if not parameters:
        return machine
    return replace(machine, plc_parameters={**machine.plc_parameters, **parameters})


# ================================================================================== the NC FMU


class NcFmu:
    """The NC FMU through FMPy's low-level FMI 2.0 API, from instantiation to ``freeInstance``."""

    def __init__(self, fmu_path: str | Path, instance_name: str = "nc"):
        description = read_model_description(str(fmu_path))
        self.unzip_dir = Path(extract(str(fmu_path)))
        # names and value references by FMI type, for one batch call per type
        self.outputs: dict[str, tuple[list[str], list[int]]] = {}
        self.inputs: dict[str, tuple[list[str], list[int]]] = {}
        self._set: dict[str, Value] = {}  # every input's value as set last (empty: none set yet)
        for variable in description.modelVariables:
            groups = {"output": self.outputs, "input": self.inputs}.get(variable.causality)
            if groups is not None:
                names, references = groups.setdefault(variable.type, ([], []))
                names.append(variable.name)
                references.append(variable.valueReference)
        self.slave = FMU2Slave(guid=description.guid, unzipDirectory=str(self.unzip_dir),
                               modelIdentifier=description.coSimulation.modelIdentifier,
                               instanceName=instance_name)
        self.slave.instantiate()
        self.slave.setupExperiment(startTime=0.0)
        self.slave.enterInitializationMode()
        self.slave.exitInitializationMode()  # the NC powers on with the machine file inside the FMU

    def machine_file(self) -> Path:
        """The machine file the FMU was exported from: the PLC must be built for that machine."""
        resources = self.unzip_dir / "resources"
        manifest = json.loads((resources / MANIFEST).read_text(encoding="utf-8"))
        return resources / str(manifest["machine"])

    def get_outputs(self) -> dict[str, Value]:
        getters = {"Boolean": self.slave.getBoolean, "Integer": self.slave.getInteger, "Real": self.slave.getReal}
        values: dict[str, Value] = {}
        for fmi_type, (names, references) in self.outputs.items():
            values.update(zip(names, getters[fmi_type](references), strict=True))
        return values

    def set_inputs(self, values: Mapping[str, Value]) -> None:
        """Set the inputs whose value differs from the one set last.  FMI inputs keep their value,
        and every value set costs FMPy's conversion and the NC's write: setting all 500 at every
        step nearly doubles the run time."""
        setters = {"Boolean": self.slave.setBoolean, "Integer": self.slave.setInteger, "Real": self.slave.setReal}
        for fmi_type, (names, references) in self.inputs.items():
            changed = [(reference, values[name]) for name, reference in zip(names, references, strict=True)
                       if self._set.get(name) != values[name]]
            if changed:
                setters[fmi_type]([reference for reference, _ in changed], [value for _, value in changed])
        self._set.update(values)

    def do_step(self, time_s: float, step_s: float) -> None:
        self.slave.doStep(currentCommunicationPoint=time_s, communicationStepSize=step_s)

    def close(self) -> None:
        self.slave.terminate()
        self.slave.freeInstance()
        shutil.rmtree(self.unzip_dir, ignore_errors=True)


# ================================================================================== the PLC


@dataclass(frozen=True, slots=True)
class _Point:
    """One FMU variable and where it sits in the PLC's images."""

    name: str
    image: ProcessImage
    ref: SignalRef


class BuiltInPlc:
    """A ``plc_stub`` program with its two process images, built as the harness builds it at
    power-on (``Simulation._power_on``), for a machine whose NC runs elsewhere."""

    def __init__(self, machine: MachineConfig, program: str):
        catalog = expand(load_catalog(), machine.layout)
        ipo_cycle_us = machine_ipo_cycle_us(machine)
        environment = PlcEnvironment(catalog, machine.plant_io, communication_step_s(machine),
                                     machine.plc_parameters, machine.name, ipo_cycle_us, machine.plc_cycle_ipo)
        self.program = InProcessConnector().connect(environment, program)
        # the link's images: each scan publishes the program's outputs into them and reads its inputs
        self.interface = ProcessImage(catalog.area_sizes)
        self.plant = ProcessImage(machine.plant_io.area_sizes())
        self.from_fmu: list[_Point] = []  # NC->PLC signals and the sensors of the FMU's plant
        self.to_fmu: list[_Point] = []  # PLC->NC signals and plant outputs Q
        for signal in catalog.signals:
            points = self.to_fmu if signal.direction is Direction.PLC_TO_NC else self.from_fmu
            points.append(_Point(signal.symbol, self.interface, signal.ref()))
        for point in machine.plant_io.points:
            if point.owner is PointOwner.PLANT:
                self.from_fmu.append(_Point(point.name, self.plant, point.ref()))
            elif point.owner is PointOwner.PLC:
                self.to_fmu.append(_Point(point.name, self.plant, point.ref()))
        self.operator_points = {point.name: point.ref() for point in machine.plant_io.points
                                if point.owner is PointOwner.OPERATOR}

    def take_inputs(self, fmu_outputs: Mapping[str, Value], from_surroundings: Mapping[str, int]) -> None:
        """The inputs of the coming scan: what the FMU shows, and what the surroundings set."""
        for point in self.from_fmu:
            point.image.write(point.ref, fmu_outputs[point.name])
        for name, value in from_surroundings.items():
            self.plant.write(self.operator_points[name], value)

    def scan(self) -> None:
        self.program.scan(self.interface, self.plant)

    def outputs(self) -> dict[str, Value]:
        """What the scan published (the previous OB1's outputs): what the harness's NC reads next,
        and the PLC's sign of life, which the NC watches from then on (alarm 2000 if it stops)."""
        published: dict[str, Value] = {point.name: point.image.read(point.ref) for point in self.to_fmu}
        published[PLC_SIGN_OF_LIFE] = self.program.sign_of_life
        return published


# ================================================================================== the surroundings


@dataclass(frozen=True, slots=True)
class PanelAction:
    """The operator sets ``keys`` ``delay_s`` after his previous action, once ``until`` reads 1."""

    keys: Mapping[str, int]
    what: str = ""  # for the timeline; a key let go goes unmentioned
    delay_s: float = KEY_PRESS_S
    until: str | None = None


def reference_then_approach_the_chuck(channel: str) -> tuple[PanelAction, ...]:
    """JOG, REF, NC start; once every axis is referenced JOG again (REF off), then rapid in Z-."""
    approach = {"MCP.rapid": 1, f"MCP.minus.{AXIAL_AXIS}": 1}
    return (
        PanelAction({"MCP.jog": 1}, "operator selects JOG", delay_s=0.0),
        PanelAction({"MCP.jog": 0}),
        PanelAction({"MCP.ref": 1}, "operator switches REF on"),
        PanelAction({"MCP.ref": 0}),
        PanelAction({"MCP.ncStart": 1}, "operator presses NC start: referencing"),
        PanelAction({"MCP.ncStart": 0}),
        PanelAction({"MCP.jog": 1}, "operator selects JOG (REF off)", until=f"{channel}.basic.in.allAxesReferenced"),
        PanelAction({"MCP.jog": 0}),
        PanelAction(approach, f"operator holds rapid and {AXIAL_AXIS}- towards the chuck"),
        PanelAction(dict.fromkeys(approach, 0), "operator lets go of the keys", delay_s=0.0,
                    until=EMERGENCY_STOP_ACTIVE),
    )


class Operator:
    """The person at the machine control panel, working through a list of actions."""

    def __init__(self, panel_at_power_on: Mapping[str, int], actions: Sequence[PanelAction]):
        self.panel = dict(panel_at_power_on)  # every operator point of the I/O list, as he holds it
        self.actions = list(actions)
        self.next_action = 0
        self.last_action_s = 0.0

    def act(self, time_s: float, read: Read) -> list[str]:
        """Carry out what is due at ``time_s``; returns what he did, for the timeline."""
        done = []
        while self.next_action < len(self.actions):
            action = self.actions[self.next_action]
            if time_s < self.last_action_s + action.delay_s - _SAME_TIME_S:
                break
            if action.until is not None and not read(action.until):
                break
            self.panel.update(action.keys)
            self.next_action += 1
            self.last_action_s = time_s
            if action.what:
                done.append(action.what)
        return done


@dataclass(frozen=True, slots=True)
class Chuck:
    """The chuck as a cylinder on the spindle nose (machine Z 0 .. face), around the spindle axis."""

    radius_mm: float = 125.0  # a 250 mm three-jaw chuck, the jaws at its rim
    face_z_mm: float = 150.0  # the jaws' front face

    def distance_mm(self, radius_mm: float, z_mm: float) -> float:
        """From a point (distance from the spindle axis, Z) to the chuck; 0 on or inside it."""
        return math.hypot(max(radius_mm - self.radius_mm, 0.0), max(z_mm - self.face_z_mm, 0.0))


@dataclass(frozen=True, slots=True)
class ToolInTurret:
    """Where the tip of the tool in the working position sits, from the slides' physical positions."""

    offset_x_mm: float = -180.0  # the tip stands 180 mm nearer the spindle axis than X1's reference ...
    offset_z_mm: float = -60.0  # ... and 60 mm nearer the chuck than Z1's

    def tip(self, read: Read) -> tuple[float, float]:
        """(distance from the spindle axis, Z) of the tool tip, mm."""
        return (abs(float(read(f"{RADIAL_AXIS}.physical")) + self.offset_x_mm),
                float(read(f"{AXIAL_AXIS}.physical")) + self.offset_z_mm)


class ChuckProtection:
    """A stand-in for the machine's 3D model: the tool tip against the chuck's protection zone.

    The zone is every point within ``margin_mm`` of the chuck; the model's safety contact is
    in series with the emergency-stop button in the chain (``EStop.chainOk``, normally closed)
    and opens while the tool tip is inside.  The margin must exceed what the machine travels
    between the tip crossing the zone's border and standing still: up to a communication step
    until the model sees it, a scan until the PLC reads the open chain and another until it
    publishes DB10.DBX56.1, an IPO cycle, and the NC's braking distance (MD36610).

    The 3D model of a commissioning tool (SIMIT, NX MCD) does this with the machine's CAD
    instead: the turret with every tool of the tool list (the active one from the NC's T
    number), the chuck with its jaws at the clamping diameter, the workpiece, tailstock and
    doors as meshes; it checks every pair of bodies for contact or a minimum distance each
    step of its own solver and reports which bodies met.  It would also drive sensors the
    FMU's plant lacks (door switches, a light curtain at the loading opening) and be coupled
    to the master exactly as here: positions in, contacts out, once per communication step.
    """

    def __init__(self, chuck: Chuck | None = None, tool: ToolInTurret | None = None, margin_mm: float = 10.0):
        self.chuck = chuck or Chuck()
        self.tool = tool or ToolInTurret()
        self.margin_mm = margin_mm
        self.contact_closed = True
        self.clearance_mm = math.inf  # tool tip to chuck at the last look

    def look(self, read: Read) -> None:
        self.clearance_mm = self.chuck.distance_mm(*self.tool.tip(read))
        self.contact_closed = self.clearance_mm >= self.margin_mm


@dataclass(slots=True)
class Timeline:
    """What happened, in seconds since power-on, as seen at the communication points."""

    communication_points: int = 0
    end_s: float = 0.0  # the last communication point looked at
    referencing_started_s: dict[str, float] = field(default_factory=dict)  # an axis's first traverse command
    referenced_s: dict[str, float] = field(default_factory=dict)  # DB31.DBX60.4 (enc1Synchronized) rises
    reference_positions: dict[str, float] = field(default_factory=dict)  # the NC's, once the axis stands
    all_referenced_s: float | None = None  # DB21.DBX36.2
    zone_entered_s: float | None = None
    emergency_stop_s: float | None = None  # DB10.DBX106.1 (emergencyStopActive)
    stopped_s: float | None = None  # the approaching axis stands again
    clearance_at_rest_mm: float | None = None  # tool tip to chuck after the stop
    events: list[tuple[float, str]] = field(default_factory=list)

    def note(self, time_s: float, text: str) -> None:
        self.events.append((time_s, text))

    def lines(self) -> list[str]:
        return [f"{time_s:8.3f} s  {text}" for time_s, text in self.events]


class Surroundings:
    """The operator, the plant model and the observer: everything around the NC and the PLC.

    ``look_and_act`` at every communication point, after the PLC's scan; what they set goes
    to the PLC's plant image for its next scan (``plant_inputs``)."""

    def __init__(self, machine: MachineConfig, read_at_power_on: Read):
        channel = machine.channels[0].name
        panel = {point.name: int(read_at_power_on(point.name)) for point in machine.plant_io.points
                 if point.owner is PointOwner.OPERATOR}
        self.operator = Operator(panel, reference_then_approach_the_chuck(channel))
        self.chuck_protection = ChuckProtection()
        self.timeline = Timeline()
        self.channel = channel
        self.linear_axes = [axis.name for axis in machine.axes if not axis.is_rotary]

    @property
    def finished(self) -> bool:
        return self.timeline.stopped_s is not None

    def plant_inputs(self) -> dict[str, int]:
        """The operator's points as the PLC should read them, the protection contact in the chain."""
        inputs = dict(self.operator.panel)
        inputs[EMERGENCY_STOP_CHAIN] = int(inputs[EMERGENCY_STOP_CHAIN] and self.chuck_protection.contact_closed)
        return inputs

    def look_and_act(self, time_s: float, read: Read) -> None:
        timeline = self.timeline
        timeline.communication_points += 1
        timeline.end_s = time_s
        self._watch_referencing(time_s, read)
        protection = self.chuck_protection
        was_closed = protection.contact_closed
        protection.look(read)
        if was_closed and not protection.contact_closed and timeline.zone_entered_s is None:
            timeline.zone_entered_s = time_s
            timeline.note(time_s, f"tool tip enters the chuck's protection zone, {protection.clearance_mm:.2f} mm"
                                  " from the chuck: the model opens the emergency-stop chain")
        if timeline.emergency_stop_s is None and read(EMERGENCY_STOP_ACTIVE):
            timeline.emergency_stop_s = time_s
            timeline.note(time_s, "NC: emergency stop active (DB10.DBX106.1)")
        if timeline.emergency_stop_s is not None and read(f"{AXIAL_AXIS}.basic.in.isStationary"):
            timeline.stopped_s = time_s
            timeline.clearance_at_rest_mm = protection.clearance_mm
            timeline.note(time_s, f"{AXIAL_AXIS} stands, the tool tip {protection.clearance_mm:.2f} mm from the chuck")
        for what in self.operator.act(time_s, read):
            timeline.note(time_s, what)

    def _watch_referencing(self, time_s: float, read: Read) -> None:
        timeline = self.timeline
        for axis in self.linear_axes:
            # every axis is referenced before anything else moves it: its first traverse command is its referencing
            moving = any(read(f"{axis}.basic.in.travers{sense}CommandActive") for sense in ("Plus", "Minus"))
            if moving and axis not in timeline.referencing_started_s:
                timeline.referencing_started_s[axis] = time_s
                timeline.note(time_s, f"{axis} starts referencing")
            referenced = read(f"{axis}.basic.in.enc1Synchronized")
            if referenced and axis not in timeline.referenced_s:
                timeline.referenced_s[axis] = time_s
                timeline.note(time_s, f"{axis} referenced")
            # DB31.DBX60.4, and even "stationary" (DB31.DBX61.4), come while the position controller
            # still closes the last micrometres: the reference point is where the slide comes to rest
            if referenced and axis not in timeline.reference_positions and read(f"{axis}.velocity") == 0:
                position = float(read(f"{axis}.position"))
                timeline.reference_positions[axis] = position
                timeline.note(time_s, f"{axis} stands at its reference point, {position:.4f} mm")
        if timeline.all_referenced_s is None and read(f"{self.channel}.basic.in.allAxesReferenced"):
            timeline.all_referenced_s = time_s
            timeline.note(time_s, f"{self.channel}: all axes referenced")


# ================================================================================== the master


def run(fmu_path: str | Path, plc_parameters: Mapping[str, Any] | None = None,
        time_limit_s: float = TIME_LIMIT_S) -> Timeline:
    """Co-simulate the NC FMU, the PLC program ``referencing`` and the surroundings until the
    tool stands after the emergency stop (or ``time_limit_s``); ``plc_parameters`` go over the
    machine's ``plc:`` section."""
    nc = NcFmu(fmu_path)
    try:
        machine = with_plc_parameters(load_machine(str(nc.machine_file())), plc_parameters)
        plc = BuiltInPlc(machine, PLC_PROGRAM)
        step_s = communication_step_s(machine)
        outputs = nc.get_outputs()
        surroundings = Surroundings(machine, outputs.__getitem__)
        for step in range(round(time_limit_s / step_s) + 1):
            time_s = step * step_s
            plc.take_inputs(outputs, surroundings.plant_inputs())
            plc.scan()
            nc.set_inputs(plc.outputs())
            surroundings.look_and_act(time_s, outputs.__getitem__)
            if surroundings.finished:
                break
            nc.do_step(time_s, step_s)
            outputs = nc.get_outputs()
        return surroundings.timeline
    finally:
        nc.close()


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--fmu", help="the FMU of turn_mill (default: export it into a temporary directory)")
    arguments = parser.parse_args(argv)
    with tempfile.TemporaryDirectory(prefix="vc_cosim_") as scratch:
        fmu_path = arguments.fmu or export_fmu(str(TURN_MILL), str(Path(scratch) / "turn_mill.fmu")).path
        started = wallclock.perf_counter()
        timeline = run(fmu_path)
        wall_s = wallclock.perf_counter() - started
    print("\n".join(timeline.lines()))
    print(f"\n{timeline.communication_points} communication points, {timeline.end_s:.2f} s simulated"
          f" in {wall_s:.2f} s of wall-clock time")
    if timeline.stopped_s is None:
        print(f"the sequence did not finish within {TIME_LIMIT_S:g} s")
        return 1
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
