"""``vc replay FILE [--machine M.yaml] [--to-scenario OUT.yaml [--name NAME]]`` and the recorder of
``vc serve --record FILE``.

Exit codes of ``vc replay``: 0 the NC behaves as recorded (or the scenario was written), 1 the NC's
behaviour differs (the first difference is printed), 2 the recording or the machine file has
problems (each ``file:line:column: message``) or the recording cannot become a scenario.
"""

from __future__ import annotations

from collections.abc import Callable
from importlib import metadata

from vc.recording.format import SIZE_LIMIT, RecordedFile, read_recording
from vc.recording.recorder import SessionInfo, SessionRecorder
from vc.recording.replay import replay
from vc.recording.to_scenario import ConversionError, to_scenario

EXIT_SAME = 0
EXIT_DIFFERENT = 1
EXIT_PROBLEMS = 2


def session_recorder(path: str, scenario: str | None, link: str, realtime: bool, limit_bytes: int,
                     say: Callable[[str], None] = print) -> SessionRecorder:
    """The recorder ``vc serve --record`` passes to the server as its observer; it stops at
    ``limit_bytes`` (``--record-limit``) and says so through ``say``."""
    played = None
    if scenario is not None:
        try:
            with open(scenario, encoding="utf-8") as handle:
                played = RecordedFile(scenario, handle.read())
        except (OSError, UnicodeDecodeError):
            played = None  # vc serve reports the scenario file's problem with its location
    with open(path, "w", encoding="utf-8"):
        pass  # a path that cannot be written fails now, before a PLC connects
    return SessionRecorder(path, SessionInfo(played, link, "free_running" if realtime else "lockstep",
                                             f"vc-harness {_version()}", limit_bytes), say)


def _version() -> str:
    try:
        return metadata.version("vc-harness")
    except metadata.PackageNotFoundError:
        return "(not installed)"


def replay_command(path: str, *, machine: str | None = None, to_scenario_path: str | None = None,
                   name: str | None = None, say: Callable[[str], None] = print,
                   complain: Callable[[str], None] = print) -> int:
    """Raises ``SourceError`` for a recording or machine file with problems (the CLI lists them)."""
    recording = read_recording(path)
    header = recording.header
    if recording.cut is not None:
        complain(f"{path}:{recording.cut.line}: the recording was cut here ({recording.cut.why}: the server was"
                 f" stopped while writing); it replays up to its last complete row, cycle {recording.last_cycle}")
    elif not recording.complete:
        complain(f"{path}: the recording has no end row (the session was cut short); it goes up to cycle"
                 f" {recording.last_cycle}")
    elif recording.end is not None and recording.end.reason == SIZE_LIMIT:
        complain(f"{path}: the recording stopped at its size limit at cycle {recording.last_cycle}; the session"
                 " went on")
    if to_scenario_path is not None:
        try:
            conversion = to_scenario(recording, to_scenario_path, name)
        except ConversionError as error:
            complain(f"vc replay --to-scenario: {error}")
            return EXIT_PROBLEMS
        if conversion.machine_file:
            with open(conversion.machine_file, "w", encoding="utf-8") as handle:
                handle.write(header.machine.text)
            say(f"{conversion.machine_file}: the recorded machine file")
        with open(to_scenario_path, "w", encoding="utf-8") as handle:
            handle.write(conversion.text)
        say(f"{to_scenario_path}: scenario with plc: none from {path}")
        for note in conversion.notes:
            complain(f"note: {note}")
        return EXIT_SAME
    result = replay(recording, machine)
    seconds = result.cycles * header.ipo_cycle_us / 1e6
    what = f"{path}: {header.mode} session of {recording.plc} on {result.machine.name}"
    if result.difference is None:
        say(f"{what}: no difference in {result.cycles} IPO cycles ({seconds:.3f} s)")
        return EXIT_SAME
    say(f"{what}: {result.difference}")
    for signal in result.difference.signals[1:]:
        say(f"  also {signal.name} ({signal.address}): recorded {signal.recorded}, replayed {signal.replayed}")
    return EXIT_DIFFERENT
