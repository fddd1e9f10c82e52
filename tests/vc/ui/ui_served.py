"""What the operator page's tests share: ``vc serve --realtime --ui`` with ``python -m plc_stub`` over
Modbus TCP on 127.0.0.1 (ephemeral ports, time-outs), and where Debian's Chromium and its driver are."""

from __future__ import annotations

import os
import queue
import shutil
import socket
import subprocess
import sys
import threading
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[3]
TIMEOUT = 60.0
CHROMIUM = shutil.which("chromium")
CHROMEDRIVER = shutil.which("chromedriver")


def free_port() -> int:
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        return int(probe.getsockname()[1])


class Lines:
    """A process's output, line by line, with a time-out."""

    def __init__(self, process: subprocess.Popen[str]):
        self.seen: list[str] = []
        self._queue: queue.Queue[str] = queue.Queue()
        assert process.stdout is not None
        threading.Thread(target=self._pump, args=(process.stdout,), daemon=True).start()

    def _pump(self, stream) -> None:  # type: ignore[no-untyped-def]
        for line in stream:
            self._queue.put(line.rstrip("\n"))

    def wait_for(self, text: str, timeout: float = TIMEOUT) -> str:
        while True:
            try:
                line = self._queue.get(timeout=timeout)
            except queue.Empty:
                raise AssertionError(f"no line with {text!r} within {timeout} s; seen: {self.seen}") from None
            self.seen.append(line)
            if text in line:
                return line


def spawn(*arguments: str) -> subprocess.Popen[str]:
    return subprocess.Popen([sys.executable, *arguments], stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                            cwd=ROOT)


def stop(process: subprocess.Popen[str]) -> None:
    if process.poll() is None:
        process.terminate()
        try:
            process.wait(10)
        except subprocess.TimeoutExpired:
            process.kill()
            process.wait()


@dataclass
class Served:
    url: str
    server: Lines


def serve_with_page(*extra: str) -> Iterator[Served]:
    """``vc serve --machine turn_mill --realtime --ui`` and ``python -m plc_stub`` over Modbus TCP."""
    modbus = free_port()
    server = spawn("-m", "vc.cli.main", "serve", "--machine", "turn_mill", "--modbus", f"127.0.0.1:{modbus}",
                   "--realtime", "--ui", "127.0.0.1:0", "--duration", "600", *extra)
    plc = None
    try:
        lines = Lines(server)
        url = lines.wait_for("operator panel: ").split("operator panel: ", 1)[1].split()[0]
        lines.wait_for("real time")
        plc = spawn("-m", "plc_stub", "--modbus", f"127.0.0.1:{modbus}", "--connect-timeout", "30")
        yield Served(url, lines)
    finally:
        if plc is not None:
            stop(plc)
        stop(server)


needs_browser = pytest.mark.skipif(
    (CHROMIUM is None or CHROMEDRIVER is None) and not os.environ.get("VC_REQUIRE_CHROMEDRIVER"),
    reason="needs Debian's chromium and chromium-driver (apt-get install chromium chromium-driver)")


