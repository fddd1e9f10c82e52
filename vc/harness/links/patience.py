"""How long the harness's end of a link waits for the PLC, and what it says meanwhile: shared by
the links of every technology (:mod:`vc.harness.links.modbus`, :mod:`vc.harness.links.can`)."""

from __future__ import annotations

import time as wallclock
from collections.abc import Callable
from dataclasses import dataclass, field

from interfaces.links.errors import LinkError


@dataclass(slots=True)
class Patience:
    """How long the harness waits for a PLC's answer and what it says meanwhile: it announces the
    wait once, and gives up after the time-out (None: never) or as soon as the PLC process is gone."""

    timeout_s: float | None
    announce_after_s: float
    on_wait: Callable[[str], None] | None
    peer_ended: Callable[[], str | None]
    silence: Callable[[float], str]  # what the harness says after waiting so many seconds
    began: float = field(default_factory=wallclock.monotonic)
    announced: bool = False

    @classmethod
    def for_scan(cls, first: bool, first_scan_timeout_s: float | None, scan_timeout_s: float | None,
                 on_wait: Callable[[str], None] | None, peer_ended: Callable[[], str | None],
                 silence: Callable[[float], str]) -> Patience:
        """The first scan of a session may take long (a PLC starts); later scans are quick."""
        timeout = first_scan_timeout_s if first else scan_timeout_s
        announce_after = 1.0 if first or scan_timeout_s is None else scan_timeout_s / 2
        return cls(timeout, announce_after, on_wait, peer_ended, silence)

    def check(self) -> None:
        """Raise :class:`LinkError` when waiting is over; announce a long wait once."""
        waited = wallclock.monotonic() - self.began
        ended = self.peer_ended()
        if ended is not None:
            raise LinkError(f"{self.silence(waited)}: {ended}")
        if self.timeout_s is not None and waited > self.timeout_s:
            raise LinkError(self.silence(waited))
        if not self.announced and waited > self.announce_after_s and self.on_wait is not None:
            self.announced = True
            self.on_wait(self.silence(waited))
