"""The PLC in its own process: lockstep gives the in-process trace, sessions restart the PLC,
a PLC that goes away is reported; in real time the NC watches the PLC's sign of life, which no
other client can keep alive.

Every test runs ``python -m plc_stub`` against a server on 127.0.0.1 with an ephemeral port.
"""

from __future__ import annotations

import signal
import subprocess
import sys
import threading
import time
from collections.abc import Callable, Iterator
from pathlib import Path

import pytest
from panel_operator import images, operate
from pyModbusTCP.client import ModbusClient

from interfaces.links.errors import LinkError
from interfaces.links.modbus.access import OwnerState
from vc.config.loader import load_machine
from vc.config.model import MachineConfig
from vc.harness.external_plc import PlcProcess
from vc.harness.links import LinkMode
from vc.harness.links.modbus import Endpoint, PlcLink, check_bind
from vc.harness.pacer import RealtimePacer
from vc.located_yaml import LocatedMap, load_text
from vc.simulation.lockstep import Simulation

ROOT = Path(__file__).resolve().parents[4]
TURN_MILL = load_machine(str(ROOT / "scenarios" / "machines" / "turn_mill.yaml"))
FIVE_AXIS = load_machine(str(ROOT / "scenarios" / "machines" / "mill_5axis.yaml"))
TURN_MILL_IPO_S = Simulation.ipo_seconds(TURN_MILL)


def _overrides(text: str) -> LocatedMap:
    document, problems = load_text(text, "<test>")
    assert not problems and isinstance(document, LocatedMap)
    return document


@pytest.fixture(scope="module")
def process() -> Iterator[PlcProcess]:
    with PlcProcess(first_scan_timeout_s=30.0, scan_timeout_s=10.0) as running:
        yield running


@pytest.mark.parametrize("machine", [TURN_MILL, FIVE_AXIS], ids=["turn_mill", "mill_5axis"])
def test_lockstep_over_modbus_gives_the_in_process_images_cycle_for_cycle(process: PlcProcess,
                                                                         machine: MachineConfig) -> None:
    linked = Simulation(machine, "basic_machine", connector=process.link)
    local = Simulation(machine, "basic_machine")
    operate(linked)
    operate(local)
    assert images(linked) == images(local)
    assert linked.nck.axes_by_name["X1"].physical == local.nck.axes_by_name["X1"].physical
    assert linked.nck.axes_by_name["X1"].physical > machine.axis("X1").sim.start_position + 100  # referencing runs


def test_a_pause_of_the_harness_between_two_scans_does_not_restart_the_plc() -> None:
    """A lockstep harness that paused for more than 3 s (a garbage collection of a long vc run on a
    busy host) made the PLC give up its request, reconnect and restart its program in the middle of
    the session: the run left the in-process trace."""
    with PlcProcess() as running:
        linked = Simulation(TURN_MILL, "basic_machine", connector=running.link)
        local = Simulation(TURN_MILL, "basic_machine")
        for simulation in (linked, local):
            simulation.step(150)
            simulation.write(simulation.plant_io.resolve("MCP.jog"), 1)
            simulation.step(10)
        time.sleep(4.0)  # the harness serves nobody meanwhile; the PLC waits for its answer
        for simulation in (linked, local):
            simulation.write(simulation.plant_io.resolve("MCP.jog"), 0)
            simulation.step(100)
        assert images(linked) == images(local)
        assert running.link.owner.claims == 1  # one connection throughout: no reconnect


def test_a_power_cycle_opens_a_new_session_and_the_plc_restarts(process: PlcProcess) -> None:
    linked = Simulation(TURN_MILL, "referencing", connector=process.link)
    local = Simulation(TURN_MILL, "referencing")
    for simulation in (linked, local):
        simulation.step(100)
        simulation.power_cycle(0.5)
        operate(simulation)
    assert images(linked) == images(local)
    assert process.link.session >= 2


def test_a_plc_process_that_ends_is_reported_instead_of_waited_for() -> None:
    with PlcProcess(first_scan_timeout_s=20.0, scan_timeout_s=20.0) as running:
        simulation = Simulation(TURN_MILL, "basic_machine", connector=running.link)
        simulation.step(50)
        assert running.process is not None
        running.process.kill()
        running.process.wait()
        with pytest.raises(LinkError, match="the PLC process ended"):
            simulation.step(50)


def test_a_plc_that_cannot_run_the_program_ends_with_a_reason() -> None:
    with PlcProcess(first_scan_timeout_s=20.0) as running, \
            pytest.raises(LinkError, match="no PLC program 'no_such_program'"):
        Simulation(TURN_MILL, "no_such_program", connector=running.link)


