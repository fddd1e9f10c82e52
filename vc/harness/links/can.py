"""The harness's end of a PLC on a CAN bus (:mod:`interfaces.links.can.codec`): sessions, cyclic frames,
the time-out monitor, lockstep and faults of the bus.

:class:`CanLink` is a :class:`~vc.harness.links.Link`: at every power-on it opens a session
(the machine's frames, the description, the session number in the NC link frame) and hands the
simulation a :class:`CanLinkedPlc`:

* **lockstep**: at every PLC scan the NC-to-PLC data frames go out (when their period is due),
  then the NC link frame with the next grant; the harness receives until the PLC link frame
  reports that scan done for this session and takes the PLC's data frames.  Simulated time
  stands while the PLC works, so a PLC that can be stepped gives the in-process trace.
* **free-running** (real time): the NC-to-PLC frames go out every period, the PLC-to-NC frames
  are taken every IPO cycle as they arrive; the PLC scans on its own clock.

The period is the machine file's ``can.period``: with every PLC scan (default), every IPO cycle,
or a multiple of it.  **Time-out monitor**: every PLC-to-NC frame (data frames and the PLC link
frame) must have arrived within ``can.timeout`` (default 50 ms), counted in NC cycles.  While
one is missing the link holds the PLC's sign of life, so the NC's watch raises alarm 2000 once
MD10100 has passed without a change: the axes stop; a reset clears it when the frames are back.

**Faults** (:mod:`vc.simulation.link_faults`) act on the frames between the bus and the NC: frames
the NC sends are lost or wait before they go on the bus, frames from the PLC are lost or wait
before the NC takes them.  A disturbance (``bus_off``) acts through the NC's CAN controller
(:class:`~vc.simulation.link_faults.CanController`): failed transmissions count its error counter
up until it is bus-off; then it sends and hears nothing until its restart (``can.restart``).  On
a real bus the controller state python-can and SocketCAN report (:attr:`CanBus.state`) counts as
well: while it is bus-off the NC sends nothing.  In lockstep the link frames are also the
stepping's handshake: a fault never withholds a grant or a scan-done report from the stepping,
only their content from the other side (the NC's sign of life from the PLC, the PLC's from the
NC); the data frames are withheld completely.  The PLC watches the NC's frames in turn
(:mod:`interfaces.links.can.plc_end`) and says so in its link frame.  What the bus itself does wrong
is a fault of the link as well, never the end of a run: a frame it refuses to send and a receive
that fails are counted (``bus_errors``, in ``vc serve``'s statistics line) and the frame is lost,
a datagram that is no frame or an error frame on the wire is counted by the adapter
(:mod:`interfaces.links.can.bus`).

The link's counters and states are scenario quantities (``CAN.lostFromPlc``, ``CAN.busState``
...: ``LINK_QUANTITIES`` in vc/simulation/observables.py), counted per session.
"""

from __future__ import annotations

import asyncio
import time as wallclock
import weakref
from collections.abc import Callable, Mapping
from types import TracebackType
from typing import Protocol

from interfaces.exchange import MODE_FREE_RUNNING, MODE_LOCKSTEP, grant_of_scan, next_session
from interfaces.image import ProcessImage
from interfaces.links.can.bus import BusSpec, CanBus, private_virtual_bus
from interfaces.links.can.codec import (
    DEFAULT_LINK_ID,
    CanLayout,
    ControllerState,
    Frame,
    NcLink,
    PlcLink,
    description_frames,
)
from interfaces.links.can.plc_end import CanPlcNode
from interfaces.links.description import LinkDescription
from interfaces.links.errors import LinkError
from interfaces.links.inprocess import plc_programs
from interfaces.links.modbus.codec import RegisterMap
from interfaces.plc import PlcEnvironment
from interfaces.signals import Direction
from vc.config.model import CanConfig, MachineConfig
from vc.harness.links import LinkMode
from vc.harness.links.patience import Patience
from vc.simulation.link_faults import LINK_AREA, CanController, FaultyWire, LinkFault, active, disturbed
from vc.simulation.lockstep import Simulation

RECEIVE_WAIT_S = 0.5  # lockstep: how long one receive waits before the patience is checked


class ServedCan(Protocol):
    """What ``vc serve`` says of its CAN bus (a field of its options)."""

    can: BusSpec | None


