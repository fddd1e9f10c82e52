"""The session-takeover part: a lost PLC's session against every client of the same host that tries it.

``vc serve --realtime --s7`` plays a scenario that holds X1's plus key in JOG; the built-in PLC
(``python -m plc_stub``) owns the session and moves X1.  The part kills the PLC in the middle of
that motion and then makes as many attempts as asked to act in its place, each over a connection
of its own or a long-lived one, as a process of the same host can:

* the claim every PLC of the protocol makes, with the session number read from input register 1:
  holding register 1 = the session by FC 6, by FC 16 with the sign of life, by FC 23; with no session
  key, with random ones;
* the sign of life alone (holding register 0), X1's minus key (FC 16, FC 5, FC 22);
* S7 writes of X1's minus key and of the other PLC-to-NC bytes (the first writer owned the link).

Every attempt must be refused (exception 01, the S7 error).  Rule violations: an attempt taken;
X1 moving minus (its traverse-minus bit, read over Modbus throughout); alarm 2000 missing from the
alarm list (DB100) a second after the kill or gone later (somebody kept the sign of life alive).
Then the PLC restarts: its claim must be refused as well (the session stays closed), and after the
operator's new session (SIGUSR1 to ``vc serve``) it must own session 2; a PLC that never does is a
hang.  Before the session closed on the PLC's loss, the first echo of the session number took the
link (docs/modbus.md, "Threat model").
"""

from __future__ import annotations

import random
import signal
import struct
import tempfile
import threading
import time as wallclock
from dataclasses import dataclass, field
from pathlib import Path

import snap7

from interfaces.catalog import load_catalog
from interfaces.links.errors import LinkError
from interfaces.links.modbus.client import ModbusLinkClient
from interfaces.links.modbus.codec import Location, RegisterMap
from interfaces.signals import expand
from vc.bench.robustness.campaign import CampaignSettings, Row, Say
from vc.bench.robustness.modbus_fuzz import _frame, _Wire
from vc.bench.robustness.processes import Child, ServedNc
from vc.config.loader import load_machine

PLC_SIGN_OF_LIFE_ALARM = 2000
ALARM_AFTER_S = 1.0  # alarm 2000 must be present this long after the kill (MD10100 is 0.1 s)
WATCH_PERIOD_S = 0.02
ATTEMPT_PAUSE_S = 0.005  # between two attempts: the full campaign's 2,000 go on for about ten seconds
RESTART_TIMEOUT_S = 60.0
# the operator's panel for the part: X1 moves plus in JOG until the part ends
SCENARIO = """name: X1 moves plus in JOG while the PLC is lost (the robustness campaign's takeover part)
machine: turn_mill
steps:
  - wait: {until: "X1.basic.in.posCtrlActive == 1", timeout: 20s}
  - press: MCP.jog
  - hold: MCP.plus.X1
  - wait: 3600s
"""


@dataclass(slots=True)
class _Places:
    """Where the part reads and writes, from turn_mill's register map."""

    minus_key: Location  # X1.basic.out.traversKeyMinus
    plus_active: Location  # X1.basic.in.traversPlusCommandActive
    minus_active: Location  # X1.basic.in.traversMinusCommandActive
    alarms: list[Location]  # ALARMS.entry[n].in.number

    @classmethod
    def of_turn_mill(cls) -> _Places:
        machine = load_machine("turn_mill")
        catalog = expand(load_catalog(), machine.layout)
        register_map = RegisterMap.build(catalog, machine.plant_io.area_sizes())

        def place(symbol: str) -> Location:
            found = register_map.location(catalog.resolve(symbol))
            assert found is not None, symbol
            return found

        return cls(place("X1.basic.out.traversKeyMinus"), place("X1.basic.in.traversPlusCommandActive"),
                   place("X1.basic.in.traversMinusCommandActive"),
                   [place(f"ALARMS.entry[{entry}].in.number") for entry in range(1, 9)])


