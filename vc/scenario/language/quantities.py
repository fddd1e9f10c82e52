"""What a name in a scenario stands for: an interface signal, a plant I/O point, an axis quantity, time.

Names are resolved once, when the file is loaded, in this order:

1. the signal catalogue of the machine, by symbol (``X1.basic.in.enc1Synchronized``) or by
   absolute address (``DB31.DBX60.4``, ``DB21.DBB4``, ``DB31.DBD88``),
2. the machine's plant I/O, by function name (``MCP.jog``) or address (``I0.3``),
3. ``<axis>.<quantity>`` for a machine axis or spindle (``X1.position``; see ``AXIS_QUANTITIES``),
   ``<channel>.<quantity>`` for the tool of a channel (``CHAN1.toolTipX``; ``CHANNEL_QUANTITIES``)
   and ``NC.<quantity>`` for the NCK and its drive line-up (``NC.dcLinkVoltage``; ``NCK_QUANTITIES``),
4. ``<instance>.MD<number>[<index>]``: a machine datum as the control holds it now, with the
   values it wrote itself (``X1.MD34210``, ``X1.MD34090[1]``, ``CHAN1.MD20700``, ``NC.MD10192``),
5. ``CAN.<quantity>``: the CAN link's counters and states (``CAN.lostFromPlc``; ``LINK_QUANTITIES``),
   for a scenario whose PLC sits behind the link (``link: can``),
6. ``time``: simulated seconds since the scenario started.
"""

from __future__ import annotations

import difflib
import re
from collections.abc import Iterable
from dataclasses import dataclass
from enum import Enum

from interfaces.address import Address, AddressError
from interfaces.plant_io import PlantIoMap, plant_function
from interfaces.signals import (
    ALARMS_INSTANCE,
    HMI_INSTANCE,
    MODE_GROUP_INSTANCE,
    NCK_INSTANCE,
    Direction,
    ExpandedCatalog,
    SignalRef,
    SignalType,
    UnknownSignalError,
)
from vc.config.machine_data import MdLevel
from vc.config.md_dictionary import BY_NUMBER, level_text
from vc.config.model import MachineConfig
from vc.simulation.observables import (
    AXIS_QUANTITIES,
    CHANNEL_QUANTITIES,
    LINK_INSTANCE,
    LINK_QUANTITIES,
    NCK_QUANTITIES,
    quantity_unit,
)

TIME = "time"


class QuantityKind(Enum):
    SIGNAL = "signal"  # interface signal or plant I/O point
    AXIS = "axis"  # a quantity of a machine axis or spindle
    MACHINE_DATUM = "machine datum"  # a machine datum as the control holds it now (X1.MD34210)
    LINK = "link"  # a counter or state of the CAN link (CAN.lostFromPlc)
    TIME = "time"


@dataclass(frozen=True, slots=True)
class Quantity:
    """A resolved name: what the runner reads and the recorder records."""

    name: str  # as shown in messages and traces
    kind: QuantityKind
    ref: SignalRef | None = None
    axis: str = ""  # the axis (or, for a machine datum, the instance: axis, channel or NC)
    quantity: str = ""  # the axis quantity, or the machine datum's number
    index: int | None = None  # the array index of a machine datum

    @property
    def is_integer(self) -> bool:
        """True for signals other than REAL (their values are whole numbers)."""
        return self.ref is not None and self.ref.type is not SignalType.REAL

    @property
    def address(self) -> str:
        return str(self.ref.address) if self.ref is not None else ""

    @property
    def scope(self) -> str:
        """Where the quantity belongs: NC, MODEGROUP, CHAN1, X1 (interface), PLANT, AXES, SIM."""
        if self.kind is QuantityKind.AXIS:
            return "AXES"
        if self.kind is QuantityKind.MACHINE_DATUM:
            return "MD"
        if self.kind is QuantityKind.LINK:
            return LINK_INSTANCE
        if self.kind is QuantityKind.TIME:
            return "SIM"
        assert self.ref is not None
        if self.ref.direction in (Direction.PLANT_TO_PLC, Direction.PLC_TO_PLANT):
            return "PLANT"
        if self.ref.signal is not None:
            return self.ref.signal.instance
        return self.ref.area_key

    @property
    def label(self) -> str:
        """The name with its address, for messages: ``X1.basic.in.enc1Synchronized (DB31.DBX60.4)``."""
        address = self.address
        return f"{self.name} ({address})" if address and address != self.name else self.name

    def __str__(self) -> str:
        return self.name


