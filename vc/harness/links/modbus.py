"""The harness's end of a PLC in another process over Modbus TCP (and S7): the servers and the exchange.

:class:`PlcLink` is a :class:`~vc.harness.links.Link`: at every power-on of the
simulation it opens a new *session* (new tables for the machine, the interface description,
the session number in the link block) and hands the simulation a :class:`LinkedPlc` whose
``scan`` exchanges the interface with the remote PLC once per PLC period:

* **lockstep**: publish the NC->PLC bytes and the plant inputs, grant the next scan (input
  register 3), then run the event loop until the PLC reports that scan done (holding register
  0) for this session (holding register 1), and take its outputs.  Simulated time stands while
  the PLC works, so a PLC that can be stepped gives the same trace as in-process.
* **free-running** (real time): publish the inputs, take the outputs the PLC wrote since the
  last exchange; the PLC scans on its own clock and its scan counter is its sign of life.

The servers share one asyncio loop with the pacer, run only while the harness waits; see
:mod:`interfaces.links.modbus.server` for the threading argument.  Only the session's PLC writes
into the NC (:mod:`interfaces.links.modbus.access`): the connection that wrote the session into holding
register 1 (or, over S7, wrote first), one owner for both servers.  When it is lost the session
closes: a restarted PLC gets a session only at the next power-on or when the operator opens one
(:meth:`PlcLink.open_new_session`).

S7 is a second server of the same link, not a link of its own: it shares the sessions, the owner
and the outputs with the Modbus server (its tables mirror the Modbus PLC's outputs, and a
free-running S7 PLC writes into the same areas), and lockstep needs the Modbus handshake
registers; the S7 protocol itself is in :mod:`interfaces.links.modbus.s7`.
"""

from __future__ import annotations

import asyncio
import contextlib
import secrets
import struct
from collections.abc import Callable, Collection, Mapping
from dataclasses import dataclass
from typing import Protocol

from interfaces.exchange import grant_of_scan, next_session
from interfaces.image import ProcessImage
from interfaces.links.description import LinkDescription
from interfaces.links.errors import LinkError
from interfaces.links.modbus.access import ConnectionLimits, LinkOwner, OwnerState
from interfaces.links.modbus.codec import (
    DESCRIPTION_REGISTER,
    LINK_VERSION,
    MODE_FREE_RUNNING,
    MODE_LOCKSTEP,
    LinkHolding,
    LinkInput,
    RegisterMap,
    Table,
)
from interfaces.links.modbus.s7 import S7ServerLink
from interfaces.links.modbus.server import SHUTDOWN_TIMEOUT_S, ModbusServerLink
from interfaces.links.modbus.tables import ModbusTables
from interfaces.plc import PlcEnvironment
from vc.config.model import MachineConfig
from vc.harness.links import LinkMode
from vc.harness.links.patience import Patience
from vc.simulation.lockstep import Simulation

_WORD = struct.Struct(">H")


@dataclass(frozen=True, slots=True)
class Endpoint:
    host: str
    port: int

    @classmethod
    def parse(cls, text: str, default_port: int) -> Endpoint:
        """``127.0.0.1:5020``, ``127.0.0.1`` (default port) or ``:5020`` (loopback)."""
        host, _, port = text.rpartition(":") if ":" in text else (text, "", "")
        try:
            number = int(port) if port else default_port
        except ValueError:
            raise LinkError(f"'{text}': the port must be a number (e.g. 127.0.0.1:{default_port})") from None
        if not 0 <= number <= 65535:
            raise LinkError(f"'{text}': port {number} is outside 0..65535")
        return cls(host or "127.0.0.1", number)

    def __str__(self) -> str:
        return f"{self.host}:{self.port}"


LOOPBACK = ("127.0.0.1", "localhost", "::1")


def check_bind(endpoint: Endpoint, allow_remote: bool) -> None:
    """A server listens on loopback unless remote access is asked for explicitly."""
    if endpoint.host not in LOOPBACK and not allow_remote:
        raise LinkError(f"{endpoint.host} is not the loopback interface: binding there lets other machines"
                        " write into the NC; add --allow-remote to do so")


class ServedModbus(Protocol):
    """What ``vc serve`` says of its Modbus TCP and S7 servers (the fields of its options)."""

    modbus: Endpoint | None
    s7: Endpoint | None
    allow_remote: bool
    allowed_clients: tuple[str, ...]
    allow_writers: tuple[str, ...]
    limits: ConnectionLimits
    plc_key: int | None


