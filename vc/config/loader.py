"""Machine files: YAML -> a checked, frozen :class:`~vc.config.model.MachineConfig`.

A machine file describes one machine as its builder knows it: the control's machine data
with the manual's numbers and names, the channel and axis structure, where the switches
sit on the slides of the simulated machine, and the I/O list wired to the PLC::

    machine: turn_mill
    description: Turn-mill centre with counter spindle
    plc_cycle_ipo: 5               # OB1 period in IPO cycles (default 5)
    nck:                           # general machine data ($MN_)
      MD10050 SYSCLOCK_CYCLE_TIME: 0.002
    channels:                      # channel k -> interface DB(20 + k), in file order
      CHAN1:
        axes: [X1, Z1, Y1, SP1]    # machine axes of the channel, in channel axis order (MD20070)
        MD20080 AXCONF_CHANAX_NAME_TAB: [X, Z, Y, SP1]
        MD20050 AXCONF_GEOAX_ASSIGN_TAB: [1, 3, 2]
    axes:                          # machine axis n -> interface DB(30 + n), in file order (MD10000)
      X1:
        MD32000 MAX_AX_VELO: 30000
        MD34100 REFP_SET_POS: [0.0, 10.0]   # an array: items from index 0 ...
        MD34100[3]: 5.0                     # ... or one index
        sim: {start_position: 150.0, zero_mark_offset: 2.5}
        plant: {ref_cam: [280.0, 295.0], hw_limits: [-12.0, 312.0]}
      SP1:
        MD35090 NUM_GEAR_STEPS: 3
        plant: {gearbox: {stages: 3, shift_time: 0.4, engaged: 1}, chuck: {travel_time: 0.3, closed: true}}
    plant_io:                      # address: plant function (interfaces/plant_io.py)
      I0.0: MCP.auto
      I9.0: SP1.gearEngaged1       # one engaged sensor and one shift actuator per gear stage:
      Q2.0: SP1.gearShift1         # ... gearEngaged2, gearShift2, ... up to the gearbox's stages
      I9.4: SP1.chuckClosed        # the chuck's sensors (chuckOpen optional) and its valve
      Q2.4: SP1.chuckClose         # solenoids: clamp ...
      Q2.5: SP1.chuckRelease       # ... and unclamp
    plc:                           # parameters of the machine's PLC program (it checks them)
      referencing_order: [[Y1], [X1], [Z1]]

Rules:

* Machine data keys take any form of :func:`~vc.config.md_dictionary.parse_md_key`:
  ``MD32000``, ``MD32000 MAX_AX_VELO``, ``$MA_MAX_AX_VELO``, ``MAX_AX_VELO``, each optionally
  with ``[n]``.  General data ($MN_) go under ``nck:``, channel data ($MC_) under a channel,
  axis data ($MA_) under an axis.  An array is written as a list (items from index 0) or
  index by index; an array written as one scalar is refused as ambiguous.  Unwritten data
  and indices keep the default of the dictionary; ``MachineData`` holds only what was
  written (plus MD10000 and MD20070, which the ``axes:`` keys and the channels' axes lists
  state, so they are not written as machine data).
* ``sim`` holds what the control cannot know: ``start_position`` (where the slide stands at
  power-on), ``zero_mark_offset`` / ``zero_mark_offset_2`` (measuring system 1 / 2: physical
  position of one zero mark, of the first distance-coded mark, or of an absolute encoder's
  zero; see vc/core/axis/encoder.py) and ``encoder_serial`` / ``encoder_serial_2`` (the serial
  numbers of the mounted encoders, which the control compares with MD34230).  ``plant`` holds switches:
  ``ref_cam: [start, end]`` and ``hw_limits: [minus, plus]`` (``null`` = no switch there), and a
  spindle's load gearbox: ``gearbox: {stages: n, shift_time: s, engaged: k}`` with n = MD35090 gear
  stages, the seconds the shift actuator must push while the motor turns for the teeth to mesh, and
  the stage in mesh at power-on (default 1, 0 = neutral).  A gearbox needs its I/O: the shift
  actuators ``<spindle>.gearShift1..n`` and the engaged sensors ``<spindle>.gearEngaged1..n`` (the
  neutral sensor ``<spindle>.gearNeutral`` is optional); gearbox I/O without a gearbox is a mistake.
  A spindle's hydraulic chuck: ``chuck: {travel_time: s, closed: true|false}``, the seconds of its
  stroke and whether it is clamped at power-on (default true).  It needs its valve solenoids
  ``<spindle>.chuckClose`` and ``<spindle>.chuckRelease`` and its sensor ``<spindle>.chuckClosed``
  wired (``<spindle>.chuckOpen`` is optional); chuck I/O without a chuck is a mistake.
* An axis's ``drive:`` holds parameters of its drive that the NC does not write: ESR generator
  operation ``{p0888: 3, p0892: s, p1240: 2, p1248: V, p2161: rev/min, p0341: kg m^2, p0342: ratio}``
  (seed 003 L41700-41769); none of it without p0888 = 3 (1 and 2 are written by ESRS / ESRR from
  the program).  It needs the machine's ``dc_link: {supply_voltage: V (r0208), capacitance_uf: uF,
  load_power: W, precharge_time: s (optional)}`` (vc/core/retraction/dc_link.py).
* The machine's devices besides the axes go under a top-level ``plant:`` (``turret``, ``coolant``,
  ``tool_changer``, each with its I/O), the texts of the PLC user alarms its PLC program raises under
  ``plc_alarms:`` (``700000: "Turret: lock pin not pulled"``): vc/config/devices.py.
* Every machine axis belongs to exactly one channel.  A channel axis without a name in
  MD20080 is called by its machine axis name in part programs.
* Scenario overrides (``load_machine(..., overrides=...)``) are ``{instance: {key: value}}``
  with instance = an axis name, a channel name or ``NC``.  They are checked exactly like the
  file and replace the file's values index by index.  An axis may also carry ``sim:`` and
  ``plant:``; the keys written replace the file's (``hw_limits`` as a pair, ``gearbox`` and ``chuck`` key
  by key); ``NC`` may carry ``dc_link:``, whose keys replace the file's.

Every problem of the file and of the overrides is collected with ``file:line:column`` and
reported at once in one :class:`~vc.located_yaml.SourceError`; no half-checked configuration
is returned.  Pure apart from reading the one file.
"""

from __future__ import annotations

import dataclasses
import os
import re
from collections import OrderedDict
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

from interfaces.plant_io import (
    DEVICE_PREFIXES,
    MAX_GEAR_STAGES,
    PlantIoError,
    PlantIoMap,
    chuck_axis,
    chuck_close,
    chuck_closed,
    chuck_release,
    gear_engaged,
    gear_shift,
    gearbox_point,
)
from vc.config import md_dictionary as mdd
from vc.config.can_config import CanSection, check_against_machine, read_can_section
from vc.config.devices import read_plant, read_plc_alarms
from vc.config.machine_data import (
    MachineData,
    MdDef,
    MdLevel,
    MdScalar,
    MdValue,
    MdValueError,
    as_number,
    checked_value,
    shown,
)
from vc.config.machine_files import machine_file, unknown_machine
from vc.config.model import (
    DC_LINK_PER_SUPPLY_VOLT,
    EXTENDED_RETRACT,
    EXTENDED_STOP,
    PULSE_CANCELLATION_PER_SUPPLY_VOLT,
    SPEED_HYSTERESIS,
    AxisConfig,
    AxisPlant,
    AxisSimulation,
    ChannelConfig,
    ChuckPlant,
    DcLinkConfig,
    DriveParameters,
    GearboxPlant,
    MachineConfig,
    MachinePlant,
    machine_ipo_cycle_us,
)
from vc.located_yaml import LocatedMap, Mark, Problem, Problems, SourceError, load_file, load_text

TOP_LEVEL_KEYS = ("machine", "description", "plc_cycle_ipo", "nck", "channels", "axes", "plant_io", "plc", "can",
                  "dc_link", "plant", "plc_alarms")