def test_binding_beyond_loopback_needs_the_explicit_flag() -> None:
    with pytest.raises(LinkError, match="--allow-remote"):
        check_bind(Endpoint.parse("0.0.0.0:5020", 5020), allow_remote=False)
    check_bind(Endpoint.parse("0.0.0.0:5020", 5020), allow_remote=True)
    check_bind(Endpoint.parse(":5020", 5020), allow_remote=False)  # loopback
    with pytest.raises(LinkError, match="port must be a number"):
        Endpoint.parse("127.0.0.1:http", 5020)


def test_lockstep_needs_the_modbus_handshake() -> None:
    with pytest.raises(LinkError, match="lockstep needs the Modbus handshake"):
        PlcLink(LinkMode.LOCKSTEP, s7=Endpoint("127.0.0.1", 0))


# ------------------------------------------------------------------------------ real time


def _plc(port: int) -> subprocess.Popen[bytes]:
    return subprocess.Popen([sys.executable, "-m", "plc_stub", "--modbus", f"127.0.0.1:{port}", "--connect-timeout",
                             "20"], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)


def _stop(plc: subprocess.Popen[bytes]) -> None:
    if plc.poll() is None:
        plc.kill()
    plc.wait()


def _step_until(simulation: Simulation, done: Callable[[], bool], seconds: float) -> bool:
    for _ in range(round(seconds / simulation.ipo_cycle_s)):
        simulation.step(1)
        if done():
            return True
    return False


def _run_until(simulation: Simulation, condition: str, seconds: float) -> bool:
    ref = simulation.catalog.resolve(condition)
    for _ in range(round(seconds / simulation.ipo_cycle_s)):
        simulation.step(1)
        if simulation.read(ref):
            return True
    return False


@pytest.mark.realtime
def test_real_time_a_silent_plc_raises_2000_and_after_its_return_a_reset_clears_it() -> None:
    link = PlcLink(LinkMode.FREE_RUNNING, modbus=Endpoint("127.0.0.1", 0))
    assert link.modbus is not None
    pacer = RealtimePacer(link.loop, TURN_MILL_IPO_S, speed=1.0)
    plc = _plc(link.modbus.port)
    try:
        simulation = Simulation(TURN_MILL, "basic_machine", connector=link, pacer=pacer)
        # the PLC starts, scans on its own clock and gives the drives their enables
        assert _run_until(simulation, "X1.basic.in.posCtrlActive", 10.0)
        assert simulation.nck.alarms.history == []
        _stop(plc)
        # MD10100 = 0.1 s without a sign of life: alarm 2000, the axes lose position control
        simulation.step(round(0.3 / TURN_MILL_IPO_S))
        assert [alarm.number for alarm in simulation.nck.alarms.present] == [2000]
        assert simulation.read(simulation.catalog.resolve("X1.basic.in.posCtrlActive")) == 0
        plc = _plc(link.modbus.port)  # the PLC comes back: its session was closed when it was lost ...
        assert _step_until(simulation, lambda: link.owner.refused_claims >= 1, 15.0)
        assert link.owner.state is OwnerState.CLOSED
        assert "session 2 opened" in link.open_new_session()  # ... until the operator opens a new one
        assert _step_until(simulation, lambda: link.owner.state is OwnerState.OWNED, 5.0)
        assert [alarm.number for alarm in simulation.nck.alarms.present] == [2000]  # the alarm stays
        reset = simulation.plant_io.resolve("MCP.reset")
        simulation.write(reset, 1)
        simulation.step(round(0.1 / TURN_MILL_IPO_S))
        simulation.write(reset, 0)
        assert _run_until(simulation, "X1.basic.in.posCtrlActive", 2.0)
        assert simulation.nck.alarms.present == []
        assert pacer.stats().cycles > 0
    finally:
        _stop(plc)
        link.close()


@pytest.mark.realtime
def test_real_time_without_any_plc_the_nc_reports_2001_after_md10120() -> None:
    config = load_machine(str(ROOT / "scenarios" / "machines" / "turn_mill.yaml"), _overrides("NC: {MD10120: 0.2}"))
    link = PlcLink(LinkMode.FREE_RUNNING, modbus=Endpoint("127.0.0.1", 0))
    try:
        simulation = Simulation(config, "basic_machine", connector=link,
                                pacer=RealtimePacer(link.loop, TURN_MILL_IPO_S, speed=None))
        simulation.step(round(0.15 / TURN_MILL_IPO_S))
        assert simulation.nck.alarms.present == []
        simulation.step(round(0.1 / TURN_MILL_IPO_S))
        assert [alarm.number for alarm in simulation.nck.alarms.present] == [2001]
    finally:
        link.close()



