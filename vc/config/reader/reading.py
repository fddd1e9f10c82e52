"""A machine file's document into a :class:`~vc.config.reader.located.LocatedMachine`: its top
level, its axes (machine axis order), its channels with their axes lists, its plant I/O list,
its ``can:`` section (vc/config/can_config.py), its DC link, its devices besides the axes
(``plant:``) and its PLC user alarm texts (``plc_alarms:``, both vc/config/devices.py).

The blocks an axis, a channel or the NCK writes are read by vc/config/reader/blocks.py, which the
overrides share.  Every value is checked alone as it is read; a value that cannot be read is
reported and left out, and reading goes on, so that one run reports every problem of the file.
"""

from __future__ import annotations

from typing import Any

from interfaces.plant_io import DEVICE_PREFIXES, PlantIoError, PlantIoMap
from vc.config import md_dictionary as mdd
from vc.config.can_config import read_can_section
from vc.config.devices import read_plant, read_plc_alarms
from vc.config.machine_data import MdDef, MdLevel, MdScalar, as_number, shown
from vc.config.model import DcLinkConfig
from vc.config.reader.blocks import AXIS_EXTRA_KEYS, DC_LINK_KEYS, BlockReader
from vc.config.reader.located import NAME, AxisEntry, ChannelEntry, Instance, LocatedMachine, Marks
from vc.located_yaml import LocatedMap, Mark, Problems

TOP_LEVEL_KEYS = ("machine", "description", "plc_cycle_ipo", "nck", "channels", "axes", "plant_io", "plc", "can",
                  "dc_link", "plant", "plc_alarms")
_OPTIONAL_DC_LINK_KEYS = ("precharge_time",)
# Instance names the interface and the plant I/O vocabulary already use.
RESERVED_NAMES = frozenset({"NC", "MODEGROUP", "HMI", "ALARMS", "MCP", "EStop", "Drives", "Lamp", "Door", "Lube",
                            "PLC", "PLCALARMS", *DEVICE_PREFIXES})  # PLC: the FMU
MAX_CHANNELS = 10  # DB21..DB30: channel 11 would collide with DB31 of machine axis 1
MAX_AXES = 31  # MD10000 has 31 entries
MAX_CHANNEL_AXES = 20  # MD20070 has 20 entries
_PLACE_IN_FILE = {MdLevel.NCK: "under nck", MdLevel.CHANNEL: "under a channel", MdLevel.AXIS: "under an axis"}


def read_machine(document: Any, path: str, problems: Problems) -> LocatedMachine:
    """The machine ``document`` describes (the parsed file at ``path``), as far as it can be read."""
    reader = _FileReader(LocatedMachine(path), BlockReader(problems, Marks(Mark(path, 1, 1))))
    reader.read(document)
    return reader.machine


