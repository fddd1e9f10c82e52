"""The machine file's devices besides the axes (``plant:``) and its PLC alarm texts (``plc_alarms:``).

::

    plant:
      turret: {stations: 8, index_time: 0.15, lock_time: 0.08, station: 1}
      coolant: {pressure_time: 0.3}
      tool_changer: {pockets: 12, index_time: 0.2, arm_time: 0.6, pocket: 1}
      clamp: {axis: 5, travel_time: 0.2, load: 600.0}
      holding_brake: {axis: 3, switch_time: 0.05, sag: -600.0}
    plc_alarms:
      700000: "Turret: lock pin not pulled"

``turret``: a tool turret the PLC indexes (vc/plant/turret.py): its stations (2..31), the seconds
from one station to the next and the lock pin's stroke time, the station it stands at when the
machine is switched on (default 1).  It needs its I/O: ``Turret.indexCw``, ``Turret.indexCcw``,
``Turret.unlock``, ``Turret.locked``, ``Turret.unlocked`` and the station code ``Turret.code1``,
``code2`` .. up to the highest bit the stations need.  ``coolant``: the pump with its pressure
switch (vc/plant/coolant.py), ``Coolant.pump`` and ``Coolant.pressureOk``, the seconds the pressure
takes to build up.  ``tool_changer``: a mill's tool magazine and changer arm
(vc/plant/tool_changer.py): pockets, seconds per pocket, the arm's stroke time, the pocket at
power-on; I/O ``Magazine.rotateCw``, ``Magazine.rotateCcw``, ``Magazine.code1`` .., ``ToolArm.toSpindle``,
``ToolArm.home``, ``ToolArm.atSpindle``.  ``clamp``: the clamp of an axis, a rotary table's
(vc/plant/clamp.py): the machine axis number it clamps, the stroke time, the speed (mm/min or deg/min)
the machining load pushes the axis with when the clamp gives way; I/O ``Clamp.close``,
``Clamp.closed``, ``Clamp.opened``.  ``holding_brake``: the holding brake of an axis's motor
(vc/plant/holding_brake.py): the machine axis number, the seconds it takes to release and to engage,
the speed (mm/min or deg/min, signed) the weight moves the slide with while the brake is open and the
drive gives no torque (a vertical axis's sag; 0 for a horizontal one).  It has no plant I/O: the
drive releases it on DB31.DBX20.5 and reports its feedback in DB31.DBX92.5.  I/O of a device the
machine lacks is a mistake (the sensors would read 0 for ever).

``plc_alarms``: the texts of the PLC user alarms 700000 .. 700063 (DB2 user area 0) the machine's
PLC program raises, as the machine builder's alarm text file gives them (vc/core/nck/plc_alarms.py).

The loader calls :func:`read_plant` and :func:`read_plc_alarms` with the section and the I/O list
once both are read; every problem is reported with ``file:line:column``.
"""

from __future__ import annotations

from collections.abc import Callable, Collection, Mapping
from typing import Any

from interfaces.plant_io import (
    AXIS_MAGAZINE,
    CLAMP,
    COOLANT,
    HOLDING_BRAKE,
    MAGAZINE,
    TAILSTOCK,
    TOOL_ARM,
    TURRET,
    station_code_bits,
)
from vc.config.machine_data import as_number, shown
from vc.config.model import (
    PLC_USER_ALARMS,
    AxisMagazinePlant,
    ClampPlant,
    CoolantPlant,
    HoldingBrakePlant,
    MachinePlant,
    TailstockPlant,
    ToolChangerPlant,
    TurretPlant,
)
from vc.located_yaml import LocatedMap, Mark, Problems

# the loader's reader of a block of numbers: (raw, mark, where, key -> (lowest, highest, whole, meaning))
ReadParameters = Callable[[Any, Mark, str, Mapping[str, tuple[float, float, bool, str]]], dict[str, Any]]

