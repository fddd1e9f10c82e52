"""The interface description a link server publishes, so that a PLC configures itself.

What a PLC needs to know about the machine it controls, and nothing of the NC: the channel
and axis names that number the DB instances, the plant I/O list, the PLC period, the
machine builder's PLC parameters and the PLC program the harness asks for (a PLC that runs a
fixed program ignores it).  It travels as UTF-8 JSON (input registers from 4096 over Modbus)::

    {"format": 1, "machine": "turn_mill", "channels": ["CHAN1"], "axes": ["X1", "Z1", ...],
     "plant_io": {"I0.0": "EStop.chainOk", ...}, "ipo_cycle_us": 2000, "plc_cycle_ipo": 5,
     "program": "basic_machine", "parameters": {...},
     "nc_to_plc_registers": 359, "plc_to_nc_registers": 163,
     "alarms": {"data_block": 100, "input_register": 325, "entries": 8, ...},
     "commissioning": {"axes": [{"axis": "X1", "approach": "plus", "cam": [280.0, 295.0], ...}],
                       "reference_order": {"CHAN1": [["Z1", "Y1"], ["X1"]]}, "plant_needs": [...]},
     "can": {"link_id": 256, "nc_to_plc_id": 512, "plc_to_nc_id": 1024, "fd": true, "checksum": true},
     "can_timeout_us": 50000}

The register counts let a client check that it computes the same layout as the server.
``alarms`` says where the NC's alarm list is (data block 100, its first input register) and what
its codes mean (:mod:`interfaces.alarm_block`); ``commissioning`` how each axis is referenced
(direction MD34010, cam and limit switch positions, MD34110 and what must come first) and what the
plant needs from the PLC (:class:`interfaces.commissioning.Commissioning`).  ``can``
comes only over the CAN link (:mod:`interfaces.links.can.codec`, there as segments of the description
frame): the identifiers and frame format the PLC must use, and the time after which its
time-out monitor treats a missing frame of the NC as a failure.
"""

from __future__ import annotations

import json
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

from interfaces import alarm_block
from interfaces.catalog import load_catalog
from interfaces.commissioning import Commissioning
from interfaces.errors import VcError
from interfaces.links.can.codec import DEFAULT_TIMEOUT_US, CanLayout, CanMapError, CanSettings
from interfaces.links.modbus.codec import RegisterMap, Table
from interfaces.plant_io import PlantIoError, PlantIoMap
from interfaces.plc import PlcEnvironment, PlcFactory, SoftPlc
from interfaces.signals import InterfaceLayout, expand

FORMAT = 1


class DescriptionError(VcError, ValueError):
    """A description that cannot be read or does not fit this side's catalogue."""


class PlcSetupError(VcError):
    """The PLC cannot run what the harness describes (unknown program, other catalogue)."""