DEFAULT_SERVED = Endpoint("127.0.0.1", 5020)  # vc serve without --modbus or --s7


def serving(options: ServedModbus, mode: LinkMode, on_wait: Callable[[str], None],
            on_notice: Callable[[str], None]) -> PlcLink:
    """``vc serve``'s link (its row in interfaces/links/__init__.py): the Modbus TCP server (by default
    on 127.0.0.1:5020) and the S7 server asked for, on loopback unless remote access is allowed; it
    waits for the PLC without a time-out."""
    modbus = options.modbus if options.modbus or options.s7 else DEFAULT_SERVED
    for endpoint in (modbus, options.s7):
        if endpoint is not None:
            check_bind(endpoint, options.allow_remote)
    return PlcLink(mode, modbus=modbus, s7=options.s7, allowed_clients=options.allowed_clients,
                   allow_writers=options.allow_writers, limits=options.limits, first_scan_timeout_s=None,
                   scan_timeout_s=None, on_wait=on_wait, required_key=options.plc_key, on_notice=on_notice)


class PlcLink:
    """Servers for a remote PLC and the sessions of one harness run (see the module docstring)."""

    def __init__(self, mode: LinkMode, *, modbus: Endpoint | None = None, s7: Endpoint | None = None,
                 allowed_clients: Collection[str] = (), allow_writers: Collection[str] = (),
                 limits: ConnectionLimits | None = None, first_scan_timeout_s: float | None = 30.0,
                 scan_timeout_s: float | None = 10.0, on_wait: Callable[[str], None] | None = None,
                 peer_ended: Callable[[], str | None] = lambda: None, boot_id: int | None = None,
                 required_key: int | None = None, on_notice: Callable[[str], None] | None = None):
        """``allowed_clients``: who may connect; ``allow_writers``: who may write besides the
        session's PLC; ``limits``: connections and idle time-out; ``required_key``: the only session
        key a claim may carry (interfaces/links/modbus/access.py).  ``peer_ended`` tells why the PLC process
        the harness started is gone (None while it runs), so that lockstep stops waiting for a PLC
        that cannot answer any more.  ``boot_id`` (default: random, 1..65535) tells a PLC this link
        from one of an earlier harness process, whose sessions counted from 1 as well; it is link
        metadata, never part of a trace.  ``on_notice`` hears what the operator must know: the
        session's PLC was lost, a new session was opened."""
        if modbus is None and s7 is None:
            raise LinkError("a PLC link needs a Modbus TCP or an S7 endpoint")
        if mode is LinkMode.LOCKSTEP and modbus is None:
            raise LinkError("lockstep needs the Modbus handshake registers: give a Modbus endpoint,"
                            " or run the S7 link in real time")
        self.mode = mode
        self.first_scan_timeout_s = first_scan_timeout_s
        self.scan_timeout_s = scan_timeout_s
        self.on_wait = on_wait
        self.peer_ended = peer_ended
        self.loop = asyncio.new_event_loop()
        self.on_notice = on_notice
        self.tables = ModbusTables(on_write=self._modbus_written)
        # the session's PLC, one for both servers
        self.owner = LinkOwner(allow_writers, required_key, on_lost=self._plc_lost)
        self.session = 0
        self.power_ons = 0  # sessions opened by a power-on (the operator's new sessions not counted)
        self.boot_id = boot_id if boot_id is not None else secrets.randbelow(0xFFFF) + 1
        self.outputs_written = False  # a Modbus client wrote PLC-to-NC registers since the last exchange
        self._handshake = asyncio.Event()
        self.modbus: ModbusServerLink | None = None
        self.s7: S7ServerLink | None = None
        try:
            if modbus is not None:
                self.modbus = ModbusServerLink(self.tables, modbus.host, modbus.port, self.loop, allowed_clients,
                                               owner=self.owner, limits=limits)
                self.modbus.start()
            if s7 is not None:
                self.s7 = S7ServerLink(s7.host, s7.port, allowed_clients, owner=self.owner, limits=limits)
                self.s7.start()
        except LinkError:
            self.close()
            raise

    # ------------------------------------------------------------------ what vc serve shows
    plc_command = "python -m plc_stub --modbus ..."  # how plc_stub follows the harness
    watched = ""  # the NC watches the PLC's sign of life only

    def configure_for(self, machine: MachineConfig) -> None:
        """Nothing per machine: the tables follow from the interface at every power-on."""

    def banner(self, machine: MachineConfig) -> list[str]:
        lines = []
        if self.modbus is not None:
            lines.append(f"Modbus TCP on {self.modbus.host}:{self.modbus.port} (register map: vc map --machine"
                         f" {machine.source} --format csv)")
        if self.s7 is not None:
            lines.append(f"S7 on {self.s7.host}:{self.s7.port}"
                         " (DB10, DB11, DB19, DB21.., DB31.., inputs PE, outputs PA)")
        return lines

    def peer_state(self, simulation: Simulation) -> str:
        """The servers' clients and requests, and who owns the link."""
        servers = [server.describe() for server in (self.modbus, self.s7) if server is not None]
        return "; ".join([*servers, self.owner.describe()])

    # ------------------------------------------------------------------ sessions
    def connect(self, environment: PlcEnvironment, program: str) -> LinkedPlc:
        """A power-on: new tables and description; the PLC (re)starts its program for them."""
        self.session = next_session(self.session)
        self.power_ons += 1
        self.owner.open_session()
        register_map = RegisterMap.build(environment.catalog, environment.plant_io.area_sizes())
        description = LinkDescription.of(environment, program, register_map)
        tables = self.tables
        tables.nc_to_plc = bytearray(register_map.table_bytes[Table.NC_TO_PLC])
        tables.plc_to_nc = bytearray(register_map.table_bytes[Table.PLC_TO_NC])
        tables.writable = register_map.writable
        tables.set_description(description.to_json())
        self.outputs_written = False
        block = {
            LinkInput.VERSION: LINK_VERSION, LinkInput.SESSION: self.session,
            LinkInput.MODE: MODE_LOCKSTEP if self.mode is LinkMode.LOCKSTEP else MODE_FREE_RUNNING,
            LinkInput.IPO_CYCLE_US: environment.ipo_cycle_us, LinkInput.PLC_CYCLE_IPO: environment.plc_cycle_ipo,
            LinkInput.DESCRIPTION_START: DESCRIPTION_REGISTER, LinkInput.DESCRIPTION_BYTES: len(tables.description),
            LinkInput.NC_TO_PLC_REGISTERS: register_map.registers(Table.NC_TO_PLC),
            LinkInput.PLC_TO_NC_REGISTERS: register_map.registers(Table.PLC_TO_NC),
            LinkInput.BOOT_ID: self.boot_id,
        }
        for register, value in block.items():
            self.set_input_register(register, value)
        if self.s7 is not None:
            self.s7.open_session(environment.catalog, environment.plant_io.area_sizes())
        return LinkedPlc(self, register_map, environment)

    def open_new_session(self) -> str:
        """The operator's new session for a restarted PLC, on the running machine (``vc serve``:
        Enter, SIGUSR1): the session number counts on and the PLC restarts its program for it,
        with the NC as it is.  Only while no PLC holds the session; what happened, in words."""
        if self.owner.state is OwnerState.OWNED:
            return f"the PLC at {self.owner.owner_peer} holds session {self.session}: no new session"
        if not self.power_ons:
            return "no machine is powered on yet: its power-on opens the first session"
        self.session = next_session(self.session)
        self.owner.open_session()
        self.set_input_register(LinkInput.SESSION, self.session)
        self._handshake.set()
        return f"session {self.session} opened: the first PLC that claims it owns the link"

    def _plc_lost(self, peer: str) -> None:
        if self.on_notice is not None:
            self.on_notice(f"the PLC at {peer} has gone: session {self.session} is closed, and no other client"
                           " may claim it")

    # ------------------------------------------------------------------ registers of the link block
    def set_input_register(self, register: int, value: int) -> None:
        _WORD.pack_into(self.tables.nc_to_plc, 2 * register, value & 0xFFFF)

    def holding_register(self, register: int) -> int:
        return int(_WORD.unpack_from(self.tables.plc_to_nc, 2 * register)[0])

    def _modbus_written(self, first: int, count: int) -> None:
        self.outputs_written = True
        if first <= LinkHolding.SESSION_READY:
            self._handshake.set()  # scan done or session ready may have changed

    # ------------------------------------------------------------------ waiting
    def wait_for_scan(self, grant: int, first: bool) -> None:
        """Serve the clients until the PLC reports scan ``grant`` of this session done."""
        def done() -> bool:
            return self.holding_register(LinkHolding.SESSION_READY) == self.session and \
                self.holding_register(LinkHolding.SCAN_DONE) == grant

        if done():
            return
        patience = Patience.for_scan(first, self.first_scan_timeout_s, self.scan_timeout_s, self.on_wait,
                                     self.peer_ended, lambda waited: self._silence(grant, first, waited))

        async def until_done() -> None:
            while not done():
                self._handshake.clear()
                with contextlib.suppress(TimeoutError):
                    await asyncio.wait_for(self._handshake.wait(), 0.5)
                patience.check()

        self.loop.run_until_complete(until_done())

    def _silence(self, grant: int, first: bool, waited: float) -> str:
        where = ", ".join(str(server) for server in (self.modbus_endpoint,) if server) or "the link"
        if first:
            return (f"no PLC has started session {self.session} on {where} after {waited:.0f} s"
                    f" ({self.modbus.clients if self.modbus else 0} client(s) connected)")
        return f"the PLC on {where} has not finished scan {grant} after {waited:.0f} s"

    @property
    def modbus_endpoint(self) -> str:
        return f"modbus {self.modbus.host}:{self.modbus.port}" if self.modbus else ""

    def serve(self) -> None:
        """Let the servers answer what has arrived (one pass of the event loop)."""
        self.loop.run_until_complete(asyncio.sleep(0))

    def close(self) -> None:
        if self.modbus is not None:
            self.modbus.close()
            self.modbus = None
        if self.s7 is not None:
            self.s7.close()
            self.s7 = None
        if not self.loop.is_closed():
            pending = asyncio.all_tasks(self.loop)
            for task in pending:
                task.cancel()
            if pending:  # bounded: a task a Ctrl-C interrupted in its step never ends (modbus/server.py)
                self.loop.run_until_complete(asyncio.wait(pending, timeout=SHUTDOWN_TIMEOUT_S))
            self.loop.close()


