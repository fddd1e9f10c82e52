"""The expanded signal map of a machine as CSV, JSON or Markdown (``vc map``).

One row per signal of every DB instance, then the machine's plant I/O, then the registers of
the Modbus link block, then the machine's commissioning facts (instance ``COMMISSIONING``:
``X1.commissioning`` how each axis is referenced and where its cam and limit switches are,
``CHAN1.referenceOrder``, and ``wiring.*`` what the plant needs from the PLC; address and
meaning only).  The CSV columns start with
``symbol,address,direction,type,modbus_table,modbus_address,bit``:

* a bit signal is listed as a coil (PLC writes) or discrete input (PLC reads): ``modbus_address``
  is its 0-based bit number, ``bit`` is empty; ``register`` and ``register_bit`` give the same
  bit inside its holding or input register;
* a byte, word or double word is listed as holding or input register(s): ``modbus_address`` is
  the first register, ``bit`` the lowest bit of the value in it (8 for a byte in the high half);
* ``modbus_number`` is the 1-based display number (0xxxx coil, 1xxxx discrete input, 3xxxx input
  register, 4xxxx holding register);
* ``modelled`` is ``yes`` when the simulated NC reads (PLC -> NC) or writes (NC -> PLC) the
  signal, else ``no: <why>`` (the catalogue's ``not_modelled``): a PLC waiting for such a signal
  waits for ever, and that is not the PLC's fault;
* ``can_id`` is the identifier of the CAN data frame that carries the signal (hexadecimal) and
  ``can_start_bit`` its start bit as the DBC file gives it (``vc map --format dbc``): frame byte x 8
  + bit for bits and bytes, the most significant bit (frame byte x 8 + 7) for S7 words and double
  words (Motorola).  The link block is Modbus only: its CAN counterpart are the link frames.

The conventions themselves are documented in :mod:`interfaces.links.modbus.codec` and :mod:`interfaces.links.can.codec`.
"""

from __future__ import annotations

from dataclasses import dataclass

from interfaces.commissioning import Commissioning
from interfaces.links.can.codec import CanLayout, CanLocation, CanSettings
from interfaces.links.modbus.codec import (
    DESCRIPTION_REGISTER,
    LINK_VERSION,
    LinkHolding,
    LinkInput,
    Location,
    RegisterMap,
    display_number,
)
from interfaces.plant_io import PlantIoMap
from interfaces.signals import ExpandedCatalog, SignalRef

COLUMNS = ("symbol", "address", "direction", "type", "modbus_table", "modbus_address", "bit", "modbus_number",
           "register", "register_bit", "can_id", "can_start_bit", "bits", "trigger", "bp_symbol", "instance", "meaning",
           "source", "origin", "note", "modelled")
COMMISSIONING_INSTANCE = "COMMISSIONING"

# The link block (interfaces/links/modbus/codec.py): (symbol, table kind, register, registers, meaning)
LINK_ROWS = (
    ("LINK.version", "input_register", LinkInput.VERSION, 1, f"link version ({LINK_VERSION}): changes with every change"
     " of the link block or of where a signal lies; 0 = no machine powered on yet"),
    ("LINK.session", "input_register", LinkInput.SESSION, 1, "session: counts the harness's power-ons and the"
     " operator's new sessions from 1 in every harness process; a new one (or a new boot id) restarts the PLC program"),
    ("LINK.mode", "input_register", LinkInput.MODE, 1, "1 = lockstep, 2 = free-running (real time)"),
    ("LINK.scanGrant", "input_register", LinkInput.SCAN_GRANT, 1, "lockstep: the number of the scan the PLC may run"),
    ("LINK.ncCycle", "input_register", LinkInput.NC_CYCLE_HIGH, 2, "NC IPO cycles at the last exchange, high word"
     " first"),
    ("LINK.ipoCycleUs", "input_register", LinkInput.IPO_CYCLE_US, 1, "IPO cycle in microseconds"),
    ("LINK.plcCycleIpo", "input_register", LinkInput.PLC_CYCLE_IPO, 1, "PLC period in IPO cycles"),
    ("LINK.descriptionStart", "input_register", LinkInput.DESCRIPTION_START, 1, "first register of the description"),
    ("LINK.descriptionBytes", "input_register", LinkInput.DESCRIPTION_BYTES, 1, "length of the description in bytes"),
    ("LINK.ncToPlcRegisters", "input_register", LinkInput.NC_TO_PLC_REGISTERS, 1, "size of the NC-to-PLC table"),
    ("LINK.plcToNcRegisters", "input_register", LinkInput.PLC_TO_NC_REGISTERS, 1, "size of the PLC-to-NC table"),
    ("LINK.bootId", "input_register", LinkInput.BOOT_ID, 1, "boot id: random 1..65535, new with every harness process;"
     " a PLC restarts its program when it or the session changes"),
    ("LINK.scanDone", "holding_register", LinkHolding.SCAN_DONE, 1, "lockstep: the granted scan the PLC finished;"
     " free-running: a counter the PLC changes every scan (its sign of life)"),
    ("LINK.sessionReady", "holding_register", LinkHolding.SESSION_READY, 1, "the session the PLC has started its"
     " program for"),
    # the session key as two double words (a PLC tool's widest integer type)
    ("LINK.sessionKeyHigh", "holding_register", LinkHolding.SESSION_KEY, 2, "the PLC's session key, its high 32"
     " bits (high word first): random, written with HR 1 in the claim, so that only this PLC takes its session back"
     " after a lost connection; reads 0"),
    ("LINK.sessionKeyLow", "holding_register", LinkHolding.SESSION_KEY + 2, 2, "the session key's low 32 bits"),
)


