"""The session recording file (``vc serve --record FILE``), version 2: reading and writing.

A recording is text, one JSON value per line (JSON lines; ``FILE.gz`` is gzip-compressed).  The
first line is the header, an object::

    {"format": "vc-recording", "version": 2, "created_by": "vc-harness 0.1.0",
     "machine": {"name": "turn_mill", "file": "turn_mill", "text": "..."},
     "scenario": {"file": "...", "text": "..."} | null,
     "plc": {"program": "basic_machine", "link": "modbus", "mode": "lockstep"},
     "ipo_cycle_us": 2000, "plc_cycle_ipo": 5,
     "areas": {"DB10": 120, ..., "I": 20, "Q": 12}}

``machine.file`` is the machine as the session named it (a path, or the name of a packaged
machine), ``machine.text`` the machine file the session ran with, ``scenario.text`` the scenario
that played the operator (its ``machine_data`` overrides belong to the machine), ``plc.program``
the program the harness asked a PLC that follows it to run (``link`` ``inprocess``: the built-in
program that ran), ``areas`` the bytes of each data block instance and of the plant I/O (a
replay checks that the interface still has them).  Every further line is a row, an array whose
first two columns are the IPO cycle count at which it happened (the boundary after that cycle:
what the PLC wrote there, the NC takes in the next cycle) and the row's kind:

    [cycle, "plc", AREA, BYTE, "HEX"]   the PLC wrote these bytes (PLC-to-NC data, plant outputs Q)
    [cycle, "nc", AREA, BYTE, "HEX"]    the NC showed these bytes (NC-to-PLC data)
    [cycle, "life"]                     the PLC's sign of life did not change in this cycle's scan
    [cycle, "op", KIND, ARGUMENT...]    an action of the operator (vc.simulation.observed.ACTION_ARGUMENTS)
    [cycle, "peer", TEXT]               the PLC on the link from here on ("external PLC over modbus
                                        from 127.0.0.1"), written when it claims the session
    [cycle, "end"]                      the session ended here
    [cycle, "end", "size_limit"]        the recording stopped at its size limit; the session went on

``plc`` and ``nc`` rows carry only bytes that changed (after a power-on: all of them), ``HEX`` two
hex digits per byte from ``BYTE`` on.  The cycles never decrease; rows of one cycle are in the order
things happened.  Version 1 (no ``peer`` rows, no end reason) is read as well.

Reading is bounded (:mod:`vc.input_limits`, :mod:`vc.bounded_json`): every line is JSON within
the limits (finite numbers, whole numbers of at most 20 digits, nesting), a line holds at most
``MAX_RECORDING_LINE`` bytes, the whole at most ``MAX_RECORDING_BYTES`` decompressed, a cycle
lies within ``MAX_RECORDED_SECONDS``, an area has at most ``MAX_AREA_BYTES``, and every
argument of an operator's action has its type and range.  :func:`read_recording` checks the
whole file first without keeping its rows (a problem is reported before anything replays);
:meth:`Recording.rows` reads them again one at a time.  A file cut short - the server killed,
its last line torn or its compressed stream unfinished - is readable: it replays up to its last
complete row, and :attr:`Recording.cut` says where it was cut.
"""

from __future__ import annotations

import gzip
import json
import math
import time as wallclock
import zlib
from collections.abc import Callable, Iterator
from dataclasses import dataclass, field
from typing import IO, Any, BinaryIO, cast

from vc.bounded_json import JsonProblem, loads
from vc.input_limits import (
    MAX_AREA_BYTES,
    MAX_DURATION_S,
    MAX_FILE_BYTES,
    MAX_MAGNITUDE,
    MAX_RECORDED_SECONDS,
    MAX_RECORDING_BYTES,
    MAX_RECORDING_LINE,
)
from vc.located_yaml import Mark, Problem, SourceError
from vc.simulation.observed import ACTION_ARGUMENTS, ActionArgument, OperatorAction

