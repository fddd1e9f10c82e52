"""``vc map --format guide``: how to connect OpenPLC or CODESYS to ``vc serve`` over Modbus TCP.

The guide is Markdown generated from the machine's register map
(:class:`interfaces.links.modbus.codec.RegisterMap`) and its commissioning facts: every register, bit,
device range and channel in it is computed, none is typed by hand, so it cannot drift from what the
server does.  The sections on what a PLC must know besides the addresses (time base, sessions,
referencing and wiring, the NC's rules, the alarm list, served scenarios) are in
:mod:`vc.cli.plc_facts_guide`.  ``docs/modbus.md`` is the guide of the default machine; a test
keeps it current.

Facts about the PLCs the arithmetic relies on:

* Modbus itself: one FC 3/4 response carries at most 125 registers, one FC 16 request at most 123
  (libmodbus, which OpenPLC uses, refuses larger requests before sending them).
* OpenPLC Runtime v3 ("Slave Devices" page): the slave devices' discrete inputs, coils, input
  registers (then holding registers read) and holding registers written are numbered on from
  ``%IX100.0``, ``%QX100.0``, ``%IW100`` and ``%QW100`` in the order of the device list;
  its polling thread copies 400 entries of each kind (``MAX_MB_IO``), so ``%IX100.0`` ..
  ``%IX149.7`` and ``%IW100`` .. ``%IW499`` (outputs alike) are all a program can reach.
* CODESYS (Modbus TCP Master, Modbus TCP Slave, "Modbus Slave Channel"): a channel is one
  request with an offset and a length; its I/O mapping is an array of WORD.
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from dataclasses import dataclass

from interfaces.commissioning import Commissioning
from interfaces.exports.client_setups import (
    OPENPLC_FIRST,
    OPENPLC_SLAVE_ENTRIES,
    RegisterBlock,
    codesys_channels,
    openplc_devices,
)
from interfaces.links.modbus.access import DEFAULT_IDLE_TIMEOUT_S, DEFAULT_MAX_CLIENTS
from interfaces.links.modbus.codec import (
    DESCRIPTION_REGISTER,
    LINK_REGISTERS,
    LINK_VERSION,
    MASK_WRITE_REGISTER,
    MODE_FREE_RUNNING,
    MODE_LOCKSTEP,
    READ_COILS,
    READ_DISCRETE_INPUTS,
    READ_HOLDING,
    READ_INPUT,
    READ_LIMIT,
    READ_WRITE_REGISTERS,
    SESSION_KEY_REGISTERS,
    WRITE_COIL,
    WRITE_COILS,
    WRITE_LIMIT,
    WRITE_REGISTER,
    WRITE_REGISTERS,
    LinkHolding,
    LinkInput,
    Location,
    RegisterMap,
    Table,
    display_number,
)
from interfaces.links.modbus.server import ANSWER_LIMIT, PENDING_LIMIT, RECEIVE_LIMIT, SERVED_FUNCTIONS
from interfaces.plant_io import PlantIoMap
from interfaces.signal_map import LINK_ROWS
from interfaces.signals import ExpandedCatalog, SignalRef, SignalType
from vc.cli.plc_facts_guide import (
    GEAR_SIGNALS,
    alarm_section,
    commissioning_section,
    nc_rules_section,
    served_scenario_section,
    time_and_sessions_section,
)
from vc.config.machine_data import MdDef
from vc.config.md_dictionary import PLC_CYCLIC_TIMEOUT, PLC_RUNNINGUP_TIMEOUT
from vc.core.nck.nck import PLC_NOT_STARTED_ALARM, PLC_SIGN_OF_LIFE_ALARM

OPENPLC_POLLING_MS = 10  # the slave devices' polling period to set (OpenPLC's default of 100 ms is too slow)
CODESYS_CYCLE_MS = 10  # the channels' cycle time: the PLC period of the example machines
SERVER_HOST, SERVER_PORT = "127.0.0.1", 5020  # what ``vc serve --modbus`` listens on by default

# The signals a basic machine PLC program needs (what plc_stub's basic_machine drives and reads),
# by instance kind; the guide resolves each in the catalogue, so a renamed signal fails the test.
NCK_SIGNALS = ("basic.out.emergencyStop", "basic.out.emergencyStopAck", "basic.in.emergencyStopActive",
               "basic.in.ncReady", "basic.in.alarmActive")
MODE_GROUP_SIGNALS = ("basic.out.autoMode", "basic.out.mdaMode", "basic.out.jogMode", "basic.out.refPoint",
                      "basic.out.reset", "basic.in.autoModeActive", "basic.in.mdaModeActive",
                      "basic.in.jogModeActive", "basic.in.refPointActive", "basic.in.ready")
CHANNEL_SIGNALS = ("basic.out.ncStart", "basic.out.ncStop", "basic.out.reset", "basic.out.disableFeed",
                   "basic.out.pathFeedrateOvr", "basic.out.pathFeedrateOvrFactor", "basic.out.pathRapidTraversOvr",
                   "basic.out.pathRapidTraversOvrFactor", "basic.in.stateReset", "basic.in.stateActive",
                   "basic.in.stateInterrupted", "basic.in.progStateRunning", "basic.in.progStateStopped",
                   "basic.in.progStateAborted", "basic.in.allAxesReferenced", "basic.in.alarmActive")
AXIS_SIGNALS = ("basic.out.enc1Activation", "basic.out.enableCtrl", "drive.out.enablePulses",
                "basic.out.followUpMode", "basic.out.enableOvr", "basic.out.feedrateOvrFactor",
                "basic.out.traversKeyMinus", "basic.out.traversKeyPlus", "basic.out.enableRapidTravers",
                "basic.out.refPointApproachCam", "basic.out.hwLimitSwitchMinus", "basic.out.hwLimitSwitchPlus",
                "basic.in.enc1Synchronized", "basic.in.isStationary")


@dataclass(frozen=True, slots=True)
class GuideSignal:
    """A signal of the guide's tables and where it lies."""

    symbol: str
    ref: SignalRef
    location: Location


