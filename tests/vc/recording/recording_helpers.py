"""Recording a scenario's session in this process (the built-in PLC in lockstep), as vc serve --record
records one with a PLC in another process: the same recorder, observing the same simulation."""

from __future__ import annotations

from pathlib import Path

from interfaces.links.inprocess import InProcessConnector, plc_programs
from interfaces.plc import PlcConnector
from vc.recording.format import Header, RecordedFile
from vc.recording.recorder import SessionInfo, SessionRecorder
from vc.scenario.language.loader import load_scenario
from vc.scenario.run.runner import ScenarioResult, run_scenario
from vc.simulation.lockstep import Simulation
from vc.simulation.observed import ObservedSimulation

ROOT = Path(__file__).resolve().parents[3]
OPERATOR = ROOT / "tests" / "vc" / "recording" / "reference_x1_operator.yaml"
HEADER = Header("mini", RecordedFile("machines/mini.yaml", "machine: mini\n"), None, "basic_machine", "modbus",
                "lockstep", 2000, 5, {"DB10": 120, "DB31": 160, "I": 4, "Q": 2}, "test")


def record_scenario(scenario_file: Path, out: Path, connector: PlcConnector | None = None) -> ScenarioResult:
    """Run ``scenario_file`` with its PLC program (through ``connector``) and record the session to ``out``."""
    scenario = load_scenario(str(scenario_file), plc_programs().keys())
    played = RecordedFile(str(scenario_file), scenario_file.read_text(encoding="utf-8"))
    recorder = SessionRecorder(str(out), SessionInfo(played, "inprocess", "lockstep", "test"))
    simulation = Simulation(scenario.machine, scenario.plc_program, connector=connector or InProcessConnector())
    try:
        return run_scenario(scenario, ObservedSimulation(simulation, [recorder]))
    finally:
        recorder.close()
