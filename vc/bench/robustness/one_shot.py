"""A ``vc`` command run once, as a user runs it on a hostile file: in its own process, bounded.

The input parts of the campaign (hostile recordings, hostile expressions, campaign size) judge
what a command does with a file: :func:`run_vc` runs ``python -m vc.cli.main ARGUMENTS`` with a
wall-clock bound and a limit on its address space (a memory bomb ends in ``MemoryError`` instead
of swapping the machine), and :class:`Outcome` says whether it ended with an exit code of the
command's own (0, 1, 2), printed a traceback, was killed by the bound (a hang) or died otherwise
(a crash).
"""

from __future__ import annotations

import resource
import subprocess
import sys
import time as wallclock
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

from vc.bench.robustness.campaign import Row
from vc.bench.robustness.processes import ROOT, TRACEBACK

MEMORY_LIMIT_BYTES = 4 << 30  # address space of one command: far above what a bounded reader needs
OWN_EXIT_CODES = (0, 1, 2)  # passed, failed / differs, problems


@dataclass(frozen=True, slots=True)
class Outcome:
    """What one command did with one input."""

    name: str
    code: int | None  # None: killed by the bound
    output: str  # standard output and error
    seconds: float

    @property
    def hang(self) -> bool:
        return self.code is None

    @property
    def traceback(self) -> bool:
        return TRACEBACK in self.output

    @property
    def crash(self) -> bool:
        """Ended otherwise than with an exit code of the command (a signal, an interpreter error)."""
        return self.code is not None and self.code not in OWN_EXIT_CODES and not self.traceback

    @property
    def bad(self) -> str:
        """"hang", "traceback", "crash" or "" (the command handled the input)."""
        return "hang" if self.hang else "traceback" if self.traceback else "crash" if self.crash else ""


def _limit_memory() -> None:
    resource.setrlimit(resource.RLIMIT_AS, (MEMORY_LIMIT_BYTES, MEMORY_LIMIT_BYTES))


def run_vc(name: str, arguments: Sequence[str], bound_s: float, cwd: Path = ROOT) -> Outcome:
    """``vc ARGUMENTS`` in its own process, killed after ``bound_s`` seconds of wall time."""
    began = wallclock.monotonic()
    process = subprocess.Popen([sys.executable, "-m", "vc.cli.main", *arguments], stdout=subprocess.PIPE,
                               stderr=subprocess.STDOUT, text=True, errors="replace", cwd=cwd,
                               preexec_fn=_limit_memory)
    try:
        output, _ = process.communicate(timeout=bound_s)
        code: int | None = process.returncode
    except subprocess.TimeoutExpired:
        process.kill()
        output, _ = process.communicate()
        code = None
    return Outcome(name, code, output, wallclock.monotonic() - began)


def tally(part: str, outcomes: Sequence[Outcome], *, false_passes: int = 0, violations: int = 0,
          notes: str = "") -> Row:
    """The part's row from its outcomes."""
    return Row(part, inputs=len(outcomes), crashes=sum(outcome.crash for outcome in outcomes),
               hangs=sum(outcome.hang for outcome in outcomes),
               tracebacks=sum(outcome.traceback for outcome in outcomes), false_passes=false_passes,
               violations=violations, notes=notes)