DEVICES = ("turret", "coolant", "tool_changer", "tailstock", "axis_magazine", "clamp", "holding_brake")
_AXIS_DEVICES = ("tailstock", "axis_magazine", "clamp", "holding_brake")  # their axis: is a machine axis number
MAX_STATIONS = 31  # a five-bit station code
# per device: key -> (lowest, highest, whole number, meaning); the keys without a default are needed
_KEYS: dict[str, dict[str, tuple[float, float, bool, str]]] = {
    "turret": {"stations": (2, MAX_STATIONS, True, "tool stations on the disk"),
               "index_time": (0.001, 60, False, "s from one station to the next"),
               "lock_time": (0.001, 60, False, "s of the lock pin's stroke"),
               "station": (1, MAX_STATIONS, True, "the station at power-on")},
    "coolant": {"pressure_time": (0.001, 60, False, "s from the pump on to the pressure switch closing")},
    "tool_changer": {"pockets": (2, MAX_STATIONS, True, "pockets of the magazine"),
                     "index_time": (0.001, 60, False, "s from one pocket to the next"),
                     "arm_time": (0.001, 60, False, "s of the arm's stroke from home to the spindle"),
                     "pocket": (1, MAX_STATIONS, True, "the pocket at power-on")},
    "tailstock": {"axis": (1, 31, True, "machine axis number of the quill (its place in axes:)"),
                  "stop": (-1.0e6, 1.0e6, False, "position of the part's face on the quill's axis, mm"),
                  "stiffness": (1.0, 1.0e9, False, "N/mm of the part and the centre"),
                  "max_force": (1.0, 1.0e7, False, "N the drive pushes with at 100 % torque"),
                  "force_limit": (1.0, 1.0e8, False, "N the part takes before it slips away"),
                  "retracted": (-1.0e6, 1.0e6, False, "position at or behind which the quill is retracted")},
    "axis_magazine": {"axis": (1, 31, True, "machine axis number of the magazine's modulo axis (its place in axes:)"),
                      "pockets": (2, 360, True, "pockets of the magazine, evenly over the turn"),
                      "lock_time": (0.001, 60, False, "s of the lock pin's stroke"),
                      "window": (0.001, 10, False, "degrees either side of a pocket the pin engages in")},
    "clamp": {"axis": (1, 31, True, "machine axis number of the clamped axis (its place in axes:)"),
              "travel_time": (0.001, 60, False, "s of the clamp's stroke from open to closed"),
              "load": (0.0, 1.0e6, False, "mm/min (deg/min) the load pushes the axis with when the clamp gives way")},
    "holding_brake": {"axis": (1, 31, True, "machine axis number of the braked axis (its place in axes:)"),
                      "switch_time": (0.001, 10, False, "s the brake takes to release and to engage"),
                      "sag": (-1.0e6, 1.0e6, False, "mm/min (deg/min), signed, the weight moves the slide with"
                                                    " while the brake is open without torque")},
}
_OPTIONAL = ("station", "pocket")


def _io_of(device: str, values: Mapping[str, Any]) -> list[str]:
    """The plant I/O a device needs wired."""
    if device == "turret":
        codes = station_code_bits(int(values.get("stations", 1)))
        return [f"{TURRET}.indexCw", f"{TURRET}.indexCcw", f"{TURRET}.unlock", f"{TURRET}.locked",
                f"{TURRET}.unlocked", *(f"{TURRET}.code{bit}" for bit in codes)]
    if device == "coolant":
        return [f"{COOLANT}.pump", f"{COOLANT}.pressureOk"]
    if device == "tailstock":
        return [f"{TAILSTOCK}.retracted", f"{TAILSTOCK}.atPart"]
    if device == "axis_magazine":
        return [f"{AXIS_MAGAZINE}.{name}" for name in ("unlock", "locked", "unlocked", "inPocket", "driveReady")]
    if device == "clamp":
        return [f"{CLAMP}.close", f"{CLAMP}.closed", f"{CLAMP}.opened"]
    if device == "holding_brake":
        return []  # the drive switches it and reports its feedback (DB31.DBX20.5 / 92.5)
    codes = station_code_bits(int(values.get("pockets", 1)))
    return [f"{MAGAZINE}.rotateCw", f"{MAGAZINE}.rotateCcw", *(f"{MAGAZINE}.code{bit}" for bit in codes),
            f"{TOOL_ARM}.toSpindle", f"{TOOL_ARM}.home", f"{TOOL_ARM}.atSpindle"]


