"""What every link between the NC and a PLC in another process shares (pure, no I/O).

* **The bytes.** Per direction the link moves the plant area and the data-block byte ranges of
  that direction, in this order: NC-to-PLC = plant inputs ``I``, then the NC->PLC ranges of
  DB10, DB11, DB19, DB21.., DB31..; PLC-to-NC = plant outputs ``Q``, then the PLC->NC ranges.  The
  Modbus tables and the CAN frames are two packings of the same list.
* **Sessions.** Every power-on of the harness opens a session, numbered 1, 2, .. 65535, 1, ..;
  a new session restarts the PLC program.
* **Lockstep.** The harness grants scan 1, 2, .. 65535, 1, .. (never 0) and the PLC reports
  each one done; simulated time stands while the PLC works.  **Free-running**: the PLC scans on
  its own clock and a counter it changes every scan is its sign of life.
"""

from __future__ import annotations

from collections.abc import Mapping

from interfaces.signals import Direction, ExpandedCatalog

MODE_LOCKSTEP = 1
MODE_FREE_RUNNING = 2

PLANT_AREA = {Direction.NC_TO_PLC: "I", Direction.PLC_TO_NC: "Q"}

ByteRange = tuple[str, int, int]  # (area key, first byte, stop)


def exchange_ranges(catalog: ExpandedCatalog, plant_sizes: Mapping[str, int],
                    direction: Direction) -> list[ByteRange]:
    """The byte ranges a link moves in ``direction`` (NC_TO_PLC or PLC_TO_NC), in link order;
    an empty plant area is left out."""
    plant = PLANT_AREA[direction]
    ranges = [(plant, 0, plant_sizes.get(plant, 0)), *catalog.byte_ranges(direction)]
    return [(area, start, stop) for area, start, stop in ranges if stop > start]


def link_direction(direction: Direction) -> Direction:
    """The way a signal of ``direction`` travels over a link: NC_TO_PLC for NC->PLC signals and plant
    inputs, PLC_TO_NC for PLC->NC signals and plant outputs."""
    return Direction.NC_TO_PLC if direction in (Direction.NC_TO_PLC, Direction.PLANT_TO_PLC) else Direction.PLC_TO_NC


def next_session(session: int) -> int:
    """The session after ``session`` (0 = none yet): 1 .. 65535, then 1 again."""
    return session % 0xFFFF + 1


def grant_of_scan(scan: int) -> int:
    """The grant number of the ``scan``-th scan of a session (1-based): 1 .. 65535, then 1 again."""
    return (scan - 1) % 0xFFFF + 1
