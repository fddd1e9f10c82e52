"""``vc map`` for the CAN link: the CSV map's ``can_id`` and ``can_start_bit``, and the DBC file of
``--format dbc`` decoding live frames between the harness and ``python -m plc_stub --can`` to the
values of the process image."""

from __future__ import annotations

import csv
import io
import threading
from pathlib import Path

import cantools
import pytest
from cantools.database.can import Database

from interfaces.image import decode
from interfaces.links.can.bus import CanBus
from interfaces.links.can.codec import Frame
from interfaces.links.can.dbc import dbc_name
from interfaces.signals import SignalRef
from vc.cli.main import main
from vc.config.loader import load_machine
from vc.harness.external_plc import CanPlcProcess
from vc.harness.links.can import CanLinkedPlc
from vc.simulation.lockstep import Simulation

ROOT = Path(__file__).resolve().parents[3]
MACHINE = str(ROOT / "scenarios" / "machines" / "turn_mill.yaml")


def test_the_csv_map_gives_the_frame_and_the_start_bit(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["map", "--machine", MACHINE, "--format", "csv"]) == 0
    rows = {row["symbol"]: row for row in csv.DictReader(io.StringIO(capsys.readouterr().out))}
    assert (rows["X1.basic.in.enc1Synchronized"]["can_id"], rows["X1.basic.in.enc1Synchronized"]["can_start_bit"]) == (
        "0x20B", "4")  # DB31.DBX60.4: byte 0, bit 4 of the frame with DB31.DBB60..103
    assert (rows["X1.basic.out.refPointApproachCam"]["can_id"],
            rows["X1.basic.out.refPointApproachCam"]["can_start_bit"]) == ("0x408", "103")  # DB31.DBX12.7
    assert (rows["MCP.jog"]["can_id"], rows["MCP.jog"]["can_start_bit"]) == ("0x200", "2")  # I0.2
    assert (rows["LINK.scanDone"]["can_id"], rows["LINK.scanDone"]["can_start_bit"]) == ("", "")


def dbc(capsys: pytest.CaptureFixture[str]) -> Database:
    assert main(["map", "--machine", MACHINE, "--format", "dbc"]) == 0
    database = cantools.database.load_string(capsys.readouterr().out, "dbc", strict=False)
    assert isinstance(database, Database)
    return database


class Listener:
    """A third node on the bus that keeps the last frame of every identifier."""

    def __init__(self, bus: CanBus):
        self.bus = bus
        self.last: dict[int, Frame] = {}
        self.stopping = threading.Event()
        self.thread = threading.Thread(target=self._listen, daemon=True)
        self.thread.start()

    def _listen(self) -> None:
        while not self.stopping.is_set():
            frame = self.bus.receive(0.05)
            if frame is not None:
                self.last[frame.can_id] = frame

    def stop(self) -> None:
        self.stopping.set()
        self.thread.join(5)
        self.bus.close()


def test_the_dbc_file_decodes_live_frames_to_the_values_of_the_image(capsys: pytest.CaptureFixture[str]) -> None:
    database = dbc(capsys)
    data_frames = [message for message in database.messages
                   if message.name not in ("NC_LINK", "PLC_LINK", "NC_DESCRIPTION")]
    with CanPlcProcess() as process:
        listener = Listener(CanBus(process.bus, listen=[message.frame_id for message in database.messages]))
        try:
            simulation = process.simulation(load_machine(MACHINE), "basic_machine")
            for key in ("MCP.jog", "MCP.plus.X1"):
                simulation.write(simulation.plant_io.resolve(key), 1)
                simulation.step(150)  # X1 moves: words and reals change
            plc = simulation.plc
            assert isinstance(plc, CanLinkedPlc)
            for _ in range(100):  # the listener follows the last exchange
                last = listener.last.get(0x101)
                if last is not None and int.from_bytes(last.data[4:6], "big") == plc.scans:
                    break
                listener.stopping.wait(0.05)
        finally:
            listener.stop()
        areas = {**simulation.interface.areas, **simulation.plant_image.areas}
        checked = 0
        for message in data_frames:
            frame = listener.last[message.frame_id]
            values = database.decode_message(frame.can_id, frame.data, decode_choices=False)
            for signal in message.signals:
                if signal.name == "checksum":
                    continue
                ref = lookup(simulation, signal.comment)
                assert dbc_name(ref.name) == signal.name
                assert values[signal.name] == pytest.approx(decode(areas[ref.area_key], ref)), ref.name
                checked += 1
        assert checked == len(simulation.catalog.signals) + len(simulation.plant_io.points)
        assert simulation.read(simulation.catalog.resolve("X1.basic.in.traversPlusCommandActive")) == 1


def lookup(simulation: Simulation, comment: object) -> SignalRef:
    """The signal a DBC comment names: ``<symbol> <address>: <meaning>``."""
    symbol = str(comment).split(" ", 1)[0]
    point = simulation.plant_io.by_name(symbol)
    return point.ref() if point is not None else simulation.catalog.resolve(symbol)


def test_run_takes_a_can_bus_only_with_the_can_link(capsys: pytest.CaptureFixture[str]) -> None:
    scenario = str(ROOT / "scenarios" / "foundation" / "jog_traverse.yaml")
    assert main(["run", "--can-bus", "udp_multicast", scenario]) == 2
    assert "--can-bus needs --link can" in capsys.readouterr().err
    assert main(["run", "--link", "can", "--can-bus", "fieldbus", scenario]) == 2
    assert "vc run: 'fieldbus': the bus is one of virtual, udp_multicast, socketcan" in capsys.readouterr().err
