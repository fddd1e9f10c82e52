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
      timeout: 0.05       # seconds: a PLC-to-NC frame missing for longer stops the PLC's sign of life;
                          # the PLC watches the NC's frames with the same time
      restart: 0.1        # seconds after bus-off until the simulated NC controller restarts itself
                          # (bus_off faults); 0: it stays bus-off until the next power-on.  A real
                          # interface restarts by its own setting (ip link ... restart-ms)

Every key is optional; a machine file without the section uses the defaults.  Frame layout and
identifiers: :mod:`interfaces.links.can.codec`.  The machine loader reads the section with the rest of
the file (:func:`read_can_section`), checks it against the machine once its IPO cycle, channels,
axes and plant I/O are known (:func:`check_against_machine`) and keeps the result in
``MachineConfig.can``; every problem is reported with ``file:line:column``.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

from interfaces.catalog import load_catalog
from interfaces.links.can.codec import (
    DEFAULT_LINK_ID,
    DEFAULT_NC_TO_PLC_ID,
    DEFAULT_PLC_TO_NC_ID,
    MAX_STANDARD_ID,
    CanLayout,
    CanMapError,
    CanSettings,
)
from interfaces.signals import InterfaceLayout, expand
from vc.config.machine_data import as_number, shown
from vc.config.model import DEFAULT_RESTART_S, DEFAULT_TIMEOUT_S, PERIOD_IPO, PERIOD_PLC, CanConfig
from vc.located_yaml import LocatedMap, Mark, Problems

SECTION = "can"
KEYS = ("ids", "fd", "checksum", "period", "timeout", "restart")
ID_KEYS = {"link": "link_id", "nc_to_plc": "nc_to_plc_id", "plc_to_nc": "plc_to_nc_id"}


@dataclass(frozen=True, slots=True)
class CanSection:
    """The section as read: the values, and where the period and the identifiers are written for
    the checks against the machine (None: not written)."""

    config: CanConfig = field(default_factory=CanConfig)
    period_mark: Mark | None = None
    ids_mark: Mark | None = None
    timeout_mark: Mark | None = None


def read_can_section(raw: Any, mark: Mark, problems: Problems) -> CanSection:
    """The section's values; each problem goes to ``problems`` and its default is used."""
    if raw is None:
        return CanSection()
    if not isinstance(raw, LocatedMap):
        problems.add(mark, f"can: expected a mapping with {', '.join(KEYS)}, got {shown(raw)}")
        return CanSection()
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
    restart = DEFAULT_RESTART_S
    if "restart" in raw:
        number = as_number(raw["restart"])
        if number is None or number < 0:
            problems.add(raw.mark_of("restart"), f"can.restart: expected seconds, 0 or more (e.g. 0.1; 0: no"
                         f" automatic restart after bus-off), got {shown(raw['restart'])}")
        else:
            restart = float(number)
    settings = CanSettings(identifiers["link_id"], identifiers["nc_to_plc_id"], identifiers["plc_to_nc_id"],
                           flags["fd"], flags["checksum"])
    def mark_of(key: str) -> Mark | None:
        return raw.mark_of(key) if key in raw else None

    return CanSection(CanConfig(settings, period, timeout, restart), mark_of("period"), mark_of("ids"),
                      mark_of("timeout"))


def check_against_machine(section: CanSection, ipo_cycle_us: int, plc_cycle_ipo: int, layout: InterfaceLayout,
                          plant_sizes: Mapping[str, int], mark: Mark, problems: Problems) -> None:
    """What needs the machine: a period of whole IPO cycles, a time-out longer than the time between
    two frames either way (the NC's period, the PLC's scan), identifiers that do not clash and fit
    11 bits for the machine's frames (``mark``: the section, where a value has no mark of its own)."""
    config = section.config
    if isinstance(config.period, float):
        cycles = config.period * 1_000_000 / ipo_cycle_us
        if abs(cycles - round(cycles)) > 1e-6 or round(cycles) < 1:
            problems.add(section.period_mark or mark, f"can.period = {config.period:g} s is not a whole number"
                         f" of IPO cycles ({ipo_cycle_us / 1000:g} ms)")
    longest_gap = max(config.period_cycles(ipo_cycle_us, plc_cycle_ipo), plc_cycle_ipo) * ipo_cycle_us / 1_000_000
    if config.timeout_s <= longest_gap:
        problems.add(section.timeout_mark or mark, f"can.timeout = {config.timeout_s:g} s must be longer than the"
                     f" time between two frames ({longest_gap * 1000:g} ms: the NC's period, the PLC's scan),"
                     " or every gap counts as a lost frame")
    try:
        CanLayout.build(expand(load_catalog(), layout), plant_sizes, config.settings)
    except CanMapError as error:
        for problem in error.problems:
            problems.add(section.ids_mark or mark, f"can.ids: {problem}")
