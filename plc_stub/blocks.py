"""IEC 61131-3 standard function blocks, as a PLC programmer knows them, and the block of the
SINUMERIK basic program that moves an axis from the PLC (FC18 SINU_TraversePosAxis).

Timers count the scan time they are built with (the OB1 period), so a program behaves the
same in lockstep and in real time.  Call an instance once per scan with its input; it
returns its output ``Q``.
"""

from __future__ import annotations

import math

from interfaces.signal_groups import PlcAxisStatus
from plc_stub.io import PlcIo


class TON:
    """On delay: Q becomes 1 when IN has been 1 for the preset time.

    The elapsed time ET is 0 in the scan in which IN rises and grows by one scan time in each
    following scan, so a 50 ms preset at a 10 ms scan sets Q in the sixth scan.
    """

    __slots__ = ("_elapsed", "_preset", "_running", "_scan", "q")

    def __init__(self, preset_s: float, scan_time_s: float):
        self._preset = preset_s
        self._scan = scan_time_s
        self._elapsed = 0.0
        self._running = False
        self.q = False

    def __call__(self, start: bool) -> bool:
        if start:
            if self._running:
                self._elapsed = min(self._elapsed + self._scan, self._preset)
            else:
                self._running = True
                self._elapsed = 0.0
            self.q = self._elapsed >= self._preset - 1e-12
        else:
            self._running = False
            self._elapsed = 0.0
            self.q = False
        return self.q


class TOF:
    """Off delay: Q is 1 while IN is 1 and for the preset time after IN falls.

    The elapsed time ET is 0 in the scan in which IN falls and grows by one scan time in each
    following scan; Q falls when ET reaches the preset.
    """

    __slots__ = ("_elapsed", "_preset", "_running", "_scan", "q")

    def __init__(self, preset_s: float, scan_time_s: float):
        self._preset = preset_s
        self._scan = scan_time_s
        self._elapsed = 0.0
        self._running = False
        self.q = False

    def __call__(self, start: bool) -> bool:
        if start:
            self._running = False
            self._elapsed = 0.0
            self.q = True
        elif self.q:
            if self._running:
                self._elapsed = min(self._elapsed + self._scan, self._preset)
            else:
                self._running = True
                self._elapsed = 0.0
            self.q = self._elapsed < self._preset - 1e-12
        return self.q


class R_TRIG:
    """Rising edge: Q is 1 for the one scan in which CLK goes from 0 to 1."""

    __slots__ = ("_last", "q")

    def __init__(self) -> None:
        self._last = False
        self.q = False

    def __call__(self, clk: bool) -> bool:
        self.q = clk and not self._last
        self._last = clk
        return self.q


class F_TRIG:
    """Falling edge: Q is 1 for the one scan in which CLK goes from 1 to 0."""

    __slots__ = ("_last", "q")

    def __init__(self) -> None:
        self._last = False
        self.q = False

    def __call__(self, clk: bool) -> bool:
        self.q = self._last and not clk
        self._last = clk
        return self.q


class SR:
    """Bistable, set dominant: S1 sets Q1, R resets it, and S1 wins while both are 1.

    The latch of a stop key and its start key: the stop must win when both are pressed.
    """

    __slots__ = ("q1",)

    def __init__(self) -> None:
        self.q1 = False

    def __call__(self, s1: bool, r: bool) -> bool:
        self.q1 = s1 or (self.q1 and not r)
        return self.q1


# FC18's State numbers the block gives itself, without asking the NC (the NC's: vc/core/axis/plc_axis.py)
FC18_PARAMETERS = 1  # Funct, Mode, Pos or FRate the block cannot hand on
FC18_STILL_RUNNING = 20  # Start while the axis's previous motion still runs
FC18_NO_AXIS = 40  # AxisNo names no axis of the machine that the NC could move
FC18_INDEXING_AXIS = 4  # Funct: indexing axis, Pos the number of an index position (seed 003 §11.2.3)
FC18_POSITIONING_AXIS = 5  # Funct: positioning axis, metric
FC18_FUNCTIONS = (FC18_INDEXING_AXIS, FC18_POSITIONING_AXIS)  # the functions this block offers
_REAL_MAX = 3.4028234663852886e38  # the largest S7 REAL


