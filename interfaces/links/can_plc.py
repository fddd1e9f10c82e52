"""The PLC's end of the CAN link (:mod:`interfaces.codec_can`), for any soft PLC.

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
dropped).  ``python -m plc_stub --can`` runs this node with the built-in programs; the harness
runs it on a virtual bus in its own process for scenarios that ask for a CAN link.
"""

from __future__ import annotations

import time as wallclock
from collections.abc import Callable, Mapping
from dataclasses import dataclass

from interfaces.codec_can import (
    DEFAULT_LINK_ID,
    LINK_VERSION,
    CanLayout,
    CanSettings,
    DescriptionAssembler,
    Frame,
    NcLink,
    PlcLink,
)
from interfaces.exchange import MODE_LOCKSTEP
from interfaces.image import ProcessImage
from interfaces.link_description import DescriptionError, LinkDescription
from interfaces.links.can_bus import CanBus
from interfaces.plc import PlcFactory, SoftPlc
from interfaces.signals import Direction

REQUEST_AGAIN_S = 0.5


class PlcSetupError(Exception):
    """The PLC cannot run what the harness describes (unknown program, other catalogue)."""


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
    last_grant: int = 0
    inputs_seen: bool = False  # an NC link frame arrived since the start: the inputs are complete


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
        frame = self.bus.receive(timeout)
        if frame is None:
            if self._wanted and wallclock.monotonic() - self._asked_at > REQUEST_AGAIN_S:
                self._ask_for_description()
            return False
        return self.handle(frame)

    def service_pending(self) -> None:
        """Handle every frame that has arrived (for a node in the harness's own thread)."""
        while (frame := self.bus.receive(0)) is not None:
            self.handle(frame)

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
            if slot is not None and slot.direction is Direction.NC_TO_PLC:
                slot.decode(frame.data, session.areas)
        return False

    def _nc_link(self, frame: Frame) -> bool:
        link = NcLink.decode(frame.can_id, frame.data)
        if link is None:
            return False
        if link.version != LINK_VERSION:
            raise PlcSetupError(f"the harness speaks CAN link version {link.version}, this PLC {LINK_VERSION}")
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
            self.bus.send(self._answer)  # the harness missed the answer (session ready, scan done)
            return False
        session.inputs_seen = True
        if not session.lockstep or link.grant in (0, session.last_grant):
            return False
        self._scan(session, link.grant)
        session.last_grant = link.grant
        return True

    def _ask_for_description(self) -> None:
        self.bus.send(PlcLink(self.life, 0, 0, needs_description=True).encode(self.link, self._fd))
        self._asked_at = wallclock.monotonic()

    def _start(self, text: bytes) -> None:
        try:
            description = LinkDescription.from_json(text)
            environment, _ = description.environment()
            layout = description.can_layout(environment)
        except DescriptionError as error:
            raise PlcSetupError(str(error)) from None
        name = self.program or description.program
        if name is None:
            raise PlcSetupError("the harness asks for no program: start the PLC with --program NAME")
        factory = self.programs.get(name)
        if factory is None:
            raise PlcSetupError(f"no PLC program '{name}' (known: {', '.join(sorted(self.programs))})")
        interface = ProcessImage(environment.catalog.area_sizes)
        plant = ProcessImage(environment.plant_io.area_sizes())
        session = _Session(self._wanted, self._wanted_lockstep, description, layout, factory(environment),
                           interface, plant, {**interface.areas, **plant.areas})
        self.session, self._wanted = session, 0
        self._listen_to_link(layout)
        self._answer = PlcLink(self.life, session.number, 0).encode(self.link, self._fd)
        self.bus.send(self._answer)
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
        session.plc.scan(session.interface, session.plant)
        self.life = (self.life + 1) & 0xFF
        for frame in session.layout.frames(Direction.PLC_TO_NC, session.areas):
            self.bus.send(frame)
        self._answer = PlcLink(self.life, session.number, done).encode(self.link, self._fd)
        self.bus.send(self._answer)
        self.scans += 1