@dataclass(slots=True)
class _Watch:
    """What a reader sees while the attempts go on: X1 moving minus, alarm 2000 missing."""

    places: _Places
    client: ModbusLinkClient
    samples: int = 0
    minus: int = 0  # samples with X1's traverse-minus bit set
    without_alarm: int = 0  # samples without alarm 2000, from ALARM_AFTER_S after the kill
    stop: threading.Event = field(default_factory=threading.Event)

    def bit(self, registers: list[int], where: Location) -> bool:
        assert where.register_bit is not None
        return bool(registers[where.register] >> where.register_bit & 1)

    def alarm_numbers(self, registers: list[int]) -> set[int]:
        return {registers[where.register] << 16 | registers[where.register + 1] for where in self.places.alarms}

    def read(self) -> list[int]:
        last = max(where.register + 2 for where in self.places.alarms)
        values: list[int] = []
        while len(values) < last:
            values += self.client.read_input_registers(len(values), min(125, last - len(values)))
        return values

    def run(self, killed_at: float) -> None:
        while not self.stop.is_set():
            try:
                registers = self.read()
            except LinkError:
                self.stop.wait(WATCH_PERIOD_S)
                continue
            self.samples += 1
            self.minus += self.bit(registers, self.places.minus_active)
            if wallclock.monotonic() - killed_at > ALARM_AFTER_S:
                self.without_alarm += PLC_SIGN_OF_LIFE_ALARM not in self.alarm_numbers(registers)
            self.stop.wait(WATCH_PERIOD_S)


@dataclass(slots=True)
class _Intruder:
    """The attempts (module docstring); each refused one is as it must be."""

    modbus_port: int
    s7_port: int
    places: _Places
    random: random.Random
    attempts: int = 0
    taken: int = 0
    unanswered: int = 0
    _transaction: int = 0
    _wire: _Wire | None = None
    _reader: ModbusLinkClient | None = None

    def session(self) -> int:
        if self._reader is None:
            self._reader = ModbusLinkClient("127.0.0.1", self.modbus_port, timeout_s=5.0)
            self._reader.connect()
        try:
            return self._reader.read_input_registers(1, 1)[0]  # what every client reads: the session number
        except LinkError:
            self._reader.close()
            self._reader = None
            return 1

    def pdus(self, session: int) -> list[bytes]:
        key = [self.random.randrange(65536) for _ in range(4)]
        register, bit = self.places.minus_key.register, self.places.minus_key.register_bit or 0
        coil = self.places.minus_key.coil or 0
        life = self.random.randrange(1, 65536)
        return [
            struct.pack(">BHH", 6, 1, session),  # the claim as every PLC makes it, no key
            struct.pack(">BHHB6H", 16, 0, 6, 12, life, session, *key),  # with the sign of life and a guessed key
            struct.pack(">BHHB5H", 16, 1, 5, 10, session, 0, 0, 0, 0),  # the key 0
            struct.pack(">BHHHHBH", 23, 0, 1, 1, 1, 2, session),  # read/write: the claim
            struct.pack(">BHH", 6, 0, life),  # the sign of life alone
            struct.pack(">BHHBH", 16, register, 1, 2, 1 << bit),  # X1's minus key
            struct.pack(">BHH", 5, coil, 0xFF00),  # the same as a coil
            struct.pack(">BHHH", 22, register, 0xFFFF, 1 << bit),  # and as a mask write
        ]

    def modbus(self, fresh_connection: bool) -> None:
        pdus = self.pdus(self.session())
        pdu = self.random.choice(pdus)
        if fresh_connection or self._wire is None or self._wire.closed:
            if self._wire is not None:
                self._wire.close()
            self._wire = _Wire(self.modbus_port)
        self._transaction = (self._transaction + 1) & 0xFFFF
        self.attempts += 1
        if not self._wire.send(_frame(self._transaction, pdu)):
            self.unanswered += 1
            return
        answers = self._wire.answers(1)
        if not answers:
            self.unanswered += 1
            return
        self.taken += not answers[0][7] & 0x80  # a write of the lost PLC's session was taken

    def s7(self, client: snap7.client.Client) -> None:
        self.attempts += 1
        block, byte = self.random.choice(((31, 4), (31, 2), (21, 6), (10, 56), (11, 0)))
        try:
            client.db_write(block, byte, bytearray([self.random.randrange(1, 256)]))
        except Exception:
            return  # refused
        self.taken += 1

    def close(self) -> None:
        if self._wire is not None:
            self._wire.close()
        if self._reader is not None:
            self._reader.close()