@dataclass(frozen=True, slots=True)
class LinkDescription:
    machine: str
    channels: tuple[str, ...]
    axes: tuple[str, ...]
    plant_io: Mapping[str, str]  # address -> function, as in the machine file
    ipo_cycle_us: int
    plc_cycle_ipo: int
    program: str | None  # the program the harness asks for; None when the PLC is the user's
    parameters: Mapping[str, Any] = field(default_factory=dict)
    nc_to_plc_registers: int = 0
    plc_to_nc_registers: int = 0
    can: CanSettings | None = None  # the CAN link's identifiers and frame format
    can_timeout_us: int = DEFAULT_TIMEOUT_US  # the CAN link's time-out monitor
    alarms: Mapping[str, Any] = field(default_factory=dict)  # where the alarm list DB100 is, its codes
    commissioning: Mapping[str, Any] = field(default_factory=dict)  # Commissioning.as_dict(): referencing, wiring

    @classmethod
    def of(cls, environment: PlcEnvironment, program: str | None, register_map: RegisterMap,
           can: CanSettings | None = None, can_timeout_us: int = DEFAULT_TIMEOUT_US) -> LinkDescription:
        layout = environment.catalog.layout
        entries = {str(point.address): point.name for point in environment.plant_io.points}
        return cls(environment.machine, layout.channels, layout.axes, entries, environment.ipo_cycle_us,
                   environment.plc_cycle_ipo, program, dict(environment.parameters),
                   register_map.registers(Table.NC_TO_PLC), register_map.registers(Table.PLC_TO_NC), can,
                   can_timeout_us, alarm_block.describe(environment.catalog, register_map),
                   environment.commissioning.as_dict() if environment.commissioning is not None else {})

    def to_json(self) -> bytes:
        document = {
            "format": FORMAT, "machine": self.machine, "channels": list(self.channels), "axes": list(self.axes),
            "plant_io": dict(self.plant_io), "ipo_cycle_us": self.ipo_cycle_us, "plc_cycle_ipo": self.plc_cycle_ipo,
            "program": self.program, "parameters": dict(self.parameters),
            "nc_to_plc_registers": self.nc_to_plc_registers, "plc_to_nc_registers": self.plc_to_nc_registers,
            "alarms": dict(self.alarms),
        }
        if self.commissioning:
            document["commissioning"] = dict(self.commissioning)
        if self.can is not None:
            document["can"] = self.can.as_dict()
            document["can_timeout_us"] = self.can_timeout_us
        return json.dumps(document, separators=(",", ":"), sort_keys=True).encode()

    @classmethod
    def from_json(cls, text: bytes) -> LinkDescription:
        try:
            document = json.loads(text.decode())
            if document.get("format") != FORMAT:
                raise DescriptionError(f"description format {document.get('format')!r}; this side reads {FORMAT}")
            can = document.get("can")
            return cls(str(document["machine"]), tuple(document["channels"]), tuple(document["axes"]),
                       dict(document["plant_io"]), int(document["ipo_cycle_us"]), int(document["plc_cycle_ipo"]),
                       document.get("program"), dict(document.get("parameters") or {}),
                       int(document["nc_to_plc_registers"]), int(document["plc_to_nc_registers"]),
                       None if can is None else CanSettings.from_dict(can),
                       int(document.get("can_timeout_us", DEFAULT_TIMEOUT_US)), dict(document.get("alarms") or {}),
                       dict(document.get("commissioning") or {}))
        except (UnicodeDecodeError, ValueError, KeyError, TypeError, AttributeError) as error:
            if isinstance(error, DescriptionError):
                raise
            raise DescriptionError(f"unreadable interface description: {error}") from None

    @property
    def scan_time_s(self) -> float:
        return self.ipo_cycle_us * self.plc_cycle_ipo / 1_000_000

    def environment(self) -> tuple[PlcEnvironment, RegisterMap]:
        """The PLC's environment and the register layout, checked against the server's counts."""
        catalog = expand(load_catalog(), InterfaceLayout(self.channels, self.axes))
        try:
            plant_io = PlantIoMap.from_mapping(self.plant_io, self.axes)
        except PlantIoError as error:
            raise DescriptionError(f"plant I/O of the description: {error}") from None
        register_map = RegisterMap.build(catalog, plant_io.area_sizes())
        counts = (register_map.registers(Table.NC_TO_PLC), register_map.registers(Table.PLC_TO_NC))
        if counts != (self.nc_to_plc_registers, self.plc_to_nc_registers):
            raise DescriptionError(f"the server's tables have {self.nc_to_plc_registers} and"
                                   f" {self.plc_to_nc_registers} registers, this side computes {counts[0]} and"
                                   f" {counts[1]}: the two sides use different catalogues")
        # the commissioning facts too: a program needs the machine's devices (the turret's stations)
        commissioning = Commissioning.from_dict(self.commissioning) if self.commissioning else None
        environment = PlcEnvironment(catalog, plant_io, self.scan_time_s, self.parameters, self.machine,
                                     self.ipo_cycle_us, self.plc_cycle_ipo, commissioning)
        return environment, register_map

    @classmethod
    def for_plc(cls, text: bytes) -> LinkDescription:
        """The description as a PLC received it; :class:`PlcSetupError` when it cannot be read."""
        try:
            return cls.from_json(text)
        except DescriptionError as error:
            raise PlcSetupError(str(error)) from None

    def start_program(self, programs: Mapping[str, PlcFactory],
                      requested: str | None) -> tuple[PlcEnvironment, RegisterMap, SoftPlc, str]:
        """A PLC's start for this description, whatever the transport: its environment, the register
        layout, the program (``requested``, else the one the harness asks for) and its name;
        raises :class:`PlcSetupError` with what prevents it."""
        try:
            environment, register_map = self.environment()
        except DescriptionError as error:
            raise PlcSetupError(str(error)) from None
        name = requested or self.program
        if name is None:
            raise PlcSetupError("the harness asks for no program: start the PLC with --program NAME")
        factory = programs.get(name)
        if factory is None:
            raise PlcSetupError(f"no PLC program '{name}' (known: {', '.join(sorted(programs))})")
        return environment, register_map, factory(environment), name

    def can_layout(self, environment: PlcEnvironment) -> CanLayout:
        """The CAN frames the harness uses, from the settings it sent; :class:`PlcSetupError` when
        they do not fit."""
        if self.can is None:
            raise PlcSetupError("the description carries no CAN settings")
        try:
            return CanLayout.build(environment.catalog, environment.plant_io.area_sizes(), self.can)
        except CanMapError as error:
            raise PlcSetupError(f"CAN identifiers of the description: {error}") from None
