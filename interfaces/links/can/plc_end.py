"""The PLC's end of the CAN link (:mod:`interfaces.links.can.codec`), for any soft PLC.

The node configures itself from the harness, as the Modbus client does: when the NC link frame
shows a new session it asks for the description (PLC link frame, flag bit 0; again every
:data:`REQUEST_AGAIN_S` while segments are missing), builds the frames from the CAN settings in
it, starts the program the description names (or the one it was told to run) and reports the
session ready.  Then it follows the NC's mode:

* **lockstep**: an NC link frame that grants a scan other than the last one handled runs one scan
  with the data frames received before it, sends the PLC-to-NC data frames and then the PLC link
  frame with the grant as scan done and its sign of life counted up;
* **free-running**: the owner calls :meth:`CanPlcNode.scan` on its own clock; a scan uses the
  data frames received so far.

Data frames are copied into the PLC's image as they arrive (a frame with a wrong checksum is
dropped).  **Time-out monitor**: every NC-to-PLC data frame, and a new sign of life in the NC link
frame, must have arrived within the description's ``can_timeout_us``: in lockstep counted in the PLC's
scans (each one the NC's PLC period), free-running on the PLC's own monotonic clock, whatever its
scan rate or the harness's speed.
While one is missing the PLC does what an S7 CPU does with the inputs of a failed station
([control]: substitute value 0): it scans with every NC-to-PLC byte and plant input at 0, so the
normally closed emergency-stop chain reads open, the drives not ready and no key pressed; the
program drops the enables and reports the emergency stop to the NC.  The PLC link frame's flag
bit 1 tells the NC the PLC misses its frames.

**Faults of the bus never end the node**: a frame the bus refuses to send, a receive that fails,
are counted (:attr:`CanPlcNode.bus_errors`, the first one logged) and the node goes on, as a PLC's
CAN module does; its time-out monitor and the NC's react to what goes missing.  An NC link frame
of another link version is dropped as well; only :data:`OTHER_VERSION_LIMIT` of them in a row (a
harness that really speaks another version) stop the node.

``python -m plc_stub --can`` runs this node with the built-in programs (:func:`run_plc`: in lockstep
it handles frames as they come and scans on every grant; free-running it scans every PLC period of the
wall clock and handles frames in between; it gives up when no harness has been heard for the idle
time-out); the harness runs it on a virtual bus in its own process for scenarios that ask for a CAN link.
"""

from __future__ import annotations

import time as wallclock
from collections.abc import Callable, Mapping
from dataclasses import dataclass

from interfaces.exchange import MODE_LOCKSTEP
from interfaces.image import ProcessImage
from interfaces.links.can.bus import BusSpec, CanBus
from interfaces.links.can.codec import (
    DEFAULT_LINK_ID,
    LINK_VERSION,
    CanLayout,
    CanSettings,
    DescriptionAssembler,
    Frame,
    NcLink,
    PlcLink,
)
from interfaces.links.description import LinkDescription, PlcSetupError
from interfaces.links.errors import LinkError
from interfaces.links.scan_loop import EXIT_NO_HARNESS, EXIT_STOPPED, PlcProcessOptions, exit_code, run_scans
from interfaces.plc import PlcFactory, SoftPlc
from interfaces.signals import Direction

REQUEST_AGAIN_S = 0.5
POLL_S = 0.1  # a PLC process in lockstep: how long one wait for the next frame lasts
OTHER_VERSION_LIMIT = 3  # NC link frames of another version in a row before the node gives up
FAILED_RECEIVE_PAUSE_S = 0.05  # after a receive the bus refused, before the next


@dataclass(slots=True)
class _Session:
    number: int
    lockstep: bool
    description: LinkDescription
    layout: CanLayout
    plc: SoftPlc
    interface: ProcessImage
    plant: ProcessImage
    areas: dict[str, bytearray]
    timeout_s: float  # how long a frame of the NC may be missing (the time-out monitor)
    scan_s: float  # lockstep: the NC's PLC period, the time one scan stands for
    arrived: dict[int, float]  # NC-to-PLC data frame or NC link frame -> when it arrived last (:meth:`now`)
    last_grant: int = 0
    inputs_seen: bool = False  # an NC link frame arrived since the start: the inputs are complete
    scans: int = 0
    nc_life: int = -1  # the NC's last sign of life
    misses_nc_frames: bool = False

    def now(self) -> float:
        """Seconds on the monitor's clock: the scans in lockstep, the wall clock free-running."""
        return self.scans * self.scan_s if self.lockstep else wallclock.monotonic()

    def watch(self) -> bool:
        """The time-out monitor before a scan: True while a frame of the NC is missing; then the
        NC's bytes are substitute values 0 for this scan."""
        now = self.now()
        missing = any(now - at > self.timeout_s + 1e-9 for at in self.arrived.values())
        if missing:
            for slot in self.layout.slots[Direction.NC_TO_PLC]:
                self.areas[slot.area][slot.start: slot.stop] = bytes(slot.stop - slot.start)
        self.misses_nc_frames = missing
        return missing