def _wait_until_moving(places: _Places, port: int, timeout_s: float = 60.0) -> bool:
    client = ModbusLinkClient("127.0.0.1", port, timeout_s=5.0)
    deadline = wallclock.monotonic() + timeout_s
    try:
        client.connect()
        while wallclock.monotonic() < deadline:
            registers = client.read_input_registers(0, places.plus_active.register + 1)
            assert places.plus_active.register_bit is not None
            if registers[places.plus_active.register] >> places.plus_active.register_bit & 1:
                return True
            wallclock.sleep(0.05)
    finally:
        client.close()
    return False


def run_session_takeover(settings: CampaignSettings, say: Say) -> Row:
    """The part's row (module docstring)."""
    attempts = max(60, settings.modbus_frames // 50)
    places = _Places.of_turn_mill()
    generator = random.Random(settings.seed)
    with tempfile.TemporaryDirectory() as directory:
        scenario = Path(directory) / "takeover.yaml"
        scenario.write_text(SCENARIO)
        with ServedNc(["--realtime", "--s7", "127.0.0.1:0", "--scenario", str(scenario), "--keep-running",
                       "--stats", "1"]) as served:
            row = _abuse(served, places, generator, attempts, say)
    return row


def _abuse(served: ServedNc, places: _Places, generator: random.Random, attempts: int, say: Say) -> Row:
    hangs = violations = 0
    if not _wait_until_moving(places, served.modbus_port):
        return Row("Session takeover", hangs=1, notes="X1 never moved: the part could not start")
    assert served.plc is not None
    served.plc.process.kill()  # the PLC is lost in the middle of the JOG
    killed_at = wallclock.monotonic()
    watch = _Watch(places, ModbusLinkClient("127.0.0.1", served.modbus_port, timeout_s=5.0))
    watch.client.connect()
    watcher = threading.Thread(target=watch.run, args=(killed_at,), daemon=True)
    watcher.start()
    intruder = _Intruder(served.modbus_port, served.s7_port, places, generator)
    s7 = snap7.client.Client()
    s7.connect("127.0.0.1", 0, 1, served.s7_port)
    try:
        for _ in range(attempts):
            if generator.random() < 0.2:
                intruder.s7(s7)
            else:
                intruder.modbus(fresh_connection=generator.random() < 0.3)
            wallclock.sleep(ATTEMPT_PAUSE_S)
        say(f"  takeover: {intruder.attempts} attempts, {intruder.taken} taken, {intruder.unanswered} unanswered;"
            f" X1 minus in {watch.minus} of {watch.samples} samples, alarm 2000 missing in {watch.without_alarm}")
        restarted = Child("plc_stub", ["-m", "plc_stub", "--modbus", f"127.0.0.1:{served.modbus_port}"])
        try:
            try:
                restarted.wait_for("refused this PLC's claim", RESTART_TIMEOUT_S, errors=True)
                refused_restart = True
            except Exception:
                refused_restart = False  # it claimed the closed session, or never tried
            violations += not refused_restart
            served.serve.process.send_signal(signal.SIGUSR1)  # the operator's new session
            try:
                served.serve.wait_for("session 2 opened", RESTART_TIMEOUT_S)
                restarted.wait_for(r"session 2 \(boot id \d+\): machine", RESTART_TIMEOUT_S, errors=True)
                took_over = True
            except Exception:
                took_over = False
            hangs += not took_over
            crashes = (not served.serve.alive) + (not restarted.alive)
            tracebacks = served.serve.tracebacks() + restarted.tracebacks()
        finally:
            restarted.stop()
    finally:
        watch.stop.set()
        watcher.join(5)
        watch.client.close()
        intruder.close()
        s7.disconnect()
    violations += intruder.taken + watch.minus + watch.without_alarm
    return Row("Session takeover (PLC killed in a JOG, then every claim a local process can make, Modbus and S7)",
               inputs=intruder.attempts, crashes=crashes, hangs=hangs, tracebacks=tracebacks,
               lost_requests=intruder.unanswered, violations=violations,
               notes=f"{intruder.taken} of {intruder.attempts} attempts taken; X1 moved minus in {watch.minus} of"
                     f" {watch.samples} samples; alarm 2000 missing in {watch.without_alarm}; the restarted PLC"
                     f" {'was refused' if refused_restart else 'took the closed session'} until the operator's"
                     f" new session, {'then owned session 2' if took_over else 'and never owned session 2'}")