def serving(options: ServedCan, mode: LinkMode, on_wait: Callable[[str], None],
            on_notice: Callable[[str], None]) -> CanLink:
    """``vc serve``'s link (its row in interfaces/links/__init__.py): a node on the bus of ``--can``; it
    waits for the PLC without a time-out (``on_notice``: the CAN link has no operator's sessions)."""
    if options.can is None:
        raise LinkError("a served CAN link needs its bus (vc serve --can BUS)")
    return CanLink(mode, options.can, first_scan_timeout_s=None, scan_timeout_s=None, on_wait=on_wait)


class CanLink:
    """A CAN bus to a remote PLC and the sessions of one harness run (module docstring).

    ``peer`` serves a PLC node in this process (a virtual bus): the link calls it whenever it
    waits and nothing has arrived.  ``peer_ended`` tells why the PLC process the harness started
    is gone (None while it runs); ``node`` is the harness's node when it was opened elsewhere."""

    loop: asyncio.AbstractEventLoop | None = None  # the CAN link needs no event loop
    watched = " and the time-out of its frames"  # besides the PLC's sign of life

    def __init__(self, mode: LinkMode, bus: BusSpec, *, config: CanConfig | None = None,
                 first_scan_timeout_s: float | None = 30.0, scan_timeout_s: float | None = 10.0,
                 on_wait: Callable[[str], None] | None = None, peer_ended: Callable[[], str | None] = lambda: None,
                 peer: Callable[[], None] | None = None, node: CanBus | None = None):
        self.mode = mode
        self.spec = bus
        self.config = config or CanConfig()
        self.first_scan_timeout_s = first_scan_timeout_s
        self.scan_timeout_s = scan_timeout_s
        self.on_wait = on_wait
        self.peer_ended = peer_ended
        self.peer = peer
        self.session = 0
        self.bus = node or CanBus(bus)

    def configure(self, config: CanConfig) -> None:
        """The ``can:`` settings the next power-on uses."""
        self.config = config

    def configure_for(self, machine: MachineConfig) -> None:
        """The ``can:`` settings of the machine the next power-on uses."""
        self.configure(machine.can)

    @property
    def plc_command(self) -> str:
        link_id = self.config.settings.link_id
        if link_id == DEFAULT_LINK_ID:
            return f"python -m plc_stub --can {self.spec}"
        return f"python -m plc_stub --can {self.spec} --can-link-id 0x{link_id:03X}"

    def banner(self, machine: MachineConfig) -> list[str]:
        return [f"CAN bus {self.spec}, link frames from 0x{machine.can.settings.link_id:03X} (frames: vc map"
                f" --machine {machine.source} --format dbc)"]

    def peer_state(self, simulation: Simulation) -> str:
        """The bus as the statistics line shows it: frames, errors, the controller, and what the
        time-out monitor misses."""
        bus = self.bus
        state = f"CAN: {bus.sent} frames sent, {bus.received} received, {bus.error_frames} error frames"
        if bus.foreign:
            state += f", {bus.foreign} datagrams that were no frames dropped"
        plc = simulation.plc
        if isinstance(plc, CanLinkedPlc):
            if plc.missing:
                state += ", missing " + " ".join(f"0x{can_id:03X}" for can_id in plc.missing)
            if plc.bus_errors:
                state += f", {plc.bus_errors} refused by the bus (last: {plc.last_bus_error})"
            controller = ControllerState(int(plc.quantity("busState")))
        else:
            controller = bus.state
        return state + ("" if controller is ControllerState.ERROR_ACTIVE else f", {controller.name.replace('_', ' ')}")

    def connect(self, environment: PlcEnvironment, program: str) -> CanLinkedPlc:
        """A power-on: a new session; the PLC (re)starts its program for it."""
        self.session = next_session(self.session)
        settings = self.config.settings
        layout = CanLayout.build(environment.catalog, environment.plant_io.area_sizes(), settings)
        register_map = RegisterMap.build(environment.catalog, environment.plant_io.area_sizes())
        description = LinkDescription.of(environment, program, register_map, settings, self.config.timeout_us)
        self.bus.listen({settings.plc_link_id, *layout.ids(Direction.PLC_TO_NC)})
        return CanLinkedPlc(self, layout, environment, description_frames(settings, description.to_json()))

    def close(self) -> None:
        self.bus.close()


