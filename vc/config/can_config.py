"""The ``can:`` section of a machine file: how the interface travels over CAN.

::

    can:
      ids:                # first identifiers, 11 bit (defaults shown)
        link: 0x100       # NC link frame; the PLC link frame is link + 1, the description link + 2
        nc_to_plc: 0x200  # the NC-to-PLC data frames count up from here, in link order
        plc_to_nc: 0x400  # the PLC-to-NC data frames
      fd: true            # CAN FD frames of up to 64 bytes; false: classic frames of 8
      checksum: true      # CRC-8 in the last byte of every data frame
      period: plc         # NC-to-PLC frames: plc = with every PLC scan, ipo = every IPO cycle, or seconds
                          # (a whole number of IPO cycles, e.g. 0.004)
      timeout: 0.05       # seconds: a PLC-to-NC frame missing for longer stops the PLC's sign of life

Every key is optional; a machine file without the section uses the defaults.  Frame layout and
identifiers: :mod:`interfaces.codec_can`.  Every problem is reported with ``file:line:column``.

Until the machine loader takes the section itself (the key ``can`` among its top-level keys, and
:func:`read_can_section` called from it), :func:`can_config_of` reads it from the machine file.
"""

from __future__ import annotations

import os
from dataclasses import dataclass, field
from typing import Any

from interfaces.catalog import load_catalog
from interfaces.codec_can import (
    DEFAULT_LINK_ID,
    DEFAULT_NC_TO_PLC_ID,
    DEFAULT_PLC_TO_NC_ID,
    MAX_STANDARD_ID,
    CanLayout,
    CanMapError,
    CanSettings,
)
from interfaces.signals import expand
from vc.config.machine_data import as_number, shown
from vc.config.model import MachineConfig, machine_ipo_cycle_us
from vc.located_yaml import LocatedMap, Mark, Problems, load_file

SECTION = "can"
KEYS = ("ids", "fd", "checksum", "period", "timeout")
ID_KEYS = {"link": "link_id", "nc_to_plc": "nc_to_plc_id", "plc_to_nc": "plc_to_nc_id"}
PERIOD_PLC = "plc"  # with every PLC scan
PERIOD_IPO = "ipo"  # every IPO cycle
DEFAULT_TIMEOUT_S = 0.05


@dataclass(frozen=True, slots=True)
class CanConfig:
    settings: CanSettings = field(default_factory=CanSettings)  # what the PLC must agree on
    period: str | float = PERIOD_PLC  # PERIOD_PLC, PERIOD_IPO or seconds
    timeout_s: float = DEFAULT_TIMEOUT_S
    period_mark: Mark | None = None  # where the period is written, for the check against the IPO cycle

    def period_cycles(self, ipo_cycle_us: int, plc_cycle_ipo: int) -> int:
        """IPO cycles between two transmissions of the NC-to-PLC frames (checked whole by can_config_of)."""
        if self.period == PERIOD_PLC:
            return plc_cycle_ipo
        if self.period == PERIOD_IPO:
            return 1
        return max(1, round(float(self.period) * 1_000_000 / ipo_cycle_us))

    def timeout_cycles(self, ipo_cycle_us: int) -> int:
        return max(1, round(self.timeout_s * 1_000_000 / ipo_cycle_us))


