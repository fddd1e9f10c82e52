"""turret: the coolant program plus a lathe's tool turret and the chucks' M functions.

Networks after those of ``coolant`` (1-11), for the first channel:

12. Tool turret (vc/plant/turret.py): the T word (``index_on: T``, the NC's MD22550 = 0) or M6
    after it (``index_on: M6``, MD22550 = 1) names the station.  The PLC holds the program with the
    read-in disable DB21.DBX6.1 in the scan in which it sees the function, turns the disk the
    shorter way and releases 6.1 once the disk is locked at the station::

        IDLE ──T n / M6, n = the station──▶ IDLE (nothing to do)
        IDLE ──T n / M6, another station──▶ UNLOCK: 6.1 = 1, Turret.unlock on
        UNLOCK ──Turret.unlocked──▶ INDEX: Turret.indexCw or indexCcw, the shorter way round
        INDEX ──the code shows n──▶ LOCK: drive off, unlock off (the spring engages the pin)
        LOCK ──Turret.locked at n──▶ IDLE: 6.1 = 0, the program goes on
        UNLOCK / INDEX / LOCK ──lock_timeout / index_timeout──▶ FAULT: drive off, 6.1 = 1,
              PLC alarm 700000 (pin not pulled), 700001 (station not reached), 700002 (pin not engaged)
        IDLE ──T outside 1..stations──▶ FAULT with PLC alarm 700003
        FAULT ──reset key──▶ IDLE: alarm gone, 6.1 = 0 (the turret stays where it is; the next T
              indexes from there)

13. Chucks (vc/plant/chuck.py): M10 clamps, M11 opens the chuck of the main spindle; with the
    extended address of a spindle (``M2=10``) that spindle's chuck.  6.1 holds the program until
    the chuck's end-position sensor confirms; opening a chuck whose spindle turns (DB31.DBX61.4 =
    0) is refused::

        IDLE ──M10 / M11──▶ MOVING: 6.1 = 1, its solenoid on (the other off)
        MOVING ──chuckClosed / chuckOpen──▶ IDLE: 6.1 = 0 (the solenoid stays on: it holds the part)
        MOVING ──chuck_timeout──▶ FAULT: PLC alarm 700020, 6.1 = 1
        IDLE ──M11 with the spindle turning──▶ FAULT: PLC alarm 700021, 6.1 = 1
        FAULT ──reset key──▶ IDLE

    At power-on the PLC holds each chuck as its sensors show it (a part stays clamped).

Parameters, besides those of ``coolant``::

    plc:
      index_on: T               # T: the T word indexes (MD22550 = 0); M6: T preselects, M6 indexes
      lock_timeout: 1.0         # s for the lock pin to leave or to engage
      index_timeout: 5.0        # s for the disk to reach the station
      chuck_timeout: 2.0        # s for a chuck to reach its end position
"""

from __future__ import annotations

from dataclasses import dataclass
from enum import Enum

from interfaces.plant_io import TURRET, chuck_close, chuck_closed, chuck_open, chuck_release, station_code_bits
from plc_stub.blocks import TON
from plc_stub.io import Bool, PlcIo
from plc_stub.programs.coolant import Coolant
from plc_stub.programs.parameters import seconds

TOOL_CHANGE_M = 6
CHUCK_CLAMP, CHUCK_OPEN = 10, 11
LOCK_NOT_PULLED, STATION_NOT_REACHED, LOCK_NOT_ENGAGED, STATION_UNKNOWN = 700000, 700001, 700002, 700003
CHUCK_NOT_REACHED, CHUCK_WHILE_TURNING = 700020, 700021
LOCK_TIMEOUT_S = 1.0
INDEX_TIMEOUT_S = 5.0
CHUCK_TIMEOUT_S = 2.0
INDEX_ON = ("T", "M6")


class TurretStep(Enum):
    IDLE = "locked at its station"
    UNLOCK = "pulling the lock pin (the program waits)"
    INDEX = "turning to the station the shorter way"
    LOCK = "at the station: the pin engages"
    FAULT = "stopped with a PLC alarm until the reset key"


class ChuckStep(Enum):
    IDLE = "at its end position"
    MOVING = "clamping or opening (the program waits)"
    FAULT = "end position not reached, or refused: PLC alarm until the reset key"


@dataclass(slots=True)
class _Chuck:
    spindle: str
    number: int  # the spindle number: the extended address of its M10 / M11
    close: Bool
    release: Bool
    closed: Bool
    open: Bool | None
    stationary: Bool  # DB31.DBX61.4
    timeout: TON
    step: ChuckStep = ChuckStep.IDLE
    clamping: bool = True


