"""The guide's sections on what a PLC must know besides the addresses (``vc map --format guide``).

Commissioning facts of the machine (referencing, wiring, what the plant needs), the rules the NC
applies to the PLC's signals (emergency stop and its acknowledgement, drive ready, the gear stage
change with its oscillation), the alarm list DB100, the time base in lockstep, sessions with the
boot id and the reconnect rule, and running a scenario against the PLC.  Every address and number
is computed from the machine, the catalogue and the register map.
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence

from interfaces import alarm_block
from interfaces.commissioning import Commissioning
from interfaces.links.modbus.codec import (
    LinkHolding,
    LinkInput,
    RegisterMap,
    Table,
)
from interfaces.signals import ExpandedCatalog, SignalRef

# DB31 signals of the gear stage change, for every spindle with a gearbox (seed 003 §13.4)
GEAR_SIGNALS = ("spindle.in.requestedGearStageNumber", "spindle.in.gearChangeoverRequested",
                "spindle.in.oscillModeActive", "spindle.out.oscillEnable", "spindle.out.oscillRequest",
                "spindle.out.oscillSetDirCw", "spindle.out.oscillSetDirCcw", "spindle.out.gearStageSelection",
                "spindle.out.gearChangeoverDone")


def _table(header: Sequence[str], rows: Iterable[Sequence[object]]) -> list[str]:
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    lines += ["| " + " | ".join(str(cell).replace("|", "\\|") for cell in row) + " |" for row in rows]
    return lines


def _position(value: float | None, unit: str) -> str:
    return "-" if value is None else f"{value:g} {unit}"


def _register(register_map: RegisterMap, ref: SignalRef) -> str:
    location = register_map.location(ref)
    assert location is not None and location.register_bit is not None
    kind = "IR" if location.table is Table.NC_TO_PLC else "HR"
    return f"{kind} {location.register} bit {location.register_bit}"


def commissioning_section(commissioning: Commissioning, channels: Sequence[str]) -> list[str]:
    """How each axis is referenced and wired, the referencing order, what the plant needs."""
    rows = []
    for facts in commissioning.axes:
        cam = "-" if facts.cam is None else f"{facts.cam[0]:g} .. {facts.cam[1]:g} {facts.unit}"
        limits = "-" if facts.hw_limit_minus is None and facts.hw_limit_plus is None else \
            f"{_position(facts.hw_limit_minus, facts.unit)} / {_position(facts.hw_limit_plus, facts.unit)}"
        software = "-" if facts.sw_limits is None else f"{facts.sw_limits[0]:g} .. {facts.sw_limits[1]:g}"
        approach = {"plus": f"{facts.axis}+", "minus": f"{facts.axis}-"}.get(facts.approach, "-")
        rows.append((f"{facts.axis} (DB{facts.db})", facts.referencing, approach, cam, limits, software,
                     facts.reference_cycle, ", ".join(facts.before) or "-"))
    lines = [
        "",
        "## Commissioning this machine",
        "",
        "How each axis is referenced: the direction its traverse key must point to in JOG-REF (MD34010"
        " REFP_CAM_DIR_IS_MINUS), where the reference cam and the hardware limit switches are on the slide"
        " (physical machine coordinates, as the plant has them wired), the software limits (MD36100 / MD36110,"
        " active once referenced), the step in channel-specific referencing (MD34110: -1 not needed for NC start,"
        " 0 not part of it) and the axes that must be referenced first:",
        "",
        *_table(("axis", "referencing", "approach", "reference cam", "limit switches - / +", "software limits",
                 "MD34110", "first"), rows),
        "",
    ]
    lines += [f"* {facts.axis}: {facts.prerequisite}." for facts in commissioning.axes if facts.before]
    lines += [f"* Channel-specific referencing of {channel} (DB21.DBX1.0): {commissioning.order_text(channel)}."
              for channel in channels]
    lines += ["", "What the plant needs from the PLC (the built-in `basic_machine`, `referencing` and `spindle`"
              " programs do all of it):", ""]
    lines += [f"* **{need.name}**: {need.text}." for need in commissioning.needs]
    lines += ["", "`vc map --format csv` lists these facts too (rows of instance COMMISSIONING), and the link"
              " description carries them as JSON (`commissioning`)."]
    return lines


def nc_rules_section(catalog: ExpandedCatalog, register_map: RegisterMap, commissioning: Commissioning,
                     channels: Sequence[str]) -> list[str]:
    """The rules the NC applies to what the PLC writes, with this machine's registers."""
    def where(symbol: str) -> str:
        ref = catalog.resolve(symbol)
        return f"`{symbol}` ({ref.address}, {_register(register_map, ref)})"

    channel = channels[0]
    geared = [facts for facts in commissioning.axes if facts.gear_stages]
    lines = [
        "",
        "## What the NC expects of the PLC",
        "",
        f"* **Emergency stop.** {where('NC.basic.out.emergencyStop')} = 1 raises alarm 3000: every axis stops"
        " with its rapid-stop ramp and loses its controller enable, NC start is refused. Leaving it takes three"
        f" things: the button released (56.1 = 0), the acknowledgement {where('NC.basic.out.emergencyStopAck')}"
        f" = 1, and, while 56.2 is 1, a rising reset: the channel's {where(f'{channel}.basic.out.reset')} or the"
        f" mode group's {where('MODEGROUP.basic.out.reset')}. 56.2 alone leaves alarm 3000 standing, as on the"
        " real control; `basic_machine` sets 56.2 with the panel's RESET key and sends the same key as the"
        " channel reset.",
        "* **Drive ready.** `<Axis>.drive.in.enabled` (DBX92.7) is 1 while the drive line-up reports ready"
        " (`Drives.ready`), the PLC gives pulse enable (DBX21.7) and controller enable (DBX2.1), and neither the"
        " NC (after a rapid stop) nor the power unit took the enable away.",
    ]
    for facts in geared:
        axis = facts.axis
        lines.append(
            f"* **Gear stage change of {axis}** ({facts.gear_stages} stages). The NC requests it with"
            f" {where(f'{axis}.spindle.in.gearChangeoverRequested')} and the stage in"
            f" {where(f'{axis}.spindle.in.requestedGearStageNumber')} (3 bits), brakes the spindle and holds the"
            f" block; {where(f'{axis}.spindle.in.oscillModeActive')} shows the oscillation mode. The gearbox meshes"
            " only while the motor turns: hold the new stage's actuator and set oscillation enable"
            f" {where(f'{axis}.spindle.out.oscillEnable')} until the stage is engaged (the NC oscillates with"
            f" MD35400 / MD35440 / MD35450; with {where(f'{axis}.spindle.out.oscillRequest')} the PLC oscillates"
            f" itself by DBX18.6 / 18.7). Without 18.5 the spindle stands still and the gearbox stays in neutral."
            f" Then report the stage in {where(f'{axis}.spindle.out.gearStageSelection')} (3 bits) and set"
            f" {where(f'{axis}.spindle.out.gearChangeoverDone')}: the NC takes the stage and drops 82.3; clear 16.3"
            " then. The rows of these signals are in the signal tables below.")
    lines.append("* **Signals the NC does not model.** `vc map` has a `modelled` column: `no: <why>` marks the"
                 " catalogued signals the simulated NC neither reads nor writes (oscillation, the drive's rapid stop,"
                 " indexing axes ...). A PLC that waits for one of them waits for ever; that is not its bug.")
    return lines