def read_can_section(raw: Any, mark: Mark, problems: Problems) -> CanConfig:
    """The section's values; each problem goes to ``problems`` and its default is used."""
    if raw is None:
        return CanConfig()
    if not isinstance(raw, LocatedMap):
        problems.add(mark, f"can: expected a mapping with {', '.join(KEYS)}, got {shown(raw)}")
        return CanConfig()
    for key in raw:
        if key not in KEYS:
            problems.add(raw.mark_of_key(key), f"unknown key '{key}' in can; allowed: {', '.join(KEYS)}")
    identifiers = {"link_id": DEFAULT_LINK_ID, "nc_to_plc_id": DEFAULT_NC_TO_PLC_ID,
                   "plc_to_nc_id": DEFAULT_PLC_TO_NC_ID}
    ids = raw.get("ids")
    if isinstance(ids, LocatedMap):
        for key, value, value_mark in ids.located_items():
            if key not in ID_KEYS:
                problems.add(ids.mark_of_key(key), f"unknown key '{key}' in can.ids; allowed: {', '.join(ID_KEYS)}")
            elif isinstance(value, bool) or not isinstance(value, int) or not 0 <= value <= MAX_STANDARD_ID:
                problems.add(value_mark, f"can.ids.{key}: expected an 11-bit identifier 0..0x{MAX_STANDARD_ID:X}"
                             f" (e.g. 0x200), got {shown(value)}")
            else:
                identifiers[ID_KEYS[key]] = value
    elif "ids" in raw:
        problems.add(raw.mark_of("ids"), f"can.ids: expected a mapping with {', '.join(ID_KEYS)}, got {shown(ids)}")
    flags = {"fd": True, "checksum": True}
    for key in flags:
        if key in raw:
            if isinstance(raw[key], bool):
                flags[key] = raw[key]
            else:
                problems.add(raw.mark_of(key), f"can.{key}: expected true or false, got {shown(raw[key])}")
    period: str | float = PERIOD_PLC
    if "period" in raw:
        value = raw["period"]
        number = as_number(value)
        if value in (PERIOD_PLC, PERIOD_IPO):
            period = str(value)
        elif number is not None and number > 0:
            period = float(number)
        else:
            problems.add(raw.mark_of("period"), f"can.period: expected {PERIOD_PLC}, {PERIOD_IPO} or seconds"
                         f" greater than 0 (e.g. 0.004), got {shown(value)}")
    timeout = DEFAULT_TIMEOUT_S
    if "timeout" in raw:
        number = as_number(raw["timeout"])
        if number is None or number <= 0:
            problems.add(raw.mark_of("timeout"), f"can.timeout: expected seconds greater than 0 (e.g. 0.05),"
                         f" got {shown(raw['timeout'])}")
        else:
            timeout = float(number)
    settings = CanSettings(identifiers["link_id"], identifiers["nc_to_plc_id"], identifiers["plc_to_nc_id"],
                           flags["fd"], flags["checksum"])
    return CanConfig(settings, period, timeout, raw.mark_of("period") if "period" in raw else None)


def check_against_machine(config: CanConfig, machine: MachineConfig, mark: Mark, problems: Problems) -> None:
    """What needs the machine: a period of whole IPO cycles, identifiers that do not clash."""
    ipo_us = machine_ipo_cycle_us(machine)
    if isinstance(config.period, float):
        cycles = config.period * 1_000_000 / ipo_us
        if abs(cycles - round(cycles)) > 1e-6 or round(cycles) < 1:
            problems.add(config.period_mark or mark, f"can.period = {config.period:g} s is not a whole number"
                         f" of IPO cycles ({ipo_us / 1000:g} ms)")
    try:
        CanLayout.build(expand(load_catalog(), machine.layout), machine.plant_io.area_sizes(), config.settings)
    except CanMapError as error:
        problems.add(mark, f"can.ids: {error}")


_cache: dict[tuple[object, ...], CanConfig] = {}


def can_config_of(machine: MachineConfig) -> CanConfig:
    """The ``can:`` section of the machine's file (defaults when there is none); raises
    :class:`~vc.located_yaml.SourceError` with every problem.  Kept per file version, IPO cycle
    and layout: a scenario library reads it once per machine."""
    try:
        version = os.stat(machine.source).st_mtime_ns
    except OSError:
        version = 0  # load_file reports the file
    key = (machine.source, version, machine_ipo_cycle_us(machine), machine.layout, machine.plant_io)
    cached = _cache.get(key)
    if cached is not None:
        return cached
    document, parse_problems = load_file(machine.source)
    problems = Problems()
    problems.extend(parse_problems)
    config = CanConfig()
    if isinstance(document, LocatedMap) and SECTION in document:
        mark = document.mark_of_key(SECTION)
        config = read_can_section(document[SECTION], document.mark_of(SECTION), problems)
        check_against_machine(config, machine, mark, problems)
    problems.raise_if_any()
    _cache[key] = config
    return config