class CanLinkedPlc:
    """The simulation's PLC for one session of a :class:`CanLink`."""

    def __init__(self, link: CanLink, layout: CanLayout, environment: PlcEnvironment, description: list[Frame]):
        self.link = link
        self.layout = layout
        self.session = link.session
        self.lockstep = link.mode is LinkMode.LOCKSTEP
        self.plc_cycle_ipo = environment.plc_cycle_ipo
        self.ipo_cycle_s = environment.ipo_cycle_us / 1_000_000
        self.period = link.config.period_cycles(environment.ipo_cycle_us, environment.plc_cycle_ipo)
        self.timeout = link.config.timeout_cycles(environment.ipo_cycle_us)
        self.controller = CanController.for_cycle(link.config.restart_cycles(environment.ipo_cycle_us),
                                                  environment.ipo_cycle_us)
        self.scans = 0
        self.cycle = 0  # the NC cycle of the last call
        self.faults: list[LinkFault] = []
        self.to_plc: FaultyWire[Frame] = FaultyWire(Direction.NC_TO_PLC)
        self.to_nc: FaultyWire[Frame] = FaultyWire(Direction.PLC_TO_NC)
        self.sent = 0  # frames the NC put on the bus (their content reached it)
        self.taken = 0  # frames from the PLC the NC took
        self.bus_errors = 0  # sends and receives the bus refused (the NC's watch reacts)
        self.last_bus_error = ""
        self._plc_link_id = layout.settings.plc_link_id
        self._areas_to_plc = [slot.area for slot in layout.slots[Direction.NC_TO_PLC]]
        self._arrived = {can_id: 0 for can_id in (self._plc_link_id, *layout.ids(Direction.PLC_TO_NC))}
        self._description = description
        self._areas: Mapping[str, bytearray] = {}
        self._grant = 0
        self._nc_life = 0
        self._nc_life_out = 0  # the NC's sign of life as the PLC got it (lockstep: held while its frame is lost)
        self._nc_link = Frame(0, b"")  # the last NC link frame sent
        self._ready = False  # the PLC reported this session started
        self._done = 0  # the scan the PLC reported done (its raw handshake)
        self._life = 0  # the PLC's sign of life as the NC got it
        self._shown_life = 0  # ... as the NC sees it: held while a frame is missing
        self._plc_misses_nc = False  # the PLC's time-out monitor misses the NC's frames
        self._quantities = self._readers()

    @property
    def sign_of_life(self) -> int:
        return self._shown_life

    @property
    def peer(self) -> str:
        """Who holds the session, for the session recording: a node has no address on the bus."""
        return f"external PLC on CAN bus {self.link.spec}" if self.taken else ""

    # ------------------------------------------------------------------ faults, observables
    def inject_fault(self, fault: LinkFault) -> None:
        self.faults = [*active(self.faults, self.cycle), fault]

    def quantity(self, name: str) -> float:
        """One of ``LINK_QUANTITIES`` (vc/simulation/observables.py) now."""
        return float(self._quantities[name]())

    def _readers(self) -> dict[str, Callable[[], float]]:
        return {
            "framesSent": lambda: self.sent,
            "framesTaken": lambda: self.taken,
            "lostToPlc": lambda: self.to_plc.lost,
            "lostFromPlc": lambda: self.to_nc.lost,
            "delayedToPlc": lambda: self.to_plc.delayed,
            "delayedFromPlc": lambda: self.to_nc.delayed,
            "plcFrameAge": lambda: (self.cycle - min(self._arrived.values())) * self.ipo_cycle_s,
            "timedOut": lambda: float(bool(self.missing)),
            "plcSignOfLife": lambda: self._shown_life,
            "plcMissesNcFrames": lambda: float(self._plc_misses_nc),
            "busState": lambda: max(self.controller.state, self.link.bus.state),
            "transmitErrors": lambda: max(self.controller.transmit_errors, self.link.bus.transmit_errors),
            "busOffs": lambda: self.controller.bus_offs,
        }

    def _disturbed(self, cycle: int) -> bool:
        return disturbed(self.faults, cycle)

    # ------------------------------------------------------------------ the simulation's calls
    def scan(self, interface: ProcessImage, plant: ProcessImage) -> None:
        if self.link.session != self.session:
            raise LinkError(f"session {self.session} was replaced by session {self.link.session}")
        self._areas = {**interface.areas, **plant.areas}
        cycle = self.cycle = self.scans * self.plc_cycle_ipo
        self.controller.tick(cycle, self._disturbed(cycle))
        self.scans += 1
        if self.lockstep:
            self._grant = grant_of_scan(self.scans)
            self._publish(cycle, data=cycle % self.period == 0)
            self._wait_for_scan(self._grant, cycle)
        else:
            if cycle % self.period == 0:
                self._publish(cycle, data=True)
            self._receive_pending(cycle)
        if self._deliver(cycle):
            interface.touch()
            plant.touch()
        self._monitor(cycle)

    def sends_at(self, cycle: int) -> bool:
        """Whether the NC-to-PLC frames go out in IPO cycle ``cycle`` (between two scans)."""
        return cycle % self.period == 0

    def ipo_cycle(self, cycle: int, interface: ProcessImage, plant: ProcessImage) -> bool:
        """Between two scans: send when the period is due, take what arrived; True when PLC-to-NC
        bytes changed."""
        self.cycle = cycle
        self.controller.tick(cycle, self._disturbed(cycle))
        if cycle % self.period == 0:
            self._areas = {**interface.areas, **plant.areas}
            self._publish(cycle, data=True)
        elif self.to_plc.waiting:
            self._flush_to_plc(cycle)
        if not self.lockstep:
            self._receive_pending(cycle)
        return self._deliver(cycle)

    # ------------------------------------------------------------------ sending
    def _publish(self, cycle: int, data: bool) -> None:
        """The NC-to-PLC data frames (when ``data``), then the NC link frame."""
        faults = self.faults
        if data:
            for frame, area in zip(self.layout.frames(Direction.NC_TO_PLC, self._areas), self._areas_to_plc,
                                   strict=True):
                self.to_plc.put(frame, area, cycle, faults)
        self._nc_life = (self._nc_life + 1) & 0xFF
        mode = MODE_LOCKSTEP if self.lockstep else MODE_FREE_RUNNING
        settings = self.layout.settings
        if not self.lockstep:
            self.to_plc.put(NcLink(mode, self._nc_life, self.session, 0).encode(settings), LINK_AREA, cycle, faults)
            self._flush_to_plc(cycle)
            return
        self._flush_to_plc(cycle)
        # The stepping's handshake is never withheld, only what the frame carries for the PLC:
        # the NC's sign of life stands while a fault or the controller keeps the frame off the bus.
        if not self.to_plc.loses(LINK_AREA, cycle, faults) and self._transmits(cycle, self._bus_state(cycle)):
            self._nc_life_out = self._nc_life
        self._nc_link = NcLink(mode, self._nc_life_out, self.session, self._grant).encode(settings)
        self._send(self._nc_link)

    def _flush_to_plc(self, cycle: int) -> None:
        if not self.to_plc.waiting:
            return
        state = self._bus_state(cycle)
        for frame in self.to_plc.take(cycle):
            if self._transmits(cycle, state):
                self._send(frame)
            else:
                self.to_plc.lost += 1

    def _bus_state(self, cycle: int) -> tuple[bool, bool]:
        """What holds the controller's frames now: the interface reports bus-off (a real bus), a
        disturbance (simulated); read once for a burst of frames."""
        return self.link.bus.bus_off, self._disturbed(cycle)

    def _transmits(self, cycle: int, state: tuple[bool, bool]) -> bool:
        """Whether the controller puts a frame on the bus now (not while bus-off, simulated or reported)."""
        reported_off, disturbance = state
        if reported_off:
            return False
        if self.controller.transmit(cycle, disturbance):
            self.sent += 1
            return True
        return False

    def _send(self, frame: Frame) -> None:
        """A frame the bus refuses is lost, as on a bus (a controller that went bus-off): counted,
        and the time-out monitors react; in lockstep the link frame goes again after the wait."""
        try:
            self.link.bus.send(frame)
        except LinkError as error:
            self._bus_error(error)

    def _bus_error(self, error: LinkError) -> None:
        self.bus_errors += 1
        self.last_bus_error = str(error)

    # ------------------------------------------------------------------ receiving
    def _wait_for_scan(self, grant: int, cycle: int) -> None:
        """Receive until the PLC reports scan ``grant`` of this session done."""
        link = self.link
        patience = Patience.for_scan(self.scans == 1, link.first_scan_timeout_s, link.scan_timeout_s, link.on_wait,
                                     link.peer_ended, lambda waited: self._silence(grant, waited))
        receive, peer = link.bus.receive, link.peer
        wait = 0.0 if peer is not None else RECEIVE_WAIT_S
        while not (self._ready and self._done == grant):
            try:
                frame = receive(wait)
            except LinkError as error:  # the bus failed: a fault like a lost frame, not the end
                self._bus_error(error)
                wallclock.sleep(wait)  # a failing bus fails at once: no busy loop
                frame = None
            if frame is not None:
                self._received(frame, cycle)
            elif peer is not None:
                peer()
            else:
                # Nothing for a while: the PLC was not listening yet, or a frame went missing.
                # The same frame again asks the PLC to repeat its last answer.
                self._send(self._nc_link)
            patience.check()

    def _silence(self, grant: int, waited: float) -> str:
        where = f"CAN bus {self.link.spec}"
        if not self._ready:
            return f"no PLC has started session {self.session} on the {where} after {waited:.0f} s"
        return f"the PLC on the {where} has not finished scan {grant} after {waited:.0f} s"

    def _receive_pending(self, cycle: int) -> None:
        """Free-running: what has arrived (a bus that fails counts as silent)."""
        receive = self.link.bus.receive
        try:
            while (frame := receive(0)) is not None:
                self._received(frame, cycle)
        except LinkError as error:
            self.bus_errors += 1
            self.last_bus_error = str(error)

    def _received(self, frame: Frame, cycle: int) -> None:
        if frame.can_id != self._plc_link_id:
            slot = self.layout.by_id.get(frame.can_id)
            if slot is not None:
                self._take_in(frame, slot.area, cycle)
            return
        link = PlcLink.decode(frame.can_id, frame.data)
        if link is None:
            return
        if link.needs_description:
            state = self._bus_state(cycle)
            for segment in self._description:
                if self._transmits(cycle, state):  # a bus-off controller answers nobody
                    self._send(segment)
            return
        if link.session_ready != self.session:
            return  # a frame of an earlier session
        self._done = link.scan_done
        if not self._ready:
            self._ready = True
            self._publish(cycle, data=True)  # what the PLC missed while it started
        self._take_in(frame, LINK_AREA, cycle)

    def _take_in(self, frame: Frame, area: str, cycle: int) -> None:
        """A frame of the PLC on its way to the NC: through the controller (a bus-off one hears
        nothing), then the faults."""
        if self.controller.receives(self._disturbed(cycle)):
            self.to_nc.put(frame, area, cycle, self.faults)
        else:
            self.to_nc.lost += 1

    def _deliver(self, cycle: int) -> bool:
        """Give the NC the PLC's frames that are due; True when data bytes changed."""
        changed = False
        by_id, arrived, areas = self.layout.by_id, self._arrived, self._areas
        for frame in self.to_nc.take(cycle):
            if frame.can_id == self._plc_link_id:
                link = PlcLink.decode(frame.can_id, frame.data)
                if link is not None:
                    self._life = link.life
                    self._plc_misses_nc = link.misses_nc_frames
                    arrived[frame.can_id] = cycle
                    self.taken += 1
            elif by_id[frame.can_id].decode(frame.data, areas):
                arrived[frame.can_id] = cycle
                self.taken += 1
                changed = True
        return changed

    def _monitor(self, cycle: int) -> None:
        """The time-out monitor: the NC sees the PLC's sign of life only while every frame is fresh."""
        oldest = min(self._arrived.values())
        if cycle - oldest <= self.timeout:
            self._shown_life = self._life

    @property
    def missing(self) -> list[int]:
        """Identifiers of the PLC-to-NC frames older than the time-out, now."""
        return [can_id for can_id, at in self._arrived.items() if self.cycle - at > self.timeout]


