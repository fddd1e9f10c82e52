"""``python -m plc_awlsim``: how it ends when the harness it ran for ends.  (The example program's
scenario: test_turn_mill_example.py.)  The PLC process runs against a server on 127.0.0.1 with an
ephemeral port."""

from __future__ import annotations

import subprocess
import sys
import time
from pathlib import Path

import pytest

pytest.importorskip("awlsim")

from vc.config.loader import load_machine
from vc.harness.links import LinkMode
from vc.harness.links.modbus import Endpoint, PlcLink
from vc.simulation.lockstep import Simulation

ROOT = Path(__file__).resolve().parents[2]
PROGRAM = ROOT / "examples" / "awlsim" / "turn_mill.awl"


@pytest.mark.timeout(180)
def test_when_the_harness_ends_the_plc_ends_with_code_1_and_says_why() -> None:
    """With --connect-timeout 3 it printed awlsim's error every 3 s and never ended."""
    link = PlcLink(LinkMode.LOCKSTEP, modbus=Endpoint("127.0.0.1", 0), first_scan_timeout_s=120.0)
    assert link.modbus is not None
    port = link.modbus.port
    plc = subprocess.Popen([sys.executable, "-m", "plc_awlsim", "--connect-timeout", "3", "--modbus",
                            f"127.0.0.1:{port}", str(PROGRAM)], stdout=subprocess.DEVNULL, stderr=subprocess.PIPE,
                           text=True)
    try:
        try:
            Simulation(load_machine("turn_mill"), "basic_machine", connector=link).step(50)
        finally:
            link.close()
        began = time.monotonic()
        code = plc.wait(30)
        waited = time.monotonic() - began
    finally:
        if plc.poll() is None:
            plc.kill()
            plc.wait()
    said = plc.stderr.read() if plc.stderr else ""
    assert code == 1, said
    assert waited < 10.0
    assert f"the harness has gone: Modbus server 127.0.0.1:{port}: the server closed the connection" in said
    assert "Awlsim error" not in said
