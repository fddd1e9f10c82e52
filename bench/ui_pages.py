"""What the operator page costs the real-time NC: ``python bench/ui_pages.py --seconds 30``.

``vc serve --machine turn_mill --realtime`` with ``python -m plc_stub`` over Modbus TCP on 127.0.0.1, run
``--seconds`` of simulated time four times: without ``--ui``, with ``--ui`` and no page open, with 1 and
with 5 pages open in Debian's headless Chromium (selenium through chromium-driver; each page watches
five signals and takes the full update rate).  A line per run with the pacer's figures at the end of
``vc serve`` (period error p99 and max, start error, overruns, share of the schedule), then the figures
as one JSON object on the last line.  Needs the extras ``ui`` and ``test`` (selenium) and the Debian
packages chromium and chromium-driver.
"""

from __future__ import annotations

import argparse
import json
import re
import shutil
import socket
import subprocess
import sys
from pathlib import Path
from typing import Any

ROOT = Path(__file__).resolve().parents[1]
WATCHED = ("DB31.DBX64.7", "DB31.DBX60.4", "X1.refCam", "DB11.DBX6.2", "DB21.DBX35.7")
FIGURES = re.compile(r"real time: (?P<cycles>\d+) cycles: period error p99 (?P<period_p99>[\d.]+) ms, max"
                     r" (?P<period_max>[\d.]+) ms; start error median (?P<start_median>[\d.]+) ms, p99"
                     r" (?P<start_p99>[\d.]+) ms; (?P<overruns>\d+) overruns \((?P<link_overruns>\d+) while"
                     r" serving the links\); NC at (?P<share>[\d.]+) %")


def free_port() -> int:
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        return int(probe.getsockname()[1])


def open_pages(url: str, count: int) -> Any:
    from selenium import webdriver
    from selenium.webdriver.chrome.service import Service

    options = webdriver.ChromeOptions()
    options.binary_location = shutil.which("chromium") or "chromium"
    for argument in ("--headless=new", "--no-sandbox", "--disable-gpu", "--disable-dev-shm-usage",
                     "--disable-background-timer-throttling", "--disable-renderer-backgrounding"):
        options.add_argument(argument)
    driver = webdriver.Chrome(options=options, service=Service(shutil.which("chromedriver") or "chromedriver"))
    for index in range(count):
        if index:
            driver.switch_to.new_window("window")
        driver.get(url)
        for name in WATCHED:
            driver.execute_script("addWatch(arguments[0])", name)
    return driver


def run(seconds: float, pages: int | None) -> dict[str, Any]:
    """One run; ``pages`` None: without --ui."""
    modbus = free_port()
    command = [sys.executable, "-m", "vc.cli.main", "serve", "--machine", "turn_mill", "--modbus",
               f"127.0.0.1:{modbus}", "--realtime", "--duration", str(seconds), "--stats", "3600"]
    if pages is not None:
        command += ["--ui", "127.0.0.1:0"]
    server = subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, cwd=ROOT)
    plc = subprocess.Popen([sys.executable, "-m", "plc_stub", "--modbus", f"127.0.0.1:{modbus}"],
                           stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, cwd=ROOT)
    driver = None
    lines = []
    try:
        assert server.stdout is not None
        for line in server.stdout:
            lines.append(line.rstrip())
            if pages and line.startswith("operator panel: "):
                driver = open_pages(line.split()[2], pages)
            if line.startswith("real time: "):
                break
        server.wait(60)
    finally:
        if driver is not None:
            driver.quit()
        for process in (plc, server):
            if process.poll() is None:
                process.terminate()
                process.wait(10)
    found = next((FIGURES.search(line) for line in lines if FIGURES.search(line)), None)
    if found is None:
        raise SystemExit("vc serve printed no real-time figures:\n" + "\n".join(lines[-20:]))
    return {key: float(value) for key, value in found.groupdict().items()}


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seconds", type=float, default=30.0, help="simulated (= wall) seconds per run")
    arguments = parser.parse_args()
    figures = {}
    for label, pages in (("without --ui", None), ("--ui, no page", 0), ("--ui, 1 page", 1), ("--ui, 5 pages", 5)):
        result = run(arguments.seconds, pages)
        figures[label] = result
        print(f"{label:15s} {int(result['cycles'])} cycles: period error p99 {result['period_p99']:.3f} ms, max"
              f" {result['period_max']:.3f} ms; start error p99 {result['start_p99']:.3f} ms;"
              f" {int(result['overruns'])} overruns; NC at {result['share']:.1f} % of the schedule", flush=True)
    print(json.dumps(figures))
    return 0


if __name__ == "__main__":
    sys.exit(main())