class LinkedPlc:
    """The simulation's PLC for one session of a :class:`PlcLink`."""

    def __init__(self, link: PlcLink, register_map: RegisterMap, environment: PlcEnvironment):
        self.link = link
        self.register_map = register_map
        self.session = link.session
        self.power_on = link.power_ons
        self.plc_cycle_ipo = environment.plc_cycle_ipo
        self.scans = 0
        self._life = 0

    @property
    def sign_of_life(self) -> int:
        return self._life

    @property
    def peer(self) -> str:
        """Who holds the session, for the session recording ("" while nobody does)."""
        owner = self.link.owner
        if owner.owner is None:
            return ""
        over = "s7" if isinstance(owner.owner, tuple) and owner.owner[:1] == ("s7",) else "modbus"
        return f"external PLC over {over} from {owner.owner_peer}"

    def scan(self, interface: ProcessImage, plant: ProcessImage) -> None:
        link, register_map = self.link, self.register_map
        if link.power_ons != self.power_on:
            raise LinkError(f"session {self.session} was replaced by session {link.session}")
        self.session = link.session  # or the operator's new session on this machine
        areas: Mapping[str, bytearray] = {**interface.areas, **plant.areas}
        register_map.fill_table(Table.NC_TO_PLC, areas, link.tables.nc_to_plc)
        cycle = self.scans * self.plc_cycle_ipo
        link.set_input_register(LinkInput.NC_CYCLE_HIGH, cycle >> 16)
        link.set_input_register(LinkInput.NC_CYCLE_HIGH + 1, cycle)
        if link.s7 is not None:
            link.s7.publish(areas)
        self.scans += 1
        if link.mode is LinkMode.LOCKSTEP:
            grant = grant_of_scan(self.scans)
            link.set_input_register(LinkInput.SCAN_GRANT, grant)
            link.wait_for_scan(grant, first=self.scans == 1)
            self._life = grant
            self._take_modbus(areas, interface, plant)
            return
        self._life = link.holding_register(LinkHolding.SCAN_DONE)
        if link.outputs_written:
            self._take_modbus(areas, interface, plant)
        elif link.s7 is not None and link.s7.take_outputs(areas):
            interface.touch()
            plant.touch()
            self.register_map.fill_table(Table.PLC_TO_NC, areas, link.tables.plc_to_nc)

    def _take_modbus(self, areas: Mapping[str, bytearray], interface: ProcessImage, plant: ProcessImage) -> None:
        """The Modbus PLC's outputs into the simulation, and into the S7 blocks so that an S7 client
        sees the whole interface (lockstep and real time alike)."""
        self.register_map.fill_areas(Table.PLC_TO_NC, self.link.tables.plc_to_nc, areas)
        self.link.outputs_written = False
        interface.touch()
        plant.touch()
        if self.link.s7 is not None:
            self.link.s7.mirror_outputs(areas)
