"""``vc serve`` as a user runs it: a second terminal's ``python -m plc_stub`` references X1 over
Modbus TCP, independent clients read the referenced bit at the address ``vc map`` documents,
and a write to a read-only address gets exception 02."""

from __future__ import annotations

import dataclasses
import os
import queue
import shutil
import signal
import socket
import subprocess
import sys
import threading
from collections.abc import Iterator
from pathlib import Path

import pytest
import snap7
from pyModbusTCP.client import ModbusClient

from interfaces.catalog import load_catalog
from interfaces.links.modbus.codec import RegisterMap, Table
from interfaces.signal_map import map_rows
from interfaces.signals import expand
from vc.cli.main import main
from vc.config.loader import load_machine

ROOT = Path(__file__).resolve().parents[3]
MACHINE = str(ROOT / "scenarios" / "machines" / "turn_mill.yaml")
SCENARIO = str(ROOT / "scenarios" / "referencing" / "incremental_jog_ref_falling_edge.yaml")
TIMEOUT = 60.0


def free_port() -> int:
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        return int(probe.getsockname()[1])


class Lines:
    """The output of a process, line by line, readable with a time-out."""

    def __init__(self, process: subprocess.Popen[str]):
        self.process = process
        self.seen: list[str] = []
        self._queue: queue.Queue[str] = queue.Queue()
        assert process.stdout is not None
        threading.Thread(target=self._pump, args=(process.stdout,), daemon=True).start()

    def _pump(self, stream) -> None:  # type: ignore[no-untyped-def]
        for line in stream:
            self._queue.put(line.rstrip("\n"))

    def wait_for(self, text: str, timeout: float = TIMEOUT) -> str:
        while True:
            try:
                line = self._queue.get(timeout=timeout)
            except queue.Empty:
                raise AssertionError(f"no line with {text!r} within {timeout} s; seen: {self.seen}") from None
            self.seen.append(line)
            if text in line:
                return line


def spawn(*arguments: str) -> subprocess.Popen[str]:
    return subprocess.Popen([sys.executable, *arguments], stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                            cwd=ROOT)


def stop(process: subprocess.Popen[str]) -> None:
    if process.poll() is None:
        process.terminate()
        try:
            process.wait(10)
        except subprocess.TimeoutExpired:
            process.kill()
            process.wait()


@pytest.fixture
def serving() -> Iterator[tuple[int, Lines]]:
    port = free_port()
    server = spawn("-m", "vc.cli.main", "serve", "--modbus", f"127.0.0.1:{port}", "--scenario", SCENARIO,
                   "--keep-running", "--duration", "600")
    plc = spawn("-m", "plc_stub", "--modbus", f"127.0.0.1:{port}", "--connect-timeout", "30")
    try:
        yield port, Lines(server)
    finally:
        stop(plc)
        stop(server)


def documented(symbol: str) -> dict[str, str]:
    machine = load_machine(MACHINE)
    rows = map_rows(expand(load_catalog(), machine.layout), machine.plant_io)
    (row,) = [row for row in rows if row.symbol == symbol]
    return {key: str(value) for key, value in dataclasses.asdict(row).items()}


def plc_to_nc_registers() -> int:
    machine = load_machine(MACHINE)
    register_map = RegisterMap.build(expand(load_catalog(), machine.layout), machine.plant_io.area_sizes())
    return register_map.registers(Table.PLC_TO_NC)