FORMAT = "vc-recording"
VERSION = 2
VERSIONS = (1, 2)  # what this reader reads
PLC, NC, LIFE, OP, PEER, END = "plc", "nc", "life", "op", "peer", "end"
KINDS = (PLC, NC, LIFE, OP, PEER, END)
SIZE_LIMIT = "size_limit"  # the reason of an end row written at the size limit
INPROCESS = "inprocess"  # the link of a session whose PLC ran in the harness's process
MAX_NAME = 256  # characters of a name in a row (a signal, an axis, an area, a PLC's description)
MAX_AREAS = 256  # data blocks and I/O areas in a header
MAX_PROBLEMS = 100  # problems after which the check of a file stops (it is not a recording)


@dataclass(frozen=True, slots=True)
class RecordedFile:
    """A file the session used, kept whole: its path (or a packaged machine's name) then and its text."""

    file: str
    text: str


@dataclass(frozen=True, slots=True)
class Header:
    machine_name: str
    machine: RecordedFile
    scenario: RecordedFile | None
    program: str  # the PLC program a PLC that follows the harness was asked to run
    link: str  # modbus, s7, can; inprocess: the built-in program ran in the harness's process
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

    @property
    def last_possible_cycle(self) -> int:
        """The highest cycle a row may name: MAX_RECORDED_SECONDS at this IPO cycle."""
        return MAX_RECORDED_SECONDS * 1_000_000 // self.ipo_cycle_us


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
class Peer:
    """A ``peer`` row: the PLC that holds the session from this cycle on."""

    cycle: int
    peer: str


@dataclass(frozen=True, slots=True)
class Marker:
    """A ``life`` or ``end`` row (an end row may say why: ``SIZE_LIMIT``)."""

    cycle: int
    kind: str
    reason: str = ""


Row = Bytes | Action | Peer | Marker


@dataclass(frozen=True, slots=True)
class Cut:
    """Where a recording cut short ends: its first incomplete line."""

    line: int
    why: str  # "a torn last line", "the compressed stream ends early"


@dataclass(slots=True)
class Recording:
    """A checked recording: its header and what its rows hold; :meth:`rows` reads them."""

    path: str
    header: Header
    row_count: int = 0
    last_cycle: int = 0
    end: Marker | None = None
    peers: list[str] = field(default_factory=list)  # the PLCs that held the session, in order, each once
    stalls: int = 0  # life rows
    cut: Cut | None = None

    @property
    def complete(self) -> bool:
        return self.end is not None

    @property
    def plc(self) -> str:
        """What the PLC of the session was: the built-in program, or the external PLCs on the link."""
        header = self.header
        if header.link == INPROCESS:
            return f"the built-in program {header.program}"
        asked = f" (a PLC that follows the harness is asked for {header.program})" if header.program else ""
        if not self.peers:
            return f"an external PLC over {header.link} that never claimed the session{asked}"
        return f"{', then '.join(self.peers)}{asked}"

    def rows(self) -> Iterator[tuple[Row, Mark]]:
        """Every row with where it is, read again from the file (checked by :func:`read_recording`)."""
        problems: list[Problem] = []
        reader = _Rows(self.path, self.header, problems)
        for number, line in _Lines(self.path, problems).numbered(first=2):
            row = reader.read(number, line)
            if row is not None:
                yield row, Mark(self.path, number, 1)


def row_json(row: Row) -> list[Any]:
    if isinstance(row, Bytes):
        return [row.cycle, row.source, row.area, row.offset, row.data.hex()]
    if isinstance(row, Action):
        return [row.cycle, OP, row.action.kind, *row.action.arguments]
    if isinstance(row, Peer):
        return [row.cycle, PEER, row.peer]
    return [row.cycle, row.kind, row.reason] if row.reason else [row.cycle, row.kind]


# ---------------------------------------------------------------------------------- writing