def test_real_time_another_client_can_neither_keep_the_sign_of_life_nor_move_an_axis() -> None:
    """It wrote holding register 0 every 10 ms and kept alarm 2000 away from a frozen PLC for
    seconds; one write of it reversed X1."""
    link = PlcLink(LinkMode.FREE_RUNNING, modbus=Endpoint("127.0.0.1", 0))
    assert link.modbus is not None
    pacer = RealtimePacer(link.loop, TURN_MILL_IPO_S, speed=1.0)
    plc = _plc(link.modbus.port)
    stop = threading.Event()
    answers: list[bool] = []

    def intruder() -> None:
        client = ModbusClient(host="127.0.0.1", port=link.modbus.port if link.modbus else 0, timeout=2,
                              auto_open=True)
        life = 0
        while not stop.is_set():
            life = (life + 1) & 0xFFFF
            answers.append(bool(client.write_single_register(0, life)))  # the sign of life
            answers.append(bool(client.write_multiple_registers(67, [0xFF80, 0, 0x8000])))  # X1's enables and key
            stop.wait(0.01)
        client.close()

    thread = threading.Thread(target=intruder, daemon=True)
    try:
        simulation = Simulation(TURN_MILL, "basic_machine", connector=link, pacer=pacer)
        assert _run_until(simulation, "X1.basic.in.posCtrlActive", 10.0)
        plc.send_signal(signal.SIGSTOP)  # the PLC freezes; its connection stays
        thread.start()
        simulation.step(round(0.5 / TURN_MILL_IPO_S))
        assert [alarm.number for alarm in simulation.nck.alarms.present] == [2000]
        assert simulation.nck.axes_by_name["X1"].velocity == 0
        stop.set()
        while thread.is_alive():  # its last request is answered too
            link.serve()
        assert answers and not any(answers)
        assert link.owner.refused == len(answers)
    finally:
        stop.set()
        plc.send_signal(signal.SIGCONT)
        _stop(plc)
        link.close()


@pytest.mark.realtime
def test_real_time_a_lost_plc_leaves_its_session_closed_to_every_other_client() -> None:
    """The PLC died in the middle of a JOG; a second Modbus client wrote holding register 1 = the
    session, became the owner, reversed X1 within 15 ms and kept alarm 2000 away with the sign of
    life; the restarted PLC was locked out.  S7 took the same write."""
    import snap7

    link = PlcLink(LinkMode.FREE_RUNNING, modbus=Endpoint("127.0.0.1", 0), s7=Endpoint("127.0.0.1", 0))
    assert link.modbus is not None and link.s7 is not None
    port = link.modbus.port
    pacer = RealtimePacer(link.loop, TURN_MILL_IPO_S, speed=1.0)
    plc = _plc(port)
    stop = threading.Event()
    answers: list[bool] = []

    def intruder() -> None:
        client = ModbusClient(host="127.0.0.1", port=port, timeout=2, auto_open=True)
        life = 0
        while not stop.is_set():
            life = (life + 1) & 0xFFFF
            session = (client.read_input_registers(1, 1) or [0])[0]
            answers.append(bool(client.write_single_register(1, session)))  # the claim as every PLC makes it
            answers.append(bool(client.write_multiple_registers(0, [life, session, 0, 0, 0, 0])))
            answers.append(bool(client.write_multiple_registers(67, [0xFF80, 0x0200, 0x4000])))  # X1 minus
            stop.wait(0.01)
        client.close()

    thread = threading.Thread(target=intruder, daemon=True)
    s7 = snap7.client.Client()
    try:
        simulation = Simulation(TURN_MILL, "basic_machine", connector=link, pacer=pacer)
        assert _run_until(simulation, "X1.basic.in.posCtrlActive", 10.0)
        x1 = simulation.nck.axes_by_name["X1"]
        simulation.write(simulation.plant_io.resolve("MCP.jog"), 1)
        simulation.step(round(0.1 / TURN_MILL_IPO_S))
        simulation.write(simulation.plant_io.resolve("MCP.jog"), 0)
        simulation.write(simulation.plant_io.resolve("MCP.plus.X1"), 1)
        assert _run_until(simulation, "X1.basic.in.traversPlusCommandActive", 2.0)
        _stop(plc)  # the PLC is lost in the middle of the JOG
        thread.start()
        s7.connect("127.0.0.1", 0, 1, link.s7.port)
        lowest = x1.velocity
        for _ in range(round(1.0 / TURN_MILL_IPO_S)):
            simulation.step(1)
            lowest = min(lowest, x1.velocity)
        assert lowest >= 0  # X1 never moved minus
        assert [alarm.number for alarm in simulation.nck.alarms.present] == [2000]
        with pytest.raises(Exception, match=r"0x84|cannot be performed"):
            s7.db_write(31, 4, bytearray([0x40]))  # S7 cannot claim the closed session either
        stop.set()
        while thread.is_alive():  # its last request is answered too
            link.serve()
        assert answers and not any(answers)
        claims = link.owner.refused_claims
        assert claims >= len(answers) // 3
        restarted = _plc(port)  # the PLC restarts: the session stays closed to it too
        try:
            assert _step_until(simulation, lambda: link.owner.refused_claims > claims, 15.0)
            assert link.owner.state is OwnerState.CLOSED
            link.open_new_session()  # the operator's new session: the restarted PLC claims it
            assert _step_until(simulation, lambda: link.owner.state is OwnerState.OWNED, 5.0)
            assert link.owner.claims == 2
        finally:
            _stop(restarted)
    finally:
        stop.set()
        s7.disconnect()
        _stop(plc)
        link.close()