class _FileReader:
    def __init__(self, machine: LocatedMachine, blocks: BlockReader):
        self.machine = machine
        self.blocks = blocks
        self.marks = blocks.marks
        self.add = blocks.add

    # ------------------------------------------------------------------ top level

    def read(self, document: Any) -> None:
        machine = self.machine
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
            machine.nck.mark = document.mark_of_key("nck")
            nck = self._mapping(document["nck"], document.mark_of("nck"), "nck")
            if nck is not None:
                self.blocks.machine_data(nck, machine.nck, _PLACE_IN_FILE)
        self._read_axes(document)
        self._read_channels(document)
        if "plant_io" in document:
            self._read_plant_io(document["plant_io"], document.mark_of("plant_io"))
        if "plc" in document:
            parameters = self._mapping(document["plc"], document.mark_of("plc"), "plc")
            if parameters is not None:
                machine.plc_parameters = dict(parameters)
        if "can" in document:
            machine.can_mark = document.mark_of_key("can")
            machine.can = read_can_section(document["can"], document.mark_of("can"), self.blocks.problems)
        if "dc_link" in document:
            self._read_dc_link(document["dc_link"], document.mark_of("dc_link"))
        # the devices besides the axes and the PLC alarm texts, after plant_io: a device needs its I/O
        machine.plant = read_plant(document.get("plant"), document.mark_of("plant"), self.blocks.problems,
                                   machine.plant_io_names, self.blocks.parameters, tuple(machine.axes))
        machine.plc_alarms = read_plc_alarms(document.get("plc_alarms"), document.mark_of("plc_alarms"),
                                             self.blocks.problems)

    def _read_dc_link(self, raw: Any, mark: Mark) -> None:
        values = self.blocks.parameters(raw, mark, "dc_link", DC_LINK_KEYS)
        required = [key for key in DC_LINK_KEYS if key not in _OPTIONAL_DC_LINK_KEYS]
        unwritten = [key for key in required if not isinstance(raw, dict) or key not in raw]
        if unwritten and (raw is None or isinstance(raw, dict)):  # an empty dc_link: is no DC link either
            self.add(mark, f"dc_link: missing {', '.join(unwritten)}")
        if all(key in values for key in required):
            self.machine.dc_link = DcLinkConfig(**values)

    def _read_name(self, document: LocatedMap) -> None:
        if "machine" not in document:
            self.add(document.mark, "missing 'machine:' (the name of the machine)")
        else:
            name = document["machine"]
            if isinstance(name, str) and name.strip():
                self.machine.name = name.strip()
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
            self.machine.plc_cycle_ipo = int(number)

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
        if not NAME.match(name):
            self.add(mark,
                     f"{kind} name '{name}' must start with a letter and use only letters, digits and _")
            return False
        if name in RESERVED_NAMES:
            self.add(mark, f"{kind} name '{name}' is reserved ({', '.join(sorted(RESERVED_NAMES))})")
            return False
        return True

    # ------------------------------------------------------------------ axes

    def _read_axes(self, document: LocatedMap) -> None:
        machine = self.machine
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
            if len(machine.axes) == MAX_AXES:
                self.add(key_mark, f"axis {name}: a machine has at most {MAX_AXES} axes (MD10000)")
                continue
            entry = AxisEntry(name, key_mark, Instance(MdLevel.AXIS, name, key_mark))
            machine.axes[name] = entry
            block = self._mapping(raw, axes.mark_of(name), f"axes.{name}")
            if block is None:
                continue
            self.blocks.machine_data(block, entry.data, _PLACE_IN_FILE, extra_keys=AXIS_EXTRA_KEYS)
            self.blocks.axis_extras(entry, block, f"axes.{name}")
        machine.nck.set_derived(mdd.AXCONF_MACHAX_NAME_TAB, _padded(mdd.AXCONF_MACHAX_NAME_TAB, tuple(machine.axes)),
                                machine.nck.mark)

    # ------------------------------------------------------------------ channels

    def _read_channels(self, document: LocatedMap) -> None:
        machine = self.machine
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
                machine.channel_lists_complete = False
                continue
            if name in machine.axes:
                self.add(key_mark, f"channel name '{name}' is already the name of an axis")
                machine.channel_lists_complete = False
                continue
            if len(machine.channels) == MAX_CHANNELS:
                self.add(key_mark,
                         f"channel {name}: a machine has at most {MAX_CHANNELS} channels (DB21..DB30)")
                continue
            entry = ChannelEntry(name, key_mark, Instance(MdLevel.CHANNEL, name, key_mark))
            machine.channels[name] = entry
            block = self._mapping(raw, channels.mark_of(name), f"channels.{name}")
            if block is not None:
                self.blocks.machine_data(block, entry.data, _PLACE_IN_FILE, extra_keys=("axes",))
            if block is None or "axes" not in block:
                machine.channel_lists_complete = False
                if block is not None:
                    self.add(key_mark, f"channel {name} has no 'axes:' list (its machine axes, in channel"
                                       " axis order)")
            elif not self._read_channel_axes(entry, block["axes"], block.mark_of("axes")):
                machine.channel_lists_complete = False
        if not machine.channel_lists_complete:
            return
        for axis in machine.axes.values():
            if not axis.channel:
                self.add(axis.mark, f"axis {axis.name} is in no channel; list it in a channel's axes")

    def _read_channel_axes(self, channel: ChannelEntry, raw: Any, mark: Mark) -> bool:
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
            axis = self.machine.axes.get(item)
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
        numbers = tuple(list(self.machine.axes).index(name) + 1 for name in channel.axes)
        used = _padded(mdd.AXCONF_MACHAX_USED, numbers, 0)
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
                self.machine.plant_io_names.setdefault(value.strip(), (key, block.mark_of_key(key)))
            else:
                self.add(value_mark,
                         f"plant_io {key}: expected a plant function such as MCP.auto, got {shown(value)}")
        try:
            self.machine.plant_io = PlantIoMap.from_mapping(entries, self.machine.axes)
        except PlantIoError as error:
            for key, message in error.problems:
                self.add(block.mark_of_key(key), f"plant_io {key}: {message}")


def _padded(md: MdDef, items: tuple[MdScalar, ...], filler: MdScalar | None = None) -> tuple[MdScalar, ...]:
    """``items`` from index 0, the rest ``filler`` or (without one) the defaults of ``md``."""
    assert isinstance(md.default, tuple)
    rest = md.default[len(items):] if filler is None else (filler,) * (md.length - len(items))
    return items + tuple(rest)
