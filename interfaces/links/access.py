"""Who may connect to the harness's servers, who may write into the NC, and how many may stay.

Three rules the Modbus TCP and the S7 server share (:mod:`interfaces.links.modbus_tcp`,
:mod:`interfaces.links.s7`):

* **Allow-list** (``vc serve --allow IP,NET``): a client outside it is disconnected as it
  connects.  Empty: every client that reaches the socket (the servers bind to loopback unless
  ``--allow-remote`` is given).
* **The PLC owns its link** (:class:`LinkOwner`): while a session is open, one connection, the
  session's PLC, may write the PLC-to-NC area (and with it the sign of life).  The connection
  becomes the owner with its *claim*: over Modbus the write of the session number into holding
  register 1 (session ready), which every PLC of the protocol makes when it starts a session;
  over S7, which has no such handshake, its first write.  It stays the owner until it
  disconnects (a new session keeps it: the same PLC restarts its program).  Other clients may
  read; their writes are refused and counted.  ``--allow-writers IP,NET`` lets the clients of
  those addresses write as well, without owning the link (tools that force signals, a PLC that
  spreads its transfers over several connections).  The owner is shared by all servers of one
  link: a PLC on Modbus locks S7 writers out and the other way round.
* **Connection limits** (:class:`ConnectionLimits`): at most ``max_clients`` connections per
  server; a connection that has sent nothing for ``idle_timeout_s`` is closed.  When a client
  connects to a full server the connection idle the longest is closed to make room for it (the
  owner never; a connection with a request in progress never), as the Modbus implementation
  guide suggests for its connection management [INF]; when every connection is busy the newcomer
  is closed.  So idle or half-open connections never lock the PLC out.

Threads: the S7 server serves each client in a thread of its own, so the owner is changed under
a lock.
"""

from __future__ import annotations

import ipaddress
import threading
from collections.abc import Collection, Hashable
from dataclasses import dataclass

from interfaces.links.errors import LinkError

Network = ipaddress.IPv4Network | ipaddress.IPv6Network

DEFAULT_MAX_CLIENTS = 64  # per server; 50 busy masters (the flood of the robustness campaign) still fit
DEFAULT_IDLE_TIMEOUT_S = 60.0  # a master polls every few ms; one silent for a minute is gone [INF]


def parse_allowed_clients(texts: Collection[str]) -> list[Network]:
    """``127.0.0.1``, ``10.0.0.0/24`` ... as networks; raises LinkError naming a bad entry."""
    networks = []
    for text in texts:
        try:
            networks.append(ipaddress.ip_network(text.strip(), strict=False))
        except ValueError:
            raise LinkError(f"'{text}' is not an IP address or network (e.g. 127.0.0.1, 10.0.0.0/24)") from None
    return networks


class AllowList:
    """Addresses and networks; an empty list lets everybody in (``admits_all_when_empty``)."""

    def __init__(self, texts: Collection[str] = (), admits_all_when_empty: bool = True):
        self.networks = parse_allowed_clients(texts)
        self._all_when_empty = admits_all_when_empty

    def __bool__(self) -> bool:
        return bool(self.networks)

    def admits(self, peer: str) -> bool:
        if not self.networks:
            return self._all_when_empty
        try:
            address = ipaddress.ip_address(peer)
        except ValueError:
            return False
        return any(address in network for network in self.networks)


@dataclass(frozen=True, slots=True)
class ConnectionLimits:
    """How many connections a server keeps and how long an idle one stays (module docstring)."""

    max_clients: int = DEFAULT_MAX_CLIENTS
    idle_timeout_s: float = DEFAULT_IDLE_TIMEOUT_S

    def __post_init__(self) -> None:
        if self.max_clients < 1:
            raise LinkError(f"at least one client must be able to connect (max clients {self.max_clients})")
        if not self.idle_timeout_s > 0:
            raise LinkError(f"the idle time-out must be longer than 0 s ({self.idle_timeout_s:g})")


class LinkOwner:
    """The session's PLC: the one connection that may write the PLC-to-NC area (module docstring).

    A connection is any hashable key its server chooses (unique while it is connected)."""

    def __init__(self, allow_writers: Collection[str] = ()):
        self.writers = AllowList(allow_writers, admits_all_when_empty=False)
        self.owner: Hashable | None = None
        self.owner_peer = ""  # the owner's address, for the statistics
        self.refused = 0  # writes refused because they did not come from the owner
        self.claims = 0  # times a connection became the owner
        self._lock = threading.Lock()

    def may_write(self, connection: Hashable, peer: str, claims: bool) -> bool:
        """Whether a write of ``connection`` (from address ``peer``) may change the PLC-to-NC area;
        ``claims``: the write is the connection's claim (it becomes the owner when there is none).
        A refused write is counted."""
        with self._lock:
            if connection == self.owner:
                return True
            if self.owner is None and claims:
                self.owner, self.owner_peer = connection, peer
                self.claims += 1
                return True
            if self.writers.admits(peer):
                return True
            self.refused += 1
            return False

    def release(self, connection: Hashable) -> None:
        """``connection`` is gone: when it owned the link, the next claim takes it."""
        with self._lock:
            if connection == self.owner:
                self.owner, self.owner_peer = None, ""

    def owns(self, connection: Hashable) -> bool:
        return connection == self.owner

    def describe(self) -> str:
        """The owner for the statistics line."""
        owner = f"PLC at {self.owner_peer}" if self.owner is not None else "no PLC has claimed the session"
        return owner + (f", {self.refused} write(s) of other clients refused" if self.refused else "")
