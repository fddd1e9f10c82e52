"""What the operator page's tests share: ``vc serve --realtime --ui`` with ``python -m plc_stub`` over
Modbus TCP on 127.0.0.1 (ephemeral ports, time-outs), and where Debian's Chromium and its driver are."""

from __future__ import annotations

import os
import shutil
import socket
import subprocess
import sys
import tempfile
import time
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[3]
TIMEOUT_S = 60.0
CHROMIUM = shutil.which("chromium")
CHROMEDRIVER = shutil.which("chromedriver")

needs_browser = pytest.mark.skipif(
    (CHROMIUM is None or CHROMEDRIVER is None) and not os.environ.get("VC_REQUIRE_CHROMEDRIVER"),
    reason="needs Debian's chromium and chromium-driver (apt-get install chromium chromium-driver)")


@dataclass
class Served:
    url: str
    output: Path  # what vc serve printed so far
    plc: subprocess.Popen[bytes] | None = None  # python -m plc_stub (a test may end it: the PLC lost)


def _modbus_port() -> int:
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        return int(probe.getsockname()[1])


def _line_with(output: Path, text: str, server: subprocess.Popen[bytes]) -> str:
    """The first line of the server's output (a file) that holds ``text``, polled until the time-out."""
    end = time.monotonic() + TIMEOUT_S
    while time.monotonic() < end:
        for line in output.read_text(encoding="utf-8", errors="replace").splitlines():
            if text in line:
                return line
        if server.poll() is not None:
            break
        time.sleep(0.1)
    raise AssertionError(f"vc serve printed no line with {text!r}:\n{output.read_text(errors='replace')[-3000:]}")


def _end(process: subprocess.Popen[bytes]) -> None:
    if process.poll() is None:
        process.terminate()
        try:
            process.wait(10)
        except subprocess.TimeoutExpired:
            process.kill()
            process.wait()


def serve_with_page(*extra: str) -> Iterator[Served]:
    """``vc serve --machine turn_mill --realtime --ui 127.0.0.1:0`` and ``python -m plc_stub`` over Modbus TCP."""
    modbus = _modbus_port()
    with tempfile.TemporaryDirectory() as folder:
        output = Path(folder) / "serve.txt"
        with output.open("wb") as sink:
            server = subprocess.Popen(
                [sys.executable, "-m", "vc.cli.main", "serve", "--machine", "turn_mill", "--modbus",
                 f"127.0.0.1:{modbus}", "--realtime", "--ui", "127.0.0.1:0", "--duration", "600", *extra],
                stdout=sink, stderr=subprocess.STDOUT, cwd=ROOT)
        plc = None
        try:
            url = _line_with(output, "operator panel: ", server).split("operator panel: ", 1)[1].split()[0]
            _line_with(output, "real time", server)
            plc = subprocess.Popen([sys.executable, "-m", "plc_stub", "--modbus", f"127.0.0.1:{modbus}",
                                    "--connect-timeout", "30"], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                                   cwd=ROOT)
            yield Served(url, output, plc)
        finally:
            for process in (plc, server):
                if process is not None:
                    _end(process)
