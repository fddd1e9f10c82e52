"""The awlsim CPU's clock follows the NC: S7 timers count the time the bridge sets, not the wall clock."""

from __future__ import annotations

import time

import pytest

pytest.importorskip("awlsim")

from plc_awlsim.awlsim_api import AwlParser, AwlSim, AwlSource, S7CPUConfig
from plc_awlsim.clock import NcClock, follow_nc

PROGRAM = """
ORGANIZATION_BLOCK OB 1
BEGIN
	A	I 0.0
	L	S5T#20MS
	SD	T 1
	A	T 1
	=	Q 0.0
	CALL	SFC 64 (RET_VAL := MD 0)
END_ORGANIZATION_BLOCK
"""


def _cpu_with_nc_clock() -> tuple[AwlSim, NcClock]:
    sim = AwlSim()
    sim.cpu.getConf().setConfiguredMnemonics(S7CPUConfig.MNEMONICS_EN)
    parser = AwlParser()
    parser.parseSource(AwlSource(name="clock", sourceBytes=PROGRAM.encode()))
    sim.load(parser.getParseTree())
    clock = NcClock()
    follow_nc(sim.cpu, clock)
    sim.startup()
    return sim, clock


def _scan(sim: AwlSim, clock: NcClock, cycles: int, start: bool = True) -> tuple[int, int]:
    """One OB 1 at NC cycle ``cycles`` (2 ms IPO): the timer's output and TIME_TCK."""
    clock.set_cycles(cycles, 2000)
    sim.cpu.storeInputRange(0, bytearray([1 if start else 0]))
    sim.runCycle()
    return sim.cpu.fetchOutputRange(0, 1)[0] & 1, int.from_bytes(sim.cpu.flags.getRawDataBytes()[0:4], "big")


def test_an_on_delay_ends_after_20_ms_of_nc_time_however_long_the_wall_clock_takes() -> None:
    sim, clock = _cpu_with_nc_clock()
    assert _scan(sim, clock, 0) == (0, 0)
    assert _scan(sim, clock, 5) == (0, 10)  # 10 ms of NC time
    time.sleep(0.05)  # 50 ms of wall time change nothing
    assert _scan(sim, clock, 5) == (0, 10)
    assert _scan(sim, clock, 10) == (1, 20)  # 20 ms: the timer has run out
    assert _scan(sim, clock, 15, start=False) == (0, 30)


def test_the_same_scans_give_the_same_times_in_every_cpu() -> None:
    runs = []
    for _ in range(2):
        sim, clock = _cpu_with_nc_clock()
        runs.append([_scan(sim, clock, cycles) for cycles in range(0, 40, 5)])
    assert runs[0] == runs[1]
