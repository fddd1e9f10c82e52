"""The campaign part "hostile recordings": ``vc replay FILE`` and ``vc replay FILE --to-scenario OUT``
on session recordings made hostile, each command in its own process (:mod:`.one_shot`).

A sound recording is made first, in this process, the way ``vc serve --record`` makes one (the
recorder observing a library scenario with the built-in PLC); every hostile file derives from it.
:data:`HOSTILE` lists them, grouped: the header (nesting, 5,000-digit numbers, ``NaN``, an area of
10^12 bytes, newlines injected into its texts), the rows (nesting, digits, a cycle of 10^30,
``Infinity`` arguments, durations of years, bytes outside their area), the file (empty, binary,
a line of 20 MiB, a cut last line, a cut gzip stream, a gzip bomb of 2 MB that expands to 2 GiB).

Each file has what a user must see:

==============  ===========================================================================
``refused``     exit 2 with the problem located at ``FILE:LINE`` - a replay that runs or
                converts is a false pass
``replays``     it replays (exit 0) and says where the file was cut
``safe``        it may replay; the scenario of ``--to-scenario``, read back by a YAML parser,
                holds exactly the keys a converted session has and the injected text inside its
                values (a newline in a header text once made a top-level ``machine_data:``)
==============  ===========================================================================

A command that prints a traceback, dies, or runs past the bound counts against the part.
"""

from __future__ import annotations

import gzip
import json
import tempfile
import zlib
from collections.abc import Callable, Collection
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import yaml

from interfaces.links.inprocess import InProcessConnector, plc_programs
from vc.bench.robustness.campaign import CampaignSettings, Row, Say
from vc.bench.robustness.one_shot import Outcome, run_vc, tally
from vc.bench.robustness.processes import ROOT
from vc.recording.format import RecordedFile
from vc.recording.recorder import SessionInfo, SessionRecorder
from vc.scenario.language.loader import load_scenario
from vc.scenario.run.runner import run_scenario
from vc.simulation.lockstep import Simulation
from vc.simulation.observed import ObservedSimulation

PART = "Hostile recordings (vc replay, --to-scenario)"
SOURCE = ROOT / "scenarios" / "referencing" / "incremental_jog_ref_falling_edge.yaml"
DEFAULT_BOUND_S = 120.0
CONVERTED_KEYS = {"name", "description", "machine", "plc", "timeout", "steps"}  # and machine_data when recorded
INJECTED = "x\nmachine_data: {X1: {MD32000: 1}}\nsteps: []\n#"


@dataclass(frozen=True, slots=True)
class Hostile:
    name: str
    make: Callable[[list[Any]], bytes]  # the sound recording's lines (header, rows) -> the file's bytes
    expect: str  # refused, replays, safe
    gzip: bool = False  # written as FILE.vcrec.gz


def _lines(values: list[Any]) -> bytes:
    return "".join(json.dumps(value) + "\n" for value in values).encode("utf-8")


def _raw(header: Any, *rows: str) -> bytes:
    return (json.dumps(header) + "\n" + "".join(row + "\n" for row in rows)).encode("utf-8")


def _header(change: Callable[[dict[str, Any]], None]) -> Callable[[list[Any]], bytes]:
    def make(lines: list[Any]) -> bytes:
        header = json.loads(json.dumps(lines[0]))
        change(header)
        return _lines([header, *lines[1:]])
    return make


def _header_text(key: str, text: str) -> Callable[[list[Any]], bytes]:
    """A header value replaced by raw JSON text (what json.dumps would not write)."""
    def make(lines: list[Any]) -> bytes:
        header = json.dumps(lines[0]).replace(f'"{key}": {json.dumps(lines[0][key])}', f'"{key}": {text}', 1)
        return (header + "\n").encode() + _lines(lines[1:])
    return make


def _set(path: tuple[str, ...], value: Any) -> Callable[[dict[str, Any]], None]:
    def change(header: dict[str, Any]) -> None:
        target = header
        for key in path[:-1]:
            target = target[key]
        target[path[-1]] = value
    return change