class TraversePosAxis:
    """FC18 SINU_TraversePosAxis (seed 003 §9.7.1, L12269-12290): the PLC positions a machine axis
    as a PLC axis, G01 at FRate (G94), exact stop fine at the end.

    Build one instance per axis with its ``AxisNo`` (machine axis n, interface DB(30 + n)) and call
    it every scan, as FC18 is called every OB1 cycle::

        self.magazine = TraversePosAxis(io, axis_no=4)
        ...
        self.magazine(start=t_word_new, stop=False, funct=5, mode=2, pos=pocket_angle, frate=7200.0)
        if self.magazine.in_pos: ...
        if self.magazine.error: alarm(self.magazine.state)

    Inputs (FC18's parameters): ``start`` (its rising edge starts a motion), ``stop`` (its rising edge
    brakes a running one), ``funct`` (5: positioning axis, metric; 4: indexing axis, ``pos`` the number
    of an index position; others are not offered: State 1), ``mode`` (0 absolute, 1 incremental,
    2 shortest path, 3 absolute positive, 4 absolute negative: of an indexing axis CAC, CIC, CDC,
    CACP, CACN), ``pos`` (mm, degrees), ``frate`` (mm/min, deg/min; 0: MD32060).  Outputs:
    ``in_pos`` (the motion ended in position), ``error`` with ``state`` (the error number), ``done`` (the job is
    over: in position or failed) and ``active`` (it runs).  Start while the previous motion runs
    gives Error with State 20 and leaves that motion alone.

    The handshake with the NC, the same for an external PLC (docs/positioning_and_indexing.md, "FC18
    over the interface"): Funct, Mode, Pos and FRate in DB31.DBB34 / DBB33 / DBD36 / DBD40, then
    Start DB31.DBX32.0 = 1 until the NC acknowledges it in DB31.DBX104.3; from then on
    DB31.DBX104.0-104.2 and DBB105 answer this start.  Stop DB31.DBX32.1 is a pulse of one PLC cycle.
    """

    __slots__ = ("_feed", "_function", "_mode", "_own_error", "_pending", "_position", "_start", "_start_edge",
                 "_status", "_stop", "_stop_edge", "active", "axis", "done", "error", "in_pos", "state")

    def __init__(self, io: PlcIo, axis_no: int):
        commissioning = io.environment.commissioning
        facts = next((item for item in commissioning.axes if item.db == 30 + axis_no), None) \
            if commissioning is not None else None
        if facts is None or facts.kind == "spindle":
            raise ValueError(f"FC18: AxisNo {axis_no} is no axis of this machine (State {FC18_NO_AXIS})")
        self.axis = facts.axis
        self._start = io.output(f"{self.axis}.plcAxis.out.start")
        self._stop = io.output(f"{self.axis}.plcAxis.out.stop")
        self._function = io.output_byte(f"{self.axis}.plcAxis.out.function")
        self._mode = io.output_byte(f"{self.axis}.plcAxis.out.mode")
        self._position = io.output_real(f"{self.axis}.plcAxis.out.position")
        self._feed = io.output_real(f"{self.axis}.plcAxis.out.feedrate")
        self._status = io.input_group(PlcAxisStatus, self.axis)
        self._start_edge = R_TRIG()
        self._stop_edge = R_TRIG()
        self._pending = False  # a Start on its way to the NC: no answer of it yet
        self._own_error = 0
        self.in_pos = False
        self.error = False
        self.state = 0
        self.done = False
        self.active = False

    def __call__(self, start: bool, stop: bool, funct: int, mode: int, pos: float, frate: float) -> bool:
        """One scan of the block; returns InPos."""
        status = self._status.read()
        self._stop.value = False  # Stop reaches the NC as one PLC cycle's pulse
        if self._start_edge(start):
            if self._pending or status.active:
                self._own_error = FC18_STILL_RUNNING
            elif funct not in FC18_FUNCTIONS or not 0 <= mode <= 255 or not _is_real(pos) or not _is_real(frate):
                self._own_error = FC18_PARAMETERS
            else:
                self._own_error = 0
                self._function.value = funct
                self._mode.value = mode
                self._position.value = pos
                self._feed.value = frate
                self._pending = True
        if self._pending:
            # the handshake: Start stays 1 until the NC has taken it (DBX104.3), and rises only
            # once the NC has let go of the last one; from then on its answer belongs to this start
            if not self._start.value and not status.start_acknowledged:
                self._start.value = True
            elif self._start.value and status.start_acknowledged:
                self._start.value = False
                self._pending = False
        if self._stop_edge(stop):
            self._stop.value = True
        if self._pending:
            self.active, self.in_pos, self.error, self.state = True, False, False, 0
        elif self._own_error:
            self.active, self.in_pos, self.error, self.state = status.active, False, True, self._own_error
        else:
            self.active, self.in_pos = status.active, status.in_position
            self.error, self.state = status.error, status.error_number
        self.done = self.in_pos or self.error
        return self.in_pos


def _is_real(value: float) -> bool:
    return math.isfinite(value) and abs(value) <= _REAL_MAX
