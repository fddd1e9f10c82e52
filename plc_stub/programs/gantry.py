"""gantry: basic_machine plus a gantry machine's handling of its gantry groupings (seed 003 chapter 12).

Networks after those of ``basic_machine`` (1-4), for every gantry grouping the NC reports (the
leading axis shows DB31.DBX101.6 = 1 and DBX101.7 = 1; its followers DBX101.7 = 1, 101.6 = 0):

5. Enables: the axes of a grouping are enabled together (network 4 gives every axis its enables;
   a follower's traverse keys are never pressed: the NC ignores them, L15570-15573).
6. Referencing of the grouping (§12.3.1, L14655-14687): in JOG-REF or MDA-REF, NC start on the
   panel starts it; the PLC holds the leading axis's traverse key of its referencing direction
   until the leading axis reports DB31.DBX60.4 and releases it then: the NC references the
   followers by itself.  Reset or leaving REF ends the sequence::

        IDLE ──NC start in REF, the grouping not referenced──▶ LEADER: key held
        LEADER ──DBX60.4 of the leading axis──▶ IDLE: key released
        LEADER ──reset, REF left──▶ IDLE

7. Synchronization (L14740-14748, L14767-14790, L14814-14826): when the NC reports DBX101.4 (the difference is
   beyond the warning limit, or the synchronism was lost), the operator checks the portal and
   presses ``MCP.gantrySync`` (or, with ``gantry_auto_sync: true``, the PLC itself starts it): in
   REF the PLC gives DBX29.4 of the leading axis until DBX101.4 falls (the run started) or at most
   ``sync_start_time``.  ``gantry_disable_auto_sync: true`` sets DBX29.5 (no automatic
   synchronization after follow-up, L14906-14944).
8. Warning and trip limits (L14467-14501): a follower's DBX101.3 raises PLC alarm 700060 (the
   portal is skewing) and holds the feed of the first channel (DB21.DBX6.0) while it stands; its
   DBX101.2 (the NC stopped the grouping with alarm 10653) raises PLC alarm 700061 until the reset
   key.  ``Lamp.gantrySync`` lights while every grouping is synchronized (DBX101.5).

Parameters (machine file)::

    plc:
      gantry_auto_sync: false            # true: the PLC starts the synchronization run itself
      gantry_disable_auto_sync: false    # true: DBX29.5 = 1 on every leading axis
      referencing_direction: {X1: plus}  # the leading axis's key (MD34010), default plus
"""

from __future__ import annotations

from dataclasses import dataclass
from enum import Enum

from plc_stub.blocks import R_TRIG, TON
from plc_stub.io import Bool, PlcIo
from plc_stub.programs.auxiliary import PLC_ALARM
from plc_stub.programs.basic_machine import BasicMachine, pressed

WARNING_ALARM, TRIP_ALARM = 700060, 700061
SYNC_START_S = 0.5  # DBX29.4 is held at most this long when the NC does not take it


class ReferenceStep(Enum):
    IDLE = "no referencing of the grouping running"
    LEADER = "the leading axis's traverse key held until DBX60.4"


@dataclass(slots=True)
class _Grouping:
    leader: str
    key: Bool  # the leading axis's traverse key of its referencing direction
    referenced: Bool  # DBX60.4 of the leading axis
    followers_referenced: list[Bool]
    sync_run_ready: Bool  # DBX101.4
    sync_ok: Bool  # DBX101.5
    start_sync_run: Bool  # DBX29.4
    disable_sync: Bool  # DBX29.5
    warnings: list[Bool]  # DBX101.3 of each follower
    trips: list[Bool]  # DBX101.2 of each follower
    start_timer: TON
    step: ReferenceStep = ReferenceStep.IDLE