@dataclass(frozen=True, slots=True)
class MapRow:
    symbol: str
    address: str
    direction: str
    type: str
    modbus_table: str
    modbus_address: int | str
    bit: int | str
    modbus_number: str
    register: int | str
    register_bit: int | str
    can_id: str
    can_start_bit: int | str
    bits: int
    trigger: str
    bp_symbol: str
    instance: str
    meaning: str
    source: str
    origin: str
    note: str
    modelled: str  # "yes", "no: <why>", "-" for facts


def _modbus_columns(location: Location | None) -> tuple[str, int | str, int | str, str, int | str, int | str]:
    if location is None:
        return ("", "", "", "", "", "")
    if location.coil is not None:
        assert location.register_bit is not None
        return (location.bit_kind, location.coil, "", display_number(location.bit_kind, location.coil),
                location.register, location.register_bit)
    return (location.register_kind, location.register, location.byte_bit,
            display_number(location.register_kind, location.register), "", "")


def _can_columns(location: CanLocation | None) -> tuple[str, int | str]:
    return ("", "") if location is None else (f"0x{location.can_id:03X}", location.start_bit)


def map_rows(catalog: ExpandedCatalog, plant_io: PlantIoMap, can: CanSettings | None = None,
             commissioning: Commissioning | None = None) -> list[MapRow]:
    """The rows of the map; ``can``: the machine's CAN settings (default identifiers otherwise);
    ``commissioning``: the machine's facts, as rows at the end."""
    register_map = RegisterMap.build(catalog, plant_io.area_sizes())
    can_layout = CanLayout.build(catalog, plant_io.area_sizes(), can or CanSettings())
    rows = []
    for item in catalog.signals:
        d = item.definition
        ref = SignalRef(item.symbol, item.address, d.type, d.bits, d.direction, item)
        rows.append(MapRow(item.symbol, str(item.address), d.direction.value, d.type.value,
                           *_modbus_columns(register_map.location(ref)), *_can_columns(can_layout.location(ref)),
                           d.bits, d.trigger.value, d.bp_symbol, item.instance, d.meaning, d.source, d.origin.value,
                           d.note, "yes" if d.modelled else f"no: {d.not_modelled}"))
    for point in plant_io.points:
        bits = 1 if point.address.is_bit else 8 * point.address.size
        ref = plant_io.resolve(point.name)
        rows.append(MapRow(point.name, str(point.address), point.direction.value, point.type.value,
                           *_modbus_columns(register_map.location(ref)), *_can_columns(can_layout.location(ref)),
                           bits, "level", "-", "PLANT", point.meaning, "machine file plant_io", "project",
                           f"driven by the {point.owner.value}", "yes"))
    for symbol, kind, register, count, meaning in LINK_ROWS:
        direction = "nc_to_plc" if kind == "input_register" else "plc_to_nc"
        rows.append(MapRow(symbol, "-", direction, "dword" if count == 2 else "word", kind, register, 0,
                           display_number(kind, register), "", "", "", "", 16 * count, "level", "-", "LINK", meaning,
                           "interfaces/links/modbus/codec.py", "project", "Modbus link block", "yes"))
    rows.append(MapRow("LINK.description", "-", "nc_to_plc", "text", "input_register", DESCRIPTION_REGISTER, 0,
                       display_number("input_register", DESCRIPTION_REGISTER), "", "", "", "", 0, "level", "-", "LINK",
                       "interface description, UTF-8 JSON, LINK.descriptionBytes long",
                       "interfaces/links/description.py", "project", "Modbus link block", "yes"))
    if commissioning is not None:
        for name, addresses, meaning in commissioning.rows(catalog.layout.channels):
            rows.append(MapRow(name, addresses, "-", "fact", "", "", "", "", "", "", "", "", 0, "-", "-",
                               COMMISSIONING_INSTANCE, meaning, "machine file (vc map)", "project",
                               "commissioning fact", "-"))
    return rows