SIM_KEYS = ("start_position", "zero_mark_offset", "zero_mark_offset_2", "encoder_serial", "encoder_serial_2")
_WHOLE_SIM_KEYS = ("encoder_serial", "encoder_serial_2")
AXIS_EXTRA_KEYS = ("sim", "plant", "drive")  # an axis block's keys besides machine data
NCK_EXTRA_KEYS = ("dc_link",)  # the NC's block of a scenario's overrides: its drive line-up's DC link too
PLANT_KEYS = ("ref_cam", "hw_limits", "gearbox", "chuck")
GEARBOX_KEYS = ("stages", "shift_time", "engaged")
CHUCK_KEYS = ("travel_time", "closed")
# drive parameters an axis block may carry under ``drive:``: (lowest, highest, whole number, meaning)
DRIVE_KEYS: dict[str, tuple[float, float, bool, str]] = {
    "p0888": (0, 3, True, "ESR configuration, 3 = generator operation"),
    "p0892": (0, 20, False, "s, how long generator operation may use the motor after the trigger"),
    "p1240": (0, 3, True, "Vdc controller configuration, 2 = buffer the DC link under ESR"),
    "p1248": (0, 1000, False, "V, lower DC-link threshold"),
    "p2161": (0, 100_000, False, "rev/min, minimum generator speed"),
    "p0341": (0, 1000, False, "kg m^2, motor moment of inertia"),
    "p0342": (1, 1_000_000, False, "ratio of the total to the motor moment of inertia"),
}
# the drive line-up's DC link under ``dc_link:`` (the first three needed)
DC_LINK_KEYS: dict[str, tuple[float, float, bool, str]] = {
    "supply_voltage": (1, 1000, False, "V, rated supply voltage r0208"),
    "capacitance_uf": (1, 10_000_000, False, "uF, DC-link capacitance"),
    "load_power": (0, 1_000_000, False, "W, what the line-up draws from the link without supply"),
    "precharge_time": (0, 60, False, "s, empty link to charged through the precharge resistors"),
}
_OPTIONAL_DC_LINK_KEYS = ("precharge_time",)
_REQUIRED_GEARBOX_KEYS = {"stages": "the number of gear stages",
                          "shift_time": "the seconds the shift actuator must push while the motor turns"}
NCK_INSTANCE = "NC"
# the control parameters LS and FS of a synchronous spindle pair must have alike (seed 003 L23736-23748)
COUPLED_LIKE_PARAMETERS = (mdd.FIPO_TYPE, mdd.AX_JERK_ENABLE, mdd.AX_JERK_MODE, mdd.AX_JERK_TIME, mdd.AX_JERK_FREQ,
                           mdd.AX_JERK_DAMP, mdd.JOG_AND_POS_JERK_ENABLE, mdd.JOG_AND_POS_MAX_JERK)
# Instance names the interface and the plant I/O vocabulary already use.
RESERVED_NAMES = frozenset({"NC", "MODEGROUP", "HMI", "ALARMS", "MCP", "EStop", "Drives", "Lamp", "Door",
                            "PLC", "PLCALARMS", *DEVICE_PREFIXES})  # PLC: the FMU
MAX_CHANNELS = 10  # DB21..DB30: channel 11 would collide with DB31 of machine axis 1
MAX_AXES = 31  # MD10000 has 31 entries
MAX_CHANNEL_AXES = 20  # MD20070 has 20 entries
DEFAULT_PLC_CYCLE_IPO = 5

_NAME = re.compile(r"^[A-Za-z][A-Za-z0-9_]*$")
_PLACE_IN_FILE = {MdLevel.NCK: "under nck", MdLevel.CHANNEL: "under a channel", MdLevel.AXIS: "under an axis"}
_PLACE_IN_OVERRIDES = {MdLevel.NCK: "for NC", MdLevel.CHANNEL: "for a channel", MdLevel.AXIS: "for an axis"}
_DERIVED = {
    mdd.AXCONF_MACHAX_NAME_TAB.number: "the names under axes:, in order",
    mdd.AXCONF_MACHAX_USED.number: "the channel's axes: list",
}


def load_machine(reference: str, overrides: LocatedMap | None = None, overrides_file: str = "") -> MachineConfig:
    """Load and check a machine file, with a scenario's ``machine_data:`` overrides.

    ``reference`` is the file's path or the name of a packaged machine (``turn_mill``, see
    :mod:`vc.config.machine_files`); the configuration's ``source`` is the reference as given.
    ``overrides_file`` names the scenario file for problems that have no mark of their own
    (an override mapping built in code); the marks of a located mapping are used otherwise.
    Raises :class:`SourceError` listing every problem of both.
    """
    path = machine_file(reference)
    if path is None:
        raise SourceError([Problem(Mark(reference, 1, 1), unknown_machine(reference))])
    document, parse_problems = _parsed(path)
    return _machine_of(document, parse_problems, path, reference, overrides, overrides_file)


def load_machine_text(text: str, name: str, overrides: LocatedMap | None = None,
                      overrides_file: str = "") -> MachineConfig:
    """``load_machine`` for the text of a machine file kept elsewhere (a session recording holds
    the one it ran with); problems are located in ``name``."""
    document, parse_problems = load_text(text, name)
    return _machine_of(document, parse_problems, name, name, overrides, overrides_file)


def _machine_of(document: Any, parse_problems: list[Problem], path: str, reference: str,
                overrides: LocatedMap | None, overrides_file: str) -> MachineConfig:
    problems = Problems()
    problems.extend(parse_problems)
    if document is None:
        problems.raise_if_any()
    reader = _MachineReader(path, problems, source=reference)
    reader.read(document)
    if overrides is not None:
        reader.apply_overrides(overrides, Mark(overrides_file or "<machine_data>", 1, 1))
    config = reader.build()
    problems.raise_if_any()
    assert config is not None  # build() returns None only together with problems
    return config


_PARSED: OrderedDict[tuple[str, int, int, int], tuple[Any, list[Problem]]] = OrderedDict()
_PARSED_FILES = 16


def _parsed(path: str) -> tuple[Any, list[Problem]]:
    """The parsed machine file, parsed once while the file stays as it is: the variants of a
    scenario matrix load one machine file with hundreds of override sets (the reader only reads it)."""
    try:
        status = os.stat(path)
    except OSError:
        return load_file(path)  # it reports the file it cannot read
    key = (os.path.abspath(path), status.st_ino, status.st_mtime_ns, status.st_size)
    if key not in _PARSED:
        _PARSED[key] = load_file(path)
        if len(_PARSED) > _PARSED_FILES:
            _PARSED.popitem(last=False)
    _PARSED.move_to_end(key)
    return _PARSED[key]


# ------------------------------------------------------------------------------ instances


@dataclass(slots=True)
class _Written:
    value: MdScalar
    mark: Mark


@dataclass(slots=True)
class _Instance:
    """Machine data written for one level instance (the NCK, a channel or an axis)."""

    level: MdLevel
    name: str
    mark: Mark  # where the instance is declared: the mark for problems with defaults
    written: dict[int, dict[int | None, _Written]] = field(default_factory=dict)

    def value(self, md: MdDef, index: int | None = None) -> MdScalar:
        written = self.written.get(md.number, {}).get(index)
        if written is not None:
            return written.value
        default = md.default
        if isinstance(default, tuple):
            return default[0 if index is None else index]
        return default

    def mark_of(self, md: MdDef, index: int | None = None) -> Mark:
        """Where the effective value comes from: its last write, else the instance."""
        entries = self.written.get(md.number, {})
        if index in entries:
            return entries[index].mark
        if index is None and entries:
            return min(entry.mark for entry in entries.values())
        return self.mark

    def is_written(self, md: MdDef) -> bool:
        return md.number in self.written

    def values(self) -> dict[int, MdValue]:
        result: dict[int, MdValue] = {}
        for number, entries in self.written.items():
            md = mdd.BY_NUMBER[number]
            if md.is_array:
                assert isinstance(md.default, tuple)
                items = list(md.default)
                for index, entry in entries.items():
                    assert index is not None
                    items[index] = entry.value
                result[number] = tuple(items)
            else:
                result[number] = entries[None].value
        return result

    def set_derived(self, md: MdDef, items: tuple[MdScalar, ...], mark: Mark) -> None:
        self.written[md.number] = {index: _Written(value, mark) for index, value in enumerate(items)}