class RecordingWriter:
    """Writes a recording as it happens.  Rows reach the file at least every ``flush_s`` seconds
    of the wall clock (a killed server loses no more), and at ``limit_bytes`` the recording ends
    with an end row of reason ``size_limit`` while the session goes on (``limited`` is then True)."""

    def __init__(self, path: str, header: Header, *, limit_bytes: int = MAX_RECORDING_BYTES, flush_s: float = 1.0,
                 clock: Callable[[], float] = wallclock.monotonic):
        self.path = path
        self.limit_bytes = limit_bytes
        self.flush_s = flush_s
        self.clock = clock
        self.written = 0
        self.limited = False
        self._file = _open_text(path, True)
        self._put(json.dumps(header.to_json(), separators=(",", ":"), ensure_ascii=False))
        self._file.flush()
        self._flushed = clock()

    @property
    def closed(self) -> bool:
        return self._file.closed

    def write(self, row: Row) -> None:
        if self._file.closed:
            return
        line = json.dumps(row_json(row), separators=(",", ":"), ensure_ascii=False)
        if self.written + len(line) + 64 > self.limit_bytes:  # room for the end row
            self.limited = True
            self._put(json.dumps(row_json(Marker(row.cycle, END, SIZE_LIMIT)), separators=(",", ":")))
            self._file.close()
            return
        self._put(line)
        self.flush_if_due()

    def flush_if_due(self) -> None:
        """Flush when ``flush_s`` has passed since the last flush (called after rows and every cycle)."""
        if not self._file.closed and self.clock() - self._flushed >= self.flush_s:
            self._file.flush()
            self._flushed = self.clock()

    def close(self, cycle: int) -> None:
        if self._file.closed:
            return
        self._put(json.dumps(row_json(Marker(cycle, END)), separators=(",", ":")))
        self._file.close()

    def _put(self, line: str) -> None:
        self._file.write(line + "\n")
        self.written += len(line.encode("utf-8")) + 1


def _open_binary(path: str) -> BinaryIO:
    if path.endswith(".gz"):
        return cast(BinaryIO, gzip.open(path, "rb"))
    return open(path, "rb")


def _open_text(path: str, writing: bool) -> IO[str]:
    if path.endswith(".gz"):
        return gzip.open(path, "wt", encoding="utf-8") if writing else gzip.open(path, "rt", encoding="utf-8")
    return open(path, "w" if writing else "r", encoding="utf-8")


# ---------------------------------------------------------------------------------- reading


def read_recording(path: str) -> Recording:
    """Read and check a recording; raises :class:`SourceError` listing every problem with its line.
    The rows are checked here and read again by :meth:`Recording.rows`."""
    problems: list[Problem] = []
    lines = _Lines(path, problems)
    numbered = lines.numbered(first=1)
    first = next(numbered, None)
    if first is None:
        if lines.cut is not None:
            problems.append(Problem(Mark(path, 1, 1), f"the recording ends inside its header ({lines.cut.why}):"
                                                      " nothing to replay"))
        elif not problems:
            problems.append(Problem(Mark(path, 1, 1), "the file is empty: not a recording of vc serve --record"))
        raise SourceError(problems)
    header = _Header(path, problems).read(first[1])
    if header is None:
        raise SourceError(problems)
    recording = Recording(path, header)
    reader = _Rows(path, header, problems)
    for number, line in numbered:
        if len(problems) >= MAX_PROBLEMS:
            problems.append(Problem(Mark(path, number, 1), f"more than {MAX_PROBLEMS} problems: the check stops here"))
            break
        row = reader.read(number, line, last=lines.last)
        if row is None:
            continue
        recording.row_count += 1
        recording.last_cycle = row.cycle
        if isinstance(row, Marker):
            recording.stalls += row.kind == LIFE
            if row.kind == END:
                recording.end = row
        elif isinstance(row, Peer) and row.peer not in recording.peers:
            recording.peers.append(row.peer)
    recording.cut = lines.cut or reader.cut
    if problems:
        raise SourceError(problems)
    return recording


