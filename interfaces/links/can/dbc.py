"""The CAN frames of one machine as a DBC file, through cantools (pure: returns the text).

One message per frame of :class:`~interfaces.links.can.codec.CanLayout`, sent by node ``NC`` or ``PLC``
with the frame's cycle time; in it one signal per catalogue signal and plant I/O point, named by
its symbol and placed at its bit (the convention of :mod:`interfaces.links.can.codec`: bits and bytes
Intel, S7 words and double words Motorola, reals IEEE 754 singles), plus the frame's ``checksum``.
DBC names are C identifiers, so the symbol's dots (and brackets) become underscores
(``X1.basic.in.enc1Synchronized`` -> ``X1_basic_in_enc1Synchronized``); the comment of every
signal gives the symbol as written and the absolute address.  Names longer than 32 characters
keep their full length through the DBC's ``SystemSignalLongSymbol`` attribute (cantools writes
and reads it).  The link frames are messages ``NC_LINK``, ``PLC_LINK`` and ``NC_DESCRIPTION``.
"""

from __future__ import annotations

import re
from collections import OrderedDict
from collections.abc import Iterable

from cantools.database.can import Database, Message, Node, Signal
from cantools.database.can.formats.dbc import DbcAttribute, DbcAttributeDefinition, DbcSpecifics
from cantools.database.conversion import BaseConversion

from interfaces.links.can.codec import LINK_FRAME_BYTES, LINK_VERSION, CanLayout, CanLocation
from interfaces.plant_io import PlantIoMap
from interfaces.signals import Direction, ExpandedCatalog, SignalRef, SignalType

NC_NODE, PLC_NODE = "NC", "PLC"
_NOT_IDENTIFIER = re.compile(r"[^A-Za-z0-9_]")


def dbc_name(symbol: str) -> str:
    """The DBC identifier of a symbol: every character a C identifier cannot hold becomes ``_``
    (``X1.basic.in.enc1Synchronized`` -> ``X1_basic_in_enc1Synchronized``)."""
    return _NOT_IDENTIFIER.sub("_", symbol)


def _signal(name: str, location: CanLocation, signal_type: SignalType, comment: str) -> Signal:
    return Signal(name, location.start_bit, location.length,
                  byte_order="big_endian" if location.big_endian else "little_endian",
                  conversion=BaseConversion.factory(is_float=signal_type is SignalType.REAL),
                  comment=comment)


def _field(name: str, start: int, length: int, comment: str) -> Signal:
    """A link-frame field: one byte or a nibble Intel, a word Motorola (start = its high byte's bit 7)."""
    big = length == 16
    return Signal(name, start + 7 if big else start, length, byte_order="big_endian" if big else "little_endian",
                  comment=comment)


_CHECKSUM = "CRC-8 SAE J1850 over the identifier and the other bytes of the frame"
# The two link frames: name, sender, the fields (name, start bit, bits, meaning) and what the frame is.
_LINK_FRAMES = (
    ("NC_LINK", NC_NODE, (
        ("mode", 0, 4, "1 lockstep, 2 free-running"),
        ("version", 4, 4, f"link version ({LINK_VERSION})"),
        ("ncLife", 8, 8, "the NC's sign of life: counts every transmission"),
        ("session", 16, 16, "counts the harness's power-ons; a new one restarts the PLC program"),
        ("scanGrant", 32, 16, "lockstep: the scan the PLC may run")),
     "the NC's link frame, after its data frames and with every scan grant"),
    ("PLC_LINK", PLC_NODE, (
        ("needsDescription", 0, 1, "1: the PLC asks for the interface description"),
        ("missesNcFrames", 1, 1, "1: the PLC's time-out monitor misses frames of the NC (substitute values 0)"),
        ("version", 4, 4, f"link version ({LINK_VERSION})"),
        ("plcLife", 8, 8, "the PLC's sign of life: counts every scan (the NC watches it)"),
        ("sessionReady", 16, 16, "the session the PLC runs its program for"),
        ("scanDone", 32, 16, "lockstep: the granted scan the PLC finished")),
     "the PLC's link frame, after its data frames at the end of every scan"),
)


def _link_messages(layout: CanLayout, nc_cycle_ms: int | None, plc_cycle_ms: int | None) -> list[Message]:
    settings = layout.settings
    messages = []
    for (name, sender, fields, comment), can_id in zip(_LINK_FRAMES, (settings.nc_link_id, settings.plc_link_id),
                                                       strict=True):
        signals = [_field(*field) for field in fields] + [_field("checksum", 56, 8, _CHECKSUM)]
        messages.append(Message(can_id, name, LINK_FRAME_BYTES, signals, senders=[sender],
                                cycle_time=nc_cycle_ms if sender == NC_NODE else plc_cycle_ms, is_fd=settings.fd,
                                strict=False, comment=comment))
    messages.append(Message(settings.description_id, "NC_DESCRIPTION", settings.frame_bytes, [
        _field("segment", 0, 16, "segment number of the description stream (length, CRC-32, UTF-8 JSON)"),
        _field("checksum", 8 * (settings.frame_bytes - 1), 8, _CHECKSUM)],
        senders=[NC_NODE], is_fd=settings.fd, strict=False,
        comment="the interface description, segment by segment, when the PLC asks for it"))
    return messages


def _references(catalog: ExpandedCatalog, plant_io: PlantIoMap) -> Iterable[tuple[SignalRef, str]]:
    for item in catalog.signals:
        yield item.ref(), item.definition.meaning
    for point in plant_io.points:
        yield point.ref(), point.meaning


def dbc_text(layout: CanLayout, catalog: ExpandedCatalog, plant_io: PlantIoMap, *, nc_cycle_ms: int | None = None,
             plc_cycle_ms: int | None = None) -> str:
    """The DBC file of the layout; the cycle times go into ``GenMsgCycleTime`` of each sender's frames."""
    signals: dict[int, list[Signal]] = {slot.can_id: [] for slot in layout.by_id.values()}
    for ref, meaning in _references(catalog, plant_io):
        location = layout.location(ref)
        if location is not None:
            signals[location.can_id].append(_signal(dbc_name(ref.name), location, ref.type,
                                                    f"{ref.name} {ref.address}: {meaning}"))
    messages = []
    for slot in layout.by_id.values():
        items = signals[slot.can_id]
        if slot.checksum:
            items.append(_field("checksum", 8 * (slot.length - 1), 8, _CHECKSUM))
        nc_sends = slot.direction is Direction.NC_TO_PLC
        messages.append(Message(slot.can_id, slot.name, slot.length, items, senders=[NC_NODE if nc_sends else PLC_NODE],
                                cycle_time=nc_cycle_ms if nc_sends else plc_cycle_ms, is_fd=slot.fd, strict=False,
                                comment=f"{slot.area} bytes {slot.start}..{slot.stop - 1}"))
    messages += _link_messages(layout, nc_cycle_ms, plc_cycle_ms)
    messages.sort(key=lambda message: message.frame_id)
    specifics = None
    if layout.settings.fd:
        bus_type = DbcAttributeDefinition("BusType", default_value="", kind=None, type_name="STRING")
        specifics = DbcSpecifics(attributes=OrderedDict(BusType=DbcAttribute("CAN FD", bus_type)),
                                 attribute_definitions=OrderedDict(BusType=bus_type))
    database = Database(messages, [Node(NC_NODE, "the NC (vc harness)"), Node(PLC_NODE, "the PLC")],
                        dbc_specifics=specifics, strict=False)
    return str(database.as_dbc_string())
