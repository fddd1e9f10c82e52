"""Recording from the operator page: the session recording of ``vc serve --record FILE`` ended from
the page, and turned into a scenario (the code behind ``vc replay --to-scenario``) for download.

A recording begins at a power-on, so that its replay and its scenario start from the state it
recorded; ``vc serve --record FILE`` records from the start, and the page can end it at any time
(the file gets its end row, as when the server stops).  Starting one in the middle of a session is
refused with that reason.  The conversion runs in the web server's thread (the file is closed by
then), never in the NC's.
"""

from __future__ import annotations

import os
import re
from dataclasses import dataclass
from typing import Any

from interfaces.errors import VcError
from vc.recording.format import read_recording
from vc.recording.recorder import SessionRecorder
from vc.recording.to_scenario import to_scenario
from vc.simulation.observed import SimulationObserver

NO_RECORDING = ("vc serve was started without --record FILE: restart it with --record FILE (and --ui) to record"
                " the session from its start")
STARTS_AT_POWER_ON = ("a recording begins at a power-on, so that its replay and its scenario start from the state"
                      " it recorded: vc serve --record FILE records from the start, the page ends it")


@dataclass(slots=True)
class Downloaded:
    """A file the page offers: its name and text, or why there is none."""

    name: str = ""
    text: str = ""
    refusal: str = ""


class PageRecording:
    """The session recording as the page sees it; ``recorder`` is ``--record``'s (or None)."""

    def __init__(self, recorder: SimulationObserver | None):
        self.recorder = recorder if isinstance(recorder, SessionRecorder) else None
        self.ended = False  # ended from the page

    def state(self) -> dict[str, Any]:
        recorder = self.recorder
        if recorder is None:
            return {"state": "none", "path": "", "note": NO_RECORDING}
        writer = recorder.writer
        if self.ended:
            state = "ended"
        elif writer is not None and writer.limited:
            state = "size limit"
        else:
            state = "recording"
        return {"state": state, "path": recorder.path, "cycle": recorder.cycle, "note": ""}

    def command(self, action: str) -> str:
        """In the NC thread: ``stop`` ends the recording, ``start`` is refused (see the module docstring)."""
        recorder = self.recorder
        if recorder is None:
            return f"refused: {NO_RECORDING}"
        if action == "start":
            return f"refused: {STARTS_AT_POWER_ON}" + (" (this one has ended)" if self.ended else " (it is running)")
        if action != "stop":
            return f"refused: record takes start or stop, not {action!r}"
        if self.ended:
            return f"refused: the recording {recorder.path} has ended already"
        recorder.close()
        self.ended = True
        return f"recording {recorder.path} ended at cycle {recorder.cycle}: its scenario can be downloaded"

    def scenario(self) -> Downloaded:
        """In the web server's thread: the ended recording as a scenario file (``plc: none``)."""
        recorder = self.recorder
        if recorder is None:
            return Downloaded(refusal=NO_RECORDING)
        if not self.ended:
            return Downloaded(refusal="the recording is still running: end it on the page first")
        stem = os.path.splitext(os.path.basename(recorder.path))[0]
        stem = re.sub(r"[^A-Za-z0-9_.-]", "_", stem) or "recording"  # a file name a browser takes as it is
        out = os.path.join(os.path.dirname(os.path.abspath(recorder.path)), f"{stem}.yaml")
        try:
            conversion = to_scenario(read_recording(recorder.path), out)
        except (VcError, OSError, ValueError) as error:  # ConversionError, the machine's SourceError
            return Downloaded(refusal=f"{recorder.path}: {error}")
        if conversion.machine_file:
            return Downloaded(refusal=f"{recorder.path} was recorded on a machine file that is no packaged machine:"
                                      f" vc replay {recorder.path} --to-scenario {out} writes the scenario and the"
                                      " machine file beside it")
        notes = "".join(f"# note: {' '.join(note.splitlines())}\n" for note in conversion.notes)
        return Downloaded(f"{stem}.yaml", notes + conversion.text)