def guide_signals(catalog: ExpandedCatalog, plant_io: PlantIoMap, register_map: RegisterMap,
                  geared: Sequence[str] = ()) -> list[GuideSignal]:
    """The signals of a basic machine PLC program, the gear stage change of the spindles with a
    gearbox (``geared``), then every plant I/O point of the machine."""
    layout = catalog.layout
    symbols = [f"NC.{name}" for name in NCK_SIGNALS] + [f"MODEGROUP.{name}" for name in MODE_GROUP_SIGNALS]
    symbols += [f"{channel}.{name}" for channel in layout.channels for name in CHANNEL_SIGNALS]
    symbols += [f"{axis}.{name}" for axis in layout.axes for name in AXIS_SIGNALS]
    symbols += [f"{axis}.{name}" for axis in geared for name in GEAR_SIGNALS]
    refs = [(symbol, catalog.resolve(symbol)) for symbol in symbols]
    refs += [(point.name, plant_io.resolve(point.name)) for point in plant_io.points]
    return [GuideSignal(symbol, ref, _located(register_map, ref)) for symbol, ref in refs]


def _located(register_map: RegisterMap, ref: SignalRef) -> Location:
    location = register_map.location(ref)
    if location is None:
        raise ValueError(f"{ref.name} ({ref.address}) lies in no Modbus table")
    return location


# ---------------------------------------------------------------------------------- text helpers


def _table(header: Sequence[str], rows: Iterable[Sequence[object]]) -> list[str]:
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    lines += ["| " + " | ".join(str(cell).replace("|", "\\|") for cell in row) + " |" for row in rows]
    return lines


def _bits(ref: SignalRef, location: Location) -> str:
    """Which bits of the register(s) hold the value."""
    if location.register_bit is not None:
        if ref.bits == 1:
            return f"bit {location.register_bit}"
        return f"bits {location.register_bit}..{location.register_bit + ref.bits - 1}"
    if location.registers == 1 and ref.type is SignalType.BYTE:
        return f"bits {location.byte_bit}..{location.byte_bit + 7} ({'high' if location.byte_bit else 'low'} byte)"
    if location.registers == 1:
        return "whole word"
    return f"{location.registers} words, high word first"


def _span(prefix: str, first: int, last: int) -> str:
    return f"{prefix}{first}" if first == last else f"{prefix}{first}..{last}"


def _register_name(location: Location) -> str:
    kind = "IR " if location.table is Table.NC_TO_PLC else "HR "
    return _span(kind, location.register, location.register + location.registers - 1)


def _openplc_word(table: Table, register: int) -> str:
    return f"%{'I' if table is Table.NC_TO_PLC else 'Q'}W{OPENPLC_FIRST + register}"


def _openplc_words(location: Location) -> str:
    first = _openplc_word(location.table, location.register)
    if location.registers == 1:
        return first
    return f"{first}..{_openplc_word(location.table, location.register + location.registers - 1)}"


def _mask(bit: int) -> str:
    return f"16#{1 << bit:04X}"


def _seconds(definition: MdDef) -> str:
    assert isinstance(definition.default, int | float)
    return f"{definition.default:g} s"


def _variable(channel: RegisterBlock) -> str:
    """The ST variable a channel is mapped to in the examples: "NC in 2" -> ncIn2."""
    first, *rest = channel.name.split()
    return first.lower() + "".join(word.capitalize() for word in rest)


def _direction(location: Location) -> str:
    return "reads" if location.table is Table.NC_TO_PLC else "writes"


# ---------------------------------------------------------------------------------- the guide


def modbus_guide(machine_name: str, machine_source: str, catalog: ExpandedCatalog, plant_io: PlantIoMap,
                 commissioning: Commissioning | None = None) -> str:
    """The Markdown guide for connecting OpenPLC or CODESYS to ``vc serve`` with this machine;
    ``commissioning``: the machine's facts, for the sections on referencing, wiring and the NC's rules."""
    register_map = RegisterMap.build(catalog, plant_io.area_sizes())
    geared = tuple(facts.axis for facts in commissioning.axes if facts.gear_stages) if commissioning else ()
    signals = guide_signals(catalog, plant_io, register_map, geared)
    serve = f"vc serve --machine {machine_source} --modbus {SERVER_HOST}:{SERVER_PORT}"
    lines = [
        f"_Generated by `vc map --machine {machine_source} --format guide`; do not edit by hand"
        " (the generator is vc/cli/modbus_guide.py)._",
        "",
        f"# Connecting a PLC over Modbus TCP: machine {machine_name}",
        "",
        f"`{serve}` serves the NC/PLC interface"
        " and the plant I/O of the machine as a Modbus TCP server (any unit id). A PLC that polls it"
        " with cyclic transfers (the OpenPLC and CODESYS setups below) runs against the NC in real time:"
        f" add `--realtime`. A PLC in another host needs `--modbus 0.0.0.0:{SERVER_PORT} --allow-remote"
        " --allow <PLC address>`. The full list of addresses: `vc map --machine "
        f"{machine_source} --format csv`.",
    ]
    lines += _convention(catalog, register_map)
    lines += time_and_sessions_section()
    if commissioning is not None:
        lines += commissioning_section(commissioning, catalog.layout.channels)
        lines += nc_rules_section(catalog, register_map, commissioning, catalog.layout.channels)
    lines += alarm_section(catalog, register_map)
    lines += _sizes(register_map)
    lines += _openplc(register_map, signals, catalog, serve)
    lines += _codesys(register_map, signals, catalog)
    lines += _lockstep(register_map)
    lines += served_scenario_section(machine_source)
    return "\n".join(lines) + "\n"


