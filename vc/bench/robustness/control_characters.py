"""The control-character part: scenario names and file names with control characters through ``vc run``.

A scenario's name, a varied value and a file's name are written by whoever wrote the files.  This
part writes scenarios whose names hold what a terminal, an XML or an HTML reader acts on: an
escape sequence that erases the line and writes PASS over a FAIL (``\\x1b[2K\\x1b[1GPASS``), a
carriage return, a line break, NUL, BEL, DEL, the C1 CSI, a terminal title sequence, vertical tab
and form feed, a right-to-left override, a line separator, a varied value with an escape sequence,
and a scenario file whose own name holds one.  Half of them fail.  It runs them as a user would,
``python -m vc.cli.main run DIR --junit --trace-dir --report`` in a process of its own, and counts
as *findings*:

* a line of the console output (standard output and error) that holds a control character other
  than the line break;
* a JUnit file that is not well-formed XML, and each of its lines that holds a control character;
* a CSV trace, a VCD trace, a GTKWave save file that holds one (other than its line ends);
* a line of the HTML report that holds one, or a report that was not written.

``\\t`` counts as a control character everywhere except in the JUnit file's indentation, which
ElementTree writes with spaces anyway.  The run must end with exit code 1 (some scenarios fail)
and without a traceback; a run that takes more than its bound is a hang.
"""

from __future__ import annotations

import re
import subprocess
import sys
import tempfile
import xml.etree.ElementTree as ElementTree
from pathlib import Path

from vc.bench.robustness.campaign import CampaignSettings, Row, Say

BOUND_S = 600.0  # wall seconds the run may take
# what a terminal, an XML or HTML reader acts on: C0 but the line break, DEL, C1, separators, bidi controls
CONTROL = re.compile("[\x00-\x09\x0b-\x1f\x7f-\x9f\u2028\u2029\u202a-\u202e\u2066-\u2069]")
# YAML double-quoted escapes: the file stays plain text, the name holds the character
HOSTILE_NAMES = (
    r"a\e[2K\e[1GPASS\e[8m",  # erase the line, back to its start, write PASS, hide the rest
    r"b\rPASS  written over",
    r"c\nPASS  a line of its own",
    r"d\0nul \a bell \b back",
    r"e\x9b2K the C1 CSI",
    r"f\u202e right to left",
    r"g\u2028 a line separator",
    r"h\x7f del \e]0;a title\a",
    r"i\t tab \v vertical tab \f form feed",
    r"j\e[31m red \e[0m",
)
SCENARIO = """name: "{name}"
machine: turn_mill
plc: basic_machine
steps:
  - wait: 20ms
  - expect: {{X1.position: {position}}}
"""
VARIED = """name: "k ${tag}"
description: "tagged ${tag}"
machine: turn_mill
plc: basic_machine
vary:
  tag: ["\\e[2K\\e[1GPASS", "\\a\\r"]
steps:
  - wait: 20ms
"""
FILE_NAME = "l\x1b[2K\x1b[1G.yaml"  # a file whose own name holds an escape sequence


def write_scenarios(directory: Path) -> int:
    """The hostile scenarios in ``directory``; how many scenarios (variants counted) they make."""
    directory.mkdir(parents=True, exist_ok=True)
    for number, name in enumerate(HOSTILE_NAMES):
        position = 0 if number % 2 else 5  # every other one fails
        (directory / f"s{number:02d}.yaml").write_text(SCENARIO.format(name=name, position=position))
    (directory / "varied.yaml").write_text(VARIED)
    (directory / FILE_NAME).write_text(SCENARIO.format(name="l", position=5))
    return len(HOSTILE_NAMES) + 2 + 1


def _lines_with_control(text: str) -> int:
    return sum(1 for line in text.split("\n") if CONTROL.search(line))


def findings(out: Path, console: str) -> dict[str, int]:
    """The findings per output of a run that wrote into ``out`` and printed ``console``."""
    found = {"terminal": _lines_with_control(console)}
    junit = out / "junit.xml"
    text = junit.read_text(encoding="utf-8", errors="replace") if junit.exists() else ""
    try:
        ElementTree.fromstring(text.encode())
        well_formed = 0
    except ElementTree.ParseError:
        well_formed = 1
    found["JUnit"] = well_formed + _lines_with_control(text)
    for kind, suffix in (("CSV", ".csv"), ("VCD", ".vcd"), ("GTKWave", ".gtkw")):
        files = sorted((out / "traces").glob(f"*{suffix}"))
        found[kind] = sum(1 for path in files
                          if CONTROL.search(path.read_text(encoding="utf-8", errors="replace").replace("\r\n", "\n")))
        found[kind] += 0 if files else 1  # no traces written at all
    page = out / "report" / "index.html"
    found["HTML"] = _lines_with_control(page.read_text(encoding="utf-8", errors="replace")) if page.exists() else 1
    return found


def run_control_characters(settings: CampaignSettings, say: Say) -> Row:
    """The part's row (module docstring); ``settings`` asks nothing of it: the names are fixed."""
    row = Row("Control characters in names (vc run: terminal, JUnit, CSV, VCD, GTKWave, HTML)", false_passes=None)
    with tempfile.TemporaryDirectory(prefix="vc-control-") as directory:
        root = Path(directory)
        row.inputs = write_scenarios(root / "scenarios")
        out = root / "out"
        command = [sys.executable, "-m", "vc.cli.main", "run", "scenarios", "-j", "1",
                   "--junit", str(out / "junit.xml"), "--trace-dir", str(out / "traces"),
                   "--report", str(out / "report")]
        try:
            done = subprocess.run(command, cwd=root, capture_output=True, timeout=BOUND_S, check=False)
        except subprocess.TimeoutExpired:
            row.hangs = 1
            row.notes = f"vc run took longer than {BOUND_S:g} s"
            return row
        console = (done.stdout + done.stderr).decode("utf-8", errors="replace")
        row.tracebacks = console.count("Traceback (most recent call last)")
        row.crashes = int(done.returncode != 1)  # some scenarios fail, none has a problem
        found = findings(out, console)
    row.violations = sum(found.values())
    row.notes = "findings: " + ", ".join(f"{kind} {count}" for kind, count in found.items()) + \
                f"; exit code {done.returncode}"
    say(f"  control characters: {row.inputs} scenarios, {row.notes}")
    return row
