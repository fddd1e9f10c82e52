"""tool_change: the coolant program plus a machining centre's tool magazine and changer arm.

The NC changes tools with M6 (MD22550 = 1, MD22560 = 6): T preselects, M6 changes.  The PLC keeps
the magazine's tool table (which tool is in which pocket, tool n in pocket n at power-on, the
spindle empty) as a machine builder's program does with a random-location magazine: the arm
swaps the spindle's tool into the pocket the new one came from.  Networks after those of
``coolant`` (1-11), for the first channel:

12. Tool search: T n turns the magazine the shorter way until the pocket holding tool n stands
    at the change position, while the program goes on machining::

        IDLE ──T n (n in a pocket)──▶ SEARCH: Magazine.rotateCw / rotateCcw
        SEARCH ──the code shows the pocket──▶ READY: drive off
        IDLE / READY ──T n, n in the spindle──▶ IDLE (nothing to fetch)
        IDLE ──T n, n neither in a pocket nor in the spindle──▶ FAULT: PLC alarm 700006
        SEARCH ──search_timeout──▶ FAULT: PLC alarm 700004
        FAULT ──reset key──▶ IDLE

13. Tool change: M6 holds the program with the read-in disable DB21.DBX6.1 until the arm is
    home again with the new tool in the spindle::

        IDLE ──M6──▶ WAIT_MAGAZINE: 6.1 = 1
        WAIT_MAGAZINE ──search READY──▶ TO_SPINDLE: ToolArm.toSpindle on
        WAIT_MAGAZINE ──nothing preselected / the tool already in the spindle──▶ IDLE: 6.1 = 0
        TO_SPINDLE ──ToolArm.atSpindle (the tools swapped)──▶ BACK: toSpindle off
        BACK ──ToolArm.home──▶ IDLE: the table updated, 6.1 = 0
        TO_SPINDLE / BACK ──arm_timeout──▶ FAULT: PLC alarm 700005, 6.1 = 1
        FAULT ──reset key──▶ IDLE

Parameters, besides those of ``coolant``::

    plc:
      search_timeout: 10.0      # s for the magazine to bring the pocket to the change position
      arm_timeout: 3.0          # s for the arm to reach the spindle or its home position
"""

from __future__ import annotations

from enum import Enum

from interfaces.plant_io import MAGAZINE, TOOL_ARM, station_code_bits
from plc_stub.blocks import TON
from plc_stub.io import PlcIo
from plc_stub.programs.coolant import Coolant
from plc_stub.programs.parameters import seconds
from plc_stub.programs.turret import TOOL_CHANGE_M, device_count, shorter_way_clockwise

POCKET_NOT_REACHED, ARM_NOT_REACHED, TOOL_UNKNOWN = 700004, 700005, 700006
SEARCH_TIMEOUT_S = 10.0
ARM_TIMEOUT_S = 3.0


class SearchStep(Enum):
    IDLE = "no tool preselected, or the preselected one needs no search"
    SEARCH = "turning the preselected tool's pocket to the change position"
    READY = "the preselected tool's pocket at the change position"
    FAULT = "PLC alarm until the reset key"


class ChangeStep(Enum):
    IDLE = "no tool change"
    WAIT_MAGAZINE = "M6: waiting for the search (the program waits)"
    TO_SPINDLE = "the arm swings to the spindle and swaps the tools"
    BACK = "the arm swings home"
    FAULT = "PLC alarm until the reset key"