def _convention(catalog: ExpandedCatalog, register_map: RegisterMap) -> list[str]:
    example_symbol = f"{catalog.layout.axes[0]}.basic.in.enc1Synchronized"
    real_symbol = f"{catalog.layout.axes[-1]}.spindle.in.sFuncValue"  # the last axis: a spindle on every machine
    real = catalog.resolve(real_symbol)
    real_at = _located(register_map, real)
    key_first, key_last = LinkHolding.SESSION_KEY, LinkHolding.SESSION_KEY + SESSION_KEY_REGISTERS - 1
    example = catalog.resolve(example_symbol)
    location = _located(register_map, example)
    assert location.register_bit is not None and location.coil is not None
    table_byte = register_map.table_byte(Table.NC_TO_PLC, example.area_key, example.address.byte)
    assert table_byte is not None
    segment = next(s for s in register_map.segments[Table.NC_TO_PLC]
                   if s.holds(example.area_key, example.address.byte))
    bit = example.address.bit
    half = "high" if table_byte % 2 == 0 else "low"
    lines = [
        "",
        "## The register convention",
        "",
        "* **Two tables.** The *NC-to-PLC table* holds what the PLC reads: the plant inputs `I` and every"
        f" NC-to-PLC byte range of the data blocks. Read it as input registers (FC {READ_INPUT}) or as discrete"
        f" inputs (FC {READ_DISCRETE_INPUTS}); Modbus has no function to write it. The *PLC-to-NC table* holds"
        f" what the PLC writes: the plant outputs `Q` and every PLC-to-NC byte range; holding registers"
        f" (FC {READ_HOLDING} read, FC {WRITE_REGISTER} and FC {WRITE_REGISTERS} write, FC {READ_WRITE_REGISTERS}"
        f" read/write) and coils (FC {READ_COILS} read, FC {WRITE_COIL} and FC {WRITE_COILS} write).",
        "* **Registers are S7 words.** Table byte 2r is the high byte of register r and byte 2r + 1 its low"
        " byte. A data-block byte keeps its parity: an even DB byte is a high byte, so `DBW n` is one whole"
        " register and `DBD n` two registers, high word first, as in the S7; a bit `DBX n.b` is bit 8 + b of"
        " its register when n is even and bit b when n is odd.",
        "* **Bits.** Table byte t, bit b is discrete input / coil number 8t + b. The bit tables count byte by"
        " byte, so a bit sits at another position in its register (S7 byte order) than in the bit numbering:"
        " discrete input / coil 16r + k is bit (k + 8) mod 16 of register r.",
        "* **Numbers.** This guide gives 0-based protocol addresses (what goes into the request and into the"
        " PLC's configuration). The 1-based display numbers of the Modicon convention are 0xxxx coils,"
        " 1xxxx discrete inputs, 3xxxx input registers and 4xxxx holding registers.",
        "",
        f"Worked example: `{example_symbol}` is `{example.address}`. {segment.area} bytes"
        f" {segment.start}..{segment.stop - 1} lie from table byte {segment.table_byte}, so"
        f" {segment.area}.DBB{example.address.byte} is table byte {table_byte}, the {half} byte of input register"
        f" {table_byte} / 2 = {location.register}. Bit {bit} of a {half} byte is register bit"
        f" {'8 + ' if half == 'high' else ''}{bit} = {location.register_bit}:",
        "",
        *_table(("view", "0-based address", "bit", "display number"), [
            ("input register", location.register, location.register_bit,
             display_number("input_register", location.register)),
            ("discrete input", f"{table_byte} x 8 + {bit} = {location.coil}", "-",
             display_number("discrete_input", location.coil)),
        ]),
        "",
        "* **Layout.** Registers 0..15 of each table are the link block (below); the data follow from"
        " register 16: the plant area first, then the byte ranges of DB10, DB11, DB19, DB21.., DB31.. in catalogue"
        " order (table *Layout* below). Each range starts on a new register; a range that begins at an odd"
        " DB byte begins in the low byte of its first register.",
        "* **Padding.** The high byte before a range that starts at an odd byte, the low byte after a range"
        " that ends at an even byte and the reserved link registers carry no signal: they read 0, a register"
        " write leaves them 0, a coil write to them is refused. Bytes inside a range that hold no catalogue"
        " signal are carried like the others.",
        "* **Write protection.** A request the tables do not hold gets exception 02 (illegal data address):"
        " any address beyond a table's size, a coil write into padding or reserved registers, a description"
        f" read beyond its length. The description (UTF-8 JSON, two bytes a register) starts at input"
        f" register {DESCRIPTION_REGISTER}.",
        f"* **The PLC owns its link.** While a session is open (IR {LinkInput.VERSION} not 0), in lockstep and in real"
        f" time, only the session's PLC writes: the connection that claimed it by writing the session (IR"
        f" {LinkInput.SESSION}) into HR {LinkHolding.SESSION_READY}, as every PLC of this protocol does when a session"
        f" starts, with its session key in HR {_span('', key_first, key_last)} (below). It keeps the link until it"
        " disconnects (a new session keeps it). Every other client may read; a write of it (FC"
        f" {WRITE_COIL}, {WRITE_REGISTER}, {WRITE_COILS}, {WRITE_REGISTERS}, {MASK_WRITE_REGISTER},"
        f" {READ_WRITE_REGISTERS}) into the PLC-to-NC table gets exception 01 (illegal function), changes nothing"
        " and is counted in `vc serve`'s statistics (an address the tables do not hold stays exception 02)."
        " So nobody but the PLC can keep its sign of life alive or move an axis."
        " `--allow-writers ADDRESS[,NETWORK]` lets the clients of those addresses write as well, without owning"
        " the link: a PLC that spreads its transfers over several connections (OpenPLC, below), a tool that"
        f" forces signals. The S7 server follows the same rule (`--s7`: its first writer owns the link, unless"
        " the Modbus PLC does).",
        "* **A lost PLC closes its session.** When the PLC's connection ends (it stopped, crashed or was restarted),"
        " no other connection may claim that session, however it learnt the number: in real time the NC raises"
        f" alarm {PLC_SIGN_OF_LIFE_ALARM} as for any silent PLC, in lockstep it waits, and `vc serve` says so. A"
        " session starts again only at the next power-on of the machine (the next scenario, a power cycle) or"
        " when the operator opens one: Enter in `vc serve`'s terminal, or `kill -USR1` with its process id; the"
        " first PLC that claims it owns the link. The PLC that held the session takes it back by itself after a"
        " lost connection when it claimed it with a *session key*: 64 random bits of its own, not all 0, in"
        f" HR {_span('', key_first, key_last)}, high word first, written in the same request as"
        f" HR {LinkHolding.SESSION_READY} (FC {WRITE_REGISTERS} of HR"
        f" {_span('', LinkHolding.SESSION_READY, key_last)});"
        f" the server never shows the key (HR {_span('', key_first, key_last)} read 0). `python -m plc_stub` and"
        " `python -m plc_awlsim` do so. With `vc serve --plc-key-file FILE` (16 hexadecimal digits; made, readable"
        " by you alone, when missing) only a claim with that key counts, in every session: give your PLC the same"
        " key (`python -m plc_stub --key-file FILE`, or the digits as `LINK.sessionKeyHigh` / `Low` in your program).",
        f"* **REAL values.** A REAL (`DBD n`, an IEEE 754 single as in the S7) spans two registers, high word first,"
        f" each word big-endian: `{real_symbol}` ({real.address}) is IR {real_at.register}..{real_at.register + 1},"
        f" and (IR {real_at.register} << 16) | IR {real_at.register + 1} is the bit pattern of the float (byte order"
        " ABCD; `mbpoll -t 3:float -B` reads it so). Cast those 32 bits to REAL (a UNION of DWORD and REAL in"
        " CODESYS, `struct.unpack('>f', struct.pack('>HH', high, low))` in Python): a conversion such as TO_REAL of"
        " the double word gives the integer's value, not the float. A DWORD lies the same way, high word first.",
        f"* **Connections.** At most {DEFAULT_MAX_CLIENTS} connections (`--max-clients`); when a client connects"
        " to a full server the connection idle the longest makes room for it (never the PLC's, never one with"
        f" a request in progress). A connection silent for {DEFAULT_IDLE_TIMEOUT_S:g} s (`--idle-timeout`) is"
        " closed. Requests are answered once each and in their order, also several in one TCP segment; function"
        f" codes other than {', '.join(str(code) for code in sorted(SERVED_FUNCTIONS))} get exception 01, counts"
        " beyond the protocol's limits exception 03, both under the request's own function code | 0x80. A client"
        f" that does not take its answers ({ANSWER_LIMIT // 1024} kB of them waiting) is served no more and not read"
        f" until it does: the server holds at most {PENDING_LIMIT} requests and {RECEIVE_LIMIT // 1024} kB of any"
        " connection's bytes, so such a client cannot grow it; it is counted in the statistics and closed after the"
        " idle time-out.",
        "",
        "**Link block.** The NC-to-PLC link block tells the PLC about the session; the PLC-to-NC link block"
        " is the PLC's handshake:",
        "",
        *_table(("register", "name", "meaning"),
                [(_span("IR " if kind == "input_register" else "HR ", register, register + count - 1),
                  f"`{symbol}`", meaning) for symbol, kind, register, count, meaning in LINK_ROWS]),
        "",
        f"**Link versions.** IR {LinkInput.VERSION} is the version of this link: of the link block and of where every"
        " signal lies. It changes with every change of either (a byte range that grows, a data block added, a"
        " register of the link block), so a PLC that checks it against the version it was built for never reads"
        " or writes the wrong registers. When they differ, stop, and build the PLC's configuration again from"
        " `vc map` of the harness you run (the variable list, the channels, the addresses of this guide); check"
        f" IR {LinkInput.NC_TO_PLC_REGISTERS} and IR {LinkInput.PLC_TO_NC_REGISTERS} against it. The versions: 1, the"
        " first layout; 2, DB100 (the alarm list) at the end of the NC-to-PLC table (turn_mill's grew from 325 to"
        f" 359 registers) and the session key in HR {_span('', key_first, key_last)}; 3, the channel's auxiliary"
        " function area (DB21.DBB58 ff.: the M, S, T, D, DL, H and F functions the NC outputs) and DB2 (the PLC's"
        " user alarms) at the end of the PLC-to-NC table (turn_mill's grew from 163 to 168 registers); 4, FC18's"
        " exchange area of every axis (DB31.DBB32-43 to the NC, DBB104-105 to the PLC: the PLC axes; turn_mill's"
        " tables grew to 365 and 204 registers); 5, the software cams' signals DB10.DBB110-117 behind every other"
        " range of the NC-to-PLC table (turn_mill's grew to 369 registers; no register of version 4 moved, so a PLC"
        " that does not read the cams needs no other change); 6, the machine gantry_mill and DB31.DBX29.4 (the"
        " gantry's start of the synchronization run, in a byte the table had: no register of version 5 moved);"
        f" this server speaks {LINK_VERSION}. A test pins every"
        " version to its"
        " layout (tests/interfaces/test_link_versions.py).",
        "",
        f"* **Lockstep** (IR {LinkInput.MODE} = {MODE_LOCKSTEP}, `vc serve` without `--realtime`): the NC advances one"
        f" PLC period per scan the PLC reports done, and time stands while it waits. For PLCs that can be"
        f" stepped; the protocol is in *Lockstep with a third-party PLC* at the end.",
        f"* **Free-running** (IR {LinkInput.MODE} = {MODE_FREE_RUNNING}, `vc serve --realtime`): the NC runs on the"
        f" wall clock and the PLC scans on its own. The PLC must write a value that changes every scan into"
        f" HR {LinkHolding.SCAN_DONE}, its sign of life (a scan counter). The NC raises alarm {PLC_SIGN_OF_LIFE_ALARM}"
        f" when it sees no change for longer than MD{PLC_CYCLIC_TIMEOUT.number} {PLC_CYCLIC_TIMEOUT.name}"
        f" (default {_seconds(PLC_CYCLIC_TIMEOUT)}): axes stop, NC start is disabled, a reset clears it"
        f" once the PLC scans again. Alarm {PLC_NOT_STARTED_ALARM} follows when the sign of life never changes"
        f" within MD{PLC_RUNNINGUP_TIMEOUT.number} {PLC_RUNNINGUP_TIMEOUT.name}"
        f" (default {_seconds(PLC_RUNNINGUP_TIMEOUT)}) of power-on. Copy IR {LinkInput.SESSION} into"
        f" HR {LinkHolding.SESSION_READY} as well: it is the claim that makes your PLC the session's. On a busy host"
        " give the server a CPU and real-time scheduling, `vc serve --realtime --cpu 1 --fifo 50`, and the PLC"
        " another (`python -m plc_stub --cpu 0 --fifo 40`; SCHED_FIFO needs root, CAP_SYS_NICE or an rtprio limit):"
        " the statistics say what each got, bench/README.md what it kept.",
    ]
    return lines + _threat_model()