_PREFIXES = {"turret": (TURRET,), "coolant": (COOLANT,), "tool_changer": (MAGAZINE, TOOL_ARM),
             "tailstock": (TAILSTOCK,), "axis_magazine": (AXIS_MAGAZINE,), "clamp": (CLAMP,),
             "holding_brake": (HOLDING_BRAKE,)}


def read_plant(raw: Any, mark: Mark, problems: Problems, wired: Mapping[str, tuple[str, Mark]],
               read_parameters: ReadParameters, axes: Collection[str] = ()) -> MachinePlant:
    """The ``plant:`` section checked against the I/O list ``wired`` (function -> address, mark);
    ``raw`` None: the machine has none of the devices (their I/O is then a mistake too).  A device's
    numbers are read by the loader's ``read_parameters`` (each key in its range, as ``dc_link:``)."""
    block: Mapping[str, Any] = {}
    if raw is not None and not isinstance(raw, dict):
        problems.add(mark, f"plant: expected a mapping of devices ({', '.join(DEVICES)}), got {shown(raw)}")
    elif raw is not None:
        block = raw
    built: dict[str, Any] = {}
    for device, value in block.items():
        key_mark, value_mark = _marks(block, device, mark)
        if device not in DEVICES:
            problems.add(key_mark, f"unknown device '{device}' in plant; the machine's devices are"
                                   f" {', '.join(DEVICES)} (an axis's plant: is under its axis)")
            continue
        values = _parameters(device, value, value_mark, problems, read_parameters)
        if values is None or not _device_axis(device, values, value, value_mark, problems, list(axes)):
            continue
        unwired = [name for name in _io_of(device, values) if name not in wired]
        if unwired:
            problems.add(key_mark, f"plant.{device}: its I/O is not wired in plant_io: {', '.join(unwired)}")
        built[device] = values
    _check_device_io(built, wired, problems)
    turret, coolant, changer = built.get("turret"), built.get("coolant"), built.get("tool_changer")
    tailstock, magazine, clamp = built.get("tailstock"), built.get("axis_magazine"), built.get("clamp")
    if tailstock and clamp and tailstock["axis"] == clamp["axis"]:
        problems.add(_marks(block["clamp"], "axis", mark)[1],
                     f"plant.clamp.axis: {clamp['axis']} is the tailstock's quill; the clamp holds another axis")
        clamp = None
    brake = built.get("holding_brake")
    held = {device["axis"]: name for name, device in (("tailstock", tailstock), ("clamp", clamp)) if device}
    if brake and brake["axis"] in held:
        problems.add(_marks(block["holding_brake"], "axis", mark)[1],
                     f"plant.holding_brake.axis: {brake['axis']} is the {held[brake['axis']]}'s axis; the brake holds"
                     " another axis")
        brake = None
    return MachinePlant(
        turret=TurretPlant(turret["stations"], turret["index_time"], turret["lock_time"],
                           turret.get("station", 1)) if turret else None,
        coolant=CoolantPlant(coolant["pressure_time"]) if coolant else None,
        tool_changer=ToolChangerPlant(changer["pockets"], changer["index_time"], changer["arm_time"],
                                      changer.get("pocket", 1)) if changer else None,
        tailstock=TailstockPlant(tailstock["axis"], tailstock["stop"], tailstock["stiffness"], tailstock["max_force"],
                                 tailstock["force_limit"], tailstock["retracted"]) if tailstock else None,
        axis_magazine=AxisMagazinePlant(magazine["axis"], magazine["pockets"], magazine["lock_time"],
                                        magazine["window"]) if magazine else None,
        clamp=ClampPlant(clamp["axis"], clamp["travel_time"], clamp["load"]) if clamp else None,
        holding_brake=HoldingBrakePlant(brake["axis"], brake["switch_time"], brake["sag"]) if brake else None)