@dataclass(frozen=True, slots=True)
class _MarkOf:
    """Marks of located YAML values, with a fallback for mappings built in code without marks."""

    fallback: Mark

    def of(self, value: Any) -> Mark:
        mark = getattr(value, "mark", None)
        return mark if isinstance(mark, Mark) else self.fallback

    def key(self, mapping: Mapping[str, Any], key: str) -> Mark:
        marks = getattr(mapping, "key_marks", None)
        return marks.get(key, self.of(mapping)) if isinstance(marks, dict) else self.of(mapping)

    def value(self, mapping: Mapping[str, Any], key: str) -> Mark:
        marks = getattr(mapping, "value_marks", None)
        return marks.get(key, self.of(mapping)) if isinstance(marks, dict) else self.of(mapping)

    def item(self, items: list[Any], index: int) -> Mark:
        marks = getattr(items, "item_marks", None)
        return marks[index] if isinstance(marks, list) and index < len(marks) else self.of(items)


# ------------------------------------------------------------------------------ the reader


@dataclass(slots=True)
class _AxisEntry:
    name: str
    mark: Mark
    data: _Instance
    sim: AxisSimulation = field(default_factory=AxisSimulation)
    plant: AxisPlant = field(default_factory=AxisPlant)  # without gearbox and chuck, which build() makes
    channel: str = ""
    gearbox: dict[str, _Written] = field(default_factory=dict)  # plant.gearbox keys: file, then overrides
    gearbox_keys: set[str] = field(default_factory=set)  # every key written, also those with a bad value
    gearbox_mark: Mark | None = None  # where the gearbox is first declared; None = no gearbox
    chuck: dict[str, _Written] = field(default_factory=dict)  # plant.chuck keys: file, then overrides
    chuck_mark: Mark | None = None  # where the chuck is first declared; None = no chuck
    drive: DriveParameters = field(default_factory=DriveParameters)
    drive_mark: Mark | None = None  # where drive: is written last


@dataclass(slots=True)
class _ChannelEntry:
    name: str
    mark: Mark
    data: _Instance
    axes: list[str] = field(default_factory=list)


