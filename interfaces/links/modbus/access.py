"""Who may connect to the harness's servers, who may write into the NC, and how many may stay.

Three rules the Modbus TCP and the S7 server share (:mod:`interfaces.links.modbus.server`,
:mod:`interfaces.links.modbus.s7`):

* **Allow-list** (``vc serve --allow IP,NET``): a client outside it is disconnected as it
  connects.  Empty: every client that reaches the socket (the servers bind to loopback unless
  ``--allow-remote`` is given).
* **The PLC owns its link** (:class:`LinkOwner`): while a session is open, one connection, the
  session's PLC, may write the PLC-to-NC area (and with it the sign of life).  The connection
  becomes the owner with its *claim*: over Modbus the write of the session number into holding
  register 1 (session ready), which every PLC of the protocol makes when it starts a session,
  with the PLC's *session key* in holding registers 2..5 (a random number the PLC chose, never
  readable by anybody); over S7, which has no such handshake, its first write.  It stays the
  owner until it disconnects (a new session keeps it: the same PLC restarts its program).  Other
  clients may read; their writes are refused and counted.  ``--allow-writers IP,NET`` lets the
  clients of those addresses write as well, without owning the link (tools that force signals, a
  PLC that spreads its transfers over several connections).  The owner is shared by all servers
  of one link: a PLC on Modbus locks S7 writers out and the other way round.
* **A lost PLC closes its session** (the states below): when the owner's connection ends, no
  other connection can claim the session, however it learnt the session number (input register
  1 is everybody's to read), so nobody can keep the NC's sign-of-life watch quiet or move an axis
  in the PLC's place; the NC raises alarm 2000 as for any silent PLC.  Only the PLC that held the
  session comes back into it, by its claim with the same key (a reconnect).  Everybody else waits
  for a new session: the next power-on of the machine, or the operator's new session in ``vc
  serve``.  With a *required key* (``vc serve --plc-key-file``) only a claim with that key counts,
  in every session::

      unclaimed --claim (with the required key, if one is set)--> owned
      owned --a new session (power-on)--> owned             the same PLC restarts its program
      owned --the owner's connection ends--> closed
      owned, closed --a claim with the owner's key (not 0)--> owned     the same PLC, reconnected
      closed --a new session (power-on, the operator)--> unclaimed
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
import os
import secrets
import threading
from collections.abc import Callable, Collection, Hashable
from dataclasses import dataclass
from enum import Enum

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


class OwnerState(Enum):
    """Where the ownership of the open session stands (module docstring)."""

    UNCLAIMED = "unclaimed"  # no PLC has claimed the session yet: the first claim takes it
    OWNED = "owned"  # the session's PLC is connected
    CLOSED = "closed"  # the session's PLC was lost: only its own key takes the session back


NO_KEY = 0  # a claim without a session key: its PLC cannot come back after a lost connection


class LinkOwner:
    """The session's PLC: the one connection that may write the PLC-to-NC area (module docstring).

    A connection is any hashable key its server chooses (unique while it is connected).
    ``required_key``: only a claim with this key takes a session (``vc serve --plc-key-file``).
    ``on_lost`` is told the address of an owner whose connection ended (the session closed)."""

    def __init__(self, allow_writers: Collection[str] = (), required_key: int | None = None,
                 on_lost: Callable[[str], None] = lambda peer: None):
        if required_key is not None and not 0 < required_key < 1 << 64:
            raise LinkError("a required session key is a number 1 .. 2**64 - 1")
        self.writers = AllowList(allow_writers, admits_all_when_empty=False)
        self.required_key = required_key
        self.on_lost = on_lost
        self.state = OwnerState.UNCLAIMED
        self.owner: Hashable | None = None
        self.owner_peer = ""  # the owner's address (the last owner's while the session is closed)
        self.key = NO_KEY  # the owner's session key
        self.refused = 0  # writes refused because they did not come from the owner
        self.refused_claims = 0  # of them: claims of a session that was taken or closed, or with a wrong key
        self.claims = 0  # times a connection became the owner
        self.lost = 0  # times the owner's connection ended (its session closed)
        self._lock = threading.Lock()

    def may_write(self, connection: Hashable, peer: str, claim: int | None) -> bool:
        """Whether a write of ``connection`` (from address ``peer``) may change the PLC-to-NC area;
        ``claim``: the session key of a write that claims the session (None: no claim).  A refused
        write is counted."""
        with self._lock:
            if connection == self.owner:
                return True
            if claim is not None and self._takes(claim):
                self.owner, self.owner_peer, self.key = connection, peer, claim
                self.state = OwnerState.OWNED
                self.claims += 1
                return True
            if self.writers.admits(peer):
                return True
            self.refused += 1
            self.refused_claims += claim is not None
            return False

    def _takes(self, key: int) -> bool:
        """Whether a claim with ``key`` takes the session (module docstring's states)."""
        if key != NO_KEY and key == self.key:
            return True  # the session's own PLC, back on a new connection (the old may not have ended yet)
        return self.state is OwnerState.UNCLAIMED and self.required_key in (None, key)

    def release(self, connection: Hashable) -> None:
        """``connection`` is gone: when it owned the link, the session closes (module docstring)."""
        with self._lock:
            if connection != self.owner:
                return
            self.owner = None
            self.state = OwnerState.CLOSED
            self.lost += 1
            peer = self.owner_peer
        self.on_lost(peer)

    def open_session(self) -> None:
        """A new session (a power-on, or the operator's): its PLC keeps it while connected; a session
        closed by a lost PLC, or never claimed, waits for the next claim."""
        with self._lock:
            if self.state is not OwnerState.OWNED:
                self.state, self.key = OwnerState.UNCLAIMED, NO_KEY

    def owns(self, connection: Hashable) -> bool:
        return connection == self.owner

    def describe(self) -> str:
        """The owner for the statistics line."""
        owner = {OwnerState.OWNED: f"PLC at {self.owner_peer}",
                 OwnerState.UNCLAIMED: "no PLC has claimed the session",
                 OwnerState.CLOSED: f"session closed: its PLC at {self.owner_peer} was lost"}[self.state]
        if self.refused:
            owner += f", {self.refused} write(s) of other clients refused"
            if self.refused_claims:
                owner += f" ({self.refused_claims} of them claims)"
        return owner


KEY_FILE_DIGITS = 16  # a session key file: 64 bits as 16 hexadecimal digits


def key_file(path: str) -> int:
    """The session key in ``path`` (``vc serve --plc-key-file``, ``python -m plc_stub --key-file``):
    16 hexadecimal digits.  A file that does not exist is created with a new random key, readable
    and writable by its owner alone, so that the harness and its PLC can share it."""
    try:
        descriptor = os.open(path, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o600)
    except FileExistsError:
        pass
    except OSError as error:
        raise LinkError(f"{path}: cannot create the key file: {error.strerror}") from None
    else:
        with os.fdopen(descriptor, "w") as created:
            created.write(f"{secrets.randbits(64) or 1:0{KEY_FILE_DIGITS}x}\n")
    try:
        with open(path, encoding="ascii") as existing:
            text = existing.read(4 * KEY_FILE_DIGITS).strip()
    except (OSError, UnicodeDecodeError) as error:
        raise LinkError(f"{path}: cannot read the key file: {error}") from None
    try:
        key = int(text, 16) if len(text) == KEY_FILE_DIGITS else 0
    except ValueError:
        key = 0
    if not key:
        raise LinkError(f"{path}: a key file holds {KEY_FILE_DIGITS} hexadecimal digits, not all 0 (delete it and a"
                        " new one is made)")
    return key
