"""magazine: the coolant program plus a tool magazine turned by a PLC axis (FC18, seed 003 §9.7).

The magazine's disk is the modulo axis of the machine's ``plant: axis_magazine:`` (12 pockets on
mill_magazine: pocket p at (p - 1) x 30 degrees); MD30460 bit 4 makes it the PLC's alone.  The
program moves it with the basic program's FC18 (``plc_stub.blocks.TraversePosAxis``) the shortest
way to the pocket of the T word, as a machine builder's program does.  Networks after those of
``coolant`` (1-11), for the first channel:

12. Magazine: T n brings pocket n to the change position; the program waits (read-in disable
    DB21.DBX6.1) until the pocket is there and locked, which acknowledges the T function::

        IDLE ──T n, pocket n at the pin already──▶ IDLE (nothing to do)
        IDLE ──T n (1 .. pockets), the drive ready──▶ UNLOCK: AxisMagazine.unlock
        IDLE ──T n outside the magazine──▶ FAULT 700043
        UNLOCK ──AxisMagazine.unlocked──▶ POSITION: FC18 Start, Mode 2 (shortest path), Pos (n - 1) x pitch
        POSITION ──FC18 InPos and AxisMagazine.inPocket──▶ LOCK: unlock off, the pin drops in
        LOCK ──AxisMagazine.locked──▶ IDLE: read-in disable off, the T function is done
        UNLOCK, LOCK ──lock_timeout without the pin's end position──▶ FAULT 700040 (the lock pin's sensor)
        IDLE (T n), UNLOCK, POSITION ──AxisMagazine.driveReady = 0──▶ FAULT 700041: FC18 Stop
        POSITION ──FC18 Error, or no InPos within position_timeout──▶ FAULT 700042: FC18 Stop
        FAULT ──reset key──▶ IDLE (the pin drops in where it can; the next T starts afresh)

While it is in FAULT the program stays held (read-in disable), the PLC alarm shows which fault.

Parameters, besides those of ``coolant``::

    plc:
      magazine_feed: 7200.0     # deg/min, FC18's FRate
      lock_timeout: 1.0         # s for the lock pin to reach its end position
      position_timeout: 5.0     # s for the pocket to reach the change position
"""

from __future__ import annotations

from enum import Enum

from interfaces.plant_io import AXIS_MAGAZINE
from plc_stub.blocks import FC18_POSITIONING_AXIS, TON, TraversePosAxis
from plc_stub.io import PlcIo
from plc_stub.programs.coolant import Coolant
from plc_stub.programs.parameters import seconds
from plc_stub.programs.turret import device_count

LOCK_NOT_REACHED, DRIVE_NOT_READY, POCKET_NOT_REACHED, POCKET_UNKNOWN = 700040, 700041, 700042, 700043
SHORTEST_PATH = 2  # FC18 Mode
MAGAZINE_FEED = 7200.0  # deg/min
LOCK_TIMEOUT_S = 1.0
POSITION_TIMEOUT_S = 5.0


class MagazineStep(Enum):
    IDLE = "the magazine stands locked (or no T is on its way)"
    UNLOCK = "the lock pin is pulled"
    POSITION = "FC18 turns the magazine the shortest way to the pocket"
    LOCK = "the lock pin drops into the pocket"
    FAULT = "PLC alarm until the reset key"


