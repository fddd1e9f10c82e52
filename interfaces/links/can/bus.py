"""CAN buses on python-can: the only module that imports it; its exceptions become :class:`LinkError`.

A bus is named by a text (:meth:`BusSpec.parse`)::

    virtual[:CHANNEL]               in this process (python-can's virtual bus); channel default "vc"
    udp_multicast[:GROUP[:PORT]]    processes on one host: UDP multicast with hop limit 0, so that no
                                    frame leaves the host; default group 239.74.163.2, port 43113
    socketcan[:INTERFACE]           a Linux CAN interface: can0 (default), vcan0 ...; FD as the
                                    frames say (the interface must be configured for CAN FD)

A node receives only the identifiers it listens to (:meth:`CanBus.listen`): on UDP multicast every
sender also receives its own frames, and a node never listens to the identifiers it sends itself,
so its own frames are dropped here, as is traffic of other nodes.

The node's CAN controller state (:class:`ControllerState`, ISO 11898-1 fault confinement) is what
the hardware reports: python-can's ``BusABC.state`` where the interface knows it, and SocketCAN's
error frames (``linux/can/error.h``): controller problems (error passive, back to error active,
with the error counters) and bus-off, until the controller is restarted (the interface's
``restart-ms``) or a frame arrives again.  On a bus without a controller (virtual, UDP multicast)
an error frame is one *on the wire*, sent by another node: it counts the receive error counter up
by one as ISO 11898-1 counts a receiver's errors (error passive from 128; every frame received
counts it down, from beyond 127 back to 127), and receive errors never make a controller
bus-off, however many arrive.  A send the bus refuses raises :class:`LinkError`; while the
controller is bus-off the node sends nothing (:attr:`CanBus.state`, read by the link before it
sends).

On UDP multicast any process of the host may send to the group: a datagram that is no
python-can message (python-can raises on it) is dropped and counted (:attr:`CanBus.foreign`),
never an error of the bus.
"""

from __future__ import annotations

import contextlib
import itertools
import logging
import os
import socket
import time as wallclock
from collections.abc import Collection
from dataclasses import dataclass

import can

from interfaces.links.can.codec import ControllerState, Frame
from interfaces.links.errors import LinkError

KINDS = ("virtual", "udp_multicast", "socketcan")
DEFAULT_GROUP = "239.74.163.2"  # python-can's IPv4 default group
DEFAULT_PORT = 43113
DEFAULT_VIRTUAL_CHANNEL = "vc"
DEFAULT_SOCKETCAN = "can0"
# SocketCAN error frames (linux/can/error.h): error classes in the identifier, details in the data
CAN_ERR_CRTL = 0x04  # controller problems, data[1]
CAN_ERR_BUSOFF = 0x40
CAN_ERR_RESTARTED = 0x100  # the controller restarted after bus-off
CAN_ERR_CNT = 0x200  # data[6] transmit error counter, data[7] receive error counter
CAN_ERR_CRTL_RX_PASSIVE = 0x10
CAN_ERR_CRTL_TX_PASSIVE = 0x20
CAN_ERR_CRTL_ACTIVE = 0x40  # back to error active
_PRIVATE_GROUPS = 0xFFFF  # 239.74.0.0 .. 239.74.255.255 for private channels
ERROR_PASSIVE_ERRORS = 128  # ISO 11898-1: a counter at 128 or more makes the controller error passive
RECEIVE_ERRORS_AFTER_RECEPTION = 127  # a frame received with the counter beyond 127 sets it to 119..127

# python-can logs every socket it could not configure; the link reports what matters itself.
logging.getLogger("can").setLevel(logging.ERROR)


_PYTHON_CAN_STATES = {can.BusState.ACTIVE: ControllerState.ERROR_ACTIVE,
                      can.BusState.PASSIVE: ControllerState.ERROR_PASSIVE,
                      can.BusState.ERROR: ControllerState.BUS_OFF}


