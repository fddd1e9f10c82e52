"""The machine as read from its file and a scenario's overrides, before the rules across it are
checked: the machine data of each level instance with the mark of each value, the axes with
their ``sim:``, ``plant:`` and ``drive:``, the channels with their axes, the plant I/O.

Reading fills it (vc/config/reader/reading.py, blocks.py, overrides.py), checking applies the
rules that relate its values (checking.py), building makes the frozen configuration of it
(building.py).  What more than one of them derives from it (a channel's axis names, an axis's
spindle number) is derived here, once.
"""

from __future__ import annotations

import re
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

from interfaces.plant_io import PlantIoMap
from interfaces.signals import NCK_INSTANCE
from vc.config import md_dictionary as mdd
from vc.config.can_config import CanSection
from vc.config.machine_data import MdDef, MdLevel, MdScalar, MdValue
from vc.config.model import AxisPlant, AxisSimulation, DcLinkConfig, DriveParameters, MachinePlant
from vc.located_yaml import Mark

DEFAULT_PLC_CYCLE_IPO = 5
NAME = re.compile(r"^[A-Za-z][A-Za-z0-9_]*$")  # an instance, channel axis or geometry axis name


@dataclass(slots=True)
class Written:
    value: MdScalar
    mark: Mark


@dataclass(slots=True)
class Instance:
    """Machine data written for one level instance (the NCK, a channel or an axis)."""

    level: MdLevel
    name: str
    mark: Mark  # where the instance is declared: the mark for problems with defaults
    written: dict[int, dict[int | None, Written]] = field(default_factory=dict)

    def value(self, md: MdDef, index: int | None = None) -> MdScalar:
        entries = self.written.get(md.number)  # asked for dozens of times a load: no empty dict each time
        written = entries.get(index) if entries is not None else None
        if written is not None:
            return written.value
        default = md.default
        if isinstance(default, tuple):
            return default[0 if index is None else index]
        return default

    def mark_of(self, md: MdDef, index: int | None = None) -> Mark:
        """Where the effective value comes from: its last write, else the instance."""
        entries = self.written.get(md.number)
        if entries:
            if index in entries:
                return entries[index].mark
            if index is None:
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
        self.written[md.number] = {index: Written(value, mark) for index, value in enumerate(items)}


@dataclass(frozen=True, slots=True)
class Marks:
    """Marks of located YAML values, with a fallback for mappings built in code without marks."""

    fallback: Mark

    def of(self, value: Any) -> Mark:
        mark = getattr(value, "mark", None)
        return mark if isinstance(mark, Mark) else self.fallback

    def key(self, mapping: Mapping[str, Any], key: str) -> Mark:
        return self._marked(mapping, getattr(mapping, "key_marks", None), key)

    def value(self, mapping: Mapping[str, Any], key: str) -> Mark:
        return self._marked(mapping, getattr(mapping, "value_marks", None), key)

    def _marked(self, mapping: Mapping[str, Any], marks: Any, key: str) -> Mark:
        # the mapping's own mark only where the key has none: reading asks twice for every key it reads
        mark = marks.get(key) if isinstance(marks, dict) else None
        return mark if isinstance(mark, Mark) else self.of(mapping)

    def item(self, items: list[Any], index: int) -> Mark:
        marks = getattr(items, "item_marks", None)
        return marks[index] if isinstance(marks, list) and index < len(marks) else self.of(items)


@dataclass(slots=True)
class AxisEntry:
    name: str
    mark: Mark
    data: Instance
    sim: AxisSimulation = field(default_factory=AxisSimulation)
    plant: AxisPlant = field(default_factory=AxisPlant)  # without gearbox and chuck, which building makes
    channel: str = ""
    gearbox: dict[str, Written] = field(default_factory=dict)  # plant.gearbox keys: file, then overrides
    gearbox_keys: set[str] = field(default_factory=set)  # every key written, also those with a bad value
    gearbox_mark: Mark | None = None  # where the gearbox is first declared; None = no gearbox
    chuck: dict[str, Written] = field(default_factory=dict)  # plant.chuck keys: file, then overrides
    chuck_mark: Mark | None = None  # where the chuck is first declared; None = no chuck
    drive: DriveParameters = field(default_factory=DriveParameters)
    drive_mark: Mark | None = None  # where drive: is written last

    @property
    def spindle_number(self) -> int:
        """MD35000 SPIND_ASSIGN_TO_MACHAX: 0 = not a spindle."""
        return int(self.data.value(mdd.SPIND_ASSIGN_TO_MACHAX))

    @property
    def is_spindle(self) -> bool:
        return self.spindle_number > 0


@dataclass(slots=True)
class ChannelEntry:
    name: str
    mark: Mark
    data: Instance
    axes: list[str] = field(default_factory=list)

    def program_names(self) -> tuple[str, ...]:
        """The name of each channel axis in part programs: MD20080, else the machine axis's name."""
        return tuple([str(self.data.value(mdd.AXCONF_CHANAX_NAME_TAB, index)) or axis
                      for index, axis in enumerate(self.axes)])

    def geometry_names(self) -> tuple[str, ...]:
        md = mdd.AXCONF_GEOAX_NAME_TAB
        return tuple([str(self.data.value(md, index)) for index in range(md.length)])

    def geometry_axis(self, index: int) -> str:
        """The machine axis serving geometry axis ``index`` (MD20050); "" for none, or for a channel
        axis the channel does not have."""
        channel_axis = int(self.data.value(mdd.AXCONF_GEOAX_ASSIGN_TAB, index))
        return self.axes[channel_axis - 1] if 0 < channel_axis <= len(self.axes) else ""


@dataclass(slots=True)
class LocatedMachine:
    """One machine file as read, and the overrides read over it."""

    path: str
    name: str = ""
    plc_cycle_ipo: int = DEFAULT_PLC_CYCLE_IPO
    nck: Instance = field(init=False)
    axes: dict[str, AxisEntry] = field(default_factory=dict)
    channels: dict[str, ChannelEntry] = field(default_factory=dict)
    plant_io: PlantIoMap = field(default_factory=lambda: PlantIoMap(()))
    plant_io_names: dict[str, tuple[str, Mark]] = field(default_factory=dict)  # function -> address text, mark
    plc_parameters: dict[str, Any] = field(default_factory=dict)
    dc_link: DcLinkConfig | None = None
    can: CanSection = field(default_factory=CanSection)
    can_mark: Mark | None = None  # where the ``can:`` section is; None: there is none
    plant: MachinePlant = field(default_factory=MachinePlant)  # ``plant:``, the devices besides the axes
    plc_alarms: dict[int, str] = field(default_factory=dict)  # ``plc_alarms:``
    channel_lists_complete: bool = True  # every channel's axes list could be read

    def __post_init__(self) -> None:
        self.nck = Instance(MdLevel.NCK, NCK_INSTANCE, Mark(self.path, 1, 1))

    def instance(self, name: str) -> Instance | None:
        """The NCK's, an axis's or a channel's machine data by the name a scenario gives it."""
        if name == NCK_INSTANCE:
            return self.nck
        if name in self.axes:
            return self.axes[name].data
        if name in self.channels:
            return self.channels[name].data
        return None


def count(number: int, singular: str, plural: str) -> str:
    return f"{number} {singular if number == 1 else plural}"
