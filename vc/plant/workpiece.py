"""A part clamped in the chucks of two spindles: the mechanical link the handover relies on.

While the chucks of both spindles are clamped (``chuckClosed`` of both), the part ties the two
spindles together: the angle relation they had when the second chuck clamped is the part's
unstrained state.  The part takes a small twist elastically; beyond ``MAX_TWIST_DEG`` between the
two spindles' angle changes it is twisted (or torn) and it blocks the drive of the second
spindle - the counter spindle that took the part over - which reports the fault to the NC (a
drive fault, "motor blocked")::

    FREE ──both chucks clamped──▶ HELD: the relation now is the part's
    HELD ──|twist| > MAX_TWIST_DEG──▶ TWISTED: the counter spindle's drive reports "blocked" (once)
    HELD, TWISTED ──a chuck no longer clamped──▶ FREE

The twist is ``(phi_counter - phi_counter_at_clamping) - (phi_main - phi_main_at_clamping)`` on
the true (physical) angles: a part turns both spindles the same way by the same angle, as the
counter spindle follows the main spindle with ratio 1 in the handover (COUPDEF(S2,S1,1,1))
[INF: the seeds give no twist figure; 1 degree is a small elastic twist of a turned part].
Time is counted in IPO cycles; the model does no I/O.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Protocol

from vc.plant.chuck import Chuck

MAX_TWIST_DEG = 1.0


class Spindle(Protocol):
    """The true angle of a spindle (the NC core's machine axis), degrees counted over the turns."""

    physical: float


@dataclass(slots=True)
class ClampedPart:
    """The part between the chucks of a main spindle and a counter spindle."""

    main: Chuck
    counter: Chuck
    main_spindle: Spindle
    counter_spindle: Spindle
    relation: float | None = None  # counter - main angle when both chucks clamped; None: not held
    twisted: bool = False

    @property
    def twist(self) -> float:
        """Degrees the part is twisted now (0 while it is not held by both chucks)."""
        if self.relation is None:
            return 0.0
        return self.counter_spindle.physical - self.main_spindle.physical - self.relation

    def step(self) -> bool:
        """One IPO cycle after the chucks moved.  True in the cycle the part becomes twisted."""
        if not (self.main.clamped and self.counter.clamped):
            self.relation = None
            self.twisted = False
            return False
        if self.relation is None:
            self.relation = self.counter_spindle.physical - self.main_spindle.physical
        if self.twisted or abs(self.twist) <= MAX_TWIST_DEG:
            return False
        self.twisted = True
        return True