@dataclass(frozen=True, slots=True)
class BusSpec:
    """Which bus: ``kind`` one of :data:`KINDS`, its channel and (udp_multicast) port."""

    kind: str
    channel: str
    port: int = 0

    @classmethod
    def parse(cls, text: str) -> BusSpec:
        kind, _, rest = text.strip().partition(":")
        if kind not in KINDS:
            raise LinkError(f"'{text}': the bus is one of {', '.join(KINDS)} (e.g. udp_multicast,"
                            f" socketcan:can0, virtual)")
        if kind == "virtual":
            return cls(kind, rest or DEFAULT_VIRTUAL_CHANNEL)
        if kind == "socketcan":
            return cls(kind, rest or DEFAULT_SOCKETCAN)
        group, _, port = rest.rpartition(":") if rest.count(":") == 1 else (rest, "", "")
        try:
            number = int(port) if port else DEFAULT_PORT
            if not 0 < number < 65536:
                raise ValueError
            socket.inet_aton(group or DEFAULT_GROUP)
        except (OSError, ValueError):
            raise LinkError(f"'{text}': udp_multicast takes GROUP:PORT, e.g. udp_multicast:{DEFAULT_GROUP}:"
                            f"{DEFAULT_PORT}") from None
        if not 224 <= int((group or DEFAULT_GROUP).split(".")[0]) <= 239:
            raise LinkError(f"'{text}': {group} is not a multicast group (224.0.0.0 .. 239.255.255.255)")
        return cls(kind, group or DEFAULT_GROUP, number)

    def __str__(self) -> str:
        return f"{self.kind}:{self.channel}:{self.port}" if self.kind == "udp_multicast" else \
            f"{self.kind}:{self.channel}"


_virtual_channels = itertools.count(1)


def private_virtual_bus() -> BusSpec:
    """A virtual bus channel no other link of this process uses."""
    return BusSpec("virtual", f"{DEFAULT_VIRTUAL_CHANNEL}-{os.getpid()}-{next(_virtual_channels)}")


def private_udp_bus() -> BusSpec:
    """A UDP multicast channel for one harness run: a port the kernel hands out as free (so two runs
    on one host do not meet), and a group derived from it."""
    with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as probe:
        probe.bind(("127.0.0.1", 0))
        port = int(probe.getsockname()[1])
    group = (os.getpid() * 7919 + port) % _PRIVATE_GROUPS + 1
    return BusSpec("udp_multicast", f"239.74.{group >> 8 & 0xFF}.{group & 0xFF}", port)


def socketcan_available(interface: str = "vcan0") -> bool:
    """Whether this kernel has SocketCAN and ``interface`` can be opened (tests skip otherwise)."""
    if not hasattr(socket, "AF_CAN"):
        return False
    try:
        with socket.socket(socket.AF_CAN, socket.SOCK_RAW, socket.CAN_RAW) as probe:
            probe.bind((interface,))
    except OSError:
        return False
    return True


def _no_frame(error: BaseException) -> bool:
    """Whether python-can failed on what arrived rather than on the bus: it raises its operation
    error *from* the exception of unpacking a UDP datagram that is no message of its own (a socket
    that fails raises an OSError, or an operation error from one)."""
    cause = error.__cause__
    return isinstance(error, can.CanOperationError) and cause is not None and not isinstance(cause, OSError)