class CanPlcNode:
    """One PLC on a CAN bus (module docstring); ``programs`` maps program names to factories."""

    def __init__(self, bus: CanBus, programs: Mapping[str, PlcFactory], *, link_id: int = DEFAULT_LINK_ID,
                 program: str | None = None, log: Callable[[str], None] = lambda text: None):
        self.bus = bus
        self.programs = programs
        self.program = program
        self.log = log
        self.link = CanSettings(link_id=link_id)  # only the link frames' identifiers are known beforehand
        self.session: _Session | None = None
        self.scans = 0
        self.life = 0
        self._wanted = 0  # the session the NC announced and the PLC does not run yet
        self._wanted_lockstep = True
        self._fd = True  # the NC's frame format, which the PLC answers in
        self._asked_at = 0.0
        self._last_heard = b""  # the last NC link frame
        self._answer: Frame | None = None  # the last PLC link frame of the running session
        self._assembler = DescriptionAssembler(self.link.description_id)
        self.bus_errors = 0  # sends and receives the bus refused
        self._other_version = 0  # NC link frames of another link version in a row
        self._listen_to_link()

    def use_link_id(self, link_id: int) -> None:
        """Listen for a harness whose link frames start at ``link_id`` (the running session ends)."""
        if link_id != self.link.link_id:
            self.link = CanSettings(link_id=link_id)
            self.session, self._wanted, self._answer, self._last_heard = None, 0, None, b""
            self._assembler = DescriptionAssembler(self.link.description_id)
            self._listen_to_link()

    def _listen_to_link(self, layout: CanLayout | None = None) -> None:
        data = layout.ids(Direction.NC_TO_PLC) if layout is not None else []
        self.bus.listen({self.link.nc_link_id, self.link.description_id, *data})

    # ------------------------------------------------------------------ frames
    def service(self, timeout: float) -> bool:
        """Handle the next frame, waiting up to ``timeout`` seconds; True when a scan ran."""
        frame = self._receive(timeout)
        if frame is None:
            if self._wanted and wallclock.monotonic() - self._asked_at > REQUEST_AGAIN_S:
                self._ask_for_description()
            return False
        return self.handle(frame)

    def service_pending(self) -> None:
        """Handle every frame that has arrived (for a node in the harness's own thread)."""
        while (frame := self._receive(0)) is not None:
            self.handle(frame)

    def _receive(self, timeout: float) -> Frame | None:
        try:
            return self.bus.receive(timeout)
        except LinkError as error:
            self._bus_error(error)
            wallclock.sleep(min(timeout, FAILED_RECEIVE_PAUSE_S))  # a failing bus fails at once: no busy loop
            return None

    def _send(self, frame: Frame) -> None:
        try:
            self.bus.send(frame)
        except LinkError as error:
            self._bus_error(error)

    def _bus_error(self, error: LinkError) -> None:
        if not self.bus_errors:
            self.log(f"{error}; the node goes on (faults of the bus are counted)")
        self.bus_errors += 1

    def handle(self, frame: Frame) -> bool:
        if frame.can_id == self.link.nc_link_id:
            return self._nc_link(frame)
        if frame.can_id == self.link.description_id:
            text = self._assembler.add(frame.data) if self._wanted else None
            if text is not None:
                self._start(text)
            return False
        session = self.session
        if session is not None:
            slot = session.layout.by_id.get(frame.can_id)
            if slot is not None and slot.direction is Direction.NC_TO_PLC and slot.decode(frame.data, session.areas):
                session.arrived[frame.can_id] = session.now()
        return False

    def _nc_link(self, frame: Frame) -> bool:
        link = NcLink.decode(frame.can_id, frame.data)
        if link is None:
            return False
        if link.version != LINK_VERSION:
            self._other_version += 1
            if self._other_version >= OTHER_VERSION_LIMIT:
                raise PlcSetupError(f"the harness speaks CAN link version {link.version}, this PLC {LINK_VERSION}")
            return False
        self._other_version = 0
        self._fd = frame.fd
        repeated, self._last_heard = frame.data == self._last_heard, frame.data
        session = self.session
        if session is None or session.number != link.session:
            if self._wanted != link.session:
                self.session, self._answer = None, None
                self._listen_to_link()
                self._wanted, self._wanted_lockstep = link.session, link.mode == MODE_LOCKSTEP
                self._assembler.reset()
                self._ask_for_description()
            return False
        if repeated and self._answer is not None:
            self._send(self._answer)  # the harness missed the answer (session ready, scan done)
            return False
        session.inputs_seen = True
        if link.life != session.nc_life:
            session.nc_life = link.life
            session.arrived[frame.can_id] = session.now()
        if not session.lockstep or link.grant in (0, session.last_grant):
            return False
        self._scan(session, link.grant)
        session.last_grant = link.grant
        return True

    def _ask_for_description(self) -> None:
        self._send(PlcLink(self.life, 0, 0, needs_description=True).encode(self.link, self._fd))
        self._asked_at = wallclock.monotonic()

    def _start(self, text: bytes) -> None:
        description = LinkDescription.for_plc(text)
        environment, _, plc, name = description.start_program(self.programs, self.program)
        layout = description.can_layout(environment)
        interface = ProcessImage(environment.catalog.area_sizes)
        plant = ProcessImage(environment.plant_io.area_sizes())
        scan_s = environment.ipo_cycle_us * environment.plc_cycle_ipo / 1_000_000
        watched = {self.link.nc_link_id, *layout.ids(Direction.NC_TO_PLC)}
        lockstep = self._wanted_lockstep
        session = _Session(self._wanted, lockstep, description, layout, plc, interface, plant,
                           {**interface.areas, **plant.areas}, description.can_timeout_us / 1_000_000, scan_s,
                           dict.fromkeys(watched, 0.0 if lockstep else wallclock.monotonic()))
        self.session, self._wanted = session, 0
        self._listen_to_link(layout)
        self._answer = PlcLink(self.life, session.number, 0).encode(self.link, self._fd)
        self._send(self._answer)
        self.log(f"session {session.number}: machine {description.machine}, program {name},"
                 f" {'lockstep' if session.lockstep else 'free-running'}, {len(layout.by_id)} data frames")

    # ------------------------------------------------------------------ scans
    @property
    def free_running(self) -> bool:
        """A session runs that scans on the PLC's own clock."""
        return self.session is not None and not self.session.lockstep

    def scan(self) -> bool:
        """One free-running scan with the inputs received so far; False while there is nothing to
        scan for (no session, lockstep, or no inputs yet)."""
        session = self.session
        if session is None or session.lockstep or not session.inputs_seen:
            return False
        self._scan(session, 0)
        return True

    def _scan(self, session: _Session, done: int) -> None:
        was_missing = session.misses_nc_frames
        if session.watch() != was_missing:
            self.log(f"session {session.number}: " + ("the NC's frames are back" if was_missing else
                     "frames of the NC missing: scanning with substitute values 0"))
        session.plc.scan(session.interface, session.plant)
        session.scans += 1
        self.life = (self.life + 1) & 0xFF
        for frame in session.layout.frames(Direction.PLC_TO_NC, session.areas):
            self._send(frame)
        self._answer = PlcLink(self.life, session.number, done,
                               misses_nc_frames=session.misses_nc_frames).encode(self.link, self._fd)
        self._send(self._answer)
        self.scans += 1

