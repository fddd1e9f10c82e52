"""docs/plc_examples/turn_mill.st runs as the PLC of ``vc serve`` in lockstep: parsed by blark with the
CODESYS variable list of ``vc map --format codesys``, scanned by the bench's evaluator over the
channels' process image, stepped by the lockstep handshake (st_bench.py).  The operator's scenario
(turn_mill_bringup.yaml) must pass, so the program must do the link's part: it once wrote neither
the sign of life nor the session echo, and a CODESYS PLC built from it had every write refused and
alarm 2001.  A program without its link network fails here with the reason."""

from __future__ import annotations

import re
import subprocess
import sys
import threading
from pathlib import Path

import pytest

pytest.importorskip("blark")

from pyModbusTCP.client import ModbusClient
from st_bench import ChannelImage, HandshakeError, LockstepMaster, Program, StError, global_variables

from interfaces.catalog import load_catalog
from interfaces.exports.codesys import codesys_gvl
from interfaces.exports.context import ExportContext
from interfaces.links.modbus.codec import RegisterMap
from interfaces.signal_map import map_rows
from interfaces.signals import expand
from vc.config.loader import load_machine

ROOT = Path(__file__).resolve().parents[2]
PROGRAM = ROOT / "docs" / "plc_examples" / "turn_mill.st"
SCENARIO = Path(__file__).resolve().parent / "turn_mill_bringup.yaml"
TIMEOUT_S = 240.0


def _register_map_and_gvl() -> tuple[RegisterMap, str]:
    machine = load_machine("turn_mill")
    catalog = expand(load_catalog(), machine.layout)
    register_map = RegisterMap.build(catalog, machine.plant_io.area_sizes())
    rows = map_rows(catalog, machine.plant_io)
    return register_map, codesys_gvl(rows, ExportContext(machine.name, register_map))


def _serve_the_scenario(program_text: str) -> tuple[int, list[str], LockstepMaster, BaseException | None]:
    """``vc serve --scenario`` with the program on the bench as its PLC: the exit code, what vc serve
    said, the master, and what stopped the bench (None: the harness ended)."""
    register_map, gvl = _register_map_and_gvl()
    program = Program(program_text, global_variables(gvl), ChannelImage(register_map))
    server = subprocess.Popen([sys.executable, "-m", "vc.cli.main", "serve", "--modbus", "127.0.0.1:0", "--scenario",
                               str(SCENARIO)], stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, cwd=ROOT)
    said: list[str] = []
    assert server.stdout is not None
    port = 0
    for line in server.stdout:
        said.append(line.rstrip("\n"))
        if match := re.match(r"Modbus TCP on 127\.0\.0\.1:(\d+)", line):
            port = int(match.group(1))
            break
    assert port, said
    pump = threading.Thread(target=lambda: said.extend(line.rstrip("\n") for line in server.stdout or ()), daemon=True)
    pump.start()
    master = LockstepMaster(ModbusClient(host="127.0.0.1", port=port, timeout=10, auto_open=True), program,
                            register_map)
    stopped: BaseException | None = None
    try:
        for _ in master.steps():
            pass
    except (HandshakeError, StError) as error:
        stopped = error
    finally:
        master.client.close()
        if server.poll() is None and stopped is not None:
            server.terminate()
        code = server.wait(TIMEOUT_S)
        pump.join(10)
    return code, said, master, stopped


@pytest.mark.link
@pytest.mark.timeout(TIMEOUT_S + 60)
def test_the_st_program_passes_the_bringup_scenario_against_vc_serve_in_lockstep() -> None:
    code, said, master, stopped = _serve_the_scenario(PROGRAM.read_text())
    assert stopped is None, f"{stopped}; vc serve said: {said[-12:]}"
    assert code == 0, "\n".join(said)
    assert "scenario done (exit code 0); the server stops (--keep-running keeps the machine running)" in said
    assert master.sessions == [1, 2]  # the power cycle: a new session the program started over for
    assert master.scans > 1000


@pytest.mark.link
@pytest.mark.timeout(TIMEOUT_S + 60)
def test_a_program_without_the_link_network_fails_with_the_reason() -> None:
    """What the example was: it never echoed the session nor answered the grant."""
    text = PROGRAM.read_text()
    without_link = text[: text.index("(* 8 Link")] + "END_PROGRAM\n"
    code, _said, master, stopped = _serve_the_scenario(without_link)
    assert isinstance(stopped, HandshakeError)
    assert "the program must claim its session, LINK_sessionReady := LINK_session" in str(stopped)
    assert master.scans == 0 and code != 0  # its first scan's writes were refused


def test_the_bench_refuses_what_it_does_not_run() -> None:
    """The evaluator never guesses: a construct outside its subset is an error with its line."""
    register_map, gvl = _register_map_and_gvl()
    program = PROGRAM.read_text().replace("END_PROGRAM", "FOR scans := 1 TO 3 DO setStage := 0; END_FOR;\nEND_PROGRAM")
    with pytest.raises(StError, match=r"turn_mill\.st:\d+: the bench does not run ForStatement"):
        Program(program, global_variables(gvl), ChannelImage(register_map)).scan(0)
