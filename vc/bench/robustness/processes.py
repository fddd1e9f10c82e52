"""The harness as the campaign runs it: ``vc serve`` and ``python -m plc_stub`` in their own processes.

:class:`Child` collects a process's output as it comes (a thread per stream), waits for a line,
samples its resident memory (``/proc/PID/status``), counts Python tracebacks in what it wrote, and
stops it as Ctrl-C would (so ``vc serve`` prints its final statistics).  :class:`ServedNc` is the
pair the link parts abuse: the NC served over Modbus TCP (and S7, or a CAN bus) and the built-in
PLC connected to it.
"""

from __future__ import annotations

import re
import signal
import subprocess
import sys
import threading
import time as wallclock
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from types import TracebackType

from interfaces.errors import VcError

ROOT = Path(__file__).resolve().parents[3]  # the repository: scenario paths are relative to it
TRACEBACK = "Traceback (most recent call last)"
START_TIMEOUT_S = 60.0


class CampaignError(VcError):
    """The harness could not be set up for a part (a process that does not start, a line that never comes)."""


class Child:
    """A process of the harness (module docstring)."""

    def __init__(self, name: str, arguments: Sequence[str]):
        self.name = name
        self.process = subprocess.Popen([sys.executable, *arguments], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                                        text=True, cwd=ROOT)
        self.lines: list[str] = []  # standard output
        self.errors: list[str] = []  # standard error
        self._changed = threading.Condition()
        self._readers = [threading.Thread(target=self._read, args=(stream, into), daemon=True)
                         for stream, into in ((self.process.stdout, self.lines), (self.process.stderr, self.errors))]
        for reader in self._readers:
            reader.start()

    def _read(self, stream: object, into: list[str]) -> None:
        for line in stream:  # type: ignore[attr-defined]
            with self._changed:
                into.append(line.rstrip("\n"))
                self._changed.notify_all()
        with self._changed:
            self._changed.notify_all()

    def wait_for(self, pattern: str, timeout_s: float = START_TIMEOUT_S, errors: bool = False) -> re.Match[str]:
        """The first line of standard output (or error) that matches ``pattern``."""
        expression = re.compile(pattern)
        lines = self.errors if errors else self.lines
        deadline = wallclock.monotonic() + timeout_s
        with self._changed:
            while True:
                for line in lines:
                    if match := expression.search(line):
                        return match
                left = deadline - wallclock.monotonic()
                if left <= 0 or (self.process.poll() is not None and not any(r.is_alive() for r in self._readers)):
                    written = " | ".join((self.lines + self.errors)[-8:])
                    raise CampaignError(f"{self.name}: no line matching {pattern!r} (exit code"
                                        f" {self.process.poll()}); it wrote: {written}")
                self._changed.wait(min(left, 0.2))

    @property
    def alive(self) -> bool:
        return self.process.poll() is None

    def rss_kb(self) -> int:
        """Resident memory now (0 once the process has ended)."""
        try:
            status = Path(f"/proc/{self.process.pid}/status").read_text()
        except OSError:
            return 0
        match = re.search(r"^VmRSS:\s+(\d+) kB", status, re.MULTILINE)
        return int(match.group(1)) if match else 0

    def tracebacks(self) -> int:
        return sum(line.count(TRACEBACK) for line in self.lines + self.errors)

    def stop(self, timeout_s: float = 60.0) -> int:
        """Ctrl-C, then the exit code (a process that does not end in time is killed: -9)."""
        if self.process.poll() is None:
            self.process.send_signal(signal.SIGINT)
            try:
                self.process.wait(timeout_s)
            except subprocess.TimeoutExpired:
                self.process.kill()
                self.process.wait()
        for reader in self._readers:
            reader.join(5)
        return self.process.returncode


@dataclass(frozen=True, slots=True)
class FinalPacing:
    """``vc serve --realtime``'s last pacing line: cycles, overruns and those caused by the links."""

    cycles: int
    overruns: int
    link_overruns: int
    share_pct: float

    def __str__(self) -> str:
        return f"{self.overruns} of {self.cycles} ({self.link_overruns} by the links)"


FINAL_PACING = re.compile(r"^real time: (\d+) cycles: .*; (\d+) overruns \((\d+) while serving the links\); NC at"
                          r" ([\d.]+) % of the schedule")


def final_pacing(child: Child) -> FinalPacing | None:
    for line in reversed(child.lines):
        if match := FINAL_PACING.search(line):
            return FinalPacing(int(match.group(1)), int(match.group(2)), int(match.group(3)), float(match.group(4)))
    return None


class ServedNc:
    """``vc serve`` with ``serve_arguments`` and ``python -m plc_stub`` connected to it (a context
    manager); Modbus on an ephemeral loopback port unless the arguments name a CAN bus."""

    def __init__(self, serve_arguments: Sequence[str], plc_arguments: Sequence[str] | None = None,
                 plc_options: Sequence[str] = ()):
        """``plc_arguments``: instead of ``--modbus`` to the server; ``plc_options``: more of them."""
        can = "--can" in serve_arguments
        modbus = [] if can or "--modbus" in serve_arguments else ["--modbus", "127.0.0.1:0"]
        self.serve = Child("vc serve", ["-m", "vc.cli.main", "serve", *modbus, *serve_arguments])
        self.plc: Child | None = None
        self.modbus_port = 0
        self.s7_port = 0
        try:
            if not can:
                self.modbus_port = int(self.serve.wait_for(r"^Modbus TCP on [\d.]+:(\d+)").group(1))
            if "--s7" in serve_arguments:
                self.s7_port = int(self.serve.wait_for(r"^S7 on [\d.]+:(\d+)").group(1))
            plc = plc_arguments if plc_arguments is not None else ["--modbus", f"127.0.0.1:{self.modbus_port}"]
            self.plc = Child("plc_stub", ["-m", "plc_stub", *plc, *plc_options])
            self.plc.wait_for(r"session \d+( \(boot id \d+\))?: machine", errors=True)
        except BaseException:
            self.close()
            raise

    def rss_kb(self) -> tuple[int, int]:
        """Resident memory of the server and of the PLC."""
        return self.serve.rss_kb(), self.plc.rss_kb() if self.plc is not None else 0

    def crashes(self) -> int:
        """Processes that ended by themselves before the part stopped them."""
        return sum(not child.alive for child in (self.serve, self.plc) if child is not None)

    def tracebacks(self) -> int:
        return sum(child.tracebacks() for child in (self.serve, self.plc) if child is not None)

    def close(self) -> None:
        """Stop the server first (it prints its statistics), then the PLC."""
        self.serve.stop()
        if self.plc is not None:
            self.plc.stop()

    def __enter__(self) -> ServedNc:
        return self

    def __exit__(self, kind: type[BaseException] | None, error: BaseException | None,
                 trace: TracebackType | None) -> None:
        self.close()


def growth_pct(before: int, after: int) -> float:
    """Relative growth of a resident memory figure in percent (0 without a first figure)."""
    return 100.0 * (after - before) / before if before else 0.0