class Turret(Coolant):
    PROGRAM = "turret"
    PARAMETERS = (*Coolant.PARAMETERS, "index_on", "lock_timeout", "index_timeout", "chuck_timeout")

    def __init__(self, io: PlcIo):
        super().__init__(io)
        parameters = io.environment.parameters
        problems: list[str] = []
        index_on = parameters.get("index_on", "T")
        if index_on not in INDEX_ON:
            problems.append(f"plc: index_on is T (the T word indexes, MD22550 = 0) or M6 (MD22550 = 1),"
                            f" got {index_on!r}")
            index_on = "T"
        lock_timeout = seconds(parameters, "lock_timeout", LOCK_TIMEOUT_S, problems)
        index_timeout = seconds(parameters, "index_timeout", INDEX_TIMEOUT_S, problems)
        chuck_timeout = seconds(parameters, "chuck_timeout", CHUCK_TIMEOUT_S, problems)
        if problems:
            raise ValueError("\n".join(problems))
        scan = io.environment.scan_time_s
        # Network 12
        self.index_on_m6 = index_on == "M6"
        self.stations = device_count(io, "turret", "stations")
        self.turret_code = [(bit, io.input(f"{TURRET}.code{bit}")) for bit in station_code_bits(self.stations)]
        wired = self.stations > 0
        self.turret_unlock = io.output(f"{TURRET}.unlock") if wired else None
        self.turret_cw = io.output(f"{TURRET}.indexCw") if wired else None
        self.turret_ccw = io.output(f"{TURRET}.indexCcw") if wired else None
        self.turret_locked = io.input(f"{TURRET}.locked") if wired else None
        self.turret_unlocked = io.input(f"{TURRET}.unlocked") if wired else None
        self.turret_alarms = {number: self.plc_alarm(number)
                              for number in (LOCK_NOT_PULLED, STATION_NOT_REACHED, LOCK_NOT_ENGAGED, STATION_UNKNOWN)}
        self.turret_step = TurretStep.IDLE
        self.turret_fault = 0  # the alarm of the fault
        self.target_station = 0
        self.preselected_station = 0  # index_on: M6: the T word's station
        self.turret_clockwise = True
        self.lock_watchdog = TON(lock_timeout, scan)
        self.index_watchdog = TON(index_timeout, scan)
        # Network 13
        self.chucks = [
            _Chuck(axis, number, io.output(chuck_close(axis)), io.output(chuck_release(axis)),
                   io.input(chuck_closed(axis)), io.input(chuck_open(axis)) if io.is_wired(chuck_open(axis)) else None,
                   io.input(f"{axis}.basic.in.isStationary"), TON(chuck_timeout, scan))
            for number, axis in enumerate(spindles(io), start=1)
            if io.is_wired(chuck_close(axis)) and io.is_wired(chuck_release(axis)) and io.is_wired(chuck_closed(axis))
        ]
        self.chuck_alarms = {number: self.plc_alarm(number) for number in (CHUCK_NOT_REACHED, CHUCK_WHILE_TURNING)}
        self.chucks_started = False

    def auxiliary_networks(self) -> None:
        super().auxiliary_networks()
        self.turret()
        self.chuck_functions()

    # Network 12 --------------------------------------------------------------------------
    def station(self) -> int:
        """The station the code shows, 0 between two."""
        return sum(bit for bit, sensor in self.turret_code if sensor.value)

    def turret(self) -> None:
        if self.turret_unlock is None or self.turret_cw is None or self.turret_ccw is None:
            return
        tool = self.last("T")
        if tool is not None and tool.value:
            self.preselected_station = int(tool.value)  # T0 selects no tool: nothing to index
        if self.index_on_m6:
            start = self.m_function(TOOL_CHANGE_M) and self.preselected_station != 0
        else:
            start = tool is not None and tool.value != 0
        step = self.turret_step
        if step is TurretStep.FAULT:
            if self.reset_pressed:
                step = TurretStep.IDLE
                self.turret_fault = 0
        elif step is TurretStep.IDLE and start:
            target = self.preselected_station
            if not 1 <= target <= self.stations:
                step, self.turret_fault = TurretStep.FAULT, STATION_UNKNOWN
            elif target != self.station() or not self._locked():
                self.target_station = target
                self.turret_clockwise = shorter_way_clockwise(self.station() or target, target, self.stations)
                step = TurretStep.UNLOCK
        if step is TurretStep.UNLOCK and self.turret_unlocked is not None and self.turret_unlocked.value:
            step = TurretStep.INDEX
        if step is TurretStep.INDEX and self.station() == self.target_station:
            step = TurretStep.LOCK
        if step is TurretStep.LOCK and self._locked() and self.station() == self.target_station:
            step = TurretStep.IDLE
        step = self._turret_watchdogs(step)
        self.turret_step = step
        self.turret_unlock.value = step in (TurretStep.UNLOCK, TurretStep.INDEX)
        self.turret_cw.value = step is TurretStep.INDEX and self.turret_clockwise
        self.turret_ccw.value = step is TurretStep.INDEX and not self.turret_clockwise
        for number, alarm in self.turret_alarms.items():
            alarm.value = step is TurretStep.FAULT and self.turret_fault == number
        self.hold_read_in = self.hold_read_in or step is not TurretStep.IDLE

    def _locked(self) -> bool:
        return self.turret_locked is not None and self.turret_locked.value

    def _turret_watchdogs(self, step: TurretStep) -> TurretStep:
        """The pin must leave and engage within lock_timeout, the disk reach the station within
        index_timeout; else the turret stops with its alarm."""
        pin_late = self.lock_watchdog(step in (TurretStep.UNLOCK, TurretStep.LOCK))
        index_late = self.index_watchdog(step is TurretStep.INDEX)
        if pin_late:
            self.turret_fault = LOCK_NOT_PULLED if step is TurretStep.UNLOCK else LOCK_NOT_ENGAGED
            return TurretStep.FAULT
        if index_late:
            self.turret_fault = STATION_NOT_REACHED
            return TurretStep.FAULT
        return step

    # Network 13 --------------------------------------------------------------------------
    def chuck_functions(self) -> None:
        if not self.chucks_started:
            self.chucks_started = True
            for chuck in self.chucks:  # hold each chuck as its sensors show it at power-on
                chuck.clamping = chuck.closed.value
        for chuck in self.chucks:
            self._chuck(chuck)
        for number, alarm in self.chuck_alarms.items():
            alarm.value = any(chuck.step is ChuckStep.FAULT and chuck_fault(chuck) == number for chuck in self.chucks)

    def _chuck(self, chuck: _Chuck) -> None:
        main = chuck is self.chucks[0]
        clamp = self.m_function(CHUCK_CLAMP, chuck.number) or (main and self.m_function(CHUCK_CLAMP))
        release = self.m_function(CHUCK_OPEN, chuck.number) or (main and self.m_function(CHUCK_OPEN))
        if chuck.step is ChuckStep.FAULT:
            if self.reset_pressed:
                chuck.step = ChuckStep.IDLE
        elif release and not chuck.stationary.value:
            chuck.step = ChuckStep.FAULT  # never open a chuck whose spindle turns
            chuck.clamping = True
        elif clamp or release:
            chuck.clamping = bool(clamp)
            chuck.step = ChuckStep.MOVING
        if chuck.step is ChuckStep.MOVING:
            reached = chuck.closed.value if chuck.clamping else (
                chuck.open.value if chuck.open is not None else not chuck.closed.value)
            if reached:
                chuck.step = ChuckStep.IDLE
        if chuck.timeout(chuck.step is ChuckStep.MOVING):
            chuck.step = ChuckStep.FAULT
        chuck.close.value = chuck.clamping
        chuck.release.value = not chuck.clamping
        self.hold_read_in = self.hold_read_in or chuck.step is not ChuckStep.IDLE


def chuck_fault(chuck: _Chuck) -> int:
    """The alarm of a chuck's fault: refused while turning (it stays clamped) or not reached."""
    return CHUCK_WHILE_TURNING if chuck.clamping and chuck.closed.value else CHUCK_NOT_REACHED


def shorter_way_clockwise(station: int, target: int, stations: int) -> bool:
    """Turn clockwise (towards higher stations) when that way is not longer."""
    return (target - station) % stations <= stations // 2


def device_count(io: PlcIo, device: str, key: str) -> int:
    """How many stations (pockets) the machine's device has, as its commissioning facts say; 0 when
    the machine has no such device."""
    commissioning = io.environment.commissioning
    facts = commissioning.devices.get(device) if commissioning is not None else None
    return int(facts.get(key, 0)) if facts else 0


def spindles(io: PlcIo) -> list[str]:
    """The machine's spindles in the order of their numbers (the machine builder's wiring: the
    commissioning facts list them in machine axis order, spindle 1 first)."""
    commissioning = io.environment.commissioning
    if commissioning is None:
        return list(io.environment.catalog.layout.axes)
    return [facts.axis for facts in commissioning.axes if facts.kind == "spindle"]
