"""The session recording file (``vc serve --record FILE``), version 1: reading and writing.

A recording is text, one JSON value per line (JSON lines; ``FILE.gz`` is gzip-compressed).  The
first line is the header, an object::

    {"format": "vc-recording", "version": 1, "created_by": "vc-harness 0.1.0",
     "machine": {"name": "turn_mill", "file": "scenarios/machines/turn_mill.yaml", "text": "..."},
     "scenario": {"file": "...", "text": "..."} | null,
     "plc": {"program": "basic_machine", "link": "modbus", "mode": "lockstep"},
     "ipo_cycle_us": 2000, "plc_cycle_ipo": 5,
     "areas": {"DB10": 120, ..., "I": 20, "Q": 12}}

``machine.text`` is the machine file the session ran with, ``scenario.text`` the scenario that
played the operator (its ``machine_data`` overrides belong to the machine), ``areas`` the bytes of
each data block instance and of the plant I/O (a replay checks that the interface still has them).
Every further line is a row, an array whose first two columns are the IPO cycle count at which it
happened (the boundary after that cycle: what the PLC wrote there, the NC takes in the next cycle)
and the row's kind:

    [cycle, "plc", AREA, BYTE, "HEX"]   the PLC wrote these bytes (PLC-to-NC data, plant outputs Q)
    [cycle, "nc", AREA, BYTE, "HEX"]    the NC showed these bytes (NC-to-PLC data)
    [cycle, "life"]                     the PLC's sign of life did not change in this cycle's scan
    [cycle, "op", KIND, ARGUMENT...]    an action of the operator (vc.simulation.observed.ACTION_ARGUMENTS)
    [cycle, "end"]                      the session ended here

``plc`` and ``nc`` rows carry only bytes that changed (after a power-on: all of them), ``HEX`` two
hex digits per byte from ``BYTE`` on.  The cycles never decrease; rows of one cycle are in the order
things happened.  A file without its ``end`` row was cut short (the server was killed): it is
readable, and replays up to its last row.
"""

from __future__ import annotations

import gzip
import json
from collections.abc import Iterator
from dataclasses import dataclass, field
from typing import IO, Any

from vc.located_yaml import Mark, Problem, SourceError
from vc.simulation.observed import ACTION_ARGUMENTS, ActionArgument, OperatorAction

FORMAT = "vc-recording"
VERSION = 1
PLC, NC, LIFE, OP, END = "plc", "nc", "life", "op", "end"
KINDS = (PLC, NC, LIFE, OP, END)


@dataclass(frozen=True, slots=True)
class RecordedFile:
    """A file the session used, kept whole: its path then and its text."""

    file: str
    text: str


@dataclass(frozen=True, slots=True)
class Header:
    machine_name: str
    machine: RecordedFile
    scenario: RecordedFile | None
    program: str  # the PLC program a PLC that follows the harness was asked to run
    link: str  # modbus, s7, can
    mode: str  # lockstep, free_running
    ipo_cycle_us: int
    plc_cycle_ipo: int
    areas: dict[str, int]
    created_by: str = ""

    def to_json(self) -> dict[str, Any]:
        return {
            "format": FORMAT, "version": VERSION, "created_by": self.created_by,
            "machine": {"name": self.machine_name, "file": self.machine.file, "text": self.machine.text},
            "scenario": None if self.scenario is None else {"file": self.scenario.file, "text": self.scenario.text},
            "plc": {"program": self.program, "link": self.link, "mode": self.mode},
            "ipo_cycle_us": self.ipo_cycle_us, "plc_cycle_ipo": self.plc_cycle_ipo, "areas": self.areas,
        }


@dataclass(frozen=True, slots=True)
class Bytes:
    """A ``plc`` or ``nc`` row: ``data`` from byte ``offset`` of ``area``."""

    cycle: int
    source: str  # PLC or NC
    area: str
    offset: int
    data: bytes


@dataclass(frozen=True, slots=True)
class Action:
    cycle: int
    action: OperatorAction


@dataclass(frozen=True, slots=True)
class Marker:
    """A ``life`` or ``end`` row."""

    cycle: int
    kind: str


Row = Bytes | Action | Marker


@dataclass(slots=True)
class Recording:
    path: str
    header: Header
    rows: list[Row] = field(default_factory=list)
    row_marks: list[Mark] = field(default_factory=list)  # where each row is (file:line:1)

    @property
    def complete(self) -> bool:
        return bool(self.rows) and isinstance(self.rows[-1], Marker) and self.rows[-1].kind == END

    @property
    def last_cycle(self) -> int:
        return self.rows[-1].cycle if self.rows else 0

    def stalls(self) -> set[int]:
        """The cycles whose PLC scan left the sign of life unchanged."""
        return {row.cycle for row in self.rows if isinstance(row, Marker) and row.kind == LIFE}