def _s7_read(link: PlcLink, db: int, size: int) -> bytes:
    """Bytes 0 .. size - 1 of data block ``db`` as a python-snap7 client reads them from the link."""
    import snap7

    assert link.s7 is not None
    client = snap7.client.Client()
    client.connect("127.0.0.1", 0, 1, link.s7.port)
    try:
        return bytes(client.db_read(db, 0, size))
    finally:
        client.disconnect()


def test_in_lockstep_an_s7_client_sees_what_the_modbus_plc_wrote() -> None:
    """With the PLC on Modbus, DB31.DBB0..31 read over S7 are the PLC's outputs in lockstep too
    (the scan used to return before the copy, and S7 read zeros; real time: test_serve)."""
    with PlcProcess(s7=Endpoint("127.0.0.1", 0)) as plc:
        simulation = Simulation(TURN_MILL, "basic_machine", connector=plc.link)
        simulation.step(250)  # 0.5 s: the PLC has enabled the axes
        served = _s7_read(plc.link, 31, 32)
        written = bytes(simulation.interface.areas["DB31"][0:32])
        assert written[2] & 0x02  # the PLC gave X1 its controller enable (DB31.DBX2.1)
        assert served == written


def test_the_alarm_block_db100_reaches_a_modbus_client_and_an_s7_client() -> None:
    """Alarm 3000 (the PLC reports the open e-stop chain) read as input registers at DB100's place in
    the NC-to-PLC table, and as S7 data block DB100."""
    import threading

    from interfaces.links.modbus.client import ModbusLinkClient
    from interfaces.links.modbus.codec import RegisterMap, Table

    with PlcProcess(s7=Endpoint("127.0.0.1", 0)) as plc:
        simulation = Simulation(TURN_MILL, "basic_machine", connector=plc.link)
        simulation.step(100)
        simulation.write(TURN_MILL.plant_io.resolve("EStop.chainOk"), 0)
        simulation.step(50)
        assert [alarm.number for alarm in simulation.alarms()] == [3000]
        register_map = RegisterMap.build(simulation.catalog, TURN_MILL.plant_io.area_sizes())
        first = register_map.table_byte(Table.NC_TO_PLC, "DB100", 0)
        assert first is not None and first % 2 == 0
        # 68 bytes, then the software cams (DB10.DBB110-117, four registers) end the table (link version 5)
        assert first // 2 + 34 + 4 == register_map.registers(Table.NC_TO_PLC)
        assert plc.link.modbus is not None
        read: list[int] = []
        client = ModbusLinkClient("127.0.0.1", plc.link.modbus.port)
        reader = threading.Thread(target=lambda: client.connect() and read.extend(
            client.read_input_registers(first // 2, 6)))
        reader.start()
        while reader.is_alive():
            plc.link.serve()  # the server answers while the harness waits
            reader.join(0.01)
        client.close()
        # count, changes, entry 1: number (two registers), channel | axis, reaction | clearedBy
        assert read[0] == 1 and read[2:4] == [0, 3000] and read[4] == 0 and read[5] == 0x3B05
        block = _s7_read(plc.link, 100, 12)
        assert block == bytes(simulation.nck.image.area("DB100")[0:12])
        assert int.from_bytes(block[4:8], "big") == 3000 and block[11] == 5


class _TablesClient:
    """The PLC's Modbus client, answered by a link's tables directly (no request on the wire)."""

    def __init__(self, link: PlcLink):
        self.link = link

    def read_input_registers(self, address: int, count: int) -> list[int]:
        registers = [0] * 65536
        assert self.link.tables.answer(4, address, count, registers, None) is None
        return registers[address: address + count]

    def write_registers(self, address: int, values: list[int]) -> None:
        assert self.link.tables.answer(16, address, len(values), [0] * 65536, values) is None

    write_registers_last_first = write_registers


def test_a_new_boot_id_restarts_the_plc_program_though_the_session_number_is_the_same() -> None:
    """Sessions count from 1 in every harness process: a PLC that carried on across a server restart
    because it saw session 1 again would run on stale state.  The boot id (IR 12) tells them apart."""
    from interfaces.links.modbus.plc_end import RemotePlc
    from plc_stub.programs import FACTORIES

    first = PlcLink(LinkMode.FREE_RUNNING, modbus=Endpoint("127.0.0.1", 0), boot_id=111)
    second = PlcLink(LinkMode.FREE_RUNNING, modbus=Endpoint("127.0.0.1", 0))
    try:
        assert 1 <= second.boot_id <= 0xFFFF
        second.boot_id = 222  # the random one, made known for the test
        client = _TablesClient(first)
        plc = RemotePlc(client, FACTORIES)  # type: ignore[arg-type]
        Simulation(TURN_MILL, "basic_machine", connector=first).step(5)
        assert plc.poll() and plc.session is not None and (plc.session.number, plc.session.boot_id) == (1, 111)
        started = plc.session
        assert plc.poll() and plc.session is started  # the same session: no restart
        Simulation(TURN_MILL, "basic_machine", connector=second).step(5)  # the "restarted server": session 1 again
        client.link = second
        assert plc.poll() and plc.session is not started
        assert (plc.session.number, plc.session.boot_id) == (1, 222)
        assert second.holding_register(1) == 1  # the PLC reported session 1 ready to the new server
    finally:
        first.close()
        second.close()


def test_the_time_base_registers_count_the_nc_cycles_one_plc_period_per_granted_scan(process: PlcProcess) -> None:
    """IR 4..5 (docs/modbus.md, time base): the NC's IPO cycles of the session at each exchange; every
    granted scan advances them by IR 7 cycles, whatever the wall clock does."""
    link = process.link
    simulation = Simulation(TURN_MILL, "basic_machine", connector=link)
    period = TURN_MILL.plc_cycle_ipo
    assert link.tables.nc_to_plc[14:16] == period.to_bytes(2, "big")  # IR 7: the PLC period in IPO cycles
    for scans in range(1, 40):
        simulation.step(period)
        grant = int.from_bytes(link.tables.nc_to_plc[6:8], "big")  # IR 3
        cycles = int.from_bytes(link.tables.nc_to_plc[8:12], "big")  # IR 4..5, high word first
        assert (grant, cycles) == (scans + 1, simulation.nck.cycle) == (scans + 1, scans * period)


def test_a_connection_lost_within_a_session_keeps_the_plc_program_and_the_trace() -> None:
    """The harness answers the PLC only while it waits for a scan; when it does not for longer than the
    PLC's answer time-out (here 0.3 s; a busy machine, a long first scan), the PLC reconnects.  Within
    the same session and boot id its program carries on and a lost write is sent again, so the run
    stays the in-process run cycle for cycle (a restart used to shift it by a scan)."""
    import time

    def run(simulation: Simulation, stall_at: set[int]) -> list[object]:
        seen = []
        for chunk in range(60):  # 0.6 s in PLC periods; the keys as an operator presses them
            if chunk in stall_at:
                time.sleep(0.8)  # the harness busy elsewhere: no Modbus answers
            key = {2: ("MCP.mda", 1), 6: ("MCP.mda", 0), 10: ("MCP.jog", 1), 14: ("MCP.jog", 0)}.get(chunk)
            if key is not None:
                simulation.write(simulation.plant_io.resolve(key[0]), key[1])
            simulation.step(TURN_MILL.plc_cycle_ipo)
            seen.append(images(simulation))
        return seen

    with PlcProcess(arguments=("--answer-timeout", "0.3")) as plc:
        linked = run(Simulation(TURN_MILL, "basic_machine", connector=plc.link), stall_at={0, 3, 12, 30})
        sessions = plc.link.session
    assert sessions == 1
    assert linked == run(Simulation(TURN_MILL, "basic_machine"), stall_at=set())
