"""IEC 61131-3 standard function blocks, as a PLC programmer knows them.

Timers count the scan time they are built with (the OB1 period), so a program behaves the
same in lockstep and in real time.  Call an instance once per scan with its input; it
returns its output ``Q``.
"""

from __future__ import annotations


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