class Magazine(Coolant):
    PROGRAM = "magazine"
    PARAMETERS = (*Coolant.PARAMETERS, "magazine_feed", "lock_timeout", "position_timeout")

    def __init__(self, io: PlcIo):
        super().__init__(io)
        parameters = io.environment.parameters
        problems: list[str] = []
        lock_timeout = seconds(parameters, "lock_timeout", LOCK_TIMEOUT_S, problems)
        position_timeout = seconds(parameters, "position_timeout", POSITION_TIMEOUT_S, problems)
        feed = parameters.get("magazine_feed", MAGAZINE_FEED)
        if isinstance(feed, bool) or not isinstance(feed, (int, float)) or not 0 < feed <= 1.0e6:
            problems.append(f"plc: magazine_feed is a feed in deg/min above 0 (at most 1000000), got {feed!r}")
            feed = MAGAZINE_FEED
        if problems:
            raise ValueError("\n".join(problems))
        scan = io.environment.scan_time_s
        # Network 12
        self.pockets = device_count(io, "axis_magazine", "pockets")
        axis_db = device_count(io, "axis_magazine", "axis_db")
        self.fc18 = TraversePosAxis(io, axis_db - 30) if self.pockets else None
        self.feed = float(feed)
        wired = self.pockets > 0
        self.unlock = io.output(f"{AXIS_MAGAZINE}.unlock") if wired else None
        self.locked = io.input(f"{AXIS_MAGAZINE}.locked") if wired else None
        self.unlocked = io.input(f"{AXIS_MAGAZINE}.unlocked") if wired else None
        self.in_pocket = io.input(f"{AXIS_MAGAZINE}.inPocket") if wired else None
        self.drive_ready = io.input(f"{AXIS_MAGAZINE}.driveReady") if wired else None
        self.magazine_step = MagazineStep.IDLE
        self.magazine_fault = 0
        self.pocket = 1  # the pocket at the change position (the magazine stands at 0 degrees at power-on)
        self.target_pocket = 0
        self.stop_pending = False
        self.lock_watchdog = TON(lock_timeout, scan)
        self.position_watchdog = TON(position_timeout, scan)
        self.magazine_alarms = {number: self.plc_alarm(number)
                                for number in (LOCK_NOT_REACHED, DRIVE_NOT_READY, POCKET_NOT_REACHED, POCKET_UNKNOWN)}

    def auxiliary_networks(self) -> None:
        super().auxiliary_networks()
        if self.fc18 is not None:
            self.magazine()
        for number, alarm in self.magazine_alarms.items():
            alarm.value = self.magazine_step is MagazineStep.FAULT and self.magazine_fault == number

    # Network 12 --------------------------------------------------------------------------
    def magazine(self) -> None:
        assert self.fc18 is not None and self.unlock is not None and self.locked is not None
        assert self.unlocked is not None and self.in_pocket is not None and self.drive_ready is not None
        step = self.magazine_step
        tool = self.last("T")
        start, stop, self.stop_pending = False, self.stop_pending, False
        if step is MagazineStep.FAULT:
            if self.reset_pressed:
                step = MagazineStep.IDLE
        elif step is MagazineStep.IDLE and tool is not None:
            target = int(tool.value)
            if not 1 <= target <= self.pockets:
                step, self.magazine_fault = MagazineStep.FAULT, POCKET_UNKNOWN
            elif target != self.pocket or not self.locked.value:
                self.target_pocket = target
                step = MagazineStep.UNLOCK
        if step in (MagazineStep.UNLOCK, MagazineStep.POSITION) and not self.drive_ready.value:
            step, self.magazine_fault, stop = MagazineStep.FAULT, DRIVE_NOT_READY, True
        if step is MagazineStep.UNLOCK and self.unlocked.value:
            step, start = MagazineStep.POSITION, True
        pitch = 360.0 / self.pockets
        self.fc18(start=start, stop=stop, funct=FC18_POSITIONING_AXIS, mode=SHORTEST_PATH,
                  pos=(self.target_pocket - 1) * pitch, frate=self.feed)
        if step is MagazineStep.POSITION and not start:
            if self.fc18.error:
                step, self.magazine_fault = MagazineStep.FAULT, POCKET_NOT_REACHED
            elif self.fc18.in_pos and self.in_pocket.value:
                self.pocket = self.target_pocket
                step = MagazineStep.LOCK
        if self.position_watchdog(step is MagazineStep.POSITION):
            step, self.magazine_fault = MagazineStep.FAULT, POCKET_NOT_REACHED
        if step is MagazineStep.LOCK and self.locked.value:
            step = MagazineStep.IDLE
        if self.lock_watchdog(step in (MagazineStep.UNLOCK, MagazineStep.LOCK)):
            step, self.magazine_fault = MagazineStep.FAULT, LOCK_NOT_REACHED
        if step is MagazineStep.FAULT and self.magazine_step is MagazineStep.POSITION and not stop:
            self.stop_pending = True  # FC18 Stop brakes the running motion in the next scan
        self.magazine_step = step
        self.unlock.value = step in (MagazineStep.UNLOCK, MagazineStep.POSITION)
        self.hold_read_in = self.hold_read_in or step is not MagazineStep.IDLE