# ---------------------------------------------------------------------------------- a PLC on a virtual bus


class VirtualCanPlc:
    """The built-in PLC programs behind a virtual CAN bus in this process: lockstep over the real
    frames and handshake, served whenever the link waits.  A context manager."""

    def __init__(self, on_log: Callable[[str], None] = lambda text: None):
        spec = private_virtual_bus()
        self.plc_bus = CanBus(spec)
        try:
            self.node = CanPlcNode(self.plc_bus, plc_programs(), log=on_log)
            self.link = CanLink(LinkMode.LOCKSTEP, spec, peer=self.node.service_pending)
        except BaseException:
            self.plc_bus.close()  # nobody gets the half-built PLC to close it
            raise

    def simulation(self, machine: MachineConfig, program: str) -> Simulation:
        """A power-on of ``machine`` with the program behind the bus (its ``can:`` settings)."""
        self.link.configure_for(machine)
        self.node.use_link_id(machine.can.settings.link_id)
        return Simulation(machine, program, connector=self.link)

    def close(self) -> None:
        self.link.close()
        self.plc_bus.close()

    def __enter__(self) -> VirtualCanPlc:
        return self

    def __exit__(self, kind: type[BaseException] | None, error: BaseException | None,
                 trace: TracebackType | None) -> None:
        self.close()


def virtual_can_simulation(machine: MachineConfig, program: str) -> Simulation:
    """A simulation whose PLC program sits behind its own virtual CAN bus; the bus closes with it."""
    virtual = VirtualCanPlc()
    try:
        simulation = virtual.simulation(machine, program)
    except BaseException:
        virtual.close()
        raise
    weakref.finalize(simulation, virtual.close)
    return simulation