def test_serve_and_a_plc_process_reference_x1_and_clients_read_the_documented_bit(serving: tuple[int, Lines]) -> None:
    port, output = serving
    output.wait_for("PASS")
    output.wait_for("the machine keeps running")
    referenced = documented("X1.basic.in.enc1Synchronized")
    assert referenced["modbus_table"] == "discrete_input"
    client = ModbusClient(host="127.0.0.1", port=port, timeout=5, auto_open=True)
    assert client.read_discrete_inputs(int(referenced["modbus_address"]), 1) == [True]
    (register,) = client.read_input_registers(int(referenced["register"]), 1)
    assert register >> int(referenced["register_bit"]) & 1
    # a coil the PLC's table holds: refused to a second writer while the PLC owns the link (01 illegal
    # function); a coil beyond the PLC-to-NC table: refused as an address (02 illegal data address)
    plc_coil = int(documented("X1.basic.out.enableCtrl")["modbus_address"])
    assert not client.write_single_coil(plc_coil, True)
    assert client.last_except == 1
    assert not client.write_single_coil(16 * plc_to_nc_registers(), True)
    assert client.last_except == 2
    client.close()
    mbpoll = shutil.which("mbpoll")
    if mbpoll is None and not os.environ.get("VC_REQUIRE_MBPOLL"):
        pytest.skip("mbpoll is not installed (.ci/run installs it)")
    assert mbpoll is not None
    reference = str(int(referenced["modbus_address"]) + 1)  # mbpoll counts from 1
    read = subprocess.run([mbpoll, "-m", "tcp", "-p", str(port), "-t", "1", "-r", reference, "-c", "1", "-1",
                           "127.0.0.1"], capture_output=True, text=True, timeout=10)
    assert read.returncode == 0 and f"[{reference}]: \t1" in read.stdout
    for coil, answer in ((plc_coil, "Illegal function"), (16 * plc_to_nc_registers(), "Illegal data address")):
        refused = subprocess.run([mbpoll, "-m", "tcp", "-p", str(port), "-t", "0", "-r", str(coil + 1), "-1",
                                  "127.0.0.1", "1"], capture_output=True, text=True, timeout=10)
        assert refused.returncode != 0 and answer in refused.stdout + refused.stderr


@pytest.mark.realtime
def test_serve_in_real_time_with_s7_a_client_reads_the_data_blocks() -> None:
    modbus, s7 = free_port(), free_port()
    server = spawn("-m", "vc.cli.main", "serve", "--modbus", f"127.0.0.1:{modbus}", "--s7", f"127.0.0.1:{s7}",
                   "--realtime", "--duration", "20", "--stats", "1")
    plc = spawn("-m", "plc_stub", "--modbus", f"127.0.0.1:{modbus}", "--connect-timeout", "30")
    try:
        output = Lines(server)
        output.wait_for("S7 on")
        output.wait_for("client(s)")  # a statistics line: the cycles run
        client = snap7.client.Client()
        client.connect("127.0.0.1", 0, 1, s7)
        # basic_machine gives the controller enables: DB31.DBX61.5 position control active
        for _ in range(50):
            if client.db_read(31, 61, 1)[0] >> 5 & 1:
                break
            output.wait_for("client(s)", timeout=5)
        assert client.db_read(31, 61, 1)[0] >> 5 & 1
        with pytest.raises(Exception, match=r"0x84|cannot be performed"):
            client.db_write(31, 61, bytearray([0]))  # NC-to-PLC: refused
        client.disconnect()
    finally:
        stop(plc)
        stop(server)


def test_serve_refuses_a_remote_bind_without_the_flag() -> None:
    result = subprocess.run([sys.executable, "-m", "vc.cli.main", "serve", "--modbus", "0.0.0.0:5020"],
                            capture_output=True, text=True, timeout=30, cwd=ROOT)
    assert result.returncode == 2
    assert "--allow-remote" in result.stderr


@pytest.mark.parametrize(("arguments", "message"), [
    (["--max-clients", "0"], "at least one client must be able to connect (max clients 0)"),
    (["--allow-writers", "127.0.0.x"], "'127.0.0.x' is not an IP address or network"),
])
def test_serve_refuses_limits_and_writers_it_cannot_use(arguments: list[str], message: str,
                                                        capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["serve", "--modbus", "127.0.0.1:0", *arguments, "--duration", "0.01"]) == 2
    assert message in capsys.readouterr().err


SERVED = """name: served without plc
machine: turn_mill
steps:
  - wait: {until: "Z1.basic.in.posCtrlActive == 1", timeout: 2s}
  - press: MCP.jog
  - hold: MCP.plus.Z1
  - wait: 300ms
  - expect: {Z1.velocity: "%s"}
  - release: MCP.plus.Z1
"""


