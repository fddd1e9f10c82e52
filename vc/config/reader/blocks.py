"""The blocks of one level instance that a machine file and a scenario's overrides both write:
its machine data, an axis's ``sim:``, ``plant:`` and ``drive:``, and the DC link's parameters.

Each value is checked alone as it is read (the datum's type, range and level, the keys a block
takes); what relates it to other values is checked once everything is read
(vc/config/reader/checking.py).  A block written over another replaces its values index by
index and key by key.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping
from typing import Any

from interfaces.plant_io import MAX_GEAR_STAGES
from vc.config import md_dictionary as mdd
from vc.config.machine_data import MdDef, MdLevel, MdScalar, MdValueError, as_number, checked_value, shown
from vc.config.model import EXTENDED_RETRACT, EXTENDED_STOP
from vc.config.reader.located import AxisEntry, Instance, Marks, Written, count
from vc.located_yaml import Mark, Problems

SIM_KEYS = ("start_position", "zero_mark_offset", "zero_mark_offset_2", "encoder_serial", "encoder_serial_2")
_WHOLE_SIM_KEYS = ("encoder_serial", "encoder_serial_2")
AXIS_EXTRA_KEYS = ("sim", "plant", "drive")  # an axis block's keys besides machine data
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
    "messages": (0, 1, True, "1 = the drive reports its messages DB31.DBX94.x / 95.0"),
    "p0604": (0, 300, False, "degC, motor temperature warning threshold"),
    "p2155": (0, 210_000, False, "rev/min, speed threshold n x"),
    "p2163": (0, 210_000, False, "rev/min, tolerance of n act = n set"),
    "p2172": (0, 2000, False, "V, DC-link voltage threshold"),
    "p2174": (0, 800, False, "percent of the maximum torque, torque threshold Mdx"),
    "p2176": (0, 10_000, False, "ms, delay of the torque threshold"),
}
# the drive parameters that act in generator operation alone (p0888 = 3)
GENERATOR_KEYS = ("p0892", "p1240", "p1248", "p0341", "p0342")
# those that act with the drive's messages (``messages: 1``); p2161 serves both
MESSAGE_KEYS = ("p0604", "p2155", "p2163", "p2172", "p2174", "p2176")
# the drive line-up's DC link under ``dc_link:`` (the first three needed)
DC_LINK_KEYS: dict[str, tuple[float, float, bool, str]] = {
    "supply_voltage": (1, 1000, False, "V, rated supply voltage r0208"),
    "capacitance_uf": (1, 10_000_000, False, "uF, DC-link capacitance"),
    "load_power": (0, 1_000_000, False, "W, what the line-up draws from the link without supply"),
    "precharge_time": (0, 60, False, "s, empty link to charged through the precharge resistors"),
}
_DERIVED = {
    mdd.AXCONF_MACHAX_NAME_TAB.number: "the names under axes:, in order",
    mdd.AXCONF_MACHAX_USED.number: "the channel's axes: list",
}


class BlockReader:
    """Reads blocks into a located machine; ``marks`` gives the marks of their values (with the
    fallback for mappings built in code), every problem goes to ``problems``."""

    def __init__(self, problems: Problems, marks: Marks):
        self.problems = problems
        self.marks = marks

    def add(self, mark: Mark, message: str) -> None:
        self.problems.add(mark, message)

    def any_mapping(self, raw: Any, mark: Mark, where: str) -> Mapping[str, Any]:
        """``raw`` as a mapping (located or built in code); a problem and an empty one otherwise."""
        if raw is None:
            return {}
        if not isinstance(raw, dict):
            self.add(mark, f"{where}: expected a mapping, got {shown(raw)}")
            return {}
        return raw

    # ------------------------------------------------------------------ machine data

    def machine_data(self, block: Mapping[str, Any], instance: Instance, place: Mapping[MdLevel, str],
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

    def _values(self, parsed: mdd.MdKey, raw: Any, mark: Mark) -> dict[int | None, Written] | None:
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
            result: dict[int | None, Written] = {}
            for index, item in enumerate(raw):
                item_mark = self.marks.item(raw, index)
                value = self._checked(md, item, index, item_mark)
                if value is not None:
                    result[index] = Written(value, item_mark)
            return result if len(result) == len(raw) else None
        if isinstance(raw, (list, dict)):
            self.add(mark, f"{parsed.label} takes one value, got {shown(raw)}")
            return None
        value = self._checked(md, raw, parsed.index, mark)
        return None if value is None else {parsed.index: Written(value, mark)}

    def _checked(self, md: MdDef, raw: Any, index: int | None, mark: Mark) -> MdScalar | None:
        try:
            return checked_value(md, raw, index)
        except MdValueError as error:
            self.add(mark, str(error))
            return None

    # ------------------------------------------------------------------ sim, plant and drive of an axis

    def axis_extras(self, entry: AxisEntry, block: Mapping[str, Any], where: str) -> None:
        """Read an axis block's ``sim:``, ``plant:`` and ``drive:``; the keys written replace the entry's values."""
        if "sim" in block:
            sim = self._sim(block["sim"], self.marks.value(block, "sim"), f"{where}.sim")
            entry.sim = dataclasses.replace(entry.sim, **sim)
        if "plant" in block:
            plant = self._plant(block["plant"], self.marks.value(block, "plant"), f"{where}.plant")
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
            drive = self.parameters(block["drive"], entry.drive_mark, f"{where}.drive", DRIVE_KEYS)
            if drive.get("p0888") in (EXTENDED_STOP, EXTENDED_RETRACT):
                self.add(self.marks.value(block["drive"], "p0888"),
                         f"{where}.drive.p0888 = {drive.pop('p0888')}: extended stop (1) and retract (2) are"
                         f" written by ESRS / ESRR from the part program; the file takes 0 or 3 (generator"
                         f" operation)")
            if "messages" in drive:
                drive["messages"] = bool(drive["messages"])
            entry.drive = dataclasses.replace(entry.drive, **drive)
            ignored = [key for key in drive if key in GENERATOR_KEYS
                       or (key == "p2161" and not entry.drive.messages)]
            if ignored and not entry.drive.generator:  # an override may still switch generator operation off
                self.add(entry.drive_mark, f"{where}.drive: {', '.join(ignored)} belong to generator operation:"
                                           f" without p0888 = 3 the drive would ignore them")
            unheard = [key for key in drive if key in MESSAGE_KEYS]
            if unheard and not entry.drive.messages:
                self.add(entry.drive_mark, f"{where}.drive: {', '.join(unheard)} belong to the drive's messages:"
                                           f" without messages: 1 the drive reports none")

    def parameters(self, raw: Any, mark: Mark, where: str,
                   table: Mapping[str, tuple[float, float, bool, str]]) -> dict[str, Any]:
        """The keys of ``table`` written in ``raw``, each a number inside its range."""
        values: dict[str, Any] = {}
        block = self.any_mapping(raw, mark, where)
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

    def _sim(self, raw: Any, mark: Mark, where: str) -> dict[str, Any]:
        """The ``sim:`` keys written in ``raw``, checked: AxisSimulation field -> value."""
        values: dict[str, Any] = {}
        block = self.any_mapping(raw, mark, where)
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

    def _plant(self, raw: Any, mark: Mark, where: str) -> dict[str, Any]:
        """The ``plant:`` keys written in ``raw``, checked: AxisPlant field -> value."""
        values: dict[str, Any] = {}
        block = self.any_mapping(raw, mark, where)
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
                values["gearbox"] = self._gearbox(value, value_mark, f"{where}.gearbox")
            elif key == "chuck":
                values["chuck"] = self._chuck(value, value_mark, f"{where}.chuck")
            else:
                self.add(key_mark, f"unknown key '{key}' in plant; allowed: {', '.join(PLANT_KEYS)}")
        return values

    def _gearbox(self, raw: Any, mark: Mark, where: str) -> tuple[dict[str, Written], set[str], Mark | None]:
        """The ``plant.gearbox`` keys written in ``raw`` (checked one by one), every key written,
        and where the gearbox is declared (None when ``raw`` is no mapping at all).

        The checks that need the whole axis (MD35000, MD35090, the stage engaged at power-on
        against the stages, the I/O list) come after the overrides (checking.py).
        """
        written: dict[str, Written] = {}
        block = self.any_mapping(raw, mark, where)
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
                written[key] = Written(stages, value_mark)
            elif key == "shift_time":
                seconds = as_number(value)
                if seconds is None or seconds <= 0:
                    self.add(value_mark, "plant.gearbox.shift_time: the seconds the shift actuator must push"
                                         f" while the motor turns, above 0, got {shown(value)}")
                    continue
                written[key] = Written(float(seconds), value_mark)
            elif key == "engaged":
                engaged = _whole_number(value, 0, MAX_GEAR_STAGES)
                if engaged is None:
                    self.add(value_mark, "plant.gearbox.engaged: the gear stage in mesh at power-on, a whole"
                                         f" number from 0 (neutral) to {MAX_GEAR_STAGES}, got {shown(value)}")
                    continue
                written[key] = Written(engaged, value_mark)
        declared = mark if raw is None or isinstance(raw, dict) else None
        return written, {key for key in block if key in GEARBOX_KEYS}, declared

    def _chuck(self, raw: Any, mark: Mark, where: str) -> tuple[dict[str, Written], Mark | None]:
        """The ``plant.chuck`` keys written in ``raw`` (checked one by one) and where the chuck is
        declared (None when ``raw`` is no mapping at all); checking.py checks the rest."""
        written: dict[str, Written] = {}
        block = self.any_mapping(raw, mark, where)
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
                written[key] = Written(float(seconds), value_mark)
            elif not isinstance(value, bool):
                self.add(value_mark, f"plant.chuck.closed: true (clamped at power-on) or false, got {shown(value)}")
            else:
                written[key] = Written(value, value_mark)
        return written, mark if raw is None or isinstance(raw, dict) else None

    def _number(self, raw: Any, mark: Mark, what: str) -> float | None:
        number = as_number(raw)
        if number is None:
            self.add(mark, f"{what}: expected a number, got {shown(raw)}")
            return None
        return float(number)

    def _pair(self, raw: Any, mark: Mark, what: str, form: str,
              allow_null: bool) -> tuple[float | None, float | None] | None:
        if not isinstance(raw, list) or len(raw) != 2:
            got = count(len(raw), "value", "values") if isinstance(raw, list) else shown(raw)
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


def _whole_number(raw: Any, lowest: int, highest: int) -> int | None:
    """``raw`` as a whole number in ``lowest .. highest``, else None."""
    number = as_number(raw)
    if number is None or not float(number).is_integer() or not lowest <= number <= highest:
        return None
    return int(number)
