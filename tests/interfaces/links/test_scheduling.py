"""Pinning to CPUs and SCHED_FIFO (interfaces/links/scheduling.py): the lists and priorities a user
gives, and what a process gets (in a process of its own: a test must not change its own scheduling)."""

from __future__ import annotations

import os
import re
import subprocess
import sys

import pytest

from interfaces.links.scheduling import SchedulingError, parse_cpus, parse_priority

FIRST = min(os.sched_getaffinity(0))


def test_cpu_lists_and_ranges() -> None:
    assert parse_cpus(str(FIRST)) == {FIRST}
    assert parse_cpus(",".join(map(str, sorted(os.sched_getaffinity(0))))) == os.sched_getaffinity(0)
    assert parse_cpus(f"{FIRST}-{FIRST}") == {FIRST}


@pytest.mark.parametrize(("text", "message"), [
    ("x", "'x' is not a CPU list (e.g. 1, 0,2 or 2-3)"),
    ("4096", "CPU 4096 is not one this process may run on"),
    ("", "is not a CPU list"),
])
def test_a_cpu_the_process_cannot_run_on_is_refused(text: str, message: str) -> None:
    with pytest.raises(SchedulingError, match=re.escape(message)):
        parse_cpus(text)


@pytest.mark.parametrize("text", ["0", "100", "high"])
def test_a_priority_outside_1_to_99_is_refused(text: str) -> None:
    with pytest.raises(SchedulingError, match=r"a SCHED_FIFO priority is 1 \.\. 99"):
        parse_priority(text)


def test_a_process_is_pinned_and_gets_sched_fifo_or_says_why_not() -> None:
    result = subprocess.run([sys.executable, "-c", "from interfaces.links.scheduling import place;"
                             f" print(place({{{FIRST}}}, 10)); import os; print(sorted(os.sched_getaffinity(0)))"],
                            capture_output=True, text=True, timeout=60)
    placement, affinity = result.stdout.splitlines()
    assert affinity == f"[{FIRST}]"
    assert placement in (f"pinned to CPU {FIRST}, SCHED_FIFO 10", f"pinned to CPU {FIRST}, SCHED_OTHER (SCHED_FIFO not"
                         " permitted: it needs root, CAP_SYS_NICE or an rtprio limit (ulimit -r,"
                         " /etc/security/limits.conf))")