def _threat_model() -> list[str]:
    return [
        "",
        "## Threat model",
        "",
        "The servers listen on 127.0.0.1 unless told otherwise, so this is about a process on the same host:"
        " another user's, or a program of yours gone astray (a remote client needs `--allow-remote` and the"
        " allow-list `--allow`). Such a process **can** read everything the PLC reads (both tables, the"
        " description, the session number); take connections up to the limit and its share of a busy server (the"
        " PLC is answered first; a client that does not take its answers is no longer read, so it cannot grow the"
        " server); and, while no PLC has claimed a session (right after `vc serve` starts, after a power-on, after"
        " the operator opened one), claim it before your PLC and be the session's PLC, with all a PLC may do: your"
        " PLC is then refused and says so, and `vc serve`'s statistics name the client that holds the session."
        " Against that, start `vc serve` with `--plc-key-file`: only a claim with your key counts. It **cannot**"
        " write into"
        " the NC while your PLC holds the session (every write is refused and counted), take the session over when"
        " your PLC is lost (the session closes and the NC stops with alarm"
        f" {PLC_SIGN_OF_LIFE_ALARM}), keep a lost PLC's sign of life alive, read the session key, write the NC-to-PLC"
        " table or download S7 blocks; with `--plc-key-file` it cannot claim any session. Out of reach of the"
        " harness: a process that can read your PLC's memory or its key file (root, or your own user through"
        " ptrace or /proc) can act as your PLC; `--allow-writers 127.0.0.1` lets every local process write; a CAN"
        " bus has no sender identity at all (docs/can.md).",
    ]


