"""The live scope's NC side (vc/ui/scope.py) through the bridge on an in-process machine: one sample
per IPO cycle of the picked lanes only while a page is open, the ring bounded by the seconds kept,
the samples handed to the snapshots once, refusals that say why, and the ring as a VCD."""

from __future__ import annotations

from pathlib import Path
from typing import Any

from vcd.reader import TokenKind, tokenize

from vc.config.loader import load_machine
from vc.config.machine_files import machine_file
from vc.scenario.run.trace import write_vcd
from vc.simulation.lockstep import Simulation
from vc.ui.bridge import Command, OperatorBridge
from vc.ui.scope import MAX_LANES


def rig() -> tuple[Simulation, OperatorBridge, list[dict[str, Any]]]:
    path = machine_file("turn_mill")
    assert path is not None
    simulation = Simulation(load_machine(path))
    bridge = OperatorBridge(update_period_s=0.0)
    published: list[dict[str, Any]] = []
    bridge.publish = published.append
    bridge.attached(simulation)
    return simulation, bridge, published


def run(simulation: Simulation, bridge: OperatorBridge, cycles: int) -> None:
    for _ in range(cycles):
        simulation.step(1)
        bridge.cycle_done(simulation)


def pick(simulation: Simulation, bridge: OperatorBridge, names: list[str], seconds: float) -> tuple[bool, str]:
    answers: list[tuple[bool, str]] = []
    bridge.commands.append(Command("scope", 1, "127.0.0.1", {"names": names, "seconds": seconds},
                                   lambda done, text: answers.append((done, text))))
    run(simulation, bridge, 1)
    return answers[0]


def test_samples_every_cycle_only_the_picked_lanes_bounded_and_sent_once() -> None:
    simulation, bridge, published = rig()
    bridge.pages = 1
    done, message = pick(simulation, bridge, ["MCP.plus.X1", "DB31.DBX64.7", "X1.position"], 0.1)
    cycles = round(0.1 / simulation.ipo_cycle_s)
    assert done and message == f"scope: 3 lanes, the last 0.1 s ({cycles} IPO cycles)"
    published.clear()
    run(simulation, bridge, 5)
    scope = published[-1]["update"]["scope"]
    assert [lane["digital"] for lane in scope["lanes"]] == [True, True, False]
    assert len(scope["samples"]) == 1 and len(scope["samples"][0]) == 4  # the cycle and 3 values
    sent = [sample[0] for snapshot in published for sample in snapshot["update"]["scope"]["samples"]]
    assert sent == list(range(sent[0], sent[0] + 5))  # every cycle once, in order
    run(simulation, bridge, 3 * cycles)
    assert len(bridge.scope.samples) == cycles  # the ring keeps the seconds picked, no more


def test_nothing_is_sampled_while_no_page_is_open() -> None:
    simulation, bridge, _ = rig()
    bridge.pages = 1
    pick(simulation, bridge, ["X1.position"], 1.0)
    bridge.pages = 0
    before = len(bridge.scope.samples)
    run(simulation, bridge, 20)
    assert len(bridge.scope.samples) == before


def test_refusals_say_why() -> None:
    simulation, bridge, _ = rig()
    bridge.pages = 1
    assert pick(simulation, bridge, ["DB31.DBX999.9"], 1.0)[0] is False
    assert pick(simulation, bridge, ["X1.position"], 0.0) == (False, "the scope keeps 0.1 .. 60 s")
    assert pick(simulation, bridge, ["X1.position"] * (MAX_LANES + 1), 1.0) == (
        False, f"at most {MAX_LANES} lanes in the scope")
    assert pick(simulation, bridge, [], 1.0) == (True, "scope stopped")


def test_the_ring_as_a_vcd(tmp_path: Path) -> None:
    simulation, bridge, _ = rig()
    bridge.pages = 1
    pick(simulation, bridge, ["MCP.plus.X1", "X1.position"], 1.0)
    run(simulation, bridge, 10)
    bridge.commands.append(Command("key", 1, "127.0.0.1", {"name": "MCP.plus.X1", "value": 1}))
    run(simulation, bridge, 10)
    recording = bridge.scope.recording(simulation.ipo_cycle_us)
    key = next(history for history in recording.histories if history.quantity.name == "MCP.plus.X1")
    assert [value for _, value in key.entries()] == [0, 1]  # the changes only
    path = tmp_path / "scope.vcd"
    write_vcd(recording, path)
    with path.open("rb") as handle:
        names = {token.data.reference for token in tokenize(handle) if token.kind is TokenKind.VAR}
    assert names == {"MCP.plus.X1", "X1.position"}
