"""``python -m plc_stub --modbus``: how it ends when the harness it ran for ends, and how it waits when
the server refuses it a session.  (The PLC with a harness in lockstep and in real time:
tests/vc/harness/links/test_modbus.py.)  Every test runs the PLC process against a server on
127.0.0.1 with an ephemeral port."""

from __future__ import annotations

import subprocess
import sys
import threading
import time
from collections.abc import Callable
from pathlib import Path

from pyModbusTCP.client import ModbusClient

from interfaces.links.modbus.access import OwnerState
from vc.config.loader import load_machine
from vc.harness.links import LinkMode
from vc.harness.links.modbus import Endpoint, PlcLink
from vc.harness.pacer import RealtimePacer
from vc.simulation.lockstep import Simulation

ROOT = Path(__file__).resolve().parents[4]
TURN_MILL = load_machine(str(ROOT / "scenarios" / "machines" / "turn_mill.yaml"))


def _plc(port: int, *arguments: str) -> subprocess.Popen[str]:
    return subprocess.Popen([sys.executable, "-m", "plc_stub", "--modbus", f"127.0.0.1:{port}", *arguments],
                            stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)


def _ended(plc: subprocess.Popen[str], timeout_s: float) -> tuple[int, str, float]:
    """Exit code, standard error and seconds until the process ended (killed after ``timeout_s``)."""
    began = time.monotonic()
    try:
        code = plc.wait(timeout_s)
    except subprocess.TimeoutExpired:
        plc.kill()
        code = plc.wait()
    return code, plc.stderr.read() if plc.stderr else "", time.monotonic() - began


def _stepping(simulation: Simulation, request: Callable[[], object]) -> object:
    """``request`` of a client in a thread while the simulation steps (its server answers meanwhile)."""
    answer: list[object] = []
    thread = threading.Thread(target=lambda: answer.append(request()), daemon=True)
    thread.start()
    while thread.is_alive():
        simulation.step(1)
    return answer[0]


def test_when_the_harness_ends_the_plc_ends_at_once_with_code_1_and_says_why() -> None:
    """It retried for its whole connect time-out (30 s) with pymodbus's own message."""
    link = PlcLink(LinkMode.LOCKSTEP, modbus=Endpoint("127.0.0.1", 0))
    assert link.modbus is not None
    port = link.modbus.port
    plc = _plc(port)  # the default connect time-out: 30 s
    try:
        Simulation(TURN_MILL, "basic_machine", connector=link).step(50)
    finally:
        link.close()
    code, said, waited = _ended(plc, 25.0)
    assert code == 1, said
    assert waited < 10.0
    assert (f"the harness has gone: Modbus server 127.0.0.1:{port}: the server closed the connection, and no server"
            f" has listened at 127.0.0.1:{port} since (2 s); stopping") in said
    assert "Modbus Error" not in said and "Errno" not in said


def test_a_plc_refused_its_session_says_so_once_and_takes_the_next_one() -> None:
    link = PlcLink(LinkMode.FREE_RUNNING, modbus=Endpoint("127.0.0.1", 0))
    assert link.modbus is not None
    simulation = Simulation(TURN_MILL, "basic_machine", connector=link,
                            pacer=RealtimePacer(link.loop, Simulation.ipo_seconds(TURN_MILL), speed=1.0))
    other = ModbusClient(host="127.0.0.1", port=link.modbus.port, timeout=2, auto_open=True)
    plc: subprocess.Popen[str] | None = None
    seen: list[object] = []
    try:
        simulation.step(10)
        assert _stepping(simulation, lambda: other.write_single_register(1, link.session))  # another PLC's session
        plc = _plc(link.modbus.port)
        deadline = time.monotonic() + 60
        while link.owner.refused_claims == 0 and time.monotonic() < deadline:
            simulation.step(10)
        simulation.step(500)  # a second: the PLC polls, and does not claim again
        seen.append(link.owner.refused_claims)
        other.close()  # the holder is lost: its session is closed
        while link.owner.state is not OwnerState.CLOSED and time.monotonic() < deadline:
            simulation.step(10)
        seen.append(link.open_new_session())
        while link.owner.state is not OwnerState.OWNED and time.monotonic() < deadline:
            simulation.step(10)
        seen += [link.owner.claims, link.owner.owner_peer]
    finally:
        other.close()
        if plc is not None:
            plc.terminate()
        link.close()
    assert plc is not None
    _code, said, _waited = _ended(plc, 10.0)
    assert seen == [1, "session 2 opened: the first PLC that claims it owns the link", 2, "127.0.0.1"], said
    assert said.count("the server refused this PLC's claim") == 1, said
    assert "session 2 (boot id" in said
