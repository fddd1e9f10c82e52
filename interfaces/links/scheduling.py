"""Where a process of a link runs: pinned to CPUs, and with real-time scheduling where permitted.

The real-time NC (``vc serve --realtime``) and its PLC (``python -m plc_stub``) share the host with
everything else, and a CPU-heavy process costs them their period (the robustness campaign's
isolation part measures how much).  What a user can ask of Linux, in both commands:

* ``--cpu LIST`` (``1``, ``0,2``, ``2-3``): ``os.sched_setaffinity`` pins the process, every thread of
  it, to these CPUs.  Other processes still run there unless they are kept away too (``taskset``
  for them, or the kernel's ``isolcpus=`` boot parameter, which keeps a CPU free of every process
  not pinned to it).
* ``--fifo PRIORITY`` (1..99): ``SCHED_FIFO``, which runs before every ordinary process on its CPU,
  however busy that is.  It needs the privilege: root, ``CAP_SYS_NICE``, or an ``rtprio`` limit
  (``/etc/security/limits.conf``, ``ulimit -r``); without it the process goes on as it was and says
  why.  The kernel keeps 5 % of every second for the others (``/proc/sys/kernel/sched_rt_runtime_us``),
  so the pacer's spinning cannot lock a CPU up.

:func:`place` applies both and returns the :class:`Placement` the process got, for its statistics.
"""

from __future__ import annotations

import os
from collections.abc import Collection
from dataclasses import dataclass

from interfaces.errors import VcError

FIFO_PRIORITIES = range(1, 100)


class SchedulingError(VcError, ValueError):
    """A CPU list or a priority the host cannot give (the message says which and why)."""


def parse_cpus(text: str) -> frozenset[int]:
    """``1``, ``0,2``, ``2-3`` as CPU numbers, each one this process may run on."""
    cpus: set[int] = set()
    for part in text.split(","):
        first, dash, last = part.strip().partition("-")
        try:
            numbers = range(int(first), int(last if dash else first) + 1)
        except ValueError:
            raise SchedulingError(f"'{text}' is not a CPU list (e.g. 1, 0,2 or 2-3)") from None
        cpus.update(numbers)
    available = os.sched_getaffinity(0)
    outside = sorted(cpus - available)
    if not cpus or outside:
        raise SchedulingError(f"CPU {', '.join(map(str, outside)) or text} is not one this process may run on"
                              f" ({_span(available)})")
    return frozenset(cpus)


def parse_priority(text: str) -> int:
    try:
        priority = int(text)
    except ValueError:
        priority = 0
    if priority not in FIFO_PRIORITIES:
        raise SchedulingError(f"'{text}': a SCHED_FIFO priority is 1 .. 99")
    return priority


@dataclass(frozen=True, slots=True)
class Placement:
    """Where the process runs and how it is scheduled."""

    cpus: frozenset[int]
    pinned: bool  # asked for: --cpu
    policy: str  # "SCHED_FIFO 50", "SCHED_OTHER"
    refused: str = ""  # why SCHED_FIFO was not granted

    def __str__(self) -> str:
        where = f"pinned to CPU {_span(self.cpus)}" if self.pinned else f"on CPU {_span(self.cpus)}"
        text = f"{where}, {self.policy}"
        return f"{text} ({self.refused})" if self.refused else text


def place(cpus: Collection[int] | None = None, fifo_priority: int | None = None) -> Placement:
    """Pin this process to ``cpus`` and ask for ``SCHED_FIFO`` at ``fifo_priority`` (module docstring)."""
    if cpus:
        os.sched_setaffinity(0, cpus)
    refused = ""
    if fifo_priority is not None:
        try:
            os.sched_setscheduler(0, os.SCHED_FIFO, os.sched_param(fifo_priority))
        except PermissionError:
            refused = ("SCHED_FIFO not permitted: it needs root, CAP_SYS_NICE or an rtprio limit (ulimit -r,"
                       " /etc/security/limits.conf)")
    return Placement(frozenset(os.sched_getaffinity(0)), bool(cpus), _policy(), refused)


def _policy() -> str:
    if os.sched_getscheduler(0) == os.SCHED_FIFO:
        return f"SCHED_FIFO {os.sched_getparam(0).sched_priority}"
    return "SCHED_OTHER" + (f", nice {os.nice(0)}" if os.nice(0) else "")


def _span(cpus: Collection[int]) -> str:
    ordered = sorted(cpus)
    if len(ordered) > 1 and ordered == list(range(ordered[0], ordered[-1] + 1)):
        return f"{ordered[0]}-{ordered[-1]}"
    return ",".join(map(str, ordered))
