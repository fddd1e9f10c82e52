"""The dry-run feed (seed 003 §7, L9380-9490): with DB21.DBX0.6 the path runs at SD42100 instead of
the programmed F, as SD42101 says.

    OFF ──DB21.DBX0.6 = 1, taken when a motion block starts, or at once while no program runs──▶ ON: 318.6 = 1
    ON ──DB21.DBX0.6 = 0, taken the same way──▶ OFF: 318.6 = 0

The dry-run feed is always a feed per minute (G94, L9402): under G95 / G96 / G97 it replaces the
feed per revolution.  SD42101 (L9447-9470): 0 the larger of the programmed feed and SD42100, 1 the
smaller, 2 SD42100 alone; 10 / 11 / 12 the same, but threads and tapping keep their feed (here they
always do: their feed comes from the spindle, never from F, so 0 / 1 / 2 act like 10 / 11 / 12 [INF]).
A feed per revolution is compared as F x the master spindle's speed when the block starts [INF].
Rapid traverse stays rapid [control].  The selection is taken when the next motion block starts, as
MD10704 = 0 says (L9401-9415); MD10704 itself (1: within the running block, 2: from a later block) is
not modelled.  While the channel
is in reset or stopped, a change of DB21.DBX0.6 is taken at once (the selection at a program stop,
L9434-9442).
"""

from __future__ import annotations

from collections.abc import Callable

from interfaces.signal_groups import DryRunStatus
from vc.config import md_dictionary as MD
from vc.config.machine_data import MachineData
from vc.core.interface_map import SignalTable

LARGER, SMALLER, DRY_RUN_ONLY = 0, 1, 2


class DryRunFeed:
    """The dry-run feed of one channel (see the module docstring)."""

    def __init__(self, md: MachineData, table: SignalTable, area: bytearray):
        self._md = md
        self.active = False  # in force: DB21.DBX318.6
        self._encode = table.codec(DryRunStatus).encode
        self._area = area

    def take(self, requested: bool) -> bool:
        """The selection DB21.DBX0.6 taken (at a block start, or in the block with MD10704 = 1);
        True: it changed."""
        if requested == self.active:
            return False
        self.active = requested
        self._encode(self._area, DryRunStatus(active=requested))
        return True

    def feed(self, programmed: float, per_revolution: bool, speed: Callable[[], float]) -> float:
        """The path feed in mm/min under dry run; ``programmed`` is F (mm/min, or mm/rev with
        ``per_revolution``, then times ``speed()`` in rev/min)."""
        dry = self._md.float(MD.DRY_RUN_FEED)
        mode = self._md.int(MD.DRY_RUN_FEED_MODE) % 10
        if mode == DRY_RUN_ONLY:
            return dry
        programmed_per_minute = programmed * speed() if per_revolution else programmed
        return max(dry, programmed_per_minute) if mode == LARGER else min(dry, programmed_per_minute)
