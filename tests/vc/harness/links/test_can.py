"""The PLC behind the CAN link: lockstep gives the in-process images cycle for cycle (on a virtual
bus in this process and on UDP multicast with ``python -m plc_stub --can`` in its own), sessions
restart the PLC, the frames go out with their period, the time-out monitor holds the sign of
life, a PLC that cannot run is reported, and in real time the NC watches the PLC.

Every UDP test uses a multicast channel of its own (a port the kernel hands out as free) with hop
limit 0: nothing leaves the host."""

from __future__ import annotations

import asyncio
import dataclasses
import subprocess
import sys
from collections.abc import Iterator
from pathlib import Path
from typing import Any, ClassVar

import can
import pytest
from panel_operator import images, operate

from interfaces.links.can.bus import BusSpec, CanBus, private_udp_bus, socketcan_available
from interfaces.links.errors import LinkError
from plc_stub.programs import REGISTRY
from vc.config.loader import load_machine
from vc.config.model import CanConfig, MachineConfig
from vc.harness.external_plc import CanPlcProcess
from vc.harness.links import LinkMode
from vc.harness.links import can as can_link  # the module, beside python-can (can)
from vc.harness.links.can import CanLink, CanLinkedPlc, VirtualCanPlc, virtual_can_simulation
from vc.harness.pacer import RealtimePacer
from vc.simulation.lockstep import Simulation
from vc.simulation.observables import LINK_QUANTITIES

ROOT = Path(__file__).resolve().parents[4]
TURN_MILL = load_machine(str(ROOT / "scenarios" / "machines" / "turn_mill.yaml"))
FIVE_AXIS = load_machine(str(ROOT / "scenarios" / "machines" / "mill_5axis.yaml"))


@pytest.fixture(scope="module")
def process() -> Iterator[CanPlcProcess]:
    with CanPlcProcess(first_scan_timeout_s=30.0, scan_timeout_s=10.0) as running:
        yield running


@pytest.mark.parametrize("machine", [TURN_MILL, FIVE_AXIS], ids=["turn_mill", "mill_5axis"])
def test_lockstep_on_a_virtual_bus_gives_the_in_process_images(machine: MachineConfig) -> None:
    with VirtualCanPlc() as virtual:
        linked = virtual.simulation(machine, "basic_machine")
        local = Simulation(machine, "basic_machine")
        operate(linked)
        operate(local)
        assert images(linked) == images(local)
        assert linked.nck.axes_by_name["X1"].physical > machine.axis("X1").sim.start_position + 100


def test_lockstep_over_udp_multicast_gives_the_in_process_images(process: CanPlcProcess) -> None:
    linked = process.simulation(TURN_MILL, "basic_machine")
    local = Simulation(TURN_MILL, "basic_machine")
    operate(linked)
    operate(local)
    assert images(linked) == images(local)
    assert isinstance(linked.plc, CanLinkedPlc)
    assert process.link.bus.received > 0 and process.link.bus.dropped >= process.link.bus.sent  # its own frames


def test_a_power_cycle_opens_a_new_session_and_the_plc_restarts(process: CanPlcProcess) -> None:
    linked = process.simulation(TURN_MILL, "referencing")
    local = Simulation(TURN_MILL, "referencing")
    before = process.link.session
    for simulation in (linked, local):
        simulation.step(100)
        simulation.power_cycle(0.5)
        operate(simulation)
    assert images(linked) == images(local)
    assert process.link.session == before + 1


def test_frames_every_ipo_cycle_give_the_same_images() -> None:
    with VirtualCanPlc() as virtual:
        virtual.link.configure(CanConfig(period="ipo"))
        linked = Simulation(TURN_MILL, "basic_machine", connector=virtual.link)
        local = Simulation(TURN_MILL, "basic_machine")
        sent = virtual.link.bus.sent
        operate(linked)
        operate(local)
        assert images(linked) == images(local)
        # 20 data frames and the NC link frame in every IPO cycle
        assert virtual.link.bus.sent - sent >= 21 * (linked.cycle - 1)


def test_the_time_out_monitor_holds_the_sign_of_life_of_a_plc_with_a_missing_frame() -> None:
    with VirtualCanPlc() as virtual:
        virtual.link.configure(CanConfig(timeout_s=0.02))
        simulation = Simulation(TURN_MILL, "basic_machine", connector=virtual.link)
        simulation.step(50)
        plc = simulation.plc
        assert isinstance(plc, CanLinkedPlc) and plc.missing == []
        life = plc.sign_of_life
        simulation.inject_link_fault("loss", 1_000_000, ("plc_to_nc",), ("DB31",))
        simulation.step(15)  # 30 ms: X1's frame is older than the 20 ms time-out
        assert plc.missing == [0x408] and plc.sign_of_life != life  # changed until the time-out
        held = plc.sign_of_life
        simulation.step(10)
        assert plc.sign_of_life == held
        simulation.step(60)
        assert 2000 in [alarm.number for alarm in simulation.alarms()]  # MD10100 = 0.1 s after the last change


