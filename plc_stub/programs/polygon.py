"""polygon: the spindle program plus the guard door, for polygon turning (G51.2 / G50.2).

During polygon turning the driven tool spindle follows the workpiece spindle in the ratio
Q : P (seed 002 L63-65; the NC runs it as a coupling: the tool spindle reports 99.1 and the
synchronism bits 98.0 / 98.1, the workpiece spindle 99.0).  The networks of ``spindle`` (1-9)
give the drives, the enables of every spindle, the modes and the panel keys; network 10 is
the guard door (plc_stub/programs/guard_door.py): opening it stops master and slave together
with 4.3 (the tool must not leave its phase on the workpiece, seed 003 L23315-23323), holds X
and Z with the channel feed disable and takes the controller enables at standstill; with the
door closed again, NC start restarts both and resynchronises the tool spindle where its
relation was lost.  Lamp.alarm (where wired) shows a resynchronisation that did not finish,
until the reset key.

Parameters, besides those of ``spindle``::

    plc:
      resync_delay: 0.2         # s after the restart for the coarse synchronism to come back
      resync_timeout: 5.0       # s for a resynchronisation (31.4) to finish
"""

from __future__ import annotations

from plc_stub.programs.guard_door import GuardedSpindle


class Polygon(GuardedSpindle):
    PROGRAM = "polygon"