def _device_axis(device: str, values: dict[str, Any], raw: Any, mark: Mark, problems: Problems,
                 axes: list[str]) -> bool:
    """The ``axis:`` of the tailstock, the axis magazine or the clamp (a machine axis number) as the
    axis's name; False when there is none."""
    if device not in _AXIS_DEVICES:
        return True
    number = values["axis"]
    if number > len(axes):
        problems.add(_marks(raw, "axis", mark)[1], f"plant.{device}.axis = {number}: the machine has {len(axes)} axes")
        return False
    values["axis"] = axes[number - 1]
    return True


def _parameters(device: str, raw: Any, mark: Mark, problems: Problems,
                read_parameters: ReadParameters) -> dict[str, Any] | None:
    """The device's keys, each checked; None when one that is needed is missing or wrong."""
    table = _KEYS[device]
    if not isinstance(raw, dict):
        problems.add(mark, f"plant.{device}: expected a mapping with {', '.join(table)}, got {shown(raw)}")
        return None
    values = read_parameters(raw, mark, f"plant.{device}", table)
    sound = all(key in values for key in raw)  # the reader reported every key it refused
    missing = [key for key in table if key not in _OPTIONAL and key not in raw]
    if missing:
        problems.add(mark, f"plant.{device} lacks {', '.join(missing)}")
        return None
    for count, position in (("stations", "station"), ("pockets", "pocket")):
        if position in values and count in values and values[position] > values[count]:
            problems.add(_marks(raw, position, mark)[1], f"plant.{device}.{position} = {values[position]}: the"
                                                         f" {device} has {values[count]} {count}")
            sound = False
    return values if sound else None


def _check_device_io(built: Mapping[str, Any], wired: Mapping[str, tuple[str, Mark]], problems: Problems) -> None:
    """Device I/O needs its device: a sensor no device drives reads 0 for ever."""
    for name, (key, mark) in wired.items():
        prefix = name.split(".", 1)[0]
        device = next((device for device, prefixes in _PREFIXES.items() if prefix in prefixes), None)
        if device is not None and device not in built:
            problems.add(mark, f"plant_io {key}: {name} needs the machine's {device} (plant: {{{device}: ...}})")
        elif device is not None and name not in _io_of(device, built[device]):
            problems.add(mark, f"plant_io {key}: {name} is no signal of the {device} as plant.{device} describes it")


def read_plc_alarms(raw: Any, mark: Mark, problems: Problems) -> dict[int, str]:
    """``plc_alarms:``: alarm number (700000 .. 700063) -> its text."""
    if raw is None:
        return {}
    if not isinstance(raw, dict):
        problems.add(mark, f"plc_alarms: expected a mapping of alarm numbers to texts, got {shown(raw)}")
        return {}
    texts: dict[int, str] = {}
    for key, value in raw.items():
        key_mark, value_mark = _marks(raw, key, mark)
        number = as_number(key)
        if number is None or not float(number).is_integer() or int(number) not in PLC_USER_ALARMS:
            problems.add(key_mark, f"plc_alarms: {key} is no PLC user alarm; the PLC's alarms are"
                                   f" {PLC_USER_ALARMS.start} .. {PLC_USER_ALARMS.stop - 1} (DB2 user area 0)")
            continue
        if not isinstance(value, str) or not value.strip():
            problems.add(value_mark, f"plc_alarms: {key}: expected the alarm's text, got {shown(value)}")
            continue
        texts[int(number)] = value.strip()
    return texts


def _marks(block: Mapping[Any, Any], key: Any, fallback: Mark) -> tuple[Mark, Mark]:
    if isinstance(block, LocatedMap):
        return block.key_marks.get(key, block.mark), block.value_marks.get(key, block.mark)
    return fallback, fallback