class _Silent(LinkError):
    """No harness heard on the bus for the idle time-out."""


class _CanTransport:
    """The node on its bus as :func:`~interfaces.links.scan_loop.run_scans` drives it; gives up (:class:`_Silent`)
    when no harness has been heard for ``idle_timeout_s``."""

    def __init__(self, node: CanPlcNode, bus: CanBus, idle_timeout_s: float):
        self.node = node
        self.bus = bus
        self.idle_timeout_s = idle_timeout_s
        self._heard_at = wallclock.monotonic()
        self._received = bus.received

    def free_running_period(self) -> float | None:
        session = self.node.session
        return session.description.scan_time_s if session is not None and self.node.free_running else None

    def follow(self) -> None:
        self.idle(POLL_S)

    def idle(self, seconds: float) -> None:
        self.node.service(seconds)
        if self.bus.received != self._received:
            self._received, self._heard_at = self.bus.received, wallclock.monotonic()
        elif wallclock.monotonic() - self._heard_at > self.idle_timeout_s:
            raise _Silent(f"no harness heard on {self.bus.spec} for {self.idle_timeout_s:g} s")

    def scan(self) -> None:
        self.node.scan()


def run_plc(bus_text: str, programs: Mapping[str, PlcFactory], options: PlcProcessOptions,
            log: Callable[[str], None], should_stop: Callable[[], bool] = lambda: False) -> int:
    """The soft PLC ``programs`` as a node on the bus ``bus_text`` until stopped; the exit code of
    ``python -m plc_stub --can``: 0 stopped, 1 no bus or no harness heard for
    ``options.connect_timeout_s``, 2 the PLC cannot run what the harness describes."""
    link_id = DEFAULT_LINK_ID if options.link_id is None else options.link_id
    try:
        bus = CanBus(BusSpec.parse(bus_text))
    except LinkError as error:
        log(str(error))
        return EXIT_NO_HARNESS
    node = CanPlcNode(bus, programs, link_id=link_id, program=options.program, log=log)
    log(f"listening on the CAN bus {bus.spec}, link frames from 0x{link_id:03X}")

    def run() -> int:
        try:
            run_scans(_CanTransport(node, bus, options.connect_timeout_s), options.period_s, should_stop)
        except _Silent as silent:
            log(str(silent))
            return EXIT_NO_HARNESS
        except LinkError as error:
            log(f"bus lost: {error}")
            return EXIT_NO_HARNESS
        return EXIT_STOPPED

    try:
        return exit_code(run, log)
    finally:
        bus.close()