@pytest.mark.parametrize(("expected", "code"), [("2000 +- 0.01", 0), ("1234", 1)], ids=["passes", "fails"])
def test_a_served_scenario_ends_the_server_with_its_exit_code_and_junit_report(tmp_path: Path, expected: str,
                                                                               code: int) -> None:
    scenario = tmp_path / "served.yaml"
    scenario.write_text(SERVED % expected)  # no plc: the PLC is the one on the link
    junit = tmp_path / "served.xml"
    port = free_port()
    server = spawn("-m", "vc.cli.main", "serve", "--modbus", f"127.0.0.1:{port}", "--scenario", str(scenario),
                   "--junit", str(junit))
    plc = spawn("-m", "plc_stub", "--modbus", f"127.0.0.1:{port}", "--connect-timeout", "30")
    try:
        output = Lines(server)
        output.wait_for(f"scenario done (exit code {code}); the server stops")
        assert server.wait(TIMEOUT) == code
        report = junit.read_text(encoding="utf-8")
        assert 'tests="1"' in report and (f'failures="{code}"' in report)
    finally:
        stop(plc)
        stop(server)


def test_a_served_scenario_with_plc_none_is_refused(tmp_path: Path) -> None:
    scenario = tmp_path / "as_plc.yaml"
    scenario.write_text((SERVED % "2000 +- 0.01").replace("machine: turn_mill\n", "machine: turn_mill\nplc: none\n"))
    result = subprocess.run([sys.executable, "-m", "vc.cli.main", "serve", "--modbus", f"127.0.0.1:{free_port()}",
                             "--scenario", str(scenario)], capture_output=True, text=True, timeout=60, cwd=ROOT)
    assert result.returncode == 2
    assert "plc: none makes the scenario the PLC" in result.stderr


def test_statistics_come_while_a_scenario_runs_in_real_time(tmp_path: Path) -> None:
    scenario = tmp_path / "served.yaml"
    scenario.write_text((SERVED % "2000 +- 0.01").replace("wait: 300ms", "wait: 2s"))
    port = free_port()
    server = spawn("-m", "vc.cli.main", "serve", "--modbus", f"127.0.0.1:{port}", "--scenario", str(scenario),
                   "--realtime", "--stats", "0.5")
    plc = spawn("-m", "plc_stub", "--modbus", f"127.0.0.1:{port}", "--connect-timeout", "30")
    try:
        output = Lines(server)
        output.wait_for("client(s)")  # a statistics line ...
        line = output.wait_for("scenario done")  # ... before the scenario ends
        assert "exit code 0" in line, output.seen
        assert server.wait(TIMEOUT) == 0
    finally:
        stop(plc)
        stop(server)



@pytest.mark.parametrize("realtime", [[], ["--realtime", "--stats", "0.5"]], ids=["lockstep", "realtime"])
def test_ctrl_c_during_a_served_scenario_ends_the_server_even_with_keep_running(tmp_path: Path,
                                                                               realtime: list[str]) -> None:
    """Ctrl-C interrupts the scenario and ends ``vc serve`` with 130, as without --keep-running (it used
    to take the interrupted scenario for a finished one and keep the machine running)."""
    scenario = tmp_path / "served.yaml"
    scenario.write_text((SERVED % "2000 +- 0.01").replace("wait: 300ms", "wait: 3600s"))
    port = free_port()
    server = spawn("-m", "vc.cli.main", "serve", "--modbus", f"127.0.0.1:{port}", "--scenario", str(scenario),
                   "--keep-running", *realtime)
    plc = spawn("-m", "plc_stub", "--modbus", f"127.0.0.1:{port}", "--connect-timeout", "30")
    try:
        Lines(plc).wait_for("session 1")  # the PLC has its session: the scenario runs
        output = Lines(server)
        server.send_signal(signal.SIGINT)
        assert server.wait(TIMEOUT) == 130
        output.wait_for("interrupted after 0 of 1 scenarios")
    finally:
        stop(plc)
        stop(server)


MILL_3AXIS_SCENARIO = (SERVED % "2000 +- 0.01").replace("machine: turn_mill", "machine: mill_3axis")


