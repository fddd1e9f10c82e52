"""The CPU's clock of an awlsim PLC follows the NC.

awlsim keeps its time in ``S7CPU.now`` (seconds) and sets it from the wall clock in
``updateTimestamp`` (its argument ``_getTime``, in the pure-Python build) plus an offset that
``initializeTimestamp`` takes from the wall clock at start-up.  Everything time-based reads
``now``: the S5 timers (SP, SE/SD, SS, SA, SF), the IEC timers SFB 3..5 and SFC 64 TIME_TCK
(``now`` in ms), the clock memory byte.  :func:`follow_nc` gives the CPU a clock of its own:
the offset becomes 0 and ``now`` the NC time the bridge sets before every scan (the NC cycle
count of input registers 4..5 times the IPO cycle of input register 6).  So a timer of 2 s
ends in the first scan whose NC time lies 2 s (or, by the rounding of the floating-point
seconds, one PLC period more) after its start, whatever the real-time factor, and the same
in every run; within a scan the time stands still.

awlsim's compiled (Cython) build binds its clock in C: there :func:`follow_nc` refuses
with an error rather than let the timers run on the wall clock unnoticed.
"""

from __future__ import annotations

from typing import Any

ZERO_OFFSET_CLOCK = 2147483.647 - 0.1  # what makes initializeTimestamp's offset exactly 0


class NcClock:
    """The NC time an awlsim CPU reads as its ``now``."""

    def __init__(self) -> None:
        self.seconds = 0.0

    def set_cycles(self, cycles: int, ipo_cycle_us: int) -> None:
        self.seconds = cycles * ipo_cycle_us / 1_000_000

    def __call__(self) -> float:
        return self.seconds


def follow_nc(cpu: Any, clock: NcClock) -> None:
    """Make ``cpu`` (an awlsim ``S7CPU``) read ``clock`` as its time, from 0."""
    import awlsim.core.cpu as cpu_module

    from plc_awlsim.awlsim_api import AwlSimError

    if not hasattr(cpu, "__dict__"):
        raise AwlSimError("this awlsim is the compiled (Cython) build: its CPU clock cannot follow the NC;"
                          " run it with AWLSIM_CYTHON=0")
    cpu_class = type(cpu)
    cpu.updateTimestamp = lambda _getTime=None: cpu_class.updateTimestamp(cpu, clock)
    wall_clock = cpu_module.monotonic_time
    cpu_module.monotonic_time = lambda: ZERO_OFFSET_CLOCK
    try:
        cpu.initializeTimestamp()
    finally:
        cpu_module.monotonic_time = wall_clock