class Gantry(BasicMachine):
    PARAMETERS = (*BasicMachine.PARAMETERS, "gantry_auto_sync", "gantry_disable_auto_sync", "referencing_direction")

    def __init__(self, io: PlcIo):
        super().__init__(io)
        parameters = io.environment.parameters
        problems: list[str] = []
        flags = {}
        for name in ("gantry_auto_sync", "gantry_disable_auto_sync"):
            value = parameters.get(name, False)
            if not isinstance(value, bool):
                problems.append(f"plc: {name} is true or false, got {value!r}")
                value = False
            flags[name] = value
        directions = parameters.get("referencing_direction", {})
        if not isinstance(directions, dict) or any(v not in ("plus", "minus") for v in directions.values()):
            problems.append(f"plc: referencing_direction maps an axis to plus or minus, got {directions!r}")
            directions = {}
        if problems:
            raise ValueError("\n".join(problems))
        self.auto_sync = flags["gantry_auto_sync"]
        self.disable_auto_sync = flags["gantry_disable_auto_sync"]
        scan = io.environment.scan_time_s
        layout = io.environment.catalog.layout
        self.gantry_axes = [(name, io.input(f"{name}.coupling.in.gantryActive"),
                             io.input(f"{name}.coupling.in.gantryLeadingActive")) for name in layout.axes]
        self._io = io
        self._directions = directions
        self._scan = scan
        self.groupings: list[_Grouping] = []  # found from the NC's feedback (its first status)
        self.start_key = R_TRIG()
        self.sync_key = R_TRIG()
        self.key_sync = io.input("MCP.gantrySync") if io.is_wired("MCP.gantrySync") else None
        self.sync_lamp = io.output("Lamp.gantrySync") if io.is_wired("Lamp.gantrySync") else None
        self.ref_active = io.input("MODEGROUP.basic.in.refPointActive")
        channel = layout.channels[0]
        self.feed_disable = io.output(f"{channel}.basic.out.disableFeed")
        self.warning_alarm = io.output(PLC_ALARM.format(number=WARNING_ALARM))
        self.trip_alarm = io.output(PLC_ALARM.format(number=TRIP_ALARM))
        self.tripped = False

    def _find_groupings(self) -> None:
        """The groupings as the NC shows them: each leading axis and the gantry axes after it up to the
        next leading axis (MD37100 puts a grouping's axes together)."""
        io = self._io
        leaders: list[str] = []
        followers: dict[str, list[str]] = {}
        for name, gantry, leading in self.gantry_axes:
            if gantry.value and leading.value:
                leaders.append(name)
                followers[name] = []
            elif gantry.value and leaders:
                followers[leaders[-1]].append(name)
        for leader in leaders:
            key = "traversKeyMinus" if self._directions.get(leader) == "minus" else "traversKeyPlus"
            names = followers[leader]
            self.groupings.append(_Grouping(
                leader, io.output(f"{leader}.basic.out.{key}"), io.input(f"{leader}.basic.in.enc1Synchronized"),
                [io.input(f"{name}.basic.in.enc1Synchronized") for name in names],
                io.input(f"{leader}.coupling.in.gantrySyncRunReady"), io.input(f"{leader}.coupling.in.gantrySyncOk"),
                io.output(f"{leader}.coupling.out.gantryStartSyncRun"),
                io.output(f"{leader}.coupling.out.gantryDisableSync"),
                [io.input(f"{name}.coupling.in.gantryWarningLimitExceeded") for name in names],
                [io.input(f"{name}.coupling.in.gantryCutOffLimitExceeded") for name in names],
                TON(SYNC_START_S, self._scan)))

    def ob1(self) -> None:
        super().ob1()
        if not self.groupings:
            self._find_groupings()
        self.referencing()
        self.synchronization()
        self.limits()

    # Network 6 ---------------------------------------------------------------------------
    def referencing(self) -> None:
        start = self.start_key(pressed(self.key_nc_start))
        in_ref = self.ref_active.value
        reset = pressed(self.key_reset)
        for grouping in self.groupings:
            if reset or not in_ref:
                grouping.step = ReferenceStep.IDLE
            elif start and grouping.step is ReferenceStep.IDLE and not grouping.referenced.value:
                grouping.step = ReferenceStep.LEADER
            elif grouping.step is ReferenceStep.LEADER and grouping.referenced.value:
                grouping.step = ReferenceStep.IDLE
            if grouping.step is ReferenceStep.LEADER:
                grouping.key.value = True  # held over network 4's panel key

    # Network 7 ---------------------------------------------------------------------------
    def synchronization(self) -> None:
        confirmed = self.sync_key(pressed(self.key_sync))
        in_ref = self.ref_active.value
        for grouping in self.groupings:
            grouping.disable_sync.value = self.disable_auto_sync
            ready = grouping.sync_run_ready.value and in_ref
            wanted = ready and (self.auto_sync or confirmed or grouping.start_sync_run.value)
            expired = grouping.start_timer(wanted)
            grouping.start_sync_run.value = wanted and not expired
        if self.sync_lamp is not None:
            self.sync_lamp.value = bool(self.groupings) and all(g.sync_ok.value for g in self.groupings)

    # Network 8 ---------------------------------------------------------------------------
    def limits(self) -> None:
        warning = any(bit.value for grouping in self.groupings for bit in grouping.warnings)
        trip = any(bit.value for grouping in self.groupings for bit in grouping.trips)
        if trip:
            self.tripped = True
        elif pressed(self.key_reset):
            self.tripped = False
        self.warning_alarm.value = warning
        self.trip_alarm.value = self.tripped
        if warning:
            self.feed_disable.value = True  # network 3's feed stop, or the portal skewing