def test_a_machine_other_than_the_scenarios_is_refused_before_anything_runs(
        tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """--machine turn_mill with a mill_3axis scenario silently served mill_3axis."""
    scenario = tmp_path / "mill.yaml"
    scenario.write_text(MILL_3AXIS_SCENARIO)
    assert main(["serve", "--machine", "turn_mill", "--modbus", "127.0.0.1:0", "--scenario", str(scenario)]) == 2
    error = capsys.readouterr().err
    assert f"--machine turn_mill names another machine than the scenario {scenario}, which runs mill_3axis" in error


@pytest.mark.parametrize("machine", ["mill_3axis", str(ROOT / "scenarios" / "machines" / "mill_3axis.yaml")],
                         ids=["by name", "by the path through scenarios/machines"])
def test_the_scenarios_machine_may_be_given_by_name_or_path(tmp_path: Path, machine: str) -> None:
    from vc.harness.serve import ServeOptions, _machine_and_program

    scenario = tmp_path / "mill.yaml"
    scenario.write_text(MILL_3AXIS_SCENARIO)
    options = ServeOptions(machine_path=machine, machine_given=True, scenario=str(scenario))
    assert _machine_and_program(options)[0].name == "mill_3axis"


def test_the_banner_of_an_awlsim_scenario_names_the_awlsim_command() -> None:
    """It said the PLC runs via python -m plc_stub."""
    server = spawn("-m", "vc.cli.main", "serve", "--modbus", "127.0.0.1:0", "--scenario",
                   "examples/awlsim/turn_mill_bringup.yaml")
    try:
        output = Lines(server)
        port = output.wait_for("Modbus TCP on 127.0.0.1:").split(":")[1].split()[0]
        line = output.wait_for("lockstep:")
        assert (f"the scenario's PLC is awlsim with examples/awlsim/turn_mill.awl: python -m plc_awlsim --modbus"
                f" 127.0.0.1:{port} examples/awlsim/turn_mill.awl") in line
        assert "plc_stub" not in line
    finally:
        stop(server)


@pytest.mark.realtime
def test_after_the_plc_is_lost_the_operator_opens_a_new_session_for_the_restarted_plc() -> None:
    port = free_port()
    server = spawn("-m", "vc.cli.main", "serve", "--modbus", f"127.0.0.1:{port}", "--realtime", "--stats", "1")
    plc = spawn("-m", "plc_stub", "--modbus", f"127.0.0.1:{port}", "--connect-timeout", "30")
    restarted: subprocess.Popen[str] | None = None
    try:
        output = Lines(server)
        output.wait_for("PLC at 127.0.0.1")  # the statistics line: the PLC owns session 1
        stop(plc)
        line = output.wait_for("has gone")
        assert ("the PLC at 127.0.0.1 has gone: session 1 is closed, and no other client may claim it; a restarted PLC"
                f" gets a new session: press Enter here, or kill -USR1 {server.pid}") in line
        output.wait_for("alarm 2000")
        restarted = spawn("-m", "plc_stub", "--modbus", f"127.0.0.1:{port}", "--connect-timeout", "30")
        output.wait_for("(1 of them claims)")  # its claim of the closed session is refused
        server.send_signal(signal.SIGUSR1)
        output.wait_for("session 2 opened: the first PLC that claims it owns the link")
        output.wait_for("PLC at 127.0.0.1")
    finally:
        if restarted is not None:
            stop(restarted)
        stop(plc)
        stop(server)


@pytest.mark.realtime
def test_the_server_pinned_with_sched_fifo_says_so_in_its_statistics() -> None:
    cpu = min(os.sched_getaffinity(0))
    result = subprocess.run([sys.executable, "-m", "vc.cli.main", "serve", "--modbus", "127.0.0.1:0", "--realtime",
                             "--cpu", str(cpu), "--fifo", "10", "--duration", "0.3"],
                            capture_output=True, text=True, timeout=60, cwd=ROOT)
    assert result.returncode == 0, result.stderr
    got = next(line for line in result.stdout.splitlines() if line.startswith("scheduling: ")).removeprefix(
        "scheduling: ")
    assert got.startswith(f"pinned to CPU {cpu}, SCHED_")
    final = next(line for line in result.stdout.splitlines() if line.startswith("real time: "))
    assert final.endswith(f"; {got}")


def test_a_cpu_the_server_cannot_run_on_is_refused_before_anything_runs(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["serve", "--modbus", "127.0.0.1:0", "--realtime", "--cpu", "4096", "--duration", "0.1"]) == 2
    assert "CPU 4096 is not one this process may run on" in capsys.readouterr().err