def _sizes(register_map: RegisterMap) -> list[str]:
    rows = []
    for table, name in ((Table.NC_TO_PLC, "NC-to-PLC (input registers, discrete inputs)"),
                        (Table.PLC_TO_NC, "PLC-to-NC (holding registers, coils)")):
        registers = register_map.registers(table)
        rows.append((name, registers, f"{LINK_REGISTERS}..{registers - 1}", 16 * registers,
                     f"0..{16 * registers - 1}"))
    layout_rows = []
    for table in Table:
        kind = "IR" if table is Table.NC_TO_PLC else "HR"
        for segment in register_map.segments[table]:
            first, last = segment.table_byte // 2, (segment.table_byte + segment.stop - segment.start - 1) // 2
            prefix = f"{segment.area}B" if segment.area in ("I", "Q") else f"{segment.area}.DBB"
            layout_rows.append((_span(prefix, segment.start, segment.stop - 1), _span(f"{kind} ", first, last),
                                "low byte" if segment.table_byte % 2 else "high byte"))
    return [
        "",
        "## Table sizes",
        "",
        *_table(("table", "registers", "data registers", "bits", "bit numbers"), rows),
        "",
        f"IR {LinkInput.NC_TO_PLC_REGISTERS} and IR {LinkInput.PLC_TO_NC_REGISTERS} report the two sizes, so a"
        f" PLC can check"
        " that its configuration matches the machine.",
        "",
        "*Layout* (the byte ranges in table order):",
        "",
        *_table(("bytes", "registers", "first byte in the"), layout_rows),
    ]