def row_json(row: Row) -> list[Any]:
    if isinstance(row, Bytes):
        return [row.cycle, row.source, row.area, row.offset, row.data.hex()]
    if isinstance(row, Action):
        return [row.cycle, OP, row.action.kind, *row.action.arguments]
    return [row.cycle, row.kind]


def _open_text(path: str, writing: bool) -> IO[str]:
    if path.endswith(".gz"):
        return gzip.open(path, "wt", encoding="utf-8") if writing else gzip.open(path, "rt", encoding="utf-8")
    return open(path, "w" if writing else "r", encoding="utf-8")


class RecordingWriter:
    """Writes a recording as it happens; rows reach the file at least every ``FLUSH_ROWS`` rows."""

    FLUSH_ROWS = 200

    def __init__(self, path: str, header: Header):
        self.path = path
        self._file = _open_text(path, True)
        self._file.write(json.dumps(header.to_json(), separators=(",", ":")) + "\n")
        self._unflushed = 0

    def write(self, row: Row) -> None:
        self._file.write(json.dumps(row_json(row), separators=(",", ":")) + "\n")
        self._unflushed += 1
        if self._unflushed >= self.FLUSH_ROWS:
            self._file.flush()
            self._unflushed = 0

    def close(self, cycle: int) -> None:
        if self._file.closed:
            return
        self.write(Marker(cycle, END))
        self._file.close()


# ---------------------------------------------------------------------------------- reading


def read_recording(path: str) -> Recording:
    """Read and check a recording; raises :class:`SourceError` listing every problem with its line."""
    problems: list[Problem] = []
    try:
        with _open_text(path, False) as handle:
            lines = list(_lines(handle))
    except OSError as error:
        message = error.strerror or str(error)
        raise SourceError([Problem(Mark(path, 1, 1), f"cannot read the recording: {message}")]) from None
    except (UnicodeDecodeError, EOFError) as error:
        raise SourceError([Problem(Mark(path, 1, 1), f"not a recording of vc serve --record ({error})")]) from None
    if not lines:
        raise SourceError([Problem(Mark(path, 1, 1), "the file is empty: not a recording of vc serve --record")])
    header = _Header(path, problems).read(lines[0])
    if header is None:
        raise SourceError(problems)
    recording = Recording(path, header)
    reader = _Rows(path, header, problems)
    for number, line in enumerate(lines[1:], start=2):
        row = reader.read(number, line)
        if row is not None:
            recording.rows.append(row)
            recording.row_marks.append(Mark(path, number, 1))
    if problems:
        raise SourceError(problems)
    return recording


def _lines(handle: IO[str]) -> Iterator[str]:
    for line in handle:
        yield line.rstrip("\n")


def _parse(path: str, number: int, line: str, problems: list[Problem]) -> Any:
    try:
        return json.loads(line)
    except json.JSONDecodeError as error:
        problems.append(Problem(Mark(path, number, error.colno), f"not JSON: {error.msg}"))
        return None


class _Header:
    def __init__(self, path: str, problems: list[Problem]):
        self.path = path
        self.problems = problems
        self.ok = True

    def add(self, message: str, column: int = 1) -> None:
        self.problems.append(Problem(Mark(self.path, 1, column), message))
        self.ok = False

    def read(self, line: str) -> Header | None:
        document = _parse(self.path, 1, line, self.problems)
        if not isinstance(document, dict) or document.get("format") != FORMAT:
            if document is not None:
                self.add(f"not a recording of vc serve --record (the first line must be its header, with"
                         f" \"format\": \"{FORMAT}\")")
            return None
        if document.get("version") != VERSION:
            self.add(f"recording format version {json.dumps(document.get('version'))}: this vc reads version"
                     f" {VERSION}")
            return None
        machine = self.file(document.get("machine"), "machine", True)
        scenario = self.file(document.get("scenario"), "scenario", False)
        plc = document.get("plc")
        if not isinstance(plc, dict) or not all(isinstance(plc.get(key), str) for key in ("program", "link", "mode")):
            self.add("header: plc must be {program, link, mode} (names)")
            plc = {}
        areas = document.get("areas")
        if not isinstance(areas, dict) or not all(isinstance(size, int) and size > 0 for size in areas.values()):
            self.add("header: areas must map each data block and I / Q to its size in bytes")
            areas = {}
        cycle_us, plc_cycle = document.get("ipo_cycle_us"), document.get("plc_cycle_ipo")
        for name, value in (("ipo_cycle_us", cycle_us), ("plc_cycle_ipo", plc_cycle)):
            if not isinstance(value, int) or value <= 0:
                self.add(f"header: {name} must be a whole number above 0")
        machine_doc = document["machine"] if isinstance(document.get("machine"), dict) else {}
        if not self.ok or machine is None:
            return None
        assert isinstance(cycle_us, int) and isinstance(plc_cycle, int)
        return Header(str(machine_doc.get("name", "")), machine, scenario, plc["program"], plc["link"], plc["mode"],
                      cycle_us, plc_cycle, dict(areas), str(document.get("created_by", "")))

    def file(self, value: Any, what: str, required: bool) -> RecordedFile | None:
        if value is None and not required:
            return None
        if not isinstance(value, dict) or not isinstance(value.get("file"), str) \
                or not isinstance(value.get("text"), str):
            self.add(f"header: {what} must be {{file, text}} (the {what} file the session used)")
            return None
        return RecordedFile(value["file"], value["text"])