class ToolChange(Coolant):
    PROGRAM = "tool_change"
    PARAMETERS = (*Coolant.PARAMETERS, "search_timeout", "arm_timeout")

    def __init__(self, io: PlcIo):
        super().__init__(io)
        parameters = io.environment.parameters
        problems: list[str] = []
        search_timeout = seconds(parameters, "search_timeout", SEARCH_TIMEOUT_S, problems)
        arm_timeout = seconds(parameters, "arm_timeout", ARM_TIMEOUT_S, problems)
        if problems:
            raise ValueError("\n".join(problems))
        scan = io.environment.scan_time_s
        # Network 12
        self.pockets = device_count(io, "tool_changer", "pockets")
        wired = self.pockets > 0
        self.magazine_code = [(bit, io.input(f"{MAGAZINE}.code{bit}")) for bit in station_code_bits(self.pockets)]
        self.rotate_cw = io.output(f"{MAGAZINE}.rotateCw") if wired else None
        self.rotate_ccw = io.output(f"{MAGAZINE}.rotateCcw") if wired else None
        self.tools = list(range(1, self.pockets + 1))  # the tool in pocket p is tools[p - 1], 0 = empty
        self.spindle_tool = 0
        self.preselected = 0  # the tool of the last T
        self.target_pocket = 0
        self.search_clockwise = True
        self.search_step = SearchStep.IDLE
        self.search_watchdog = TON(search_timeout, scan)
        # Network 13
        self.arm_to_spindle = io.output(f"{TOOL_ARM}.toSpindle") if wired else None
        self.arm_home = io.input(f"{TOOL_ARM}.home") if wired else None
        self.arm_at_spindle = io.input(f"{TOOL_ARM}.atSpindle") if wired else None
        self.change_step = ChangeStep.IDLE
        self.arm_watchdog = TON(arm_timeout, scan)
        self.change_alarms = {number: self.plc_alarm(number)
                              for number in (POCKET_NOT_REACHED, ARM_NOT_REACHED, TOOL_UNKNOWN)}
        self.search_fault = 0

    def auxiliary_networks(self) -> None:
        super().auxiliary_networks()
        if self.rotate_cw is None:
            return
        self.tool_search()
        self.tool_change()
        for number, alarm in self.change_alarms.items():
            alarm.value = (self.search_step is SearchStep.FAULT and self.search_fault == number) or (
                self.change_step is ChangeStep.FAULT and number == ARM_NOT_REACHED)

    def pocket(self) -> int:
        """The pocket at the change position, 0 between two."""
        return sum(bit for bit, sensor in self.magazine_code if sensor.value)

    # Network 12 --------------------------------------------------------------------------
    def tool_search(self) -> None:
        assert self.rotate_cw is not None and self.rotate_ccw is not None
        step = self.search_step
        tool = self.last("T")
        if step is SearchStep.FAULT:
            if self.reset_pressed:
                step = SearchStep.IDLE
        elif tool is not None:
            self.preselected = int(tool.value)
            if self.preselected in (0, self.spindle_tool):
                step = SearchStep.IDLE  # nothing to fetch
            elif self.preselected not in self.tools:
                step, self.search_fault = SearchStep.FAULT, TOOL_UNKNOWN
            else:
                self.target_pocket = self.tools.index(self.preselected) + 1
                self.search_clockwise = shorter_way_clockwise(self.pocket() or self.target_pocket,
                                                              self.target_pocket, self.pockets)
                step = SearchStep.SEARCH
        if step is SearchStep.SEARCH and self.pocket() == self.target_pocket:
            step = SearchStep.READY
        if self.search_watchdog(step is SearchStep.SEARCH):
            step, self.search_fault = SearchStep.FAULT, POCKET_NOT_REACHED
        self.search_step = step
        turning = step is SearchStep.SEARCH and self.arm_home is not None and self.arm_home.value
        self.rotate_cw.value = turning and self.search_clockwise
        self.rotate_ccw.value = turning and not self.search_clockwise
        self.hold_read_in = self.hold_read_in or step is SearchStep.FAULT

    # Network 13 --------------------------------------------------------------------------
    def tool_change(self) -> None:
        assert self.arm_to_spindle is not None and self.arm_home is not None and self.arm_at_spindle is not None
        step = self.change_step
        if step is ChangeStep.FAULT:
            if self.reset_pressed:
                step = ChangeStep.IDLE
        elif step is ChangeStep.IDLE and self.m_function(TOOL_CHANGE_M):
            step = ChangeStep.WAIT_MAGAZINE
        if step is ChangeStep.WAIT_MAGAZINE:
            if self.search_step is SearchStep.READY:
                step = ChangeStep.TO_SPINDLE
            elif self.search_step is SearchStep.IDLE:
                step = ChangeStep.IDLE  # T0, or the tool is in the spindle already
        if step is ChangeStep.TO_SPINDLE and self.arm_at_spindle.value:
            step = ChangeStep.BACK
        if step is ChangeStep.BACK and self.arm_home.value:
            pocket = self.target_pocket
            self.tools[pocket - 1], self.spindle_tool = self.spindle_tool, self.tools[pocket - 1]
            self.search_step = SearchStep.IDLE
            step = ChangeStep.IDLE
        if self.arm_watchdog(step in (ChangeStep.TO_SPINDLE, ChangeStep.BACK)):
            step = ChangeStep.FAULT
        self.change_step = step
        self.arm_to_spindle.value = step is ChangeStep.TO_SPINDLE
        self.hold_read_in = self.hold_read_in or step is not ChangeStep.IDLE