def _openplc(register_map: RegisterMap, signals: Sequence[GuideSignal], catalog: ExpandedCatalog,
             serve: str) -> list[str]:
    inputs, outputs = register_map.registers(Table.NC_TO_PLC), register_map.registers(Table.PLC_TO_NC)
    devices = openplc_devices(register_map)
    last_word = OPENPLC_FIRST + OPENPLC_SLAVE_ENTRIES - 1
    fits = inputs <= OPENPLC_SLAVE_ENTRIES and outputs <= OPENPLC_SLAVE_ENTRIES
    bit_bytes = OPENPLC_SLAVE_ENTRIES // 8

    def start_size(part: RegisterBlock | None) -> str:
        return f"{part.offset} / {part.length}" if part is not None else "0 / 0"

    device_rows = [(device.name, SERVER_HOST, SERVER_PORT, 1, "0 / 0", "0 / 0", start_size(device.inputs), "0 / 0",
                    start_size(device.outputs)) for device in devices]
    fit = (f"The NC-to-PLC table becomes %IW{OPENPLC_FIRST}..%IW{OPENPLC_FIRST + inputs - 1} and the PLC-to-NC"
           f" table %QW{OPENPLC_FIRST}..%QW{OPENPLC_FIRST + outputs - 1}, within %IW{last_word} / %QW{last_word}.")
    if not fits:
        fit = (f"**This machine's tables ({inputs} and {outputs} registers) exceed OpenPLC's"
               f" {OPENPLC_SLAVE_ENTRIES} words;** registers above {OPENPLC_SLAVE_ENTRIES - 1} are out of reach.")
    lines = [
        "",
        "## OpenPLC",
        "",
        "OpenPLC Runtime (v3, Linux) reaches Modbus servers as *slave devices*. Its slave-device addresses"
        f" start at %IX{OPENPLC_FIRST}.0 (discrete inputs), %QX{OPENPLC_FIRST}.0 (coils), %IW{OPENPLC_FIRST}"
        f" (input registers, then holding registers read) and %QW{OPENPLC_FIRST} (holding registers written),"
        " numbered on in the order of the device list, and it copies"
        f" {OPENPLC_SLAVE_ENTRIES} of each: %IX{OPENPLC_FIRST}.0..%IX{OPENPLC_FIRST + bit_bytes - 1}.7 and"
        f" %IW{OPENPLC_FIRST}..%IW{last_word}, outputs alike. {OPENPLC_SLAVE_ENTRIES} bits would reach table"
        f" bytes 0..{bit_bytes - 1} only, while this machine's tables have {16 * inputs} and {16 * outputs} bits:"
        " use registers for everything and leave the bit ranges empty.",
        "",
        f"One request carries at most {READ_LIMIT} registers read or {WRITE_LIMIT} written,"
        " and OpenPLC sends one request per range of a device, so the tables are split over several devices"
        " on the same server. Each device is a connection of its own, and only one connection owns the link"
        f" (the one that writes HR {LinkHolding.SESSION_READY}, *{devices[0].name}*): let the PLC's address write from"
        f" all of them. Start the harness in real time (`{serve} --realtime --allow-writers {SERVER_HOST}`), then:",
        "",
        f"1. *Settings*, *Slave Devices*: Polling Period {OPENPLC_POLLING_MS} ms (the default of 100 ms lets the"
        f" sign of life stand still for longer than MD{PLC_CYCLIC_TIMEOUT.number}); keep the timeout at 1000 ms."
        f" The program's task interval must stay well below MD{PLC_CYCLIC_TIMEOUT.number} as well.",
        "2. *Slave Devices*, *Add new device*, once per row below and **in this order**, device protocol"
        " *Generic Modbus TCP Device* (start / size of each range):",
        "",
        *_table(("device name", "IP address", "IP port", "slave id", "Discrete Inputs (%IX100.0)",
                 "Coils (%QX100.0)", "Input Registers (%IW100)", "Holding Registers - Read (%IW100)",
                 "Holding Registers - Write (%QW100)"), device_rows),
        "",
        fit,
        "",
        "**Arithmetic.** A signal in input register r, bit b is bit b of %IW(100 + r); a signal in holding"
        " register r, bit b is bit b of %QW(100 + r). OpenPLC stores the register value as it comes, so bit b"
        " is the bit of value 2^b; ST reads it with `(word AND mask) <> 0`. A byte signal in the high byte is"
        " `SHR(word, 8)`, in the low byte `word AND 16#00FF`.",
        "",
        "Every %QW of the write ranges is sent every poll, including the words your program does not"
        " declare: a PLC-to-NC signal the program does not drive is 0 (an override factor of 0 stops the"
        " axes). A program that drives one bit of a word therefore builds the whole word.",
        "",
        *_openplc_program(register_map, catalog),
        "",
        "Signals of a basic machine program (for every instance of the machine) and the plant I/O:",
        "",
        *_table(("signal", "S7 address", "PLC", "register", "OpenPLC", "bits"),
                [(f"`{s.symbol}`", s.ref.address, _direction(s.location), _register_name(s.location),
                  _openplc_words(s.location), _bits(s.ref, s.location)) for s in signals]),
    ]
    return lines