class CanBus:
    """One node on a bus: sends frames, receives the identifiers it listens to."""

    def __init__(self, spec: BusSpec, fd: bool = True, listen: Collection[int] = (),
                 opened: can.BusABC | None = None):
        """``opened``: a python-can bus opened elsewhere (a test's stand-in for an interface)."""
        self.spec = spec
        self.fd = fd
        self._listen = frozenset(listen)
        self.sent = 0  # frames sent
        self.received = 0  # frames received that the node listens to
        self.dropped = 0  # own frames and other traffic
        self.error_frames = 0
        self.foreign = 0  # datagrams that are no frames (UDP multicast), dropped
        self.transmit_errors = 0  # the controller's error counters, as its last error frame gave them
        self.receive_errors = 0
        self._reported = ControllerState.ERROR_ACTIVE  # by error frames
        try:
            if opened is not None:
                self._bus: can.BusABC = opened
            elif spec.kind == "virtual":
                self._bus = can.Bus(interface="virtual", channel=spec.channel,
                                                protocol=can.CanProtocol.CAN_FD if fd else can.CanProtocol.CAN_20)
            elif spec.kind == "udp_multicast":
                self._bus = can.Bus(interface="udp_multicast", channel=spec.channel, port=spec.port, hop_limit=0,
                                    fd=fd)
            else:
                self._bus = can.Bus(interface="socketcan", channel=spec.channel, fd=fd)
        except (can.CanError, OSError, ValueError) as error:
            raise LinkError(f"cannot open the CAN bus {spec}: {error}") from None

    @property
    def state(self) -> ControllerState:
        """The controller's state: the worse of what the interface reports and what its error frames said."""
        try:
            reported = _PYTHON_CAN_STATES.get(self._bus.state, ControllerState.ERROR_ACTIVE)
        except (NotImplementedError, can.CanError, OSError):
            # an interface that cannot report its controller's state (a plug-in may raise
            # NotImplementedError, a closed socket OSError): only the error frames tell
            reported = ControllerState.ERROR_ACTIVE
        return max(reported, self._reported)

    @property
    def bus_off(self) -> bool:
        return self.state is ControllerState.BUS_OFF

    def _error_frame(self, message: can.Message) -> None:
        """Follow the controller's state through a SocketCAN error frame, or count an error frame
        on the wire of a bus without a controller (module docstring)."""
        self.error_frames += 1
        if self.spec.kind != "socketcan":
            self.receive_errors += 1
            if self.receive_errors >= ERROR_PASSIVE_ERRORS:
                self._reported = max(self._reported, ControllerState.ERROR_PASSIVE)
            return
        error_class, data = message.arbitration_id, bytes(message.data) + bytes(8)
        if error_class & CAN_ERR_CNT:
            self.transmit_errors, self.receive_errors = data[6], data[7]
        if error_class & CAN_ERR_BUSOFF:
            self._reported = ControllerState.BUS_OFF
        elif error_class & CAN_ERR_RESTARTED:
            self._back_on_the_bus()
        elif error_class & CAN_ERR_CRTL:
            if data[1] & (CAN_ERR_CRTL_RX_PASSIVE | CAN_ERR_CRTL_TX_PASSIVE):
                self._reported = ControllerState.ERROR_PASSIVE
            elif data[1] & CAN_ERR_CRTL_ACTIVE:
                self._reported = ControllerState.ERROR_ACTIVE

    def _received_a_frame(self) -> None:
        """A frame received: a bus-off controller is back; without a controller the receive error
        counter counts down (ISO 11898-1)."""
        if self._reported is ControllerState.BUS_OFF:
            self._back_on_the_bus()
        elif self.spec.kind != "socketcan" and self.receive_errors:
            self.receive_errors = min(self.receive_errors - 1, RECEIVE_ERRORS_AFTER_RECEPTION)
            if self.receive_errors < ERROR_PASSIVE_ERRORS:
                self._reported = ControllerState.ERROR_ACTIVE

    def _back_on_the_bus(self) -> None:
        """A restart leaves the controller error active with its counters at 0 (ISO 11898-1)."""
        self._reported = ControllerState.ERROR_ACTIVE
        self.transmit_errors = self.receive_errors = 0

    def listen(self, identifiers: Collection[int]) -> None:
        """Receive these identifiers from now on (and nothing else)."""
        self._listen = frozenset(identifiers)

    def send(self, frame: Frame) -> None:
        try:
            self._bus.send(can.Message(arbitration_id=frame.can_id, data=frame.data, is_fd=frame.fd,
                                       is_extended_id=False, check=False))
        except (can.CanError, OSError) as error:
            raise LinkError(f"CAN bus {self.spec}: frame 0x{frame.can_id:03X} not sent: {error}") from None
        self.sent += 1

    def send_error_frame(self, error_class: int, data: bytes = bytes(8)) -> None:
        """An error frame on the wire of a bus without controllers (virtual, UDP multicast), as a
        disturbance of the bus would give it: for fault injection."""
        try:
            self._bus.send(can.Message(arbitration_id=error_class, data=data, is_error_frame=True,
                                       is_extended_id=False, check=False))
        except (can.CanError, OSError) as error:
            raise LinkError(f"CAN bus {self.spec}: error frame not sent: {error}") from None

    def receive(self, timeout: float | None) -> Frame | None:
        """The next frame the node listens to, or None after ``timeout`` seconds (0: only what is
        there; None: wait for ever)."""
        deadline = None if timeout is None else wallclock.monotonic() + timeout
        while True:
            remaining = None if deadline is None else max(0.0, deadline - wallclock.monotonic())
            try:
                message = self._bus.recv(remaining)
            except (can.CanError, OSError) as error:
                if not _no_frame(error):
                    raise LinkError(f"CAN bus {self.spec}: {error}") from None
                self.foreign += 1
            else:
                if message is None:
                    return None
                frame = self._take(message)
                if frame is not None:
                    return frame
            if timeout and deadline is not None and wallclock.monotonic() >= deadline:
                return None  # (with timeout 0 the loop drains what is there: recv answers None when empty)

    def _take(self, message: can.Message) -> Frame | None:
        """The frame of a message the node listens to; None for an error frame or other traffic."""
        if message.is_error_frame:
            self._error_frame(message)
            return None
        self._received_a_frame()
        if message.arbitration_id in self._listen and not message.is_remote_frame:
            self.received += 1
            return Frame(message.arbitration_id, bytes(message.data), message.is_fd)
        self.dropped += 1
        return None

    def close(self) -> None:
        with contextlib.suppress(can.CanError, OSError):
            self._bus.shutdown()
