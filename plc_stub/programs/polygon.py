"""polygon: the spindle program plus the guard door and the interlocks of a polygon turning job.

During polygon turning (G51.2 / G50.2, seed 002) the driven tool spindle follows the workpiece
spindle in the ratio Q : P (L63-65); the NC runs it as a coupling: the tool spindle reports
following spindle 99.1 and the synchronism bits 98.0 / 98.1, the workpiece spindle leading
spindle 99.0 (seed 003 L22062, L22421).  Networks after those of ``spindle`` (1-9, which give
the drives, the controller enables of every axis and spindle - both spindles get theirs there,
the NC switches them to position control itself with G51.2, seed 003 L22816-22835 - the modes
and the panel keys):

10. Guard door (plc_stub/programs/guard_door.py): opening it stops workpiece and tool spindle
    together with 4.3 (the tool must not leave its phase on the part, seed 003 L23315-23323),
    holds X and Z with the channel feed disable and takes the controller enables at standstill;
    with the door closed again, NC start restarts both and resynchronises the tool spindle where
    its relation was lost.

11. Polygon interlocks, for the first channel and every spindle the NC reports as following
    spindle (99.1):

    * no NC start while the door is open: DB21.DBX7.0 ``disableNcStart`` follows the open door
      (the door's network stops a running job; this one keeps a job from starting);
    * the tool cuts only in fine synchronism: from G51.2 on, the feed disable DB21.DBX6.0
      holds the slides until 98.0 is there (a relation still running to its offset - G51.2's R,
      a resynchronisation - has no 98.0 yet, seed 003 L22434);
    * a loss of synchronism while cutting holds the slides and is a fault::

        IDLE ──99.1 on a spindle──▶ WAIT_FINE: 6.0 = 1
        WAIT_FINE ──98.0 on every following spindle──▶ SYNCHRONOUS: 6.0 = 0
        SYNCHRONOUS ──98.0 lost with the door's network idle──▶ LOST: 6.0 = 1, Lamp.alarm
        SYNCHRONOUS ──the door's network busy (door opened)──▶ WAIT_FINE (the door handles it)
        WAIT_FINE, SYNCHRONOUS ──99.1 off on all (G50.2, reset)──▶ IDLE
        LOST ──reset key──▶ IDLE

      In LOST the slides stay held until the operator acknowledges with the reset key, which
      also ends the synchronisation (parameter 0201 HBR = 0, seed 002 L198-202) [INF: the seed
      names no reaction of the PLC; a SINUMERIK PLC holds the feed and shows a message].

Lamp.alarm (where wired) shows a fault of network 10 or 11 until the reset key.

Parameters, besides those of ``spindle``::

    plc:
      resync_delay: 0.2         # s after the restart for the coarse synchronism to come back
      resync_timeout: 5.0       # s for a resynchronisation (31.4) to finish
"""

from __future__ import annotations

from dataclasses import dataclass
from enum import Enum

from plc_stub.io import Bool, PlcIo
from plc_stub.programs.guard_door import DOOR, GuardedSpindle


class PolygonStep(Enum):
    IDLE = "idle"  # no spindle follows another: nothing to interlock
    WAIT_FINE = "wait fine"  # coupled: the slides held until every following spindle is in fine synchronism
    SYNCHRONOUS = "synchronous"  # in fine synchronism: the slides may cut
    LOST = "lost"  # fine synchronism lost while cutting: the slides held, Lamp.alarm, until the reset key


@dataclass(slots=True)
class _CoupledSpindle:
    following: Bool  # DB31.DBX99.1
    fine: Bool  # DB31.DBX98.0


class Polygon(GuardedSpindle):
    PROGRAM = "polygon"

    def __init__(self, io: PlcIo):
        super().__init__(io)
        layout = io.environment.catalog.layout
        # Network 11
        self.door_closed = io.input(DOOR) if io.is_wired(DOOR) else None
        self.coupled_spindles = [
            _CoupledSpindle(io.input(f"{name}.coupling.in.followingSpindleActive"),
                            io.input(f"{name}.coupling.in.syncFineReached"))
            for name in layout.axes
        ]
        channel = layout.channels[0]
        self.nc_start_disable = io.output(f"{channel}.basic.out.disableNcStart")
        self.feed_disable = io.output(f"{channel}.basic.out.disableFeed")
        self.polygon = PolygonStep.IDLE

    def process_networks(self, reset: bool) -> None:
        self.polygon_interlocks(reset)

    @property
    def faulted(self) -> bool:
        return self.polygon is PolygonStep.LOST or self.guard_door.fault

    # Network 11 --------------------------------------------------------------------------
    def polygon_interlocks(self, reset: bool) -> None:
        door_open = self.door_closed is not None and not self.door_closed.value
        self.nc_start_disable.value = door_open
        following = [spindle for spindle in self.coupled_spindles if spindle.following.value]
        fine = all(spindle.fine.value for spindle in following)
        step = self.polygon
        if step is PolygonStep.LOST:
            if reset:
                step = PolygonStep.IDLE
        elif not following:
            step = PolygonStep.IDLE
        elif step is PolygonStep.IDLE or (step is PolygonStep.SYNCHRONOUS and not self.guard_door.running):
            step = PolygonStep.SYNCHRONOUS if fine else PolygonStep.WAIT_FINE
        elif step is PolygonStep.WAIT_FINE and fine:
            step = PolygonStep.SYNCHRONOUS
        elif step is PolygonStep.SYNCHRONOUS and not fine:
            step = PolygonStep.LOST
        self.polygon = step
        if step in (PolygonStep.WAIT_FINE, PolygonStep.LOST):
            self.feed_disable.value = True  # network 4 writes it every scan; the door and this network add to it
