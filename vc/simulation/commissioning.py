"""The commissioning facts of a machine (:mod:`interfaces.commissioning`) from its machine file.

What a PLC engineer would otherwise find by probing: the referencing of each axis (measuring
system, direction MD34010, reference point MD34100, the cam, MD34110 and the inclined-axis rule
of seed 000), the positions of cams and limit switches as the plant has them wired, and what the
plant needs from the PLC (the copies of cams and limit switches, the drive line-up, the gearbox
with its oscillation, the chucks, the emergency stop with its acknowledgement).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence

from interfaces.commissioning import AxisFacts, Commissioning, PlantNeed
from interfaces.plant_io import PlantIoMap, station_code_bits
from interfaces.signals import ExpandedCatalog
from vc.config import md_dictionary as MD
from vc.config.model import AxisConfig, ChannelConfig, MachineConfig
from vc.core.axis.encoder import ENC_TYPE_ABSOLUTE
from vc.core.kinematics.inclined_axis import InclinedAxisParameters, parameters_for_channel
from vc.core.transforms.inclined_axis_control import NOZAGC_SIGNAL
from vc.plant.plant import DRIVE_READY_DELAY_S

DISTANCE_CODED = {3: "distance-coded scale, 2 marks", 8: "distance-coded scale, 4 marks"}


def commissioning_of(machine: MachineConfig, catalog: ExpandedCatalog) -> Commissioning:
    inclined = _inclined_pairs(machine.channels)
    axes = tuple(_axis_facts(axis, inclined) for axis in machine.axes)
    order = {channel.name: _reference_order(machine, channel) for channel in machine.channels}
    return Commissioning(axes, order, tuple(_needs(machine, catalog)), _devices(machine))


def _devices(machine: MachineConfig) -> dict[str, dict[str, float]]:
    """The devices besides the axes, with what a PLC program must know of them."""
    plant = machine.plant
    devices: dict[str, dict[str, float]] = {}
    if plant.turret is not None:
        devices["turret"] = {"stations": plant.turret.stations, "index_time": plant.turret.index_time_s,
                             "lock_time": plant.turret.lock_time_s}
    if plant.tool_changer is not None:
        devices["tool_changer"] = {"pockets": plant.tool_changer.pockets,
                                   "index_time": plant.tool_changer.index_time_s,
                                   "arm_time": plant.tool_changer.arm_time_s}
    if plant.coolant is not None:
        devices["coolant"] = {"pressure_time": plant.coolant.pressure_time_s}
    if plant.tailstock is not None:
        # the quill's axis by its interface data block DB(30 + n), as the PLC addresses it
        quill = next(axis for axis in machine.axes if axis.name == plant.tailstock.axis)
        devices["tailstock"] = {"axis_db": quill.db}
    if plant.axis_magazine is not None:
        magazine = next(axis for axis in machine.axes if axis.name == plant.axis_magazine.axis)
        devices["axis_magazine"] = {"axis_db": magazine.db, "pockets": plant.axis_magazine.pockets}
    if plant.clamp is not None:
        clamped = next(axis for axis in machine.axes if axis.name == plant.clamp.axis)
        devices["clamp"] = {"axis_db": clamped.db, "travel_time": plant.clamp.travel_time_s}
    if plant.holding_brake is not None:
        braked = next(axis for axis in machine.axes if axis.name == plant.holding_brake.axis)
        devices["holding_brake"] = {"axis_db": braked.db, "switch_time": plant.holding_brake.switch_time_s}
    return devices


def _inclined_pairs(channels: Sequence[ChannelConfig]) -> dict[str, str]:
    """Orthogonal axis -> the inclined axis that must be referenced before it."""
    pairs = {}
    for channel in channels:
        parameters = parameters_for_channel(channel)
        if isinstance(parameters, InclinedAxisParameters):
            pairs[channel.axes[parameters.orthogonal_axis - 1]] = channel.axes[parameters.inclined_axis - 1]
    return pairs


def _axis_facts(axis: AxisConfig, inclined: dict[str, str]) -> AxisFacts:
    md = axis.md
    name = axis.name
    spindle = axis.is_spindle
    kind = "spindle" if spindle else "rotary axis" if axis.is_rotary else "linear axis"
    unit = "deg" if axis.is_rotary else "mm"
    cam = md.bool(MD.REFP_CAM_IS_ACTIVE)
    absolute = md.int(MD.ENC_TYPE, 0) == ENC_TYPE_ABSOLUTE
    mode = md.int(MD.ENC_REFP_MODE, 0)
    if absolute:
        referencing = (f"absolute encoder, MD34210 = {md.int(MD.ENC_REFP_STATE, 0)} (2: calibrated, referenced at"
                       " power-on; 0: to be calibrated)")
    elif mode in DISTANCE_CODED:
        referencing = f"{DISTANCE_CODED[mode]}, referenced after crossing them"
    elif spindle:
        referencing = "synchronises on the first zero mark it passes while it turns (no REF needed)"
    else:
        referencing = "incremental encoder: reference cam, then its zero mark" if cam else \
            "incremental encoder: the next zero mark, no cam"
    directed = not spindle and not absolute
    before = (inclined[name],) if name in inclined else ()
    prerequisite = ""
    if before:
        prerequisite = (f"reference {before[0]} (inclined axis) first: {name} starts only while {before[0]} stands at"
                        " its reference point, else alarm 65820 (seed 000 L62-66, L375)")
    elif name in inclined.values():
        orthogonal = next(key for key, value in inclined.items() if value == name)
        prerequisite = f"the inclined axis: reference it before {orthogonal}"
    plant = axis.plant
    return AxisFacts(
        axis=name, db=axis.db, kind=kind, unit=unit, referencing=referencing,
        approach=("minus" if md.bool(MD.REFP_CAM_DIR_IS_MINUS) else "plus") if directed else "",
        reference_cycle=md.int(MD.REFP_CYCLE_NR),
        reference_position=None if spindle or absolute else md.float(MD.REFP_SET_POS, 0),
        cam=plant.ref_cam, hw_limit_minus=plant.hw_limit_minus, hw_limit_plus=plant.hw_limit_plus,
        sw_limits=None if spindle else (md.float(MD.POS_LIMIT_MINUS), md.float(MD.POS_LIMIT_PLUS)),
        before=before, prerequisite=prerequisite,
        gear_stages=plant.gearbox.stages if plant.gearbox is not None else 0,
    )


def _reference_order(machine: MachineConfig, channel: ChannelConfig) -> tuple[tuple[str, ...], ...]:
    steps: dict[int, list[str]] = {}
    for name in channel.axes:
        cycle = machine.axis(name).md.int(MD.REFP_CYCLE_NR)
        if cycle > 0:
            steps.setdefault(cycle, []).append(name)
    return tuple(tuple(steps[cycle]) for cycle in sorted(steps))


def _needs(machine: MachineConfig, catalog: ExpandedCatalog) -> list[PlantNeed]:
    io = machine.plant_io

    def point(name: str) -> str | None:
        found = io.by_name(name)
        return None if found is None else f"{name} ({found.address})"

    def at(symbol: str) -> str:
        return str(catalog.resolve(symbol).address)

    needs = _safety_and_drives(io, catalog, machine)
    for axis in machine.axes:
        name = axis.name
        cam = point(f"{name}.refCam")
        if cam is not None and axis.plant.ref_cam is not None:
            target = at(f"{name}.basic.out.refPointApproachCam")
            needs.append(PlantNeed(f"{name}.refCam", "copy", (cam,), (target,),
                                   f"copy {cam} to {name}.basic.out.refPointApproachCam ({target}) every scan: the NC"
                                   " references on the PLC's copy, one scan late"))
        for side, switch in (("Minus", axis.plant.hw_limit_minus), ("Plus", axis.plant.hw_limit_plus)):
            wired = point(f"{name}.hwLimit{side}")
            if wired is None or switch is None:
                continue
            target = at(f"{name}.basic.out.hwLimitSwitch{side}")
            needs.append(PlantNeed(f"{name}.hwLimit{side}", "copy_inverse", (wired,), (target,),
                                   f"normally closed, 0 = actuated ({'<=' if side == 'Minus' else '>='} {switch:g}):"
                                   f" copy its inverse to {name}.basic.out.hwLimitSwitch{side} ({target}); the NC"
                                   " stops the axis with alarm 21614"))
        if axis.plant.gearbox is not None:
            needs.append(_gearbox(axis, io))
        if axis.plant.chuck is not None:
            valves = [text for text in (point(f"{name}.chuckClose"), point(f"{name}.chuckRelease")) if text]
            sensors = [text for text in (point(f"{name}.chuckClosed"), point(f"{name}.chuckOpen")) if text]
            needs.append(PlantNeed(f"{name}.chuck", "chuck", (*valves, *sensors), (),
                                   f"{' / '.join(valves)}: one solenoid at a time strokes the chuck in"
                                   f" {axis.plant.chuck.travel_time_s:g} s while the drive line-up (its hydraulics)"
                                   f" is on; {' / '.join(sensors)} report the end positions"))
    needs.extend(_auxiliary_functions(machine, catalog))
    needs.extend(_device_needs(machine, point))
    nozagc = point("MCP.noOrthogonalCompensation")
    for channel in machine.channels:
        if nozagc is not None and isinstance(parameters_for_channel(channel), InclinedAxisParameters):
            target = at(f"{channel.name}.{NOZAGC_SIGNAL}")
            needs.append(PlantNeed(f"{channel.name}.nozagc", "copy", (nozagc,), (target,),
                                   f"copy {nozagc} to {channel.name}.{NOZAGC_SIGNAL} ({target}): the inclined axis"
                                   " moves without carrying the orthogonal one (G63.5 NOZAGC)"))
    return needs


def _safety_and_drives(io: PlantIoMap, catalog: ExpandedCatalog, machine: MachineConfig) -> list[PlantNeed]:
    needs = []
    chain = io.by_name("EStop.chainOk")
    stop, ack = catalog.resolve("NC.basic.out.emergencyStop").address, catalog.resolve(
        "NC.basic.out.emergencyStopAck").address
    resets = [str(catalog.resolve(f"{channel.name}.basic.out.reset").address) for channel in machine.channels]
    mode_group_reset = catalog.resolve("MODEGROUP.basic.out.reset").address
    chain_text = f"EStop.chainOk ({chain.address}, 1 = healthy): copy its inverse to " if chain else ""
    needs.append(PlantNeed("EStop", "emergency_stop", (f"EStop.chainOk ({chain.address})",) if chain else (),
                           (str(stop), str(ack), *resets, str(mode_group_reset)),
                           f"{chain_text}NC.basic.out.emergencyStop ({stop}): alarm 3000, rapid stop. To leave it"
                           f" the button must be released (56.1 = 0), the acknowledgement {ack} held at 1, and a"
                           f" reset rise while it is 1: the channel's {' / '.join(resets)} or the mode group's"
                           f" {mode_group_reset}. {ack} alone leaves alarm 3000 standing"))
    on, ready = io.by_name("Drives.on"), io.by_name("Drives.ready")
    if ready is not None:
        precharge = f" and the DC link's precharge ({machine.dc_link.precharge_time:g} s)" if machine.dc_link else ""
        switch = f"Drives.on ({on.address}) switches the infeed on; " if on is not None else ""
        wired = tuple(f"{p.name} ({p.address})" for p in (on, ready) if p is not None)
        needs.append(PlantNeed("Drives", "drives", wired, ("DB3x.DBX21.7", "DB3x.DBX2.1", "DB3x.DBX92.7"),
                               f"{switch}Drives.ready ({ready.address}) follows after {DRIVE_READY_DELAY_S:g} s"
                               f"{precharge}. Then give each axis pulse enable DBX21.7 and controller enable DBX2.1"
                               " (with measuring system 1, DBX1.5): the drive answers DBX92.7 drive ready"))
    return needs


def _gearbox(axis: AxisConfig, io: PlantIoMap) -> PlantNeed:
    name = axis.name
    gearbox = axis.plant.gearbox
    assert gearbox is not None
    shifts = [f"{name}.gearShift{n} ({p.address})" for n in range(1, gearbox.stages + 1)
              if (p := io.by_name(f"{name}.gearShift{n}")) is not None]
    sensors = [f"{name}.gearEngaged{n} ({p.address})" for n in range(1, gearbox.stages + 1)
               if (p := io.by_name(f"{name}.gearEngaged{n}")) is not None]
    db = f"DB{axis.db}"
    return PlantNeed(
        f"{name}.gearbox", "gearbox", (*shifts, *sensors), (f"{db}.DBX82.0-82.3", f"{db}.DBX18.4-18.7", f"{db}.DBX84.6",
                                                  f"{db}.DBX16.0-16.3"),
        f"{gearbox.stages} gear stages. The NC asks with {db}.DBX82.3 and the stage in 82.0-82.2, brakes and shows"
        f" oscillation mode 84.6. Hold the stage's actuator ({', '.join(shifts)}) on; its teeth mesh only while the"
        f" motor turns for {gearbox.shift_time_s:g} s, so set oscillation enable {db}.DBX18.5 meanwhile (the NC"
        f" oscillates; with 18.4 the PLC oscillates by 18.6 / 18.7). When {' / '.join(sensors)} reports the stage,"
        f" write it to {db}.DBX16.0-16.2 and set 16.3 (gear changed) until 82.3 falls")


def _auxiliary_functions(machine: MachineConfig, catalog: ExpandedCatalog) -> list[PlantNeed]:
    """The handshake of the auxiliary function output, per channel (vc/core/auxiliary/output.py)."""
    needs = []
    for channel in machine.channels:
        name = channel.name

        def at(symbol: str, channel: str = name) -> str:
            return str(catalog.resolve(f"{channel}.{symbol}").address)

        read_in = at("basic.out.disableReadIn")
        needs.append(PlantNeed(
            f"{name}.auxiliaryFunctions", "auxiliary_functions", (),
            (at("auxMFuncs[1].in.change"), at("auxMFuncs[1].in.value"), at("auxTFuncs[1].in.value"),
             at("auxMDynFuncs.in.m00Decoded"), read_in),
            f"The NC outputs a block's M, S, T, D, DL, H (and F with MD22240) functions into {name}'s slots: a change"
            f" signal per slot (M 1..5 {at('auxMFuncs[1].in.change')} ff., S DBX60.0-2, T DBX61.0, D DBX62.0, DL"
            f" DBX62.1, H DBX64.0-2, F DBX65.0), the extended address (INT) and the value (DINT or REAL) behind it,"
            f" M00..M99 without extended address also decoded from {at('auxMDynFuncs.in.m00Decoded')}. The change"
            " signals stand for exactly one PLC scan; read them in every scan. The NC takes a function as"
            " acknowledged one scan after the scan that saw it, and a normal function holds its block until then (a"
            f" quick one, QU, never). To hold the program longer (a tool change) set the read-in disable {read_in} in"
            " the scan that sees the function, and release it when done: the next block waits (program state"
            " waiting)"))
    return needs


def _device_needs(machine: MachineConfig, point: Callable[[str], str | None]) -> list[PlantNeed]:
    plant = machine.plant
    needs = []

    def wired(*names: str) -> tuple[str, ...]:
        return tuple(text for name in names if (text := point(name)) is not None)

    if plant.turret is not None:
        turret = plant.turret
        codes = [f"Turret.code{bit}" for bit in station_code_bits(turret.stations)]
        needs.append(PlantNeed(
            "Turret", "turret", wired("Turret.unlock", "Turret.unlocked", "Turret.indexCw", "Turret.indexCcw",
                                      *codes, "Turret.locked"), (),
            f"{turret.stations} stations. Pull the lock pin with Turret.unlock until Turret.unlocked"
            f" ({turret.lock_time_s:g} s); only then may Turret.indexCw (towards higher stations) or Turret.indexCcw"
            f" turn the disk, {turret.index_time_s:g} s per station; {' / '.join(codes)} show the station in binary"
            " while the disk stands at one, 0 between two. Drop the drive at the station, then Turret.unlock: the"
            " spring engages the pin (only at a station) and Turret.locked reports it"))
    if plant.tool_changer is not None:
        changer = plant.tool_changer
        codes = [f"Magazine.code{bit}" for bit in station_code_bits(changer.pockets)]
        needs.append(PlantNeed(
            "ToolChanger", "tool_changer", wired("Magazine.rotateCw", "Magazine.rotateCcw", *codes,
                                                 "ToolArm.toSpindle", "ToolArm.home", "ToolArm.atSpindle"), (),
            f"{changer.pockets} pockets, tool n in pocket n at power-on. Magazine.rotateCw / rotateCcw turn the"
            f" magazine ({changer.index_time_s:g} s per pocket, only while ToolArm.home); {' / '.join(codes)} show the"
            f" pocket at the change position. ToolArm.toSpindle swings the arm to the spindle in"
            f" {changer.arm_time_s:g} s (ToolArm.atSpindle): it swaps the spindle's tool with the pocket's; dropping it"
            " brings the arm home (ToolArm.home)"))
    if plant.coolant is not None:
        needs.append(PlantNeed(
            "Coolant", "coolant", wired("Coolant.pump", "Coolant.pressureOk"), (),
            f"Coolant.pump runs the pump; Coolant.pressureOk closes {plant.coolant.pressure_time_s:g} s later and"
            " opens at once when the pump stops (or the pressure is lost)"))
    if plant.tailstock is not None:
        tailstock = plant.tailstock
        quill = tailstock.axis
        needs.append(PlantNeed(
            "Tailstock", "tailstock", wired("Tailstock.retracted", "Tailstock.atPart"), (),
            f"The quill {quill} travels to the part's face at {tailstock.stop:g} (travel to fixed stop, FXS):"
            f" give {quill}.basic.out.fixedStopEnable while {quill}.basic.in.fixedStopRequest is 1,"
            f" {quill}.basic.out.fixedStopAckReached once {quill}.basic.in.fixedStopReached comes, take both away"
            f" when the request falls; Tailstock.atPart (the sleeve at the part) may go to"
            f" {quill}.basic.out.fixedStopSensor; Tailstock.retracted reads 1 at or behind {tailstock.retracted:g}"))
    if plant.axis_magazine is not None:
        magazine = plant.axis_magazine
        needs.append(PlantNeed(
            "AxisMagazine", "axis_magazine", wired(*(f"AxisMagazine.{name}" for name in
                                                   ("unlock", "locked", "unlocked", "inPocket", "driveReady"))), (),
            f"The magazine's {magazine.pockets} pockets turn with the modulo axis {magazine.axis}: pocket p at"
            f" (p - 1) x {360.0 / magazine.pockets:g} degrees; move it with FC18 (shortest path) while"
            f" AxisMagazine.unlocked (AxisMagazine.unlock pulls the pin in {magazine.lock_time_s:g} s); dropping"
            f" the solenoid engages the pin within {magazine.window:g} degrees of a pocket (AxisMagazine.locked,"
            " AxisMagazine.inPocket); AxisMagazine.driveReady is the drive's ready contact"))
    if plant.clamp is not None:
        clamp = plant.clamp
        needs.append(PlantNeed(
            "Clamp", "clamp", wired("Clamp.close", "Clamp.closed", "Clamp.opened"), (),
            f"The clamp of {clamp.axis}: Clamp.close closes it in {clamp.travel_time_s:g} s (Clamp.closed), dropping it"
            f" opens it (Clamp.opened); closed, it holds {clamp.axis}. Set {clamp.axis}.basic.out.clampingInProgress"
            f" while it clamps (the NC's clamping monitor, MD36050, alarm 26000) and open it before"
            f" {clamp.axis} moves"))
    if plant.holding_brake is not None:
        brake = plant.holding_brake
        axis = brake.axis
        needs.append(PlantNeed(
            "Brake", "holding_brake", (), (),
            f"The holding brake of {axis}'s motor holds its slide until {axis}.drive.out.releaseHoldingBrake"
            f" releases it; {axis}.drive.in.holdingBrakeReleased reports it {brake.switch_time_s:g} s later."
            f" Release it only once {axis}.drive.in.enabled (the drive holds the axis), keep {axis} from moving"
            f" until it is released, engage it before taking {axis}.basic.out.enableCtrl and"
            f" {axis}.drive.out.enablePulses away and wait until the feedback has fallen"
            + (f": released without torque the slide sags at {abs(brake.sag):g} per minute" if brake.sag else "")))
    return needs
