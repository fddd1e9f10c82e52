"""Recording from the page (vc/ui/recording.py) on an in-process machine: the page ends the session
recording, gets its scenario, and the scenario passes; without --record, and for a start in the
middle of a session, the page is told why not."""

from __future__ import annotations

from pathlib import Path
from typing import Any

from interfaces.links.inprocess import plc_programs
from vc.config.loader import load_machine
from vc.config.machine_files import machine_file
from vc.recording.format import RecordedFile
from vc.recording.recorder import SessionInfo, SessionRecorder
from vc.scenario.language.loader import load_scenario
from vc.scenario.run.runner import run_scenario
from vc.simulation.lockstep import Simulation
from vc.ui.bridge import Command, OperatorBridge
from vc.ui.recording import NO_RECORDING, STARTS_AT_POWER_ON


def served(recorder: SessionRecorder | None) -> tuple[Simulation, OperatorBridge]:
    path = machine_file("turn_mill")
    assert path is not None
    simulation = Simulation(load_machine(path))
    bridge = OperatorBridge(recorder=recorder, update_period_s=0.0)
    bridge.attached(simulation)
    return simulation, bridge


def ask(simulation: Simulation, bridge: OperatorBridge, kind: str, **arguments: Any) -> tuple[bool, str]:
    answers: list[tuple[bool, str]] = []
    bridge.commands.append(Command(kind, 1, "127.0.0.1", arguments, lambda done, text: answers.append((done, text))))
    simulation.step(1)
    bridge.cycle_done(simulation)
    (answer,) = answers
    return answer


def test_the_page_ends_the_recording_and_its_scenario_passes(tmp_path: Path) -> None:
    record = tmp_path / "session.jsonl"
    recorder = SessionRecorder(str(record), SessionInfo(None, "inprocess", "lockstep", "test"))
    simulation, bridge = served(recorder)
    assert bridge.recording.state()["state"] == "recording"
    assert bridge.recording.scenario().refusal.startswith("the recording is still running")
    assert ask(simulation, bridge, "key", name="MCP.jog", value=1)[0]
    for _ in range(50):
        simulation.step(1)
        bridge.cycle_done(simulation)
    assert ask(simulation, bridge, "key", name="MCP.jog", value=0)[0]
    for _ in range(200):
        simulation.step(1)
        bridge.cycle_done(simulation)
    done, message = ask(simulation, bridge, "record", action="stop")
    assert done and message.startswith(f"recording {record} ended at cycle")
    assert bridge.recording.state()["state"] == "ended"
    cycle = recorder.cycle
    for _ in range(20):  # the session goes on, the recording does not
        simulation.step(1)
        bridge.cycle_done(simulation)
    assert recorder.cycle == cycle
    assert ask(simulation, bridge, "record", action="stop") == (False, f"the recording {record} has ended already")

    download = bridge.recording.scenario()
    assert download.refusal == "" and download.name == "session.yaml"
    scenario_file = tmp_path / download.name
    scenario_file.write_text(download.text, encoding="utf-8")
    scenario = load_scenario(str(scenario_file), plc_programs().keys())
    assert scenario.plc_program is None  # plc: none: the recorded PLC's writes are its steps
    assert run_scenario(scenario, Simulation(scenario.machine, None)).passed


def test_without_record_the_page_is_told_why_not() -> None:
    simulation, bridge = served(None)
    assert bridge.recording.state() == {"state": "none", "path": "", "note": NO_RECORDING}
    assert ask(simulation, bridge, "record", action="stop") == (False, NO_RECORDING)
    assert bridge.recording.scenario().refusal == NO_RECORDING


def test_a_recording_is_not_started_in_the_middle_of_a_session(tmp_path: Path) -> None:
    recorder = SessionRecorder(str(tmp_path / "s.jsonl"), SessionInfo(
        RecordedFile("x.yaml", ""), "inprocess", "lockstep", "test"))
    simulation, bridge = served(recorder)
    done, message = ask(simulation, bridge, "record", action="start")
    assert not done and message.startswith(STARTS_AT_POWER_ON)
    assert ask(simulation, bridge, "record", action="pause")[1] == "record takes start or stop, not 'pause'"
    recorder.close()


def test_every_snapshot_says_what_is_recorded(tmp_path: Path) -> None:
    recorder = SessionRecorder(str(tmp_path / "s.jsonl"), SessionInfo(None, "inprocess", "lockstep", "test"))
    simulation, bridge = served(recorder)
    published: list[dict[str, Any]] = []
    bridge.publish = published.append
    bridge.pages = 1
    simulation.step(3)
    bridge.cycle_done(simulation)
    assert published[-1]["update"]["recording"] == {"state": "recording", "path": str(tmp_path / "s.jsonl"),
                                                    "cycle": recorder.cycle, "note": ""}
    recorder.close()