def unit_of(quantity: Quantity, machine: MachineConfig) -> str:
    """The unit a quantity is shown in (``SP1.velocity``: rev/min, ``X1.position``: mm, ``time``: s), as
    declared once in :mod:`vc.simulation.observables`; "" for interface signals, machine data and counts."""
    if quantity.kind is QuantityKind.AXIS:
        return quantity_unit(machine, quantity.axis, quantity.quantity)
    return "s" if quantity.kind is QuantityKind.TIME else ""


def signal_quantity(ref: SignalRef) -> Quantity:
    return Quantity(ref.name, QuantityKind.SIGNAL, ref)


def axis_quantity(axis: str, quantity: str) -> Quantity:
    return Quantity(f"{axis}.{quantity}", QuantityKind.AXIS, axis=axis, quantity=quantity)


TIME_QUANTITY = Quantity(TIME, QuantityKind.TIME)

_MACHINE_DATUM = re.compile(r"^MD(\d+)(?:\[(\d+)\])?$")
_LEVEL_OF = {"axis": MdLevel.AXIS, "channel": MdLevel.CHANNEL, "nck": MdLevel.NCK}


class NameResolver:
    """Resolves the names of one machine; unknown names raise :class:`UnknownSignalError`."""

    def __init__(self, catalog: ExpandedCatalog, plant_io: PlantIoMap, axes: Iterable[str],
                 channels: Iterable[str], link: bool = False, dc_link: bool = False):
        """``link``: the PLC sits behind the CAN link, whose quantities can be read; ``dc_link``: the
        machine models its drive line-up's DC link (``NC.dcLinkVoltage``)."""
        self.link = link
        self.dc_link = dc_link
        self.catalog = catalog
        self.plant_io = plant_io
        self.axes = tuple(axes)
        self.channels = tuple(channels)
        self._instances = {NCK_INSTANCE, MODE_GROUP_INSTANCE, HMI_INSTANCE, ALARMS_INSTANCE, *self.axes,
                           *self.channels}
        self._cache: dict[str, Quantity] = {}

    def resolve(self, name: str) -> Quantity:
        text = name.strip()
        cached = self._cache.get(text)
        if cached is None:
            cached = self._cache[text] = self._resolve(text)
        return cached

    def _resolve(self, text: str) -> Quantity:
        head, _, tail = text.partition(".")
        # the simulation's own quantities first: no catalogue symbol or plant I/O name has their
        # form (those read X1.basic.in... and MCP.jog), and a catalogue miss costs a "did you
        # mean" search of a millisecond
        own = self._own_quantity(text, head, tail)
        if own is not None:
            return own
        try:
            return signal_quantity(self.plant_io.resolve(text))
        except UnknownSignalError as error:
            plant_error = error
        try:
            return signal_quantity(self.catalog.resolve(text))
        except UnknownSignalError as error:
            catalog_error = error
        raise UnknownSignalError(self._unknown_message(text, head, tail, catalog_error, plant_error))

    def _own_quantity(self, text: str, head: str, tail: str) -> Quantity | None:
        """An axis, channel, NC or link quantity, a machine datum or the time; None for other names."""
        if head in self.axes and tail in AXIS_QUANTITIES:
            return axis_quantity(head, tail)
        if head in self.channels and tail in CHANNEL_QUANTITIES:
            return axis_quantity(head, tail)  # read like an axis quantity, from the channel
        if head == NCK_INSTANCE and tail in NCK_QUANTITIES:
            if not self.dc_link:
                raise UnknownSignalError(f"'{text}' is a quantity of the DC link: this machine has no dc_link:"
                                         " section (it would read 0)")
            return axis_quantity(head, tail)  # read like an axis quantity, from the NCK
        if head == LINK_INSTANCE and tail in LINK_QUANTITIES:
            if not self.link:
                raise UnknownSignalError(f"'{text}' is a quantity of the CAN link: the scenario needs 'link: can'"
                                         " and a PLC program behind it")
            return Quantity(text, QuantityKind.LINK, quantity=tail)
        datum = _MACHINE_DATUM.match(tail)
        if datum is not None and head in (NCK_INSTANCE, *self.axes, *self.channels):
            return self._machine_datum(text, head, int(datum.group(1)), datum.group(2))
        if text == TIME:
            return TIME_QUANTITY
        return None

    def _machine_datum(self, text: str, instance: str, number: int, index_text: str | None) -> Quantity:
        md = BY_NUMBER.get(number)
        if md is None:
            raise UnknownSignalError(f"'{text}': unknown machine datum MD{number}")
        kind = "nck" if instance == NCK_INSTANCE else ("axis" if instance in self.axes else "channel")
        if md.level is not _LEVEL_OF[kind]:
            what = "the NCK" if kind == "nck" else f"a {kind}"
            raise UnknownSignalError(f"'{text}': {md.label} is {level_text(md.level)}, {instance} is {what}")
        index = int(index_text) if index_text is not None else None
        if index is not None and not (md.length and index < md.length):
            indices = f"indices 0..{md.length - 1}" if md.length else "no index"
            raise UnknownSignalError(f"'{text}': {md.label} has {indices}")
        return Quantity(text, QuantityKind.MACHINE_DATUM, axis=instance, quantity=str(number), index=index)

    def _unknown_message(self, text: str, head: str, tail: str, catalog_error: UnknownSignalError,
                         plant_error: UnknownSignalError) -> str:
        try:
            address = Address.parse(text)
        except AddressError:
            address = None
        if address is not None:
            return plant_error.message if address.area in ("I", "Q") else catalog_error.message
        if head in self.axes and tail and "." not in tail:
            close = difflib.get_close_matches(tail, AXIS_QUANTITIES, n=1, cutoff=0.6)
            hint = f"; did you mean {head}.{close[0]}?" if close else ""
            return (f"'{text}' is not a quantity of axis {head}{hint}"
                    f" (axis quantities: {', '.join(AXIS_QUANTITIES)})")
        if head == LINK_INSTANCE and tail:
            close = difflib.get_close_matches(tail, LINK_QUANTITIES, n=1, cutoff=0.6)
            hint = f"; did you mean {head}.{close[0]}?" if close else ""
            return f"'{text}' is not a quantity of the CAN link{hint} (link quantities: {', '.join(LINK_QUANTITIES)})"
        if head in self._instances:
            return catalog_error.message
        if plant_function(text) is not None:
            return f"{text} is not wired on this machine (its plant_io list has no entry for it)"
        suggestions = difflib.get_close_matches(text, self._all_names(), n=2, cutoff=0.75)
        if suggestions:
            return f"unknown signal '{text}'; did you mean {' or '.join(suggestions)}?"
        return (f"unknown signal '{text}': not a catalogue signal of this machine (instances"
                f" {', '.join(sorted(self._instances))}), not wired plant I/O, not an axis quantity")

    def _all_names(self) -> list[str]:
        names = [item.symbol for item in self.catalog.signals]
        names += [point.name for point in self.plant_io.points]
        names += [f"{axis}.{quantity}" for axis in self.axes for quantity in AXIS_QUANTITIES]
        names += [f"{channel}.{quantity}" for channel in self.channels for quantity in CHANNEL_QUANTITIES]
        names += [f"{NCK_INSTANCE}.{quantity}" for quantity in NCK_QUANTITIES if self.dc_link]
        names.append(TIME)
        return names

    def place(self, name: str) -> str:
        """An axis or channel name as the second argument of ``alarm(...)``; raises ``KeyError``."""
        if name in self.axes or name in self.channels:
            return name
        known = ", ".join((*self.axes, *self.channels))
        raise KeyError(f"'{name}' is neither an axis nor a channel of this machine (known: {known})")