class _Lines:
    """The lines of a recording, bounded: each at most MAX_RECORDING_LINE bytes, all together at
    most MAX_RECORDING_BYTES decompressed.  A last line without its newline and a compressed
    stream that ends early are a cut (the server was killed), not a problem."""

    def __init__(self, path: str, problems: list[Problem]):
        self.path = path
        self.problems = problems
        self.cut: Cut | None = None
        self.last = False  # the line handed out is the last one and has no newline (it may be torn)

    def add(self, line: int, message: str) -> None:
        self.problems.append(Problem(Mark(self.path, line, 1), message))

    def numbered(self, first: int) -> Iterator[tuple[int, str]]:
        try:
            handle = _open_binary(self.path)
        except OSError as error:
            self.add(1, f"cannot read the recording: {error.strerror or error}")
            return
        with handle:
            yield from self._read(handle, first)

    def _read(self, handle: BinaryIO, first: int) -> Iterator[tuple[int, str]]:
        total = 0
        number = 0
        while True:
            number += 1
            try:
                raw = handle.readline(MAX_RECORDING_LINE + 1)
            except EOFError:  # a gzip stream without its end: the server was killed while writing
                self.cut = Cut(number, "the compressed stream ends early")
                return
            except (OSError, zlib.error) as error:
                self.add(number, f"not a recording of vc serve --record ({error})")
                return
            if not raw:
                return
            if len(raw) > MAX_RECORDING_LINE:
                self.add(number, f"a line of more than {MAX_RECORDING_LINE >> 20} MiB")
                skipped, more = self._skip_rest_of_line(handle)
                total += len(raw) + skipped
                if not more or total > MAX_RECORDING_BYTES:
                    return
                continue
            total += len(raw)
            if total > MAX_RECORDING_BYTES:
                self.add(number, f"the recording holds more than {MAX_RECORDING_BYTES >> 20:,} MiB (decompressed),"
                                 " the most vc serve --record writes")
                return
            self.last = not raw.endswith(b"\n")
            try:
                text = raw.decode("utf-8")
            except UnicodeDecodeError as error:
                if self.last:
                    self.cut = Cut(number, "a torn last line")
                    return
                self.add(number, f"not UTF-8 text ({error.reason} at byte {error.start + 1})")
                continue
            if number >= first:
                yield number, text.rstrip("\r\n")

    @staticmethod
    def _skip_rest_of_line(handle: BinaryIO) -> tuple[int, bool]:
        """Read past the end of an over-long line (up to MAX_RECORDING_BYTES): the bytes skipped,
        and False at the end of the file."""
        skipped = 0
        while skipped <= MAX_RECORDING_BYTES:
            try:
                chunk = handle.readline(MAX_RECORDING_LINE)
            except (EOFError, OSError, zlib.error):
                return skipped, False
            if not chunk:
                return skipped, False
            skipped += len(chunk)
            if chunk.endswith(b"\n"):
                return skipped, True
        return skipped, False


def _parse(path: str, number: int, line: str, problems: list[Problem]) -> Any:
    try:
        return loads(line)
    except JsonProblem as error:
        problems.append(Problem(Mark(path, number, error.column), error.message))
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
        if document.get("version") not in VERSIONS:
            self.add(f"recording format version {json.dumps(document.get('version'))}: this vc reads versions"
                     f" {', '.join(str(version) for version in VERSIONS)}")
            return None
        machine = self.file(document.get("machine"), "machine", True)
        scenario = self.file(document.get("scenario"), "scenario", False)
        plc = document.get("plc")
        if not isinstance(plc, dict) or not all(_name(plc.get(key)) for key in ("program", "link", "mode")):
            self.add("header: plc must be {program, link, mode} (names)")
            plc = {}
        areas = self.areas(document.get("areas"))
        cycle_us, plc_cycle = document.get("ipo_cycle_us"), document.get("plc_cycle_ipo")
        for name, value, highest in (("ipo_cycle_us", cycle_us, 1_000_000), ("plc_cycle_ipo", plc_cycle, 1_000)):
            if not (_whole(value) and isinstance(value, int) and 0 < value <= highest):
                self.add(f"header: {name} must be a whole number from 1 to {highest:,}")
        machine_doc = document["machine"] if isinstance(document.get("machine"), dict) else {}
        if not self.ok or machine is None:
            return None
        assert isinstance(cycle_us, int) and isinstance(plc_cycle, int)
        return Header(str(machine_doc.get("name", ""))[:MAX_NAME], machine, scenario, plc["program"], plc["link"],
                      plc["mode"], cycle_us, plc_cycle, areas, str(document.get("created_by", ""))[:MAX_NAME])

    def areas(self, value: Any) -> dict[str, int]:
        if not isinstance(value, dict) or not 0 < len(value) <= MAX_AREAS or not all(
                _name(area) and _whole(size) and 0 < size <= MAX_AREA_BYTES for area, size in value.items()):
            self.add(f"header: areas must map each data block and I / Q (at most {MAX_AREAS}) to its size in bytes,"
                     f" 1 to {MAX_AREA_BYTES:,}")
            return {}
        return dict(value)

    def file(self, value: Any, what: str, required: bool) -> RecordedFile | None:
        if value is None and not required:
            return None
        if not isinstance(value, dict) or not _name(value.get("file"), 4096) \
                or not isinstance(value.get("text"), str) or len(value["text"]) > MAX_FILE_BYTES:
            self.add(f"header: {what} must be {{file, text}} (the {what} file the session used, at most"
                     f" {MAX_FILE_BYTES >> 20} MiB)")
            return None
        return RecordedFile(value["file"], value["text"])


