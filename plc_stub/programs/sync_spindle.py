"""sync_spindle: the spindle program plus the guard door and the counter-spindle handover.

The part program turns the part over from the main spindle to the counter spindle: both
spindles in position control, the counter spindle coupled to the main spindle with
``COUPON(S2,S1,<offset>)`` and block change at fine synchronism, the cut-off tool approaching,
the cut-off, ``COUPOF``.  The PLC changes the chucks in between and holds the program
meanwhile with the read-in disable DB21.DBX6.1.  Networks after those of ``spindle`` (1-9):

10. Guard door (plc_stub/programs/guard_door.py, seed 003 L23315-23323): opening the door
    brakes the coupled spindles together with 4.3, holds the slides, takes the controller
    enables at standstill; door closed and NC start restart them and resynchronise the counter
    spindle with 31.4 if its relation was lost.  "Machine running" below = this network is idle.

11. Chuck handover, one step chain ("clamp" = chuckClose on, chuckRelease off; "open" = the
    other way round)::

        IDLE ──99.1 and 98.0 on the counter spindle, counter chuck open, main chuck clamped,
               channel active (DB21.DBX35.5), machine running (door)──▶ CLAMP_COUNTER:
               6.1 = 1, clamp the counter chuck
        CLAMP_COUNTER ──counter chuckClosed, machine running──▶ UNCLAMP_MAIN: open the main chuck
        CLAMP_COUNTER ──door open or 98.0 lost before the counter chuck holds──▶ WAIT_SYNC:
               open the counter chuck again (a part is clamped in both chucks only in synchronism)
        WAIT_SYNC ──counter chuck open again, 99.1 and 98.0, machine running──▶ CLAMP_COUNTER
        UNCLAMP_MAIN ──main chuckOpen──▶ HANDED_OVER: 6.1 = 0, the program cuts off
        HANDED_OVER ──99.1 = 0 (COUPOF)──▶ IDLE
        WAIT_SYNC ──99.1 = 0 (the coupling ended, e.g. reset)──▶ IDLE: 6.1 = 0
        any step but IDLE ──a chuck's stroke overdue──▶ FAULT: Lamp.alarm, 6.1 = 1
        FAULT ──reset key──▶ IDLE: 6.1 = 0

    Chuck supervision: a chuck that has not reached the end position its solenoid asks for
    within ``chuck_timeout`` (stroke, pressure, sensor) is a fault.  The solenoids keep their
    state at the fault and at the reset: the operator decides what to do with the part.  At
    power-on the PLC holds each chuck in the end position its sensors show (neither solenoid
    between the end positions), so that a clamped part stays clamped.

Lamp.alarm (where wired) shows a fault of network 10 or 11 until the reset key.

Parameters (the machine file's ``plc:`` section, a scenario's ``plc_parameters``), besides
those of ``spindle``::

    plc:
      main_spindle: SP1         # default: the first spindle with a chuck wired (chuckClose ...)
      counter_spindle: SP2      # default: the second one
      chuck_timeout: 2.0        # s for a chuck to reach its end position
      resync_delay: 0.2         # s after the restart for the coarse synchronism to come back
      resync_timeout: 5.0       # s for a resynchronisation (31.4) to finish
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from enum import Enum

from interfaces.plant_io import chuck_close, chuck_closed, chuck_open, chuck_release
from plc_stub.blocks import TON
from plc_stub.io import Bool, PlcIo
from plc_stub.programs.guard_door import GuardedSpindle
from plc_stub.programs.parameters import seconds

CHUCK_TIMEOUT_S = 2.0


class HandoverStep(Enum):
    IDLE = "idle"  # no handover: waits for the counter spindle in fine synchronism with an open chuck
    CLAMP_COUNTER = "clamp counter"  # the program held (6.1); the counter chuck clamps the part
    UNCLAMP_MAIN = "unclamp main"  # the counter chuck holds the part; the main chuck lets go
    HANDED_OVER = "handed over"  # the program runs on (cut-off); until the coupling ends
    WAIT_SYNC = "wait sync"  # interrupted (door, synchronism lost): the counter chuck opened again
    FAULT = "fault"  # a chuck did not reach its end position: the program stays held


@dataclass(slots=True)
class Chuck:
    """A spindle's chuck as the PLC sees it: the two solenoids of its valve, the end positions and
    the stroke supervision."""

    clamp_solenoid: Bool  # <spindle>.chuckClose
    release_solenoid: Bool  # <spindle>.chuckRelease
    closed: Bool  # <spindle>.chuckClosed
    open: Bool  # <spindle>.chuckOpen
    supervision: TON
    clamping: bool | None = None  # True = clamp, False = open, None = neither solenoid (the chuck holds)
    taken_over: bool = False

    def overdue(self) -> bool:
        """Called first in every scan: True when the commanded end position is overdue.  In the
        first scan the command becomes what the sensors show."""
        if not self.taken_over:
            self.clamping = True if self.closed.value else (False if self.open.value else None)
            self.taken_over = True
        reached = self.clamping is None or (self.closed.value if self.clamping else self.open.value)
        return self.supervision(not reached)

    def drive(self) -> None:
        """Called last in every scan: the solenoid of the command on, the other off."""
        self.clamp_solenoid.value = self.clamping is True
        self.release_solenoid.value = self.clamping is False


@dataclass(slots=True)
class _CounterSpindle:
    following: Bool  # DB31.DBX99.1
    fine: Bool  # DB31.DBX98.0


@dataclass(frozen=True, slots=True)
class _Parameters:
    main: str
    counter: str
    chuck_timeout_s: float


class SyncSpindle(GuardedSpindle):
    PROGRAM = "sync_spindle"
    PARAMETERS = (*GuardedSpindle.PARAMETERS, "main_spindle", "counter_spindle", "chuck_timeout")

    def __init__(self, io: PlcIo):
        super().__init__(io)
        scan = io.environment.scan_time_s
        layout = io.environment.catalog.layout
        parameters = _parameters(io, layout.axes)
        # Network 11
        self.main_chuck, self.counter_chuck = (
            Chuck(io.output(chuck_close(axis)), io.output(chuck_release(axis)), io.input(chuck_closed(axis)),
                  io.input(chuck_open(axis)), TON(parameters.chuck_timeout_s, scan))
            for axis in (parameters.main, parameters.counter))
        self.counter = _CounterSpindle(io.input(f"{parameters.counter}.coupling.in.followingSpindleActive"),
                                       io.input(f"{parameters.counter}.coupling.in.syncFineReached"))
        channel = layout.channels[0]
        self.channel_active = io.input(f"{channel}.basic.in.stateActive")
        self.read_in_disable = io.output(f"{channel}.basic.out.disableReadIn")
        self.handover = HandoverStep.IDLE

    def process_networks(self, reset: bool) -> None:
        self.chuck_handover(reset)

    @property
    def faulted(self) -> bool:
        return self.handover is HandoverStep.FAULT or self.guard_door.fault

    # Network 11 --------------------------------------------------------------------------
    def chuck_handover(self, reset: bool) -> None:
        main, counter = self.main_chuck, self.counter_chuck
        main_overdue = main.overdue()  # both supervisions run every scan
        counter_overdue = counter.overdue()
        timed_out = main_overdue or counter_overdue
        coupled = self.counter.following.value
        synchronous = coupled and self.counter.fine.value
        running = self.guard_door.running
        step = self.handover
        if step is HandoverStep.FAULT:
            if reset:
                step = HandoverStep.IDLE
        elif step is not HandoverStep.IDLE and timed_out:
            step = HandoverStep.FAULT
        elif step is HandoverStep.IDLE:
            if synchronous and counter.open.value and main.closed.value and self.channel_active.value and running:
                step = HandoverStep.CLAMP_COUNTER
                counter.clamping = True
        elif step is HandoverStep.CLAMP_COUNTER:
            if counter.closed.value:
                if running:
                    step = HandoverStep.UNCLAMP_MAIN  # the part is in both chucks
                    main.clamping = False
            elif not running or not synchronous:
                step = HandoverStep.WAIT_SYNC
                counter.clamping = False
        elif step is HandoverStep.UNCLAMP_MAIN:
            if main.open.value:
                step = HandoverStep.HANDED_OVER
        elif step is HandoverStep.HANDED_OVER:
            if not coupled:
                step = HandoverStep.IDLE
        elif step is HandoverStep.WAIT_SYNC:
            if not coupled:
                step = HandoverStep.IDLE
            elif synchronous and counter.open.value and running:
                step = HandoverStep.CLAMP_COUNTER
                counter.clamping = True
        self.handover = step
        main.drive()
        counter.drive()
        self.read_in_disable.value = step in (HandoverStep.CLAMP_COUNTER, HandoverStep.UNCLAMP_MAIN,
                                              HandoverStep.WAIT_SYNC, HandoverStep.FAULT)


def _parameters(io: PlcIo, axes: Sequence[str]) -> _Parameters:
    """Check the program's own parameters (``spindle`` checked the rest); every mistake at once."""
    parameters = io.environment.parameters
    chucked = [axis for axis in axes if io.is_wired(chuck_close(axis))]
    problems: list[str] = []

    def spindle(name: str, position: int) -> str:
        default = chucked[position] if len(chucked) > position else None
        value = parameters.get(name, default)
        if value is None:
            problems.append(f"plc: {name}: the machine has no {'second ' if position else ''}spindle with a chuck"
                            f" wired ({chuck_close('<spindle>')}); name the spindle")
            return ""
        if not isinstance(value, str) or value not in axes:
            problems.append(f"plc: {name} names {value!r}, which the machine lacks")
            return ""
        unwired = [point for point in (chuck_close(value), chuck_release(value), chuck_closed(value),
                                       chuck_open(value)) if not io.is_wired(point)]
        if unwired:
            problems.append(f"plc: {name} {value} needs its chuck wired: {', '.join(unwired)}")
        return value

    main = spindle("main_spindle", 0)
    counter = spindle("counter_spindle", 1)
    if main and main == counter:
        problems.append(f"plc: main_spindle and counter_spindle are both {main}")
    timeout = seconds(parameters, "chuck_timeout", CHUCK_TIMEOUT_S, problems)
    if problems:
        raise ValueError("\n".join(problems))
    return _Parameters(main, counter, timeout)