def alarm_section(catalog: ExpandedCatalog, register_map: RegisterMap) -> list[str]:
    """Where the NC's alarm list DB100 lies in the NC-to-PLC table, and its codes."""
    first = register_map.table_byte(Table.NC_TO_PLC, f"DB{alarm_block.ALARM_DB}", 0)
    assert first is not None and first % 2 == 0
    register = first // 2
    entries = alarm_block.entries(catalog)
    last = register + (alarm_block.FIRST_ENTRY_BYTE + entries * alarm_block.ENTRY_BYTES) // 2 - 1
    rows = [("DBW0", f"IR {register}", "count: alarms present (may exceed the entries)"),
            ("DBW2", f"IR {register + 1}", "changes: counts every change of the list (65535 wraps to 0)")]
    for number in (1, 2):
        base = alarm_block.FIRST_ENTRY_BYTE + (number - 1) * alarm_block.ENTRY_BYTES
        at = register + base // 2
        rows += [(f"DBD{base}", f"IR {at}..{at + 1}", f"entry {number}: alarm number, high word first (0: none)"),
                 (f"DBB{base + 4} / DBB{base + 5}", f"IR {at + 2} high / low byte",
                  f"entry {number}: channel n = DB(20 + n) / machine axis n = DB(30 + n); 0 = none"),
                 (f"DBB{base + 6} / DBB{base + 7}", f"IR {at + 3} high / low byte",
                  f"entry {number}: reaction bits / cleared by")]
    rows.append(("...", "...", f"entries 3..{entries} alike, {alarm_block.ENTRY_BYTES} bytes (4 registers) each"))
    return [
        "",
        f"## Alarms: DB{alarm_block.ALARM_DB}",
        "",
        f"The NC's alarm list is data block {alarm_block.ALARM_DB} (a project block: the real control shows its"
        " alarms on the HMI and gives the PLC only DB10.DBX109.0 and DB21.DBX36.6 / 36.7). It is the last range"
        " of the NC-to-PLC table but the software cams' DB10.DBB110-117 (link version 5), input registers"
        f" {register}..{last}, and S7 data block {alarm_block.ALARM_DB}"
        f" over `--s7`. The NC rewrites it whenever the list changes: the number of alarms present, a change"
        f" counter, and the first {entries} alarms in the order they were raised:",
        "",
        *_table(("bytes", "registers", "meaning"), rows),
        "",
        "Reaction bits: " + "; ".join(f"bit {bit} {text}" for bit, text in enumerate(alarm_block.REACTION_BITS))
        + ". Cleared by: " + "; ".join(f"{code} {text}" for code, text in enumerate(alarm_block.CLEARED_BY_TEXT,
                                                                                    start=1)) + ".",
        "",
        "The link description says the same (`alarms`: its first input register, the entries and the codes).",
    ]