def test_the_links_counters_as_scenario_quantities() -> None:
    """Every PLC period the NC sends 20 data frames and its link frame and takes the PLC's 15 and
    its link frame; nothing lost, every frame fresh."""
    with VirtualCanPlc() as virtual:
        simulation = virtual.simulation(TURN_MILL, "basic_machine")
        simulation.step(50)
        before = {name: simulation.link_quantity(name) for name in LINK_QUANTITIES}
        simulation.step(50)  # ten PLC periods
        after = {name: simulation.link_quantity(name) for name in LINK_QUANTITIES}
    assert after["framesSent"] - before["framesSent"] == 210
    assert after["framesTaken"] - before["framesTaken"] == 160
    assert after["plcSignOfLife"] - before["plcSignOfLife"] == 10
    assert all(after[name] == 0 for name in ("lostToPlc", "lostFromPlc", "delayedToPlc", "delayedFromPlc",
                                             "plcFrameAge", "timedOut", "plcMissesNcFrames", "busState",
                                             "transmitErrors", "busOffs"))


def test_a_link_fault_needs_the_can_link() -> None:
    simulation = Simulation(TURN_MILL, "basic_machine")
    with pytest.raises(LinkError) as caught:
        simulation.inject_link_fault("loss", 100_000)
    assert str(caught.value) == ("a link fault or quantity needs the PLC behind the CAN link; this simulation has a PLC"
                                 " without a bus (in process, Modbus TCP)")


def test_a_plc_that_cannot_run_the_program_is_reported() -> None:
    bus = private_udp_bus()
    child = subprocess.Popen([sys.executable, "-m", "plc_stub", "--can", str(bus), "--program", "nonesuch"],
                             stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)

    def ended() -> str | None:
        if child.poll() is None:
            return None
        return (child.stderr.read() if child.stderr else b"").decode()

    link = CanLink(LinkMode.LOCKSTEP, bus, first_scan_timeout_s=30.0, peer_ended=ended)
    try:
        with pytest.raises(LinkError) as caught:
            Simulation(TURN_MILL, "basic_machine", connector=link)
        assert "no PLC has started session 1 on the CAN bus" in str(caught.value)
        assert f"cannot run: no PLC program 'nonesuch' (known: {', '.join(sorted(REGISTRY))})" in str(caught.value)
        assert child.wait(10) == 2
    finally:
        link.close()
        if child.poll() is None:
            child.kill()
        child.wait()
        if child.stderr is not None:
            child.stderr.close()


@pytest.mark.realtime
def test_in_real_time_the_nc_watches_the_plc_on_the_bus() -> None:
    # The PLC watches the NC's frames on its own clock: on a host shared with other work the harness
    # may stall for longer than 50 ms, and the PLC would rightly react (emergency stop).
    machine = dataclasses.replace(TURN_MILL, can=dataclasses.replace(TURN_MILL.can, timeout_s=1.0))
    with CanPlcProcess(LinkMode.FREE_RUNNING) as running:
        pacer = RealtimePacer(asyncio.new_event_loop(), Simulation.ipo_seconds(machine), 1.0)
        simulation = running.simulation(machine, "basic_machine", pacer=pacer)
        simulation.step(250)  # the PLC process starts: MD10120 (50 s) allows it
        simulation.step(500)  # one second with the PLC scanning on its own clock
        assert [alarm.number for alarm in simulation.alarm_history()] == []
        assert isinstance(simulation.plc, CanLinkedPlc) and simulation.plc.missing == []
        assert running.process is not None
        running.process.kill()  # the PLC stops talking
        simulation.step(100)  # 0.2 s: longer than MD10100 (0.1 s)
        assert 2000 in [alarm.number for alarm in simulation.alarms()]
        pacer.loop.close()


class _Interface(can.BusABC):
    """A stand-in for a SocketCAN interface whose controller state the test sets."""

    def __init__(self) -> None:
        super().__init__(channel="fake")
        self.reported = can.BusState.ACTIVE
        self.sent = 0

    @property
    def state(self) -> can.BusState:
        return self.reported

    def send(self, msg: can.Message, timeout: float | None = None) -> None:
        self.sent += 1

    def _recv_internal(self, timeout: float | None) -> tuple[can.Message | None, bool]:
        return None, False


