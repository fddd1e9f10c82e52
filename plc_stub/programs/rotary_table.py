"""rotary_table: the auxiliary-function program plus an indexing rotary table with its clamp.

Networks after those of ``auxiliary`` (1-10), for the axis the machine's ``plant: clamp:`` holds:

11. Rotary table (vc/plant/clamp.py; the table an indexing axis, docs/positioning_and_indexing.md).
    The part program unclamps the table with M11, indexes it (``POS[C]=CIC(1)``, ``CAC(3)`` ..) and
    clamps it with M10 [INF: the machine builder's M functions].  The PLC holds the program with the
    read-in disable DB21.DBX6.1 while the clamp moves, clamps only on an index position (DB31.DBX76.6)
    and tells the NC with DB31.DBX2.3 "clamping in progress" while it clamps, whose clamping monitor
    (MD36050, alarm 26000) then watches the table::

        CLAMPED ──M11, the table in position control (DBX61.5)──▶ UNCLAMPING: 6.1 = 1, Clamp.close off,
                  DBX2.3 off
        CLAMPED ──M11, the table's drive not ready──▶ FAULT 700042 (the clamp stays closed)
        UNCLAMPING ──Clamp.opened──▶ FREE: 6.1 = 0, the table may turn
        FREE ──M10, the table on an index position (DBX76.6)──▶ CLAMPING: 6.1 = 1, Clamp.close, DBX2.3
        FREE ──M10 off an index position──▶ FAULT 700043 (the clamp stays open)
        CLAMPING ──Clamp.closed──▶ CLAMPED: 6.1 = 0
        UNCLAMPING / CLAMPING ──clamp_timeout──▶ FAULT 700041 (not open) / 700040 (not closed)
        CLAMPED ──Clamp.closed drops (the clamp gave way)──▶ FAULT 700044: feed disable DB21.DBX6.0;
                  the valve and DBX2.3 stay (the clamping monitor watches the table: 26000)
        FAULT ──reset key──▶ CLAMPED while Clamp.closed, else FREE (Clamp.close follows the sensor);
                  after 700044 FREE: the clamp opens, the drive takes the table back to its position

    In a fault 6.1 stays set: the program waits until the reset key.  At power-on the PLC takes the
    clamp as its sensors show it.

Parameters, besides those of ``auxiliary``::

    plc:
      clamp_timeout: 1.0        # s for the clamp to reach its end position
"""

from __future__ import annotations

from enum import Enum

from interfaces.plant_io import CLAMP
from plc_stub.blocks import TON
from plc_stub.io import Bool, PlcIo
from plc_stub.programs.auxiliary import AuxiliaryMachine
from plc_stub.programs.parameters import seconds

CLAMP_M, UNCLAMP_M = 10, 11
NOT_CLOSED, NOT_OPEN, DRIVE_NOT_READY, POSITION_NOT_REACHED, GAVE_WAY = 700040, 700041, 700042, 700043, 700044
CLAMP_TIMEOUT_S = 1.0


class TableStep(Enum):
    CLAMPED = "the clamp holds the table (DBX2.3)"
    UNCLAMPING = "the clamp opens (the program waits)"
    FREE = "the clamp is open: the table may turn"
    CLAMPING = "the clamp closes on an index position (the program waits)"
    FAULT = "stopped with a PLC alarm until the reset key"


class RotaryTable(AuxiliaryMachine):
    PROGRAM = "rotary_table"
    PARAMETERS = (*AuxiliaryMachine.PARAMETERS, "clamp_timeout")

    def __init__(self, io: PlcIo):
        super().__init__(io)
        problems: list[str] = []
        timeout = seconds(io.environment.parameters, "clamp_timeout", CLAMP_TIMEOUT_S, problems)
        if problems:
            raise ValueError("\n".join(problems))
        # Network 11
        commissioning = io.environment.commissioning
        facts = commissioning.devices.get("clamp") if commissioning is not None else None
        db = int(facts.get("axis_db", 0)) if facts else 0
        table = next((axis.axis for axis in commissioning.axes if axis.db == db), None) \
            if commissioning is not None and db else None
        self.table = table
        self.clamp_close: Bool | None = None
        if table is not None:
            self.clamp_close = io.output(f"{CLAMP}.close")
            self.clamp_closed = io.input(f"{CLAMP}.closed")
            self.clamp_opened = io.input(f"{CLAMP}.opened")
            self.clamping_in_progress = io.output(f"{table}.basic.out.clampingInProgress")
            self.in_position = io.input(f"{table}.basic.in.indexAxisInPos")
            self.position_control = io.input(f"{table}.basic.in.posCtrlActive")
        self.table_alarms = {number: self.plc_alarm(number)
                             for number in (NOT_CLOSED, NOT_OPEN, DRIVE_NOT_READY, POSITION_NOT_REACHED, GAVE_WAY)} \
            if table is not None else {}
        self.table_step: TableStep | None = None  # None until the first scan reads the clamp's sensors
        self.table_fault = 0
        self.clamp_watchdog = TON(timeout, io.environment.scan_time_s)

    def auxiliary_networks(self) -> None:
        super().auxiliary_networks()
        self.rotary_table()

    # Network 11 --------------------------------------------------------------------------
    def rotary_table(self) -> None:
        if self.clamp_close is None:
            return
        closed = self.clamp_closed.value
        step = self.table_step
        if step is None:
            step = TableStep.CLAMPED if closed else TableStep.FREE  # as the sensors show it at power-on
        if step is TableStep.FAULT:
            if self.reset_pressed:
                # a clamp that gave way holds the table off its position: the reset opens it (FREE)
                held = closed and self.table_fault != GAVE_WAY
                step, self.table_fault = (TableStep.CLAMPED if held else TableStep.FREE), 0
        elif step is TableStep.CLAMPED:
            if self.m_function(UNCLAMP_M):
                step, self.table_fault = (TableStep.UNCLAMPING, 0) if self.position_control.value else \
                    (TableStep.FAULT, DRIVE_NOT_READY)
            elif not closed:
                step, self.table_fault = TableStep.FAULT, GAVE_WAY
        elif step is TableStep.FREE:
            if self.m_function(CLAMP_M):
                step, self.table_fault = (TableStep.CLAMPING, 0) if self.in_position.value else \
                    (TableStep.FAULT, POSITION_NOT_REACHED)
        elif step is TableStep.UNCLAMPING and self.clamp_opened.value:
            step = TableStep.FREE
        elif step is TableStep.CLAMPING and closed:
            step = TableStep.CLAMPED
        if self.clamp_watchdog(step in (TableStep.UNCLAMPING, TableStep.CLAMPING)):
            step, self.table_fault = TableStep.FAULT, NOT_OPEN if step is TableStep.UNCLAMPING else NOT_CLOSED
        self.table_step = step
        # in a fault the valve stays as it was: closed where the clamp holds, or where it gave way (the
        # NC's clamping monitor then sees the table pushed off: 26000)
        clamping = step in (TableStep.CLAMPING, TableStep.CLAMPED) or \
            (step is TableStep.FAULT and (closed or self.table_fault == GAVE_WAY))
        self.clamp_close.value = clamping
        self.clamping_in_progress.value = clamping
        for number, alarm in self.table_alarms.items():
            alarm.value = step is TableStep.FAULT and self.table_fault == number
        self.hold_read_in = self.hold_read_in or step in (TableStep.UNCLAMPING, TableStep.CLAMPING, TableStep.FAULT)
        self.hold_feed = self.hold_feed or (step is TableStep.FAULT and self.table_fault == GAVE_WAY)
