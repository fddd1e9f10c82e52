"""The PLC connection the page shows (vc/ui/connection.py) on an in-process machine: in lockstep, in
real time with the pacer's overruns, and with the sign-of-life alarms."""

from __future__ import annotations

import asyncio

import pytest

from vc.config.loader import load_machine
from vc.config.machine_files import machine_file
from vc.harness.pacer import RealtimePacer
from vc.simulation.lockstep import Simulation
from vc.ui.bridge import OperatorBridge
from vc.ui.connection import connection_state


def turn_mill(**keywords: object) -> Simulation:
    path = machine_file("turn_mill")
    assert path is not None
    return Simulation(load_machine(path), **keywords)  # type: ignore[arg-type]


def test_in_process_and_lockstep_say_so_and_count_no_overruns() -> None:
    simulation = turn_mill()
    simulation.step(10)
    state = connection_state(simulation)
    assert state["link"] == "the PLC runs in this process"
    assert state["mode"] == "lockstep"
    assert state["overruns"] is None and state["cycles"] is None
    assert state["sign_of_life"].startswith("lockstep") and state["sign_of_life_lost"] is None


class Reporting:
    """``vc serve``'s pacer: it wraps the real-time pacer to print --stats."""

    def __init__(self, pacer: RealtimePacer):
        self.pacer = pacer

    def wait_next_cycle(self) -> None:
        self.pacer.wait_next_cycle()


def test_real_time_shows_the_cycles_paced_and_the_overruns_of_the_pacer() -> None:
    loop = asyncio.new_event_loop()
    try:
        simulation = turn_mill()
        realtime = RealtimePacer(loop, simulation.ipo_cycle_s, 1.0)
        simulation.pacer = Reporting(realtime)
        simulation.step(20)
        state = connection_state(simulation)
    finally:
        loop.close()
    assert state["mode"] == "real time"
    assert state["cycles"] == realtime.cycles > 0
    assert state["overruns"] == realtime.overruns
    assert state["link_overruns"] <= state["overruns"]
    assert f"{realtime.cycles} cycles" in state["pacing"]


@pytest.mark.parametrize(("number", "said"), [(2000, "lost: alarm 2000"), (2001, "not started: alarm 2001")])
def test_the_sign_of_life_alarms_are_shown_as_such(number: int, said: str) -> None:
    """What the NC's watch raises (the browser test sees 2000 raised by a PLC that ends)."""
    simulation = turn_mill()
    simulation.step(1)
    simulation.nck.alarms.raise_alarm(number, simulation.cycle)
    state = connection_state(simulation)
    assert state["sign_of_life_lost"] == number
    assert state["sign_of_life"].startswith(said)


def test_every_snapshot_carries_the_connection() -> None:
    simulation = turn_mill()
    bridge = OperatorBridge(update_period_s=0.0)
    published: list[dict[str, object]] = []
    bridge.publish = published.append
    bridge.attached(simulation)
    bridge.pages = 1
    simulation.step(1)
    bridge.cycle_done(simulation)
    (snapshot,) = published
    update = snapshot["update"]
    assert isinstance(update, dict)
    assert update["connection"] == connection_state(simulation)