# What each argument of an operator's action is, so that a replay gets nothing it cannot do in
# a bounded time: a name, a text (a program), a number, a time, a whole number, a list of names.
_NAME, _TEXT, _NUMBER, _SECONDS, _MICROSECONDS, _WHOLE, _NAMES, _VALUE = (
    "a name", "a text", "a number", "a time in seconds", "a time in microseconds", "a whole number",
    "a list of names", "a value")
_ARGUMENTS: dict[str, tuple[str, ...]] = {
    "write": (_NAME, _VALUE), "force": (_NAME, _VALUE), "release": (_NAME,), "mda": (_NAME, _TEXT),
    "program": (_NAME, _NAME, _TEXT), "power_cycle": (_SECONDS,),
    "fault": (_NAME, _NAME, _NUMBER, _NUMBER, _NUMBER, _WHOLE),
    "link_fault": (_NAME, _MICROSECONDS, _NAMES, _NAMES, _MICROSECONDS, _WHOLE),
    "clear_faults": (_NAME,), "acknowledge": (), "move_by_hand": (_NAME, _NUMBER),
    "handwheel": (_WHOLE, _WHOLE, _WHOLE),
}
assert _ARGUMENTS.keys() == ACTION_ARGUMENTS.keys()


def _argument(value: Any, kind: str) -> bool:
    if kind == _NAME:
        return _name(value)
    if kind == _TEXT:
        return isinstance(value, str) and len(value) <= MAX_FILE_BYTES
    if kind == _NAMES:
        return isinstance(value, list) and len(value) <= MAX_AREAS and all(_name(item) for item in value)
    if kind == _VALUE and isinstance(value, bool):
        return True
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        return False
    if kind == _SECONDS:
        return 0 <= value <= MAX_DURATION_S
    if kind == _MICROSECONDS:
        return _whole(value) and value <= MAX_DURATION_S * 1_000_000
    if kind == _WHOLE:
        return isinstance(value, int) and abs(value) <= 1_000_000_000
    return abs(value) <= MAX_MAGNITUDE


