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

12. Indexing by the PLC (seed 003 §11.2.3, L13522-13530: the PLC indexes an indexing axis as a
    concurrent positioning axis, FC18 SINU_TraversePosAxis with Funct 4).  ``H<n>`` in the part
    program [INF: the machine builder's H function] hands the whole station change to the PLC: it
    unclamps the table (as M11), indexes it the shorter way to index position n (FC18 Mode 2, CDC;
    FRate ``index_feed``, 0: MD32060), clamps it on the position (as M10) and holds the program
    until the table is clamped::

        CLAMPED ──H n──▶ UNCLAMPING ──Clamp.opened──▶ INDEXING (FC18 Start)
        FREE ──H n──▶ INDEXING
        INDEXING ──FC18 InPos, DBX76.6──▶ CLAMPING ──Clamp.closed──▶ CLAMPED (the H function done)
        INDEXING ──FC18 Error──▶ FAULT 700045 (refused: State 100 no such index position ...) or
                  700043 (aborted: State 30)
        INDEXING ──no InPos within index_timeout (the drive holds the table)──▶ FAULT 700043, FC18 Stop
        INDEXING ──reset key (the NC's reset aborts the motion)──▶ FREE, the H function dropped

    An H function while the PLC does not wait for one (a fault, the clamp moving) is dropped with
    the fault's alarm as M10 / M11 are.

Parameters, besides those of ``auxiliary``::

    plc:
      clamp_timeout: 1.0        # s for the clamp to reach its end position
      index_feed: 0.0           # deg/min of the PLC's indexing (0: MD32060 POS_AX_VELO)
      index_timeout: 5.0        # s for the table to reach its index position
"""

from __future__ import annotations

from enum import Enum

from interfaces.plant_io import CLAMP
from plc_stub.blocks import FC18_INDEXING_AXIS, TON, TraversePosAxis
from plc_stub.io import Bool, PlcIo
from plc_stub.programs.auxiliary import AuxiliaryMachine
from plc_stub.programs.parameters import seconds

CLAMP_M, UNCLAMP_M = 10, 11
NOT_CLOSED, NOT_OPEN, DRIVE_NOT_READY, POSITION_NOT_REACHED, GAVE_WAY = 700040, 700041, 700042, 700043, 700044
INDEXING_REFUSED = 700045
CLAMP_TIMEOUT_S = 1.0
INDEX_TIMEOUT_S = 5.0
SHORTER_WAY = 2  # FC18 Mode of an indexing axis: CDC
FC18_ABORTED = 30  # FC18 State: the NC aborted the motion (vc/core/axis/plc_axis.py)


class TableStep(Enum):
    CLAMPED = "the clamp holds the table (DBX2.3)"
    UNCLAMPING = "the clamp opens (the program waits)"
    FREE = "the clamp is open: the table may turn"
    INDEXING = "FC18 indexes the table to the H function's position (the program waits)"
    CLAMPING = "the clamp closes on an index position (the program waits)"
    FAULT = "stopped with a PLC alarm until the reset key"


class RotaryTable(AuxiliaryMachine):
    PROGRAM = "rotary_table"
    PARAMETERS = (*AuxiliaryMachine.PARAMETERS, "clamp_timeout", "index_feed", "index_timeout")

    def __init__(self, io: PlcIo):
        super().__init__(io)
        problems: list[str] = []
        parameters = io.environment.parameters
        timeout = seconds(parameters, "clamp_timeout", CLAMP_TIMEOUT_S, problems)
        index_timeout = seconds(parameters, "index_timeout", INDEX_TIMEOUT_S, problems)
        feed = parameters.get("index_feed", 0.0)
        if isinstance(feed, bool) or not isinstance(feed, (int, float)) or not 0 <= feed <= 1.0e6:
            problems.append(f"plc: index_feed is a feed in deg/min, 0 (MD32060) .. 1000000, got {feed!r}")
            feed = 0.0
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
                             for number in (NOT_CLOSED, NOT_OPEN, DRIVE_NOT_READY, POSITION_NOT_REACHED, GAVE_WAY,
                                            INDEXING_REFUSED)} \
            if table is not None else {}
        self.table_step: TableStep | None = None  # None until the first scan reads the clamp's sensors
        self.table_fault = 0
        self.clamp_watchdog = TON(timeout, io.environment.scan_time_s)
        # Network 12
        self.index_fc18 = TraversePosAxis(io, db - 30) if table is not None else None
        self.index_feed = float(feed)
        self.index_target: float | None = None  # the H function's index position until the table is clamped
        self.index_stop_pending = False
        self.index_watchdog = TON(index_timeout, io.environment.scan_time_s)

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
        station = self.last("H")  # network 12's indexing by the PLC
        start = False
        if step is TableStep.FAULT:
            if self.reset_pressed:
                # a clamp that gave way holds the table off its position: the reset opens it (FREE)
                held = closed and self.table_fault != GAVE_WAY
                step, self.table_fault = (TableStep.CLAMPED if held else TableStep.FREE), 0
                self.index_target = None
        elif step is TableStep.CLAMPED:
            if self.m_function(UNCLAMP_M) or station is not None:
                step, self.table_fault = (TableStep.UNCLAMPING, 0) if self.position_control.value else \
                    (TableStep.FAULT, DRIVE_NOT_READY)
                self.index_target = station.value if station is not None and step is TableStep.UNCLAMPING else None
            elif not closed:
                step, self.table_fault = TableStep.FAULT, GAVE_WAY
        elif step is TableStep.FREE:
            if self.m_function(CLAMP_M):
                step, self.table_fault = (TableStep.CLAMPING, 0) if self.in_position.value else \
                    (TableStep.FAULT, POSITION_NOT_REACHED)
            elif station is not None:
                step, start, self.index_target = TableStep.INDEXING, True, station.value
        elif step is TableStep.UNCLAMPING and self.clamp_opened.value:
            step, start = (TableStep.INDEXING, True) if self.index_target is not None else (TableStep.FREE, False)
        elif step is TableStep.CLAMPING and closed:
            step, self.index_target = TableStep.CLAMPED, None
        step = self.plc_indexing(step, start)
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
        self.hold_read_in = self.hold_read_in or step in (TableStep.UNCLAMPING, TableStep.INDEXING,
                                                          TableStep.CLAMPING, TableStep.FAULT)
        self.hold_feed = self.hold_feed or (step is TableStep.FAULT and self.table_fault == GAVE_WAY)

    # Network 12 --------------------------------------------------------------------------
    def plc_indexing(self, step: TableStep, start: bool) -> TableStep:
        """FC18 (Funct 4) every scan; INDEXING ends clamping on the position, in a fault or by the reset."""
        assert self.index_fc18 is not None
        stop, self.index_stop_pending = self.index_stop_pending, False
        fc18 = self.index_fc18
        fc18(start=start, stop=stop, funct=FC18_INDEXING_AXIS, mode=SHORTER_WAY,
             pos=self.index_target if self.index_target is not None else 0.0, frate=self.index_feed)
        if step is TableStep.INDEXING and not start:
            if self.reset_pressed:
                step, self.index_target = TableStep.FREE, None  # the NC's reset aborts the motion (State 30)
            elif fc18.error:
                step, self.table_fault = TableStep.FAULT, \
                    POSITION_NOT_REACHED if fc18.state == FC18_ABORTED else INDEXING_REFUSED
            elif fc18.in_pos and self.in_position.value:
                step = TableStep.CLAMPING
        if self.index_watchdog(step is TableStep.INDEXING):
            step, self.table_fault = TableStep.FAULT, POSITION_NOT_REACHED
            self.index_stop_pending = True  # FC18 Stop brakes the motion in the next scan
        return step