def test_free_running_the_nc_sends_nothing_while_the_interface_reports_bus_off() -> None:
    interface = _Interface()
    spec = BusSpec("socketcan", "can0")
    link = CanLink(LinkMode.FREE_RUNNING, spec, node=CanBus(spec, opened=interface))
    simulation = Simulation(TURN_MILL, "basic_machine", connector=link)
    plc = simulation.plc
    assert isinstance(plc, CanLinkedPlc)
    simulation.step(10)
    sent = interface.sent
    assert sent > 0 and plc.quantity("busState") == 0 and plc.quantity("lostToPlc") == 0
    interface.reported = can.BusState.ERROR
    simulation.step(10)  # two periods: 20 data frames and the link frame each, none sent
    assert interface.sent == sent and plc.quantity("lostToPlc") == 42 and plc.quantity("busState") == 2
    interface.reported = can.BusState.ACTIVE
    simulation.step(5)
    assert interface.sent == sent + 21 and plc.quantity("busState") == 0


def test_vc_serve_on_a_can_bus_runs_a_scenario_with_a_plc_process() -> None:
    bus = private_udp_bus()
    plc = subprocess.Popen([sys.executable, "-m", "plc_stub", "--can", str(bus), "--connect-timeout", "60"],
                           stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True, cwd=ROOT)
    try:
        served = subprocess.run(
            [sys.executable, "-m", "vc.cli.main", "serve", "--can", str(bus), "--scenario",
             "scenarios/referencing/incremental_jog_ref_falling_edge.yaml", "--duration", "6"],
            capture_output=True, text=True, timeout=120, cwd=ROOT)
    finally:
        plc.terminate()
        _, errors = plc.communicate(timeout=10)
    assert served.returncode == 0, served.stdout + served.stderr
    assert f"CAN bus {bus}, link frames from 0x100" in served.stdout and "PASS" in served.stdout
    assert "session 1: machine turn_mill, program basic_machine, lockstep, 35 data frames" in errors


def test_vc_serve_takes_a_can_bus_or_the_servers_not_both() -> None:
    result = subprocess.run([sys.executable, "-m", "vc.cli.main", "serve", "--can", "udp_multicast", "--modbus",
                             "127.0.0.1:5020"], capture_output=True, text=True, timeout=30, cwd=ROOT)
    assert result.returncode == 2
    assert "serve either a CAN bus or Modbus TCP / S7, not both" in result.stderr


@pytest.mark.skipif(not socketcan_available("vcan0"), reason="this kernel has no SocketCAN / no vcan0 interface")
def test_lockstep_over_socketcan_gives_the_in_process_images() -> None:
    with CanPlcProcess(bus=BusSpec("socketcan", "vcan0")) as running:
        linked = running.simulation(TURN_MILL, "basic_machine")
        local = Simulation(TURN_MILL, "basic_machine")
        operate(linked)
        operate(local)
        assert images(linked) == images(local)


class _RecordedBus(CanBus):
    """A node that remembers it was opened and whether it was closed."""

    opened: ClassVar[list[_RecordedBus]] = []

    def __init__(self, *arguments: Any, **options: Any) -> None:
        super().__init__(*arguments, **options)
        self.closed = False
        _RecordedBus.opened.append(self)

    def close(self) -> None:
        self.closed = True
        super().close()


@pytest.fixture()
def recorded_buses(monkeypatch: pytest.MonkeyPatch) -> list[_RecordedBus]:
    _RecordedBus.opened = []
    monkeypatch.setattr(can_link, "CanBus", _RecordedBus)
    return _RecordedBus.opened


def test_a_virtual_plc_whose_setup_fails_closes_the_bus_it_opened(recorded_buses: list[_RecordedBus],
                                                                  monkeypatch: pytest.MonkeyPatch) -> None:
    def no_second_node(*arguments: object, **options: object) -> CanLink:
        raise LinkError("cannot open the CAN bus")

    monkeypatch.setattr(can_link, "CanLink", no_second_node)
    with pytest.raises(LinkError):
        VirtualCanPlc()
    assert len(recorded_buses) == 1 and recorded_buses[0].closed


def test_a_simulation_behind_a_virtual_bus_that_cannot_start_closes_both_nodes(
        recorded_buses: list[_RecordedBus], monkeypatch: pytest.MonkeyPatch) -> None:
    def refused(*arguments: object, **options: object) -> Simulation:
        raise ValueError("the machine cannot power on")

    monkeypatch.setattr(can_link, "Simulation", refused)
    with pytest.raises(ValueError):
        virtual_can_simulation(TURN_MILL, "basic_machine")
    assert len(recorded_buses) == 2 and all(bus.closed for bus in recorded_buses)


def test_the_plc_command_names_a_link_id_other_than_the_default() -> None:
    spec = BusSpec("udp_multicast", "239.0.0.1")
    node = CanBus(BusSpec("virtual", "plc-command"))
    try:
        link = CanLink(LinkMode.LOCKSTEP, spec, node=node)
        assert link.plc_command == f"python -m plc_stub --can {spec}"
        moved = CanConfig(dataclasses.replace(CanConfig().settings, link_id=0x300))
        link.configure(moved)
        assert link.plc_command == f"python -m plc_stub --can {spec} --can-link-id 0x300"
    finally:
        node.close()