class _MachineReader:
    """Reads one machine file into instances, then cross-checks and builds the config."""

    def __init__(self, path: str, problems: Problems, source: str):
        self.path = path
        self.source = source  # how the file was named: its path, or a packaged machine's name
        self.problems = problems
        self.marks = _MarkOf(Mark(path, 1, 1))
        self.name = ""
        self.plc_cycle_ipo = DEFAULT_PLC_CYCLE_IPO
        self.nck = _Instance(MdLevel.NCK, NCK_INSTANCE, Mark(path, 1, 1))
        self.axes: dict[str, _AxisEntry] = {}
        self.channels: dict[str, _ChannelEntry] = {}
        self.plant_io = PlantIoMap(())
        self.plant_io_names: dict[str, tuple[str, Mark]] = {}  # function name -> address text, mark
        self.plc_parameters: dict[str, Any] = {}
        self.dc_link: DcLinkConfig | None = None
        self.can = CanSection()
        self.can_mark: Mark | None = None  # where the ``can:`` section is; None: there is none
        self.plant = MachinePlant()  # ``plant:``, the devices besides the axes
        self.plc_alarms: dict[int, str] = {}  # ``plc_alarms:``
        self.channel_lists_complete = True  # every channel's axes list could be read

    def add(self, mark: Mark, message: str) -> None:
        self.problems.add(mark, message)

    # ------------------------------------------------------------------ top level

    def read(self, document: Any) -> None:
        if not isinstance(document, LocatedMap):
            self.add(self.marks.of(document), "a machine file is a mapping with the keys "
                     + ", ".join(TOP_LEVEL_KEYS))
            return
        for key in document:
            if key not in TOP_LEVEL_KEYS:
                self.add(document.mark_of_key(key), f"unknown key '{key}'; a machine file has "
                         + ", ".join(TOP_LEVEL_KEYS))
        self._read_name(document)
        if "plc_cycle_ipo" in document:
            self._read_plc_cycle(document["plc_cycle_ipo"], document.mark_of("plc_cycle_ipo"))
        if "nck" in document:
            self.nck.mark = document.mark_of_key("nck")
            nck = self._mapping(document["nck"], document.mark_of("nck"), "nck")
            if nck is not None:
                self._write_block(nck, self.nck, _PLACE_IN_FILE)
        self._read_axes(document)
        self._read_channels(document)
        if "plant_io" in document:
            self._read_plant_io(document["plant_io"], document.mark_of("plant_io"))
        if "plc" in document:
            parameters = self._mapping(document["plc"], document.mark_of("plc"), "plc")
            if parameters is not None:
                self.plc_parameters = dict(parameters)
        if "can" in document:
            self.can_mark = document.mark_of_key("can")
            self.can = read_can_section(document["can"], document.mark_of("can"), self.problems)
        if "dc_link" in document:
            self._read_dc_link(document["dc_link"], document.mark_of("dc_link"))
        # the devices besides the axes and the PLC alarm texts (vc/config/devices.py), after plant_io
        self.plant = read_plant(document.get("plant"), document.mark_of("plant"), self.problems,
                                self.plant_io_names, self._read_parameters)
        self.plc_alarms = read_plc_alarms(document.get("plc_alarms"), document.mark_of("plc_alarms"),
                                          self.problems)

    def _read_dc_link(self, raw: Any, mark: Mark) -> None:
        values = self._read_parameters(raw, mark, "dc_link", DC_LINK_KEYS)
        required = [key for key in DC_LINK_KEYS if key not in _OPTIONAL_DC_LINK_KEYS]
        unwritten = [key for key in required if not isinstance(raw, dict) or key not in raw]
        if unwritten and (raw is None or isinstance(raw, dict)):  # an empty dc_link: is no DC link either
            self.add(mark, f"dc_link: missing {', '.join(unwritten)}")
        if all(key in values for key in required):
            self.dc_link = DcLinkConfig(**values)

    def _read_parameters(self, raw: Any, mark: Mark, where: str,
                         table: Mapping[str, tuple[float, float, bool, str]]) -> dict[str, Any]:
        """The keys of ``table`` written in ``raw``, each a number inside its range."""
        values: dict[str, Any] = {}
        block = self._any_mapping(raw, mark, where)
        for key, value in block.items():
            key_mark, value_mark = self.marks.key(block, key), self.marks.value(block, key)
            if key not in table:
                self.add(key_mark, f"unknown key '{key}' in {where}; allowed: {', '.join(table)}")
                continue
            lowest, highest, whole, meaning = table[key]
            number = as_number(value)
            if number is None or not lowest <= number <= highest or (whole and not float(number).is_integer()):
                kind = "a whole number" if whole else "a number"
                self.add(value_mark, f"{where}.{key} ({meaning}): {kind} from {lowest:g} to {highest:g},"
                                     f" got {shown(value)}")
                continue
            values[key] = int(number) if whole else float(number)
        return values

    def _read_name(self, document: LocatedMap) -> None:
        if "machine" not in document:
            self.add(document.mark, "missing 'machine:' (the name of the machine)")
        else:
            name = document["machine"]
            if isinstance(name, str) and name.strip():
                self.name = name.strip()
            else:
                self.add(document.mark_of("machine"), f"machine: expected a name, got {shown(name)}")
        description = document.get("description", "")
        if not isinstance(description, str):
            self.add(document.mark_of("description"), f"description: expected text, got {shown(description)}")

    def _read_plc_cycle(self, raw: Any, mark: Mark) -> None:
        number = as_number(raw)
        if number is None or not float(number).is_integer():
            self.add(mark, f"plc_cycle_ipo: expected a whole number of IPO cycles, got {shown(raw)}")
        elif number < 1:
            self.add(mark, f"plc_cycle_ipo = {shown(raw)}: the PLC cycle must be at least 1 IPO cycle")
        else:
            self.plc_cycle_ipo = int(number)

    def _mapping(self, raw: Any, mark: Mark, where: str) -> LocatedMap | None:
        if raw is None:
            empty = LocatedMap()
            empty.mark, empty.key_marks, empty.value_marks = mark, {}, {}
            return empty
        if not isinstance(raw, dict):
            self.add(mark, f"{where}: expected a mapping, got {shown(raw)}")
            return None
        return raw if isinstance(raw, LocatedMap) else None

    def _instance_name(self, name: str, mark: Mark, kind: str) -> bool:
        if not _NAME.match(name):
            self.add(mark,
                     f"{kind} name '{name}' must start with a letter and use only letters, digits and _")
            return False
        if name in RESERVED_NAMES:
            self.add(mark, f"{kind} name '{name}' is reserved ({', '.join(sorted(RESERVED_NAMES))})")
            return False
        return True

    # ------------------------------------------------------------------ axes

    def _read_axes(self, document: LocatedMap) -> None:
        if "axes" not in document:
            self.add(document.mark, "missing 'axes:' (the machine axes, in machine axis order)")
            return
        axes = self._mapping(document["axes"], document.mark_of("axes"), "axes")
        if axes is None:
            return
        if not axes:
            self.add(document.mark_of("axes"), "axes: the machine needs at least one axis")
        for name, raw in axes.items():
            key_mark = axes.mark_of_key(name)
            if not self._instance_name(name, key_mark, "axis"):
                continue
            if len(self.axes) == MAX_AXES:
                self.add(key_mark, f"axis {name}: a machine has at most {MAX_AXES} axes (MD10000)")
                continue
            entry = _AxisEntry(name, key_mark, _Instance(MdLevel.AXIS, name, key_mark))
            self.axes[name] = entry
            block = self._mapping(raw, axes.mark_of(name), f"axes.{name}")
            if block is None:
                continue
            self._write_block(block, entry.data, _PLACE_IN_FILE, extra_keys=AXIS_EXTRA_KEYS)
            self._apply_sim_and_plant(entry, block, f"axes.{name}")
        self.nck.set_derived(mdd.AXCONF_MACHAX_NAME_TAB, self._padded(mdd.AXCONF_MACHAX_NAME_TAB,
                                                                      tuple(self.axes)), self.nck.mark)

    @staticmethod
    def _padded(md: MdDef, items: tuple[MdScalar, ...],
                filler: MdScalar | None = None) -> tuple[MdScalar, ...]:
        """``items`` from index 0, the rest ``filler`` or (without one) the defaults of ``md``."""
        assert isinstance(md.default, tuple)
        rest = md.default[len(items):] if filler is None else (filler,) * (md.length - len(items))
        return items + tuple(rest)

    def _read_sim(self, raw: Any, mark: Mark, where: str) -> dict[str, Any]:
        """The ``sim:`` keys written in ``raw``, checked: AxisSimulation field -> value."""
        values: dict[str, Any] = {}
        block = self._any_mapping(raw, mark, where)
        for key, value in block.items():
            key_mark, value_mark = self.marks.key(block, key), self.marks.value(block, key)
            if key not in SIM_KEYS:
                self.add(key_mark, f"unknown key '{key}' in sim; allowed: {', '.join(SIM_KEYS)}")
                continue
            number = self._number(value, value_mark, f"sim.{key}")
            if number is None:
                continue
            if key in _WHOLE_SIM_KEYS:
                if not float(number).is_integer() or number < 0:
                    self.add(value_mark, f"sim.{key} is a serial number: a whole number >= 0, got {value!r}")
                    continue
                values[key] = int(number)
            else:
                values[key] = number
        return values

    def _read_plant(self, raw: Any, mark: Mark, where: str) -> dict[str, Any]:
        """The ``plant:`` keys written in ``raw``, checked: AxisPlant field -> value."""
        values: dict[str, Any] = {}
        block = self._any_mapping(raw, mark, where)
        for key, value in block.items():
            key_mark, value_mark = self.marks.key(block, key), self.marks.value(block, key)
            if key == "ref_cam":
                pair = self._pair(value, value_mark, "plant.ref_cam", "[start, end]", allow_null=False)
                if pair is not None:
                    start, end = pair
                    assert start is not None and end is not None
                    if start >= end:
                        self.add(value_mark, f"plant.ref_cam [{start}, {end}]: the start of the cam must be"
                                             " below its end")
                    else:
                        values["ref_cam"] = (start, end)
            elif key == "hw_limits":
                pair = self._pair(value, value_mark, "plant.hw_limits", "[minus, plus]", allow_null=True)
                if pair is not None:
                    minus, plus = pair
                    if minus is not None and plus is not None and minus >= plus:
                        self.add(value_mark, f"plant.hw_limits [{minus}, {plus}]: the minus limit switch must"
                                             " be below the plus limit switch")
                    else:
                        values["hw_limit_minus"], values["hw_limit_plus"] = minus, plus
            elif key == "gearbox":
                values["gearbox"] = self._read_gearbox(value, value_mark, f"{where}.gearbox")
            elif key == "chuck":
                values["chuck"] = self._read_chuck(value, value_mark, f"{where}.chuck")
            else:
                self.add(key_mark, f"unknown key '{key}' in plant; allowed: {', '.join(PLANT_KEYS)}")
        return values

    def _read_gearbox(self, raw: Any, mark: Mark,
                      where: str) -> tuple[dict[str, _Written], set[str], Mark | None]:
        """The ``plant.gearbox`` keys written in ``raw`` (checked one by one), every key written,
        and where the gearbox is declared (None when ``raw`` is no mapping at all).

        The checks that need the whole axis (MD35000, MD35090, the stage engaged at power-on
        against the stages, the I/O list) come in :meth:`_build_gearbox`, after the overrides.
        """
        written: dict[str, _Written] = {}
        block = self._any_mapping(raw, mark, where)
        for key, value in block.items():
            key_mark, value_mark = self.marks.key(block, key), self.marks.value(block, key)
            if key not in GEARBOX_KEYS:
                self.add(key_mark, f"unknown key '{key}' in plant.gearbox; allowed: {', '.join(GEARBOX_KEYS)}")
            elif key == "stages":
                stages = _whole_number(value, 1, MAX_GEAR_STAGES)
                if stages is None:
                    self.add(value_mark, f"plant.gearbox.stages: the number of gear stages, a whole number"
                                         f" from 1 to {MAX_GEAR_STAGES}, got {shown(value)}")
                    continue
                written[key] = _Written(stages, value_mark)
            elif key == "shift_time":
                seconds = as_number(value)
                if seconds is None or seconds <= 0:
                    self.add(value_mark, "plant.gearbox.shift_time: the seconds the shift actuator must push"
                                         f" while the motor turns, above 0, got {shown(value)}")
                    continue
                written[key] = _Written(float(seconds), value_mark)
            elif key == "engaged":
                engaged = _whole_number(value, 0, MAX_GEAR_STAGES)
                if engaged is None:
                    self.add(value_mark, "plant.gearbox.engaged: the gear stage in mesh at power-on, a whole"
                                         f" number from 0 (neutral) to {MAX_GEAR_STAGES}, got {shown(value)}")
                    continue
                written[key] = _Written(engaged, value_mark)
        declared = mark if raw is None or isinstance(raw, dict) else None
        return written, {key for key in block if key in GEARBOX_KEYS}, declared

    def _read_chuck(self, raw: Any, mark: Mark, where: str) -> tuple[dict[str, _Written], Mark | None]:
        """The ``plant.chuck`` keys written in ``raw`` (checked one by one) and where the chuck is
        declared (None when ``raw`` is no mapping at all); :meth:`_build_chuck` checks the rest."""
        written: dict[str, _Written] = {}
        block = self._any_mapping(raw, mark, where)
        for key, value in block.items():
            key_mark, value_mark = self.marks.key(block, key), self.marks.value(block, key)
            if key not in CHUCK_KEYS:
                self.add(key_mark, f"unknown key '{key}' in plant.chuck; allowed: {', '.join(CHUCK_KEYS)}")
            elif key == "travel_time":
                seconds = as_number(value)
                if seconds is None or seconds <= 0:
                    self.add(value_mark, "plant.chuck.travel_time: the seconds of the chuck's stroke, above 0,"
                                         f" got {shown(value)}")
                    continue
                written[key] = _Written(float(seconds), value_mark)
            elif not isinstance(value, bool):
                self.add(value_mark, f"plant.chuck.closed: true (clamped at power-on) or false, got {shown(value)}")
            else:
                written[key] = _Written(value, value_mark)
        return written, mark if raw is None or isinstance(raw, dict) else None

    def _any_mapping(self, raw: Any, mark: Mark, where: str) -> Mapping[str, Any]:
        """``raw`` as a mapping (located or built in code); a problem and an empty one otherwise."""
        if raw is None:
            return {}
        if not isinstance(raw, dict):
            self.add(mark, f"{where}: expected a mapping, got {shown(raw)}")
            return {}
        return raw

    def _apply_sim_and_plant(self, entry: _AxisEntry, block: Mapping[str, Any], where: str) -> None:
        """Read an axis block's ``sim:`` and ``plant:``; the keys written replace the entry's values."""
        if "sim" in block:
            sim = self._read_sim(block["sim"], self.marks.value(block, "sim"), f"{where}.sim")
            entry.sim = dataclasses.replace(entry.sim, **sim)
        if "plant" in block:
            plant = self._read_plant(block["plant"], self.marks.value(block, "plant"), f"{where}.plant")
            if "gearbox" in plant:
                gearbox, keys, declared = plant.pop("gearbox")
                entry.gearbox.update(gearbox)
                entry.gearbox_keys.update(keys)
                if entry.gearbox_mark is None:
                    entry.gearbox_mark = declared
            if "chuck" in plant:
                chuck, declared = plant.pop("chuck")
                entry.chuck.update(chuck)
                if entry.chuck_mark is None:
                    entry.chuck_mark = declared
            entry.plant = dataclasses.replace(entry.plant, **plant)
        if "drive" in block:
            entry.drive_mark = self.marks.value(block, "drive")
            drive = self._read_parameters(block["drive"], entry.drive_mark, f"{where}.drive", DRIVE_KEYS)
            if drive.get("p0888") in (EXTENDED_STOP, EXTENDED_RETRACT):
                self.add(self.marks.value(block["drive"], "p0888"),
                         f"{where}.drive.p0888 = {drive.pop('p0888')}: extended stop (1) and retract (2) are"
                         f" written by ESRS / ESRR from the part program; the file takes 0 or 3 (generator"
                         f" operation)")
            entry.drive = dataclasses.replace(entry.drive, **drive)
            ignored = [key for key in drive if key != "p0888"]
            if ignored and not entry.drive.generator:  # an override may still switch generator operation off
                self.add(entry.drive_mark, f"{where}.drive: {', '.join(ignored)} belong to generator operation:"
                                           f" without p0888 = 3 the drive would ignore them")

    def _number(self, raw: Any, mark: Mark, what: str) -> float | None:
        number = as_number(raw)
        if number is None:
            self.add(mark, f"{what}: expected a number, got {shown(raw)}")
            return None
        return float(number)

    def _pair(self, raw: Any, mark: Mark, what: str, form: str,
              allow_null: bool) -> tuple[float | None, float | None] | None:
        if not isinstance(raw, list) or len(raw) != 2:
            got = _count(len(raw), "value", "values") if isinstance(raw, list) else shown(raw)
            self.add(mark, f"{what}: expected two numbers {form}, got {got}")
            return None
        result: list[float | None] = []
        for index, item in enumerate(raw):
            if item is None and allow_null:
                result.append(None)
                continue
            number = self._number(item, self.marks.item(raw, index), what)
            if number is None:
                return None
            result.append(number)
        return result[0], result[1]

    # ------------------------------------------------------------------ channels

    def _read_channels(self, document: LocatedMap) -> None:
        if "channels" not in document:
            self.add(document.mark, "missing 'channels:' (at least one channel with its axes)")
            return
        channels = self._mapping(document["channels"], document.mark_of("channels"), "channels")
        if channels is None:
            return
        if not channels:
            self.add(document.mark_of("channels"), "channels: the machine needs at least one channel")
        for name, raw in channels.items():
            key_mark = channels.mark_of_key(name)
            if not self._instance_name(name, key_mark, "channel"):
                self.channel_lists_complete = False
                continue
            if name in self.axes:
                self.add(key_mark, f"channel name '{name}' is already the name of an axis")
                self.channel_lists_complete = False
                continue
            if len(self.channels) == MAX_CHANNELS:
                self.add(key_mark,
                         f"channel {name}: a machine has at most {MAX_CHANNELS} channels (DB21..DB30)")
                continue
            entry = _ChannelEntry(name, key_mark, _Instance(MdLevel.CHANNEL, name, key_mark))
            self.channels[name] = entry
            block = self._mapping(raw, channels.mark_of(name), f"channels.{name}")
            if block is not None:
                self._write_block(block, entry.data, _PLACE_IN_FILE, extra_keys=("axes",))
            if block is None or "axes" not in block:
                self.channel_lists_complete = False
                if block is not None:
                    self.add(key_mark, f"channel {name} has no 'axes:' list (its machine axes, in channel"
                                       " axis order)")
            elif not self._read_channel_axes(entry, block["axes"], block.mark_of("axes")):
                self.channel_lists_complete = False
        if not self.channel_lists_complete:
            return
        for axis in self.axes.values():
            if not axis.channel:
                self.add(axis.mark, f"axis {axis.name} is in no channel; list it in a channel's axes")

    def _read_channel_axes(self, channel: _ChannelEntry, raw: Any, mark: Mark) -> bool:
        """Read the channel's axes list; False if it is not a list at all."""
        where = f"channels.{channel.name}.axes"
        if not isinstance(raw, list):
            self.add(mark, f"{where}: expected a list of machine axes, got {shown(raw)}")
            return False
        if not raw:
            self.add(mark, f"{where}: a channel needs at least one axis")
        for index, item in enumerate(raw):
            item_mark = self.marks.item(raw, index)
            if not isinstance(item, str):
                self.add(item_mark, f"{where}: expected an axis name, got {shown(item)}")
                continue
            axis = self.axes.get(item)
            if axis is None:
                self.add(item_mark, f"axis {item} in {where} is not declared under axes")
            elif item in channel.axes:
                self.add(item_mark, f"axis {item} is listed twice in {where}")
            elif axis.channel:
                self.add(item_mark, f"axis {item} is already an axis of channel {axis.channel};"
                                    " a machine axis belongs to one channel")
            elif len(channel.axes) == MAX_CHANNEL_AXES:
                self.add(item_mark, f"{where}: a channel has at most {MAX_CHANNEL_AXES} axes (MD20070)")
            else:
                axis.channel = channel.name
                channel.axes.append(item)
        numbers = tuple(list(self.axes).index(name) + 1 for name in channel.axes)
        used = self._padded(mdd.AXCONF_MACHAX_USED, numbers, 0)
        channel.data.set_derived(mdd.AXCONF_MACHAX_USED, used, mark)
        return True

    # ------------------------------------------------------------------ plant I/O

    def _read_plant_io(self, raw: Any, mark: Mark) -> None:
        block = self._mapping(raw, mark, "plant_io")
        if block is None:
            return
        entries: dict[str, str] = {}
        for key, value, value_mark in block.located_items():
            if isinstance(value, str):
                entries[key] = value
                self.plant_io_names.setdefault(value.strip(), (key, block.mark_of_key(key)))
            else:
                self.add(value_mark,
                         f"plant_io {key}: expected a plant function such as MCP.auto, got {shown(value)}")
        try:
            self.plant_io = PlantIoMap.from_mapping(entries, self.axes)
        except PlantIoError as error:
            for key, message in error.problems:
                self.add(block.mark_of_key(key), f"plant_io {key}: {message}")

    # ------------------------------------------------------------------ machine data

    def _write_block(self, block: Mapping[str, Any], instance: _Instance, place: Mapping[MdLevel, str],
                     extra_keys: tuple[str, ...] = ()) -> None:
        """Check and record every machine datum of one mapping; ``extra_keys`` are read elsewhere."""
        first_write: dict[tuple[int, int | None], Mark] = {}
        for key_value, raw in block.items():
            key = str(key_value)
            if key in extra_keys:
                continue
            key_mark = self.marks.key(block, key)
            value_mark = self.marks.value(block, key)
            try:
                parsed = mdd.parse_md_key(key)
            except mdd.MdKeyError as error:
                if key != key.upper() and not key.startswith(("MD", "md", "$")):
                    takes = ", ".join(f"{extra}:" for extra in extra_keys)
                    self.add(key_mark, f"unknown key '{key}'; {instance.name} takes "
                                       f"{takes + ' and ' if takes else ''}machine data")
                else:
                    self.add(key_mark, str(error))
                continue
            md = parsed.md
            if md.level is not instance.level:
                self.add(key_mark, f"{md.label} is {mdd.level_text(md.level)}; set it {place[md.level]}")
                continue
            if md.read_only:
                self.add(key_mark, f"{md.label} is read-only: the control writes it")
                continue
            if md.number in _DERIVED:
                self.add(key_mark,
                         f"{md.label} is not written as machine data: it comes from {_DERIVED[md.number]}")
                continue
            values = self._values(parsed, raw, value_mark)
            if values is None:
                continue
            clash = next((first_write[(md.number, index)] for index in values
                          if (md.number, index) in first_write), None)
            if clash is not None:
                self.add(key_mark, f"{parsed.label} is already set at line {clash.line}")
                continue
            entries = instance.written.setdefault(md.number, {})
            for index, written in values.items():
                first_write[(md.number, index)] = key_mark
                entries[index] = written

    def _values(self, parsed: mdd.MdKey, raw: Any, mark: Mark) -> dict[int | None, _Written] | None:
        """The checked values a key writes, by index (None = a scalar datum); None after a problem."""
        md = parsed.md
        if md.is_array and parsed.index is None:
            if not isinstance(raw, list):
                self.add(mark, f"{md.label} has {md.length} values; write a list [...] or"
                               f" MD{md.number}[n]: value (got {shown(raw)})")
                return None
            if len(raw) > md.length:
                self.add(mark, f"{md.label} has {md.length} values; {len(raw)} given")
                return None
            result: dict[int | None, _Written] = {}
            for index, item in enumerate(raw):
                item_mark = self.marks.item(raw, index)
                value = self._checked(md, item, index, item_mark)
                if value is not None:
                    result[index] = _Written(value, item_mark)
            return result if len(result) == len(raw) else None
        if isinstance(raw, (list, dict)):
            self.add(mark, f"{parsed.label} takes one value, got {shown(raw)}")
            return None
        value = self._checked(md, raw, parsed.index, mark)
        return None if value is None else {parsed.index: _Written(value, mark)}

    def _checked(self, md: MdDef, raw: Any, index: int | None, mark: Mark) -> MdScalar | None:
        try:
            return checked_value(md, raw, index)
        except MdValueError as error:
            self.add(mark, str(error))
            return None

    # ------------------------------------------------------------------ overrides

    def apply_overrides(self, overrides: Any, fallback: Mark) -> None:
        marks = _MarkOf(fallback)
        if not isinstance(overrides, dict):
            self.add(marks.of(overrides), f"machine_data: expected a mapping of axis, channel or NC names to"
                                          f" machine data, got {shown(overrides)}")
            return
        saved, self.marks = self.marks, marks
        try:
            for name, raw in overrides.items():
                instance = self._instance(name)
                if instance is None:
                    known = ", ".join([*self.axes, *self.channels, NCK_INSTANCE])
                    self.add(marks.key(overrides, name),
                             f"machine_data: {self.name or 'the machine'} has no axis"
                             f" or channel '{name}' (it has {known})")
                    continue
                if raw is not None and not isinstance(raw, dict):
                    self.add(marks.value(overrides, name),
                             f"machine_data.{name}: expected a mapping of machine"
                             f" data, got {shown(raw)}")
                    continue
                block: Mapping[str, Any] = raw or {}
                scratch = _Instance(instance.level, name, marks.key(overrides, name))
                axis_entry = self.axes.get(name)
                self._write_block(block, scratch, _PLACE_IN_OVERRIDES,
                                  extra_keys=AXIS_EXTRA_KEYS if axis_entry is not None
                                  else NCK_EXTRA_KEYS if name == NCK_INSTANCE else ())
                if name == NCK_INSTANCE and "dc_link" in block:
                    self._override_dc_link(block["dc_link"], marks.value(block, "dc_link"))
                if axis_entry is not None:
                    # the slide and the switches of this one test: where the cam sits, where the
                    # scale's first mark is, where the slide stands at power-on
                    self._apply_sim_and_plant(axis_entry, block, f"machine_data.{name}")
                for number, entries in scratch.written.items():
                    instance.written.setdefault(number, {}).update(entries)
        finally:
            self.marks = saved

    def _override_dc_link(self, raw: Any, mark: Mark) -> None:
        """``NC: {dc_link: {...}}``: the keys written replace the machine file's."""
        values = self._read_parameters(raw, mark, "machine_data.NC.dc_link", DC_LINK_KEYS)
        if self.dc_link is None:
            self.add(mark, f"machine_data.NC.dc_link: {self.name or 'the machine'} has no dc_link: section")
        elif values:
            self.dc_link = dataclasses.replace(self.dc_link, **values)

    def _instance(self, name: str) -> _Instance | None:
        if name == NCK_INSTANCE:
            return self.nck
        if name in self.axes:
            return self.axes[name].data
        if name in self.channels:
            return self.channels[name].data
        return None

    # ------------------------------------------------------------------ cross checks and build

    def build(self) -> MachineConfig | None:
        self._check_ipo_cycle()
        axes = self._build_axes()
        channels = tuple(self._build_channel(number, entry, axes)
                         for number, entry in enumerate(self.channels.values(), start=1))
        if self.problems:
            return None
        config = MachineConfig(
            name=self.name,
            source=self.source,
            nck=MachineData(NCK_INSTANCE, self.nck.values()),
            channels=channels,
            axes=tuple(axes.values()),
            plant_io=self.plant_io,
            plc_parameters=self.plc_parameters,
            plc_cycle_ipo=self.plc_cycle_ipo,
            dc_link=self.dc_link,
            can=self.can.config,
            plant=self.plant,
            plc_alarms=self.plc_alarms,
        )
        if self.can_mark is not None:  # without a section the defaults fit every machine the loader accepts
            check_against_machine(self.can, machine_ipo_cycle_us(config), config.plc_cycle_ipo, config.layout,
                                  self.plant_io.area_sizes(), self.can_mark, self.problems)
        return None if self.problems else config

    def _check_ipo_cycle(self) -> None:
        clock = float(self.nck.value(mdd.SYSCLOCK_CYCLE_TIME))
        microseconds = clock * int(self.nck.value(mdd.IPO_SYSCLOCK_TIME_RATIO)) * 1e6
        if abs(microseconds - round(microseconds)) > 1e-6:
            mark = self.nck.mark_of(mdd.SYSCLOCK_CYCLE_TIME)
            if not self.nck.is_written(mdd.SYSCLOCK_CYCLE_TIME):
                mark = self.nck.mark_of(mdd.IPO_SYSCLOCK_TIME_RATIO)
            self.add(mark, f"the IPO cycle MD10050 SYSCLOCK_CYCLE_TIME x MD10070 IPO_SYSCLOCK_TIME_RATIO ="
                           f" {microseconds:g} us is not a whole number of microseconds")

    def _build_axes(self) -> dict[str, AxisConfig]:
        spindles: dict[int, str] = {}
        result: dict[str, AxisConfig] = {}
        channel_numbers = {name: number for number, name in enumerate(self.channels, start=1)}
        for number, entry in enumerate(self.axes.values(), start=1):
            data = entry.data
            is_rotary = bool(data.value(mdd.IS_ROT_AX))
            spindle = int(data.value(mdd.SPIND_ASSIGN_TO_MACHAX))
            if spindle:
                mark = data.mark_of(mdd.SPIND_ASSIGN_TO_MACHAX)
                if spindle in spindles:
                    self.add(mark,
                             f"{entry.name}: spindle number {spindle} (MD35000 SPIND_ASSIGN_TO_MACHAX) is"
                             f" already the number of {spindles[spindle]}")
                else:
                    spindles[spindle] = entry.name
                if not is_rotary:
                    self.add(mark,
                             f"{entry.name}: MD35000 SPIND_ASSIGN_TO_MACHAX = {spindle} makes it a spindle,"
                             " which needs MD30300 IS_ROT_AX = 1")
            minus, plus = data.value(mdd.POS_LIMIT_MINUS), data.value(mdd.POS_LIMIT_PLUS)
            assert isinstance(minus, float) and isinstance(plus, float)
            if minus >= plus:
                self.add(data.mark_of(mdd.POS_LIMIT_MINUS if data.is_written(mdd.POS_LIMIT_MINUS)
                                      else mdd.POS_LIMIT_PLUS),
                         f"{entry.name}: MD36100 POS_LIMIT_MINUS ({minus}) must be below"
                         f" MD36110 POS_LIMIT_PLUS ({plus})")
            master = int(data.value(mdd.AXCONF_ASSIGN_MASTER_CHAN))
            if master and entry.channel and master != channel_numbers[entry.channel]:
                self.add(data.mark_of(mdd.AXCONF_ASSIGN_MASTER_CHAN),
                         f"{entry.name}: MD30550 AXCONF_ASSIGN_MASTER_CHAN = {master}, but {entry.name} is an"
                         f" axis of channel {channel_numbers[entry.channel]} ({entry.channel})")
            values = MachineData(entry.name, data.values())
            plant = dataclasses.replace(entry.plant, gearbox=self._build_gearbox(entry, spindle),
                                        chuck=self._build_chuck(entry, spindle))
            self._check_generator(entry)
            result[entry.name] = AxisConfig(entry.name, number, values, is_rotary, spindle, entry.sim, plant,
                                            entry.drive)
        self._check_gearbox_io()
        self._check_chuck_io()
        return result

    def _check_generator(self, entry: _AxisEntry) -> None:
        """Generator operation needs the DC link it buffers, the Vdc_min controller on, a threshold
        between where the pulses go and where the supply holds the link, the motor's inertia and a
        minimum speed the drive can tell from standstill."""
        drive, mark = entry.drive, entry.drive_mark
        if not drive.generator or mark is None:
            return
        where = f"{entry.name}: drive p0888 = 3 (generator operation)"
        if self.dc_link is None:
            self.add(mark, f"{where} needs the DC link it buffers: a dc_link: section")
        else:
            lowest = PULSE_CANCELLATION_PER_SUPPLY_VOLT * self.dc_link.supply_voltage
            highest = DC_LINK_PER_SUPPLY_VOLT * self.dc_link.supply_voltage
            if not lowest < drive.p1248 < highest:
                self.add(mark, f"{where}: p1248 = {drive.p1248:g} V must lie between the pulse cancellation"
                               f" at {lowest:g} V and the link's {highest:g} V on the supply")
        if drive.p1240 != 2:
            self.add(mark, f"{where} needs p1240 = 2 (the Vdc_min controller brakes the motor under ESR)")
        if drive.p0341 <= 0:
            self.add(mark, f"{where} needs p0341, the motor's moment of inertia (kg m^2), above 0")
        if drive.p2161 <= SPEED_HYSTERESIS:
            self.add(mark, f"{where} needs p2161, the minimum generator speed, above the speed comparison's"
                           f" hysteresis {SPEED_HYSTERESIS:g} rev/min (got {drive.p2161:g})")

    def _build_gearbox(self, entry: _AxisEntry, spindle: int) -> GearboxPlant | None:
        """The axis's gearbox, checked against its machine data and the I/O list; None without one."""
        declared = entry.gearbox_mark
        if declared is None:
            return None
        written = entry.gearbox
        missing = [f"{key} ({meaning})" for key, meaning in _REQUIRED_GEARBOX_KEYS.items()
                   if key not in entry.gearbox_keys]
        if missing:
            self.add(declared, f"{entry.name}: plant.gearbox lacks {' and '.join(missing)}")
        if not spindle:
            self.add(declared, f"{entry.name}: plant.gearbox on an axis that is not a spindle"
                               " (MD35000 SPIND_ASSIGN_TO_MACHAX = 0); only a spindle changes gear stages")
        if "stages" not in written:
            return None
        stages = int(written["stages"].value)
        configured = int(entry.data.value(mdd.NUM_GEAR_STEPS))
        if spindle and stages != configured:
            # at MD35090 where it is written (a scenario may change it), else at the stages
            if entry.data.is_written(mdd.NUM_GEAR_STEPS):
                mark, default = entry.data.mark_of(mdd.NUM_GEAR_STEPS), ""
            else:
                mark, default = written["stages"].mark, " (the default)"
            self.add(mark, f"{entry.name}: plant.gearbox.stages = {stages}, but MD35090 NUM_GEAR_STEPS ="
                           f" {configured}{default}")
        engaged = written.get("engaged")
        if engaged is not None and int(engaged.value) > stages:
            self.add(engaged.mark, f"{entry.name}: plant.gearbox.engaged = {engaged.value}: the gearbox has"
                                   f" {_count(stages, 'stage', 'stages')} (0 = neutral)")
        needed = [*(gear_shift(entry.name, stage) for stage in range(1, stages + 1)),
                  *(gear_engaged(entry.name, stage) for stage in range(1, stages + 1))]
        unwired = [name for name in needed if name not in self.plant_io_names]
        if unwired:
            self.add(declared, f"{entry.name}: the gearbox's I/O is not wired in plant_io: {', '.join(unwired)}")
        if "shift_time" not in written:
            return None
        return GearboxPlant(stages, float(written["shift_time"].value),
                            int(engaged.value) if engaged is not None else 1)

    def _check_gearbox_io(self) -> None:
        """Gearbox I/O needs a gearbox with that stage: a sensor no gearbox drives reads 0 for ever."""
        for name, (key, mark) in self.plant_io_names.items():
            point = gearbox_point(name)
            if point is None or point.axis not in self.axes:
                continue  # not gearbox I/O, or an unknown axis (the I/O list check reports it)
            entry = self.axes[point.axis]
            if entry.gearbox_mark is None:
                self.add(mark, f"plant_io {key}: {name} needs a gearbox on {point.axis}"
                               " (plant: {gearbox: {stages: n, shift_time: s}})")
                continue
            stages = entry.gearbox.get("stages")
            if stages is not None and point.stage > int(stages.value):
                self.add(mark, f"plant_io {key}: {name}: the gearbox of {point.axis} has"
                               f" {_count(int(stages.value), 'stage', 'stages')}")

    def _build_chuck(self, entry: _AxisEntry, spindle: int) -> ChuckPlant | None:
        """The spindle's chuck, checked against the I/O list; None without one."""
        declared = entry.chuck_mark
        if declared is None:
            return None
        if not spindle:
            self.add(declared, f"{entry.name}: plant.chuck on an axis that is not a spindle"
                               " (MD35000 SPIND_ASSIGN_TO_MACHAX = 0)")
        unwired = [name for name in (chuck_close(entry.name), chuck_release(entry.name), chuck_closed(entry.name))
                   if name not in self.plant_io_names]
        if unwired:
            self.add(declared, f"{entry.name}: the chuck's I/O is not wired in plant_io: {', '.join(unwired)}")
        travel = entry.chuck.get("travel_time")
        if travel is None:
            self.add(declared, f"{entry.name}: plant.chuck lacks travel_time (the seconds of the chuck's stroke)")
            return None
        closed = entry.chuck.get("closed")
        return ChuckPlant(float(travel.value), bool(closed.value) if closed is not None else True)

    def _check_chuck_io(self) -> None:
        """Chuck I/O needs a chuck: its sensors would read 0 for ever."""
        for name, (key, mark) in self.plant_io_names.items():
            axis = chuck_axis(name)
            if axis is not None and axis in self.axes and self.axes[axis].chuck_mark is None:
                self.add(mark, f"plant_io {key}: {name} needs a chuck on {axis} (plant: {{chuck: {{travel_time: s}}}})")

    def _build_channel(self, number: int, entry: _ChannelEntry,
                       axes: Mapping[str, AxisConfig]) -> ChannelConfig:
        data = entry.data
        geometry_names = self._geometry_names(entry)
        program_names: tuple[str, ...] = ()
        geometry_axes: tuple[str, ...] = ("",) * len(geometry_names)
        if entry.axes:  # a channel without a readable axes list has been reported already
            program_names = self._program_names(entry)
            geometry_axes = self._geometry_axes(entry, axes, geometry_names, program_names)
            self._check_coupling(entry)
            self._check_master_spindle(entry, axes)
        return ChannelConfig(entry.name, number, MachineData(entry.name, data.values()), tuple(entry.axes),
                             program_names, geometry_names, geometry_axes)

    def _program_names(self, entry: _ChannelEntry) -> tuple[str, ...]:
        md = mdd.AXCONF_CHANAX_NAME_TAB
        written = entry.data.written.get(md.number, {})
        for index, item in sorted(written.items(), key=lambda pair: pair[0] or 0):
            assert index is not None
            if index >= len(entry.axes) and item.value:
                self.add(item.mark, f"{md.label}[{index}] = '{item.value}': {entry.name} has only"
                                    f" {_count(len(entry.axes), 'axis', 'axes')}")
        names: list[str] = []
        for index, axis in enumerate(entry.axes):
            name = str(entry.data.value(md, index)) or axis
            mark = entry.data.mark_of(md, index)
            if not _NAME.match(name):
                self.add(mark,
                         f"{md.label}[{index}] = '{name}' is not a name (a letter, then letters, digits, _)")
            elif name in names:
                self.add(mark, f"{md.label}[{index}]: {entry.name} already has a channel axis named {name}")
            names.append(name)
        return tuple(names)

    def _geometry_names(self, entry: _ChannelEntry) -> tuple[str, ...]:
        md = mdd.AXCONF_GEOAX_NAME_TAB
        names: list[str] = []
        for index in range(md.length):
            name = str(entry.data.value(md, index))
            mark = entry.data.mark_of(md, index)
            if not _NAME.match(name):
                self.add(mark,
                         f"{md.label}[{index}] = '{name}' is not a name (a letter, then letters, digits, _)")
            elif name in names:
                self.add(mark, f"{md.label}[{index}]: geometry axis {name} is named twice")
            names.append(name)
        return tuple(names)

    def _geometry_axes(self, entry: _ChannelEntry, axes: Mapping[str, AxisConfig],
                       geometry_names: tuple[str, ...], program_names: tuple[str, ...]) -> tuple[str, ...]:
        md = mdd.AXCONF_GEOAX_ASSIGN_TAB
        result: list[str] = []
        used: dict[int, str] = {}
        for index, geometry_name in enumerate(geometry_names):
            channel_axis = int(entry.data.value(md, index))
            mark = entry.data.mark_of(md, index)
            label = f"{md.label}[{index}] = {channel_axis}"
            if channel_axis == 0:
                result.append("")
                continue
            if channel_axis > len(entry.axes):
                default = "" if entry.data.is_written(md) else " (the default)"
                self.add(mark,
                         f"{label}{default}: geometry axis {geometry_name} names channel axis {channel_axis},"
                         f" but {entry.name} has {_count(len(entry.axes), 'axis', 'axes')}")
                result.append("")
                continue
            machine_axis = entry.axes[channel_axis - 1]
            if channel_axis in used:
                self.add(mark,
                         f"{label}: geometry axes {used[channel_axis]} and {geometry_name} both use channel"
                         f" axis {channel_axis} ({machine_axis})")
            used[channel_axis] = geometry_name
            if machine_axis in axes and axes[machine_axis].is_spindle:
                self.add(mark, f"{label}: geometry axis {geometry_name} would be the spindle {machine_axis}")
            if geometry_name in program_names and program_names.index(geometry_name) != channel_axis - 1:
                self.add(mark, f"{label}: geometry axis {geometry_name} is channel axis {channel_axis}"
                               f" ({machine_axis}), but MD20080 gives the name {geometry_name} to channel"
                               " axis"
                               f" {program_names.index(geometry_name) + 1}")
            result.append(machine_axis)
        return tuple(result)

    def _check_coupling(self, entry: _ChannelEntry) -> None:
        md = mdd.COUPLE_AXIS_1
        machine_axes = list(self.axes)
        for index in range(md.length):
            number = int(entry.data.value(md, index))
            if number and (number > len(machine_axes) or machine_axes[number - 1] not in entry.axes):
                self.add(entry.data.mark_of(md, index),
                         f"{md.label}[{index}] = {number}: machine axis {number} is not an axis of"
                         f" {entry.name}")
        numbers = [int(entry.data.value(md, index)) for index in range(md.length)]
        if all(numbers) and max(numbers) <= len(machine_axes):
            self._check_coupled_control_parameters(*(self.axes[machine_axes[number - 1]] for number in numbers))

    def _check_coupled_control_parameters(self, following: _AxisEntry, leading: _AxisEntry) -> None:
        """LS and FS of the configured pair need like control parameters (L23736-23748).  The seed
        names no alarm; the control does not check them [control], this loader refuses the machine
        so that the pair does not run with unlike setpoints."""
        for md in COUPLED_LIKE_PARAMETERS:
            fs_value, ls_value = following.data.value(md), leading.data.value(md)
            if fs_value != ls_value:
                self.add(following.data.mark_of(md),
                         f"{md.label} = {fs_value} on {following.name}, {ls_value} on {leading.name}: the"
                         f" synchronous spindle pair of MD21300 needs the same value on both (seed 003 L23736-23748)")

    def _check_master_spindle(self, entry: _ChannelEntry, axes: Mapping[str, AxisConfig]) -> None:
        md = mdd.SPIND_DEF_MASTER_SPIND
        master = int(entry.data.value(md))
        spindles = sorted({axes[name].spindle_number for name in entry.axes
                           if name in axes and axes[name].is_spindle})
        if master == 0 and spindles:
            self.add(entry.data.mark_of(md),
                     f"{md.label} = 0: {entry.name} has spindles ({', '.join(str(number) for number in spindles)});"
                     " S, M3, M4 and M5 without a spindle number address the master spindle, so it needs one")
            return
        if master == 0 or master in spindles or not (spindles or entry.data.is_written(md)):
            return
        default = "" if entry.data.is_written(md) else " (the default)"
        own = ", ".join(str(number) for number in spindles) or "none"
        self.add(entry.data.mark_of(md),
                 f"{md.label} = {master}{default}: {entry.name} has no spindle {master}"
                 f" (its spindles: {own})")


def _whole_number(raw: Any, lowest: int, highest: int) -> int | None:
    """``raw`` as a whole number in ``lowest .. highest``, else None."""
    number = as_number(raw)
    if number is None or not float(number).is_integer() or not lowest <= number <= highest:
        return None
    return int(number)


def _count(number: int, singular: str, plural: str) -> str:
    return f"{number} {singular if number == 1 else plural}"