def _openplc_program(register_map: RegisterMap, catalog: ExpandedCatalog) -> list[str]:
    axis = catalog.layout.axes[0]
    status_symbol, key_symbol = f"{axis}.basic.in.enc1Synchronized", f"{axis}.basic.out.traversKeyPlus"
    status, key = catalog.resolve(status_symbol), catalog.resolve(key_symbol)
    status_at, key_at = _located(register_map, status), _located(register_map, key)
    assert status_at.register_bit is not None and key_at.register_bit is not None
    session = _openplc_word(Table.NC_TO_PLC, LinkInput.SESSION)
    life = _openplc_word(Table.PLC_TO_NC, LinkHolding.SCAN_DONE)
    ready = _openplc_word(Table.PLC_TO_NC, LinkHolding.SESSION_READY)
    return [
        "Structured Text for OpenPLC: one input bit, one output bit, the sign of life:",
        "",
        "```",
        "PROGRAM nc_link",
        "  VAR",
        f"    session AT {session} : UINT;        (* IR {LinkInput.SESSION}: the session *)",
        f"    signOfLife AT {life} : UINT;     (* HR {LinkHolding.SCAN_DONE}: changes every scan *)",
        f"    sessionReady AT {ready} : UINT;   (* HR {LinkHolding.SESSION_READY}: the session echoed *)",
        f"    statusWord AT {_openplc_word(Table.NC_TO_PLC, status_at.register)} : WORD;"
        f"     (* IR {status_at.register} *)",
        f"    keyWord AT {_openplc_word(Table.PLC_TO_NC, key_at.register)} : WORD;"
        f"        (* HR {key_at.register} *)",
        "    scans : UINT;",
        "    synchronized : BOOL;",
        "    plusKey : BOOL;  (* set by your traverse-key logic *)",
        "  END_VAR",
        f"  (* {status_symbol} = {status.address} = IR {status_at.register} bit {status_at.register_bit} *)",
        f"  synchronized := (statusWord AND WORD#{_mask(status_at.register_bit)}) <> 0;",
        f"  (* {key_symbol} = {key.address} = HR {key_at.register} bit {key_at.register_bit} *)",
        "  IF plusKey THEN",
        f"    keyWord := keyWord OR WORD#{_mask(key_at.register_bit)};",
        "  ELSE",
        f"    keyWord := keyWord AND NOT WORD#{_mask(key_at.register_bit)};",
        "  END_IF;",
        "  scans := scans + 1;  (* wraps from 65535 to 0: still a change *)",
        "  signOfLife := scans;",
        "  sessionReady := session;",
        "END_PROGRAM",
        "```",
    ]


def _codesys(register_map: RegisterMap, signals: Sequence[GuideSignal], catalog: ExpandedCatalog) -> list[str]:
    channels = codesys_channels(register_map)

    def channel_of(table: Table, register: int) -> RegisterBlock:
        return next(channel for channel in channels if channel.table is table and channel.holds(register))

    channel_rows = [(c.name, f"{'Read Input Registers' if c.table is Table.NC_TO_PLC else 'Write Multiple Registers'}"
                     f" (FC {c.function_code})", c.offset, c.length, f"{c.offset}..{c.stop - 1}",
                     f"Cyclic, {CODESYS_CYCLE_MS} ms") for c in channels]

    def where(signal: GuideSignal) -> tuple[str, str]:
        location = signal.location
        channel = channel_of(location.table, location.register)
        index = f"{location.register - channel.offset}"
        last = location.register + location.registers - 1
        if location.registers > 1:
            index += f"..{last - channel.offset}" if channel.holds(last) else \
                f" (continues in {channel_of(location.table, last).name})"
        return channel.name, index

    axis = catalog.layout.axes[0]
    status_symbol = f"{axis}.basic.in.enc1Synchronized"
    status_at = _located(register_map, catalog.resolve(status_symbol))
    status_channel = channel_of(Table.NC_TO_PLC, status_at.register)
    link_in, link_out = channels[0], channels[-1]
    return [
        "",
        "## CODESYS",
        "",
        "In the device tree: an Ethernet adapter, under it a *Modbus TCP Master*, under that a *Modbus TCP"
        f" Slave* with the server's IP address ({SERVER_HOST} when CODESYS runs on the same host) and port"
        f" {SERVER_PORT}; the unit id does not matter. Start the harness with `--realtime` (cyclic channels run"
        " beside the program, not in step with it). Then, on the slave's *Modbus Slave Channel* tab, one"
        f" channel per row, trigger *Cyclic* with {CODESYS_CYCLE_MS} ms (no channel reads more than"
        f" {READ_LIMIT} or writes more than {WRITE_LIMIT} registers, the protocol's limits):",
        "",
        *_table(("channel", "access type", "offset", "length", "registers", "trigger"), channel_rows),
        "",
        f"*{link_out.name}* writes the sign of life (index {LinkHolding.SCAN_DONE}), the session (index"
        f" {LinkHolding.SESSION_READY}) and the session key (indexes {LinkHolding.SESSION_KEY}.."
        f"{LinkHolding.SESSION_KEY + SESSION_KEY_REGISTERS - 1}; 0 when your program sets none, see *A lost PLC"
        " closes its session*); it comes last so that, when channels go out in list order, the scan-done word"
        " follows the outputs. Its first write makes the slave's connection the session's PLC: the output"
        " channels before it are refused (exception 01) in the very first cycle only. docs/plc_examples/turn_mill.st"
        " is a whole program for these channels, with the link's part in its network 8.",
        "",
        "**Arithmetic.** On the *Modbus TCP Slave I/O Mapping* tab each channel is an ARRAY OF WORD; map it to a"
        " variable. Register r lies in the channel whose registers include it, at index r - offset; bit b of"
        " the register is bit b of that WORD (`word.b` in ST).",
        "",
        "```",
        f"// channels mapped to variables: \"{link_in.name}\" to {_variable(link_in)},"
        f" \"{status_channel.name}\" to {_variable(status_channel)}, \"{link_out.name}\" to {_variable(link_out)}",
        f"synchronized := {_variable(status_channel)}[{status_at.register - status_channel.offset}]"
        f".{status_at.register_bit};  // {status_symbol}: IR {status_at.register} bit {status_at.register_bit}",
        f"{_variable(link_out)}[{LinkHolding.SCAN_DONE}] := {_variable(link_out)}[{LinkHolding.SCAN_DONE}] + 1;"
        f"  // sign of life",
        f"{_variable(link_out)}[{LinkHolding.SESSION_READY}] := {_variable(link_in)}[{LinkInput.SESSION}];  //"
        f" the session echoed",
        "```",
        "",
        "As with OpenPLC, every word of a write channel is sent: drive every PLC-to-NC signal you need,"
        " including the override factors. The same signals as above:",
        "",
        *_table(("signal", "S7 address", "PLC", "register", "channel", "index", "bits"),
                [(f"`{s.symbol}`", s.ref.address, _direction(s.location), _register_name(s.location),
                  *where(s), _bits(s.ref, s.location)) for s in signals]),
    ]