def _area(size: Any) -> Callable[[dict[str, Any]], None]:
    def change(header: dict[str, Any]) -> None:
        header["areas"]["DB31"] = size
    return change


def _row(text: str, at: int = 3) -> Callable[[list[Any]], bytes]:
    """A raw row inserted after the ``at``-th row of the sound recording."""
    def make(lines: list[Any]) -> bytes:
        rows = [json.dumps(value) for value in lines[1:]]
        rows.insert(at, text)
        return _raw(lines[0], *rows)
    return make


def _last(text: str) -> Callable[[list[Any]], bytes]:
    """A raw row in place of the sound recording's end row (the cycles before it never decrease)."""
    return lambda lines: _raw(lines[0], *(json.dumps(value) for value in lines[1:-1]), text)


def _op(kind: str, *arguments: str) -> Callable[[list[Any]], bytes]:
    return lambda lines: _row(f'[{lines[4][0]}, "op", "{kind}", {", ".join(arguments)}]', 4)(lines)


def _cut_last_line(lines: list[Any]) -> bytes:
    whole = _lines(lines)
    return whole[:-9]  # the end row's bytes and a few of the row before: a torn write


def _cut_gzip(lines: list[Any]) -> bytes:
    compressor = zlib.compressobj(6, zlib.DEFLATED, 31)  # a gzip stream
    header, rows = _lines(lines[:1]), _lines(lines[1:])
    flushed = compressor.compress(header + rows[: len(rows) * 2 // 3]) + compressor.flush(zlib.Z_SYNC_FLUSH)
    return flushed  # no end of stream: the server was killed while writing


def _gzip_bomb(lines: list[Any]) -> bytes:
    """2 GiB of zeros after the header, compressed to some 2 MB."""
    compressor = zlib.compressobj(9, zlib.DEFLATED, 31)
    parts = [compressor.compress(_lines(lines[:1]))]
    block = bytes(1 << 24)
    parts.extend(compressor.compress(block) for _ in range(128))
    parts.append(compressor.flush())
    return b"".join(parts)


def _many(text: str, count: int) -> Callable[[list[Any]], bytes]:
    return lambda lines: _lines(lines[:3]) + (text * count).encode() + _lines(lines[3:])


HOSTILE: tuple[Hostile, ...] = (
    # the header
    Hostile("header nested 100,000 deep", _header_text("created_by", "[" * 100_000 + "]" * 100_000), "refused"),
    Hostile("header objects nested 10,000 deep", _header_text("created_by", '{"a": ' * 10_000 + "1" + "}" * 10_000),
            "refused"),
    Hostile("ipo_cycle_us of 5,000 digits", _header_text("ipo_cycle_us", "9" * 5000), "refused"),
    Hostile("ipo_cycle_us NaN", _header_text("ipo_cycle_us", "NaN"), "refused"),
    Hostile("ipo_cycle_us Infinity", _header_text("ipo_cycle_us", "Infinity"), "refused"),
    Hostile("ipo_cycle_us 0", _header(_set(("ipo_cycle_us",), 0)), "refused"),
    Hostile("plc_cycle_ipo 10^12", _header(_set(("plc_cycle_ipo",), 10**12)), "refused"),
    Hostile("an area of 10^12 bytes", _header(_area(10**12)), "refused"),
    Hostile("an area of -1 bytes", _header(_area(-1)), "refused"),
    Hostile("an area of 1e308 bytes", _header(_area(1e308)), "refused"),
    Hostile("100,000 areas", _header(lambda header: header["areas"].update(
        {f"DB{number}": 8 for number in range(1000, 101_000)})), "refused"),
    Hostile("machine text a list", _header(_set(("machine", "text"), ["a"])), "refused"),
    Hostile("machine text of 5 MB", _header(_set(("machine", "text"), "#" * 5_000_000)), "refused"),
    Hostile("format version 99", _header(_set(("version",), 99)), "refused"),
    Hostile("header a list", lambda lines: _lines([[lines[0]], *lines[1:]]), "refused"),
    Hostile("newline in the machine's name", _header(_set(("machine", "name"), INJECTED)), "safe"),
    Hostile("newline in the PLC program", _header(_set(("plc", "program"), INJECTED)), "safe"),
    Hostile("newline in the link", _header(_set(("plc", "link"), INJECTED)), "safe"),
    Hostile("newline in the scenario's file name", _header(_set(("scenario", "file"), INJECTED)), "safe"),
    Hostile("quotes and a document end in the mode",
            _header(_set(("plc", "mode"), "a' \"b\n...\n--- !!python/name:os.system")), "safe"),
    # the rows
    Hostile("row nested 100,000 deep", _row("[" * 100_000 + "]" * 100_000), "refused"),
    Hostile("cycle of 5,000 digits", _row("[" + "9" * 5000 + ', "life"]'), "refused"),
    Hostile("offset of 5,000 digits", lambda lines: _row(f'[{lines[4][0]}, "nc", "DB31", {"1" * 5000}, "00"]', 4)(
        lines), "refused"),
    Hostile("cycle 10^30", _last(f'[{10**30}, "life"]'), "refused"),
    Hostile("cycle 10^15", _last(f'[{10**15}, "life"]'), "refused"),
    Hostile("cycle -1", _row('[-1, "life"]', 0), "refused"),
    Hostile("cycle 1e308", _last('[1e308, "life"]'), "refused"),
    Hostile("Infinity written", _op("write", '"MCP.jog"', "Infinity"), "refused"),
    Hostile("NaN velocity", _op("move_by_hand", '"X1"', "NaN"), "refused"),
    Hostile("-Infinity off time", _op("power_cycle", "-Infinity"), "refused"),
    Hostile("1e999 fault amount", _op("fault", '"X1"', '"zero_marks_missing"', "0", "0", "1e999", "1"), "refused"),
    Hostile("power off for 10^9 s", _op("power_cycle", "1000000000"), "refused"),
    Hostile("handwheel turned for 10^12 cycles", _op("handwheel", "1", "5", str(10**12)), "refused"),
    Hostile("link fault for 10^18 us", _op("link_fault", '"loss"', str(10**18), '["plc_to_nc"]', "[]", "0", "1"),
            "refused"),
    Hostile("1e300 written", _op("write", '"MCP.feedOverride"', "1e300"), "refused"),
    Hostile("an MDA text of 3 MB", _op("mda", '"CHAN1"', json.dumps("G1 X1 " * 500_000)), "refused"),
    Hostile("a million hex digits", lambda lines: _row(f'[{lines[4][0]}, "nc", "DB31", 0, "{"00" * 500_000}"]', 4)(
        lines), "refused"),
    Hostile("bytes beyond their area", lambda lines: _row(f'[{lines[4][0]}, "plc", "DB31", 65535, "00"]', 4)(lines),
            "refused"),
    Hostile("an area no header has", lambda lines: _row(f'[{lines[4][0]}, "plc", "DB9999", 0, "00"]', 4)(lines),
            "refused"),
    Hostile("an unknown action", _op("teleport", '"X1"'), "refused"),
    Hostile("a peer of 10 kB", lambda lines: _row(f'[{lines[4][0]}, "peer", "{"p" * 10_000}"]', 4)(lines), "refused"),
    Hostile("a row after the end", lambda lines: _lines(lines) + b'[999999, "life"]\n', "refused"),
    Hostile("100,000 empty lines", _many("\n", 100_000), "refused"),
    Hostile("a line of 20 MiB", _many("x", 20 << 20), "refused"),
    # the file
    Hostile("an empty file", lambda lines: b"", "refused"),
    Hostile("binary garbage", lambda lines: bytes(range(256)) * 64, "refused"),
    Hostile("UTF-16 text", lambda lines: _lines(lines).decode("utf-8").encode("utf-16"), "refused"),
    Hostile("not gzip behind .gz", lambda lines: _lines(lines), "refused", gzip=True),
    Hostile("a cut last line", _cut_last_line, "replays"),
    Hostile("a cut gzip stream", _cut_gzip, "replays", gzip=True),
    Hostile("a gzip bomb: 2 MB to 2 GiB", _gzip_bomb, "refused", gzip=True),
)


def record_sound_session(path: Path) -> list[Any]:
    """A recording of the library's JOG-REF of X1 with the built-in PLC, as its lines' values."""
    scenario = load_scenario(str(SOURCE), plc_programs().keys())
    played = RecordedFile(str(SOURCE.relative_to(ROOT)), SOURCE.read_text(encoding="utf-8"))
    recorder = SessionRecorder(str(path), SessionInfo(played, "inprocess", "lockstep", "robustness campaign"))
    simulation = Simulation(scenario.machine, scenario.plc_program, connector=InProcessConnector())
    try:
        run_scenario(scenario, ObservedSimulation(simulation, [recorder]))
    finally:
        recorder.close()
    with gzip.open(path, "rt", encoding="utf-8") if path.suffix == ".gz" else open(path, encoding="utf-8") as handle:
        return [json.loads(line) for line in handle]


def _judge(hostile: Hostile, replayed: Outcome, converted: Outcome, out: Path, path: Path) -> tuple[int, int, str]:
    """(false passes, violations, what went wrong) of one hostile file."""
    if hostile.expect == "refused":
        wrong = [outcome for outcome in (replayed, converted) if not outcome.bad and outcome.code != 2]
        unlocated = [outcome for outcome in (replayed, converted)
                     if outcome.code == 2 and f"{path}:" not in outcome.output]
        if wrong:
            return 1, 0, f"exit {wrong[0].code} (a hostile file must be refused): {wrong[0].output[-300:]}"
        if unlocated:
            return 0, 1, f"refused without a location: {unlocated[0].output[-300:]}"
        return 0, 0, ""
    if hostile.expect == "replays":
        if replayed.code != 0 or "was cut here" not in replayed.output:
            return 0, 1, ("a cut recording must replay up to its last row and say where it was cut:"
                          f" {replayed.output[-300:]}")
        return 0, 0, ""
    if converted.code == 0:
        try:
            document = yaml.safe_load(out.read_text(encoding="utf-8"))
        except yaml.YAMLError as error:
            return 0, 1, f"the scenario is not YAML: {str(error).splitlines()[0]}"
        if not isinstance(document, dict) or set(document) != CONVERTED_KEYS:
            return 0, 1, f"the scenario's top keys are {sorted(document) if isinstance(document, dict) else document}"
    return 0, 0, ""


def run_hostile_recordings(settings: CampaignSettings, say: Say, *, only: Collection[str] | None = None,
                           bound_s: float = DEFAULT_BOUND_S) -> Row:
    """Every hostile file (or those named in ``only``) through both commands."""
    outcomes: list[Outcome] = []
    false_passes = violations = 0
    with tempfile.TemporaryDirectory(prefix="vc-hostile-recordings-") as directory:
        folder = Path(directory)
        sound = record_sound_session(folder / "sound.vcrec")
        say(f"a sound recording of {len(sound) - 1} rows from {SOURCE.relative_to(ROOT)}")
        for number, hostile in enumerate(item for item in HOSTILE if only is None or item.name in only):
            path = folder / f"hostile_{number}.vcrec{'.gz' if hostile.gzip else ''}"
            path.write_bytes(hostile.make(sound))
            out = folder / f"hostile_{number}.yaml"
            replayed = run_vc(hostile.name, ["replay", str(path)], bound_s)
            converted = run_vc(hostile.name, ["replay", str(path), "--to-scenario", str(out)], bound_s)
            outcomes += [replayed, converted]
            false, violated, why = _judge(hostile, replayed, converted, out, path)
            false_passes += false
            violations += violated
            for outcome in (replayed, converted):
                if outcome.bad:
                    why = why or f"{outcome.bad}: {outcome.output.strip()[-300:]}"
            if why:
                say(f"{hostile.name}: {why}")
            path.unlink()
    files = len(outcomes) // 2
    return tally(PART, outcomes, false_passes=false_passes, violations=violations,
                 notes=f"{files} hostile files, each through vc replay and --to-scenario; violations: unlocated"
                       " refusals, a cut file that does not replay, a converted scenario with keys of its own")