class _Rows:
    def __init__(self, path: str, header: Header, problems: list[Problem]):
        self.path = path
        self.header = header
        self.problems = problems
        self.cycle = 0
        self.ended = False
        self.last_cycle = header.last_possible_cycle
        self.cut: Cut | None = None

    def add(self, number: int, message: str) -> None:
        self.problems.append(Problem(Mark(self.path, number, 1), message))

    def read(self, number: int, line: str, last: bool = False) -> Row | None:
        """The row of line ``number``; None for an empty line or one with problems (reported).
        ``last``: the line is the file's last and has no newline: if it is not a row, it is torn."""
        if not line.strip():
            self.add(number, "an empty line: a recording has none")
            return None
        found: list[Problem] = []
        value = _parse(self.path, number, line, found)
        if value is None:
            if last:
                self.cut = Cut(number, "a torn last line")
            else:
                self.problems.extend(found)
            return None
        return self.row(number, value, line)

    def row(self, number: int, value: Any, line: str) -> Row | None:
        if not (isinstance(value, list) and len(value) >= 2 and _whole(value[0]) and value[1] in KINDS):
            self.add(number, f"a row is [cycle, kind, ...] with kind one of {', '.join(KINDS)}, not {line[:60]}")
            return None
        cycle, kind, rest = value[0], value[1], value[2:]
        if self.ended:
            self.add(number, "a row after the end row")
            return None
        if cycle > self.last_cycle:
            self.add(number, f"cycle {cycle} lies beyond {MAX_RECORDED_SECONDS // 86_400} days of IPO cycles"
                             f" ({self.last_cycle:,} at {self.header.ipo_cycle_us} us), the longest recording")
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
        if kind == PEER:
            if len(rest) != 1 or not _name(rest[0]):
                self.add(number, f"a peer row is [cycle, \"peer\", \"the PLC on the link\"] (at most {MAX_NAME}"
                                 " characters)")
                return None
            return Peer(cycle, rest[0])
        if kind == END and rest:
            if rest != [SIZE_LIMIT]:
                self.add(number, f"an end row is [cycle, \"end\"] or [cycle, \"end\", \"{SIZE_LIMIT}\"]")
                return None
            self.ended = True
            return Marker(cycle, END, SIZE_LIMIT)
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
            self.add(number, f"area {area[:MAX_NAME]} is not one of the header's areas"
                             f" ({', '.join(self.header.areas)})")
            return None
        if offset >= size or len(text) > 2 * (size - offset):
            self.add(number, f"bytes {offset}..{offset + len(text) // 2 - 1} lie outside {area} (0..{size - 1})")
            return None
        try:
            data = bytes.fromhex(text)
        except ValueError:
            self.add(number, f"'{text[:20]}' is not hex (two digits per byte)")
            return None
        if not data:
            self.add(number, f"a {kind} row holds at least one byte")
            return None
        return Bytes(cycle, kind, area, offset, data)

    def action(self, number: int, cycle: int, rest: list[Any]) -> Action | None:
        if not rest or rest[0] not in ACTION_ARGUMENTS:
            self.add(number, f"an op row is [cycle, \"op\", kind, ...] with kind one of {', '.join(ACTION_ARGUMENTS)}")
            return None
        kind, arguments = rest[0], rest[1:]
        names, kinds = ACTION_ARGUMENTS[kind], _ARGUMENTS[kind]
        if len(arguments) != len(names):
            self.add(number, f"an op row {kind} has the arguments {', '.join(names) or 'none'}")
            return None
        for name, argument_kind, argument in zip(names, kinds, arguments, strict=True):
            if not _argument(argument, argument_kind):
                shown = json.dumps(argument)
                self.add(number, f"an op row {kind}: {name} must be {argument_kind}"
                                 f"{_RANGES.get(argument_kind, '')}, not {shown[:40]}")
                return None
        checked: tuple[ActionArgument, ...] = tuple(arguments)
        if kind == "handwheel" and not 0 <= int(arguments[2]) <= self.last_cycle - cycle:
            self.add(number, "an op row handwheel: its cycles run beyond the longest recording")
            return None
        return Action(cycle, OperatorAction(kind, checked))


_RANGES = {
    _NAME: f" of at most {MAX_NAME} characters", _TEXT: f" of at most {MAX_FILE_BYTES >> 20} MiB",
    _NUMBER: f" (finite, at most {MAX_MAGNITUDE:g})", _VALUE: f" (finite, at most {MAX_MAGNITUDE:g})",
    _SECONDS: f" from 0 to {MAX_DURATION_S:,}", _MICROSECONDS: f" from 0 to {MAX_DURATION_S * 1_000_000:,}",
    _WHOLE: " (at most 10^9)", _NAMES: f" (at most {MAX_AREAS})",
}


def _whole(value: Any) -> bool:
    return isinstance(value, int) and not isinstance(value, bool) and value >= 0


def _name(value: Any, longest: int = MAX_NAME) -> bool:
    return isinstance(value, str) and len(value) <= longest