def _lockstep(register_map: RegisterMap) -> list[str]:
    inputs, outputs = register_map.registers(Table.NC_TO_PLC), register_map.registers(Table.PLC_TO_NC)
    return [
        "",
        "## Lockstep with a third-party PLC",
        "",
        "In lockstep (`vc serve` without `--realtime`) the NC stands still until the PLC has finished the scan"
        " it granted, so a run is repeatable however slow the PLC is. The PLC must make its Modbus requests"
        " itself, in this order, from its program (a soft PLC stepped by a test bench, a program that triggers"
        " its channels, a client in Python or C): cyclic transfers beside the program, as in the setups above,"
        " cannot keep the order.",
        "",
        f"1. Read IR 0..{LINK_REGISTERS - 1}. IR {LinkInput.VERSION} = 0: no machine is powered on yet, poll again."
        f" Check IR {LinkInput.NC_TO_PLC_REGISTERS} = {inputs} and IR {LinkInput.PLC_TO_NC_REGISTERS} = {outputs}"
        f" (the table sizes this configuration expects) and IR {LinkInput.MODE} = {MODE_LOCKSTEP}.",
        f"2. When IR {LinkInput.SESSION} (the session) or IR {LinkInput.BOOT_ID} (the boot id) differs from"
        f" those you run:"
        f" the machine was powered on again, or another harness process serves it. Restart the program from its"
        f" initial state, forget the last grant, and claim the session: HR {LinkHolding.SESSION_READY} = IR"
        f" {LinkInput.SESSION} with your session key in HR {LinkHolding.SESSION_KEY}.."
        f"{LinkHolding.SESSION_KEY + SESSION_KEY_REGISTERS - 1}, one FC {WRITE_REGISTERS} request, once per session."
        " The claim makes your connection the session's PLC, the only one whose writes the server takes; make all"
        " writes over it, and after a lost connection claim again with the same key. A claim refused with"
        " exception 01 means another client holds the session, or it was closed when its PLC was lost: wait for"
        f" IR {LinkInput.SESSION} to change.",
        f"3. Read IR {LinkInput.SCAN_GRANT}, the scan grant. While it is 0 or equal to the last grant you finished,"
        " poll again (no scan).",
        f"4. When it changed: read the NC-to-PLC data (IR {LINK_REGISTERS}..{inputs - 1}; the server published"
        " them before the grant and holds them while it waits), run exactly one scan, write the PLC-to-NC data"
        f" (HR {LINK_REGISTERS}..{outputs - 1}), then write HR {LinkHolding.SCAN_DONE} = the grant. The scan-done word"
        " must be the last write of the scan; it may share the last FC 16 request with outputs, because the"
        " server applies a request as a whole. The server holds the PLC-to-NC registers for the whole session:"
        " registers unchanged since the last scan of the session need not be written again. Remember the grant.",
        f"5. The NC accepts the scan when HR {LinkHolding.SCAN_DONE} equals the grant and HR"
        f" {LinkHolding.SESSION_READY} equals"
        f" the session, advances one PLC period (IR {LinkInput.PLC_CYCLE_IPO} IPO cycles), publishes the new inputs"
        " and grants the next scan: the grant counts 1, 2, .. 65535, 1, .. and is never 0.",
        "",
        "`python -m plc_stub --modbus HOST:PORT` is a client that follows this protocol"
        " (interfaces/links/modbus/plc_end.py).",
    ]