class _Rows:
    def __init__(self, path: str, header: Header, problems: list[Problem]):
        self.path = path
        self.header = header
        self.problems = problems
        self.cycle = 0
        self.ended = False

    def add(self, number: int, message: str) -> None:
        self.problems.append(Problem(Mark(self.path, number, 1), message))

    def read(self, number: int, line: str) -> Row | None:
        if not line.strip():
            return None
        value = _parse(self.path, number, line, self.problems)
        if value is None:
            return None
        if not (isinstance(value, list) and len(value) >= 2 and _whole(value[0]) and value[1] in KINDS):
            self.add(number, f"a row is [cycle, kind, ...] with kind one of {', '.join(KINDS)}, not {line[:60]}")
            return None
        cycle, kind, rest = value[0], value[1], value[2:]
        if self.ended:
            self.add(number, "a row after the end row")
            return None
        if cycle < self.cycle:
            self.add(number, f"cycle {cycle} comes after cycle {self.cycle}: the cycles of a recording never"
                             " decrease")
            return None
        self.cycle = cycle
        if kind in (PLC, NC):
            return self.bytes_row(number, cycle, kind, rest)
        if kind == OP:
            return self.action(number, cycle, rest)
        if rest:
            self.add(number, f"a {kind} row is [cycle, \"{kind}\"]")
            return None
        self.ended = kind == END
        return Marker(cycle, kind)

    def bytes_row(self, number: int, cycle: int, kind: str, rest: list[Any]) -> Bytes | None:
        if len(rest) != 3 or not isinstance(rest[0], str) or not _whole(rest[1]) or not isinstance(rest[2], str):
            self.add(number, f"a {kind} row is [cycle, \"{kind}\", area, byte, hex]")
            return None
        area, offset, text = rest
        size = self.header.areas.get(area)
        if size is None:
            self.add(number, f"area {area} is not one of the header's areas ({', '.join(self.header.areas)})")
            return None
        try:
            data = bytes.fromhex(text)
        except ValueError:
            self.add(number, f"'{text[:20]}' is not hex (two digits per byte)")
            return None
        if not data or offset + len(data) > size:
            self.add(number, f"bytes {offset}..{offset + len(data) - 1} lie outside {area} (0..{size - 1})")
            return None
        return Bytes(cycle, kind, area, offset, data)

    def action(self, number: int, cycle: int, rest: list[Any]) -> Action | None:
        if not rest or rest[0] not in ACTION_ARGUMENTS:
            self.add(number, f"an op row is [cycle, \"op\", kind, ...] with kind one of {', '.join(ACTION_ARGUMENTS)}")
            return None
        kind, arguments = rest[0], rest[1:]
        names = ACTION_ARGUMENTS[kind]
        if len(arguments) != len(names) or not all(_argument(item) for item in arguments):
            self.add(number, f"an op row {kind} has the arguments {', '.join(names) or 'none'}")
            return None
        checked: tuple[ActionArgument, ...] = tuple(arguments)
        return Action(cycle, OperatorAction(kind, checked))


def _whole(value: Any) -> bool:
    return isinstance(value, int) and not isinstance(value, bool) and value >= 0


def _argument(value: Any) -> bool:
    if isinstance(value, list):
        return all(isinstance(item, str) for item in value)
    return isinstance(value, (str, int, float)) and not isinstance(value, bool)
