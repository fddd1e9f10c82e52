"""The guard door of the machining area: a function block, and the spindle program with it.

Opening the door with coupled spindles (seed 003 §14.4.3, L23315-23323): the PLC sets
DB31.DBX4.3 on leading and following spindle, which then brake together with the coupling
kept; it waits for DB31.DBX61.4 and takes the controller enable DB31.DBX2.1 away.  The block
does this for every axis the NC reports as a spindle (DB31.DBX60.0) when the door opens, and
holds the slides with the channel feed disable DB21.DBX6.0.  Closing the door starts nothing
(a guard that closes must not start the machine): the operator closes it and presses NC start,
then the enables come back and 4.3 goes (recovery composed from L23250-23290).  Where a
following spindle (DB31.DBX99.1) lost its relation meanwhile - turned by hand in follow-up,
or a part twisted - its coarse synchronism 98.1 does not come back, and the block
resynchronises it with DB31.DBX31.4 (L23098-23145, spec SEQ-SS-3)::

    CLOSED ──Door.closed = 0──▶ STOPPING: 4.3 on the spindles, feed disable
    STOPPING ──61.4 on all of them but the following spindles──▶ DISABLING: 2.1 off but on those
    DISABLING ──next scan──▶ STOPPED: 2.1 off on the following spindles too
    STOPPED ──Door.closed = 1 and NC start──▶ RESTARTING: 2.1 on, 4.3 off
    RESTARTING ──resync_delay, 98.1 on every following spindle──▶ RUNNING_UP
    RESTARTING ──resync_delay, 98.1 missing on some──▶ RESYNC: 31.4 = 1 on those (one scan)
    RESYNC ──next scan──▶ WAIT_SYNC: 31.4 = 0
    WAIT_SYNC ──99.4 = 0 and 98.0 = 1 on each──▶ RUNNING_UP
    WAIT_SYNC ──resync_timeout──▶ RUNNING_UP with a fault (Lamp.alarm until the reset key)
    RUNNING_UP ──83.5 on every spindle that had it when the door opened──▶ CLOSED: feed disable off
    RESTARTING, RESYNC, WAIT_SYNC, RUNNING_UP ──Door.closed = 0──▶ STOPPING

The feed disable holds the slides until the spindles are back at their speed ("spindle in set
range" 83.5, L20840-20858) and in synchronism: a tool does not meet the part while its spindle
runs up.

A following spindle turns with k x its leading spindle and stands when that stands, so its own
61.4 is not waited for; its enable goes one scan after the leading spindle's, when the NC,
which couples it to the leading spindle's actual value once that has no enable (L23232-23246),
sees that value at rest.  31.4 is a pulse: the NC starts the resynchronisation on its rising
edge (L23134) and finishes it on its own; the block then waits for "synchronisation in
progress" 99.4 to fall and fine synchronism 98.0.  A machine without ``Door.closed`` in its I/O
list has no door: the block does nothing.

:class:`GuardedSpindle` is the ``spindle`` program (networks 1-9) with the door as network 10
and a place for the networks of a machining process after it (``polygon``, ``sync_spindle``).
Lamp.alarm (where wired) shows a fault of those networks until the reset key.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from enum import Enum
from typing import Any

from plc_stub.blocks import R_TRIG, TON
from plc_stub.io import Bool, PlcIo
from plc_stub.programs.basic_machine import pressed
from plc_stub.programs.parameters import seconds
from plc_stub.programs.spindle import Spindle

DOOR = "Door.closed"
RESYNC_DELAY_S = 0.2  # a spindle in hold mode is back on its held position well within this
RESYNC_TIMEOUT_S = 5.0
DOOR_PARAMETERS = ("resync_delay", "resync_timeout")


class DoorStep(Enum):
    CLOSED = "closed"  # the machine runs; the block adds nothing
    STOPPING = "stopping"  # door open: the spindles brake (4.3) and the slides hold; until all spindles stand
    DISABLING = "disabling"  # the enables of all but the following spindles go, for one scan
    STOPPED = "stopped"  # standing without controller enable; until the door is closed and NC start pressed
    RESTARTING = "restarting"  # enables back, 4.3 off; the following spindles get resync_delay to be coarse again
    RESYNC = "resync"  # the rising edge of 31.4 on the following spindles that lost their relation
    WAIT_SYNC = "wait sync"  # until the NC reports them synchronous (99.4 = 0, 98.0 = 1) or resync_timeout
    RUNNING_UP = "running up"  # until the spindles that were at speed are at speed again; then the slides


@dataclass(slots=True)
class _GuardedAxis:
    name: str
    is_spindle: Bool  # DB31.DBX60.0
    stationary: Bool  # DB31.DBX61.4
    following: Bool  # DB31.DBX99.1
    coarse: Bool  # DB31.DBX98.1
    fine: Bool  # DB31.DBX98.0
    resync_running: Bool  # DB31.DBX99.4
    at_speed: Bool  # DB31.DBX83.5
    spindle_stop: Bool  # DB31.DBX4.3
    controller_enable: Bool  # DB31.DBX2.1
    resync: Bool  # DB31.DBX31.4


class GuardDoor:
    """Call once per scan after the networks that write 2.1 and 6.0 (it only takes those away);
    it writes 4.3 of the spindles."""

    def __init__(self, io: PlcIo, resync_delay_s: float, resync_timeout_s: float):
        scan = io.environment.scan_time_s
        layout = io.environment.catalog.layout
        self.door = io.input(DOOR) if io.is_wired(DOOR) else None
        self.key_nc_start = io.input("MCP.ncStart") if io.is_wired("MCP.ncStart") else None
        self.start_edge = R_TRIG()
        self.axes = [
            _GuardedAxis(
                name=name,
                is_spindle=io.input(f"{name}.basic.in.spindleModeActive"),
                stationary=io.input(f"{name}.basic.in.isStationary"),
                following=io.input(f"{name}.coupling.in.followingSpindleActive"),
                coarse=io.input(f"{name}.coupling.in.syncCoarseReached"),
                fine=io.input(f"{name}.coupling.in.syncFineReached"),
                resync_running=io.input(f"{name}.coupling.in.ProcessActive"),
                at_speed=io.input(f"{name}.spindle.in.speedSetpointReached"),
                spindle_stop=io.output(f"{name}.basic.out.feedStopSpindleStop"),
                controller_enable=io.output(f"{name}.basic.out.enableCtrl"),
                resync=io.output(f"{name}.coupling.out.syncSpindleResync"),
            )
            for name in layout.axes
        ]
        self.feed_disables = [io.output(f"{name}.basic.out.disableFeed") for name in layout.channels]
        self.restart_delay = TON(resync_delay_s, scan)
        self.resync_watchdog = TON(resync_timeout_s, scan)
        self.step = DoorStep.CLOSED
        self.guarded: list[_GuardedAxis] = []  # the spindles stopped when the door opened
        self.were_at_speed: list[_GuardedAxis] = []  # those of them at their speed then (83.5)
        self.resynchronised: list[_GuardedAxis] = []  # the following spindles 31.4 went to
        self.fault = False  # the resynchronisation did not finish in time

    @property
    def running(self) -> bool:
        """Door closed and the machine back in operation (no stop, no resynchronisation pending)."""
        return self.step is DoorStep.CLOSED

    def __call__(self, reset: bool) -> None:
        """One scan; ``reset``: the reset key's rising edge, which acknowledges a fault."""
        if self.door is None:
            return
        closed = self.door.value
        start = self.start_edge(pressed(self.key_nc_start))
        if reset:
            self.fault = False
        step = self.step
        if not closed and step in (DoorStep.CLOSED, DoorStep.RESTARTING, DoorStep.RESYNC, DoorStep.WAIT_SYNC,
                                   DoorStep.RUNNING_UP):
            if step is DoorStep.CLOSED:
                self.guarded = [axis for axis in self.axes if axis.is_spindle.value]
                self.were_at_speed = [axis for axis in self.guarded if axis.at_speed.value]
            step = DoorStep.STOPPING
        if step is DoorStep.DISABLING:
            step = DoorStep.STOPPED
        elif step is DoorStep.STOPPING and all(axis.stationary.value for axis in self.guarded
                                               if not axis.following.value):
            step = DoorStep.DISABLING  # L23322: the enables go only at standstill
        if step is DoorStep.STOPPED and closed and start:
            step = DoorStep.RESTARTING
        restarted = self.restart_delay(step is DoorStep.RESTARTING)
        if restarted:
            self.resynchronised = [axis for axis in self.guarded
                                   if axis.following.value and not axis.coarse.value]
            step = DoorStep.RESYNC if self.resynchronised else DoorStep.RUNNING_UP
        elif step is DoorStep.RESYNC:
            step = DoorStep.WAIT_SYNC  # 31.4 was 1 for one scan: the NC has its rising edge
        gave_up = self.resync_watchdog(step is DoorStep.WAIT_SYNC)
        if step is DoorStep.WAIT_SYNC and (gave_up or all(
                not axis.resync_running.value and axis.fine.value for axis in self.resynchronised)):
            self.fault = self.fault or gave_up
            step = DoorStep.RUNNING_UP
        # a spindle coupled as following spindle meanwhile has 83.5 only for a differential speed
        # (L23507-23511): its speed is its leading spindle's, its synchronism WAIT_SYNC's
        if step is DoorStep.RUNNING_UP and all(axis.at_speed.value or axis.following.value
                                               for axis in self.were_at_speed):
            step = DoorStep.CLOSED
        self.step = step
        self._outputs()

    def _outputs(self) -> None:
        step = self.step
        stopping = step in (DoorStep.STOPPING, DoorStep.DISABLING, DoorStep.STOPPED)
        for axis in self.axes:
            guarded = axis in self.guarded
            if guarded or axis.is_spindle.value:
                axis.spindle_stop.value = stopping and guarded
            if guarded and (step is DoorStep.STOPPED or (step is DoorStep.DISABLING and not axis.following.value)):
                axis.controller_enable.value = False
            axis.resync.value = step is DoorStep.RESYNC and axis in self.resynchronised
        if step is not DoorStep.CLOSED:
            for feed_disable in self.feed_disables:
                feed_disable.value = True


