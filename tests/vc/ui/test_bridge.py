"""The NC's side of the page (vc/ui/bridge.py) on an in-process machine: commands are done between two
cycles as the operator's actions (the recording sees them), refusals say why, snapshots only while a
page is open and at most once per update period."""

from __future__ import annotations

from typing import Any

import pytest

from vc.config.loader import load_machine
from vc.config.machine_files import machine_file
from vc.simulation.lockstep import Simulation
from vc.simulation.observed import OperatorAction
from vc.ui.bridge import Command, OperatorBridge


class Told:
    """A recording's stand-in: what the observer chain passes on."""

    def __init__(self) -> None:
        self.actions: list[OperatorAction] = []
        self.cycles = 0

    def attached(self, simulation: Simulation) -> None:
        pass

    def cycle_done(self, simulation: Simulation) -> None:
        self.cycles += 1

    def acted(self, simulation: Simulation, action: OperatorAction) -> None:
        self.actions.append(action)


@pytest.fixture
def rig():  # type: ignore[no-untyped-def]
    path = machine_file("turn_mill")
    assert path is not None
    simulation = Simulation(load_machine(path))
    told = Told()
    bridge = OperatorBridge(("10.0.0.0/8",), told, update_period_s=0.0)
    published: list[dict[str, Any]] = []
    bridge.publish = published.append
    bridge.attached(simulation)
    return simulation, bridge, told, published


def run(simulation: Simulation, bridge: OperatorBridge, cycles: int) -> None:
    for _ in range(cycles):
        simulation.step(1)
        bridge.cycle_done(simulation)


def ask(bridge: OperatorBridge, kind: str, peer: str = "127.0.0.1", **arguments: Any) -> list[tuple[bool, str]]:
    answers: list[tuple[bool, str]] = []
    bridge.commands.append(Command(kind, 1, peer, arguments, lambda done, message: answers.append((done, message))))
    return answers


def test_nothing_is_published_while_no_page_is_open(rig) -> None:  # type: ignore[no-untyped-def]
    simulation, bridge, told, published = rig
    run(simulation, bridge, 50)
    assert published == [] and told.cycles == 50
    bridge.pages = 1
    run(simulation, bridge, 3)
    assert len(published) == 3
    update = published[-1]["update"]
    assert [axis["name"] for axis in update["axes"]][:3] == ["X1", "Z1", "Y1"]
    assert ["mode_group", "MODEGROUP", "JOG"] in update["states"]
    assert update["panel"]["EStop.chainOk"] == 1


def test_a_key_is_the_operators_action_and_the_plc_sees_it(rig) -> None:  # type: ignore[no-untyped-def]
    simulation, bridge, told, _ = rig
    bridge.pages = 1
    answers = ask(bridge, "key", name="MCP.plus.X1", value=1)
    run(simulation, bridge, 100)
    assert answers == [(True, "MCP.plus.X1 = 1")]
    assert told.actions == [OperatorAction("write", ("MCP.plus.X1", 1))]
    assert simulation.read(simulation.catalog.resolve("DB31.DBX64.7")) == 1
    assert simulation.axis_quantity("X1", "velocity") > 0


def test_refusals_say_why(rig) -> None:  # type: ignore[no-untyped-def]
    simulation, bridge, told, _ = rig
    answers = [ask(bridge, "key", name="X1.refCam", value=1), ask(bridge, "force", name="DB31.DBX4.7", value=1),
               ask(bridge, "force", name="DB31.DBX64.7", value=1), ask(bridge, "force", name="NoSuch.signal", value=1),
               ask(bridge, "release", name="X1.refCam"), ask(bridge, "mda", channel="CHAN9", text="G0 X1"),
               ask(bridge, "key", name="MCP.jog", value="x"), ask(bridge, "handwheel", number=4, detents=1)]
    run(simulation, bridge, 1)
    texts = [answer[0] for answer in answers]
    assert all(not done for done, _ in texts), texts
    assert "no key or switch" in texts[0][1]
    assert "--allow-writers naming this page's address 127.0.0.1" in texts[1][1]
    assert "watched, not forced" in texts[2][1]
    assert "NoSuch.signal" in texts[3][1]
    assert "not forced" in texts[4][1]
    assert "CHAN9" in texts[5][1]
    assert "handwheel 1..3" in texts[7][1]
    assert told.actions == []


def test_forces_by_the_rules_shown_and_released(rig) -> None:  # type: ignore[no-untyped-def]
    simulation, bridge, told, published = rig
    bridge.pages = 1
    watch = ask(bridge, "watch", names=["X1.refCam", "DB31.DBX4.7"])
    cam = ask(bridge, "force", name="X1.refCam", value=1)
    writer = ask(bridge, "force", peer="10.1.2.3", name="DB31.DBX4.7", value=1)  # --allow-writers 10.0.0.0/8
    run(simulation, bridge, 10)
    assert watch == [(True, "watching 2 signals")] and cam[0][0] and writer[0][0], (cam, writer)
    update = published[-1]["update"]
    assert update["watch"]["X1.refCam"] == {"symbol": "X1.refCam", "address": "I7.0", "value": 1, "forced": True}
    assert update["watch"]["DB31.DBX4.7"]["forced"] and update["watch"]["DB31.DBX4.7"]["value"] == 1
    assert update["forces"] == {"X1.refCam": 1, "X1.basic.out.traversKeyPlus": 1}
    release = ask(bridge, "release", name="X1.refCam")
    run(simulation, bridge, 10)
    assert release == [(True, "X1.refCam released")]
    assert published[-1]["update"]["watch"]["X1.refCam"]["forced"] is False
    assert [action.kind for action in told.actions] == ["force", "force", "release"]


def test_mda_loaded_as_the_operators_action(rig) -> None:  # type: ignore[no-untyped-def]
    simulation, bridge, told, _ = rig
    answers = ask(bridge, "mda", channel="CHAN1", text="G91 G1 Z5 F2000")
    run(simulation, bridge, 1)
    assert answers[0][0]
    assert told.actions == [OperatorAction("mda", ("CHAN1", "G91 G1 Z5 F2000"))]


def test_a_closed_page_stops_its_watch(rig) -> None:  # type: ignore[no-untyped-def]
    simulation, bridge, _, published = rig
    bridge.pages = 1
    ask(bridge, "watch", names=["X1.refCam"])
    run(simulation, bridge, 1)
    assert "X1.refCam" in published[-1]["update"]["watch"]
    bridge.commands.append(Command("closed", 1, "127.0.0.1"))
    run(simulation, bridge, 1)
    assert published[-1]["update"]["watch"] == {}