def time_and_sessions_section() -> list[str]:
    """The PLC's time base in lockstep, sessions, the boot id and the reconnect rule."""
    return [
        "",
        "## Time base, sessions and reconnecting",
        "",
        "* **Time base.** In lockstep the NC stands while the PLC works, so the wall clock says nothing about"
        " machine time: when the pair runs 4 to 7 times faster than real time, a TON of 2 s on the wall clock of"
        " a soft PLC (awlsim, OpenPLC, CODESYS) lasts 8 to 14 s of machine time, and less than 2 s when the"
        f" pair runs slower. Take the time from the NC: IR {LinkInput.NC_CYCLE_HIGH}..{LinkInput.NC_CYCLE_LOW}"
        f" count the NC's"
        " IPO cycles since the power-on of the session at each exchange (high word first), IR"
        f" {LinkInput.IPO_CYCLE_US} is the IPO cycle in microseconds: machine time = cycles x IR"
        f" {LinkInput.IPO_CYCLE_US} us."
        f" Every granted scan advances the count by exactly IR {LinkInput.PLC_CYCLE_IPO} cycles (the PLC period), so a"
        " timer that adds the PLC period per scan, or compares the count with the one at its start, runs on"
        " machine time and gives the same result at any speed. In real time the count follows the wall clock.",
        f"* **Sessions.** IR {LinkInput.SESSION} counts the sessions (1, 2, ..) from 1 in every `vc serve` process:"
        " the harness's power-ons, and the new sessions its operator opens for a restarted PLC after the PLC of a"
        f" session was lost; IR {LinkInput.BOOT_ID} is a random boot id (1..65535) of the process. A PLC restarts"
        f" its program from its initial state whenever IR {LinkInput.SESSION} or IR {LinkInput.BOOT_ID} differs from"
        f" the values it started for, and claims the session: HR {LinkHolding.SESSION_READY} = IR {LinkInput.SESSION},"
        f" with its session key in HR {LinkHolding.SESSION_KEY}..{LinkHolding.SESSION_KEY + 3}.",
        "* **Reconnecting.** After a lost connection read IR 0..15 anew before anything else. A server"
        " restarted in between starts at session 1 again, and only the boot id tells it from the session you"
        " ran: carrying on would act on stale state, so restart. With the same session and boot id claim it again"
        " on the new connection with the same key and carry on with the program as it is (a PLC whose key was 0"
        " waits for a new session: the server closed its session when the connection ended); the harness answers"
        " only while it waits for a scan, so a busy harness can"
        f" leave a request unanswered for seconds without anything being lost. In lockstep, if IR"
        f" {LinkInput.SCAN_GRANT}"
        f" still grants the scan whose outputs you were writing, write them again (with HR {LinkHolding.SCAN_DONE} ="
        " the grant last) instead of running the scan a second time; if it grants a later one, the harness"
        " took them.",
    ]


def served_scenario_section(machine_source: str) -> list[str]:
    """Running a scenario of the operator against a PLC of one's own."""
    return [
        "",
        "## A scenario against your PLC",
        "",
        f"`vc serve --machine {machine_source} --modbus 127.0.0.1:5020 --scenario FILE --junit report.xml` runs a"
        " scenario as the operator (panel keys, MDA programs, forces of plant inputs) for whatever PLC connects."
        " Its `plc:` is optional: it names the program the harness asks `python -m plc_stub` to run, a PLC of"
        " your own runs its own (`plc: none` is refused: that scenario would be the PLC). When the scenario"
        " ends, the server stops and `vc serve` exits with its result: 0 passed, 1 failed, 2 a problem in the"
        " file; `--junit` writes the report for CI. `--keep-running` keeps the machine running afterwards"
        " (Ctrl-C or `--duration S` ends it, the exit code stays the scenario's). With `--realtime`, `--stats S`"
        " prints the real-time figures every S seconds, while the scenario runs too.",
    ]