def door_parameters(parameters: Mapping[str, Any], problems: list[str]) -> tuple[float, float]:
    """``resync_delay`` and ``resync_timeout`` of the program's parameters (seconds)."""
    return (seconds(parameters, "resync_delay", RESYNC_DELAY_S, problems),
            seconds(parameters, "resync_timeout", RESYNC_TIMEOUT_S, problems))


class GuardedSpindle(Spindle):
    """``spindle`` plus the guard door (network 10); process networks follow in subclasses."""

    PARAMETERS = (*Spindle.PARAMETERS, *DOOR_PARAMETERS)

    def __init__(self, io: PlcIo):
        super().__init__(io)
        problems: list[str] = []
        resync_delay, resync_timeout = door_parameters(io.environment.parameters, problems)
        if problems:
            raise ValueError("\n".join(problems))
        self.guard_door = GuardDoor(io, resync_delay, resync_timeout)
        self.reset_edge = R_TRIG()
        self.fault_lamp = io.output("Lamp.alarm") if io.is_wired("Lamp.alarm") else None

    def ob1(self) -> None:
        super().ob1()
        reset = self.reset_edge(pressed(self.key_reset))
        self.guard_door(reset)
        if self.master_spindle_stop is not None and self.spindle_stop_latch.q1:
            self.master_spindle_stop.value = True  # the spindle stop key of network 9 acts as well
        self.process_networks(reset)
        if self.fault_lamp is not None:
            self.fault_lamp.value = self.faulted

    def process_networks(self, reset: bool) -> None:
        """The networks of a machining process, after the door; ``reset``: the reset key's edge."""

    @property
    def faulted(self) -> bool:
        """A step chain gave up; the reset key acknowledges it."""
        return self.guard_door.fault
