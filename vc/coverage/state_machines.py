"""The NC functions with a state machine whose coverage is measured: states, transitions, meanings.

Each :class:`StateMachine` declares what its function can do, taken from the module that runs it
(the enum of its states where there is one, the diagram of its docstring for the transitions);
``vc.coverage.probes`` reads the states of a running NC, the report compares the two.  A state
machine is counted over all its instances (every axis, spindle or channel of every machine that
ran): a state is covered when any instance entered it.  Referencing is one state machine per
variant of the measuring system, as the phases differ.

The states are sampled at the end of every IPO cycle: a state entered and left within one cycle
is not seen, and its two transitions show as one (listed as "other transitions" in the report).
Each state and transition names the text of its module that defines it (``anchor``), so that the
report can point to the line.
"""

from __future__ import annotations

from dataclasses import dataclass
from enum import Enum

from vc.core.axis.command_axis import CommandState
from vc.core.channel.program_run import ChannelState, ProgramState
from vc.core.referencing.referencing import State as ReferencingState
from vc.core.retraction.drive_esr import DriveEsrReaction as DriveReaction
from vc.core.spindle.coupling_state import SyncPhase as CouplingPhase
from vc.core.spindle.gear_change import GearState
from vc.core.spindle.spindle import SpindleMode


@dataclass(frozen=True, slots=True)
class StateDef:
    name: str
    meaning: str
    anchor: str  # a text of the module that defines the state (for its line)


@dataclass(frozen=True, slots=True)
class TransitionDef:
    before: str
    after: str
    trigger: str  # what takes the state machine from ``before`` to ``after``


@dataclass(frozen=True, slots=True)
class StateMachine:
    name: str  # "referencing.distance_coded": what --fail-under-function names (a prefix names a group)
    title: str
    module: str  # the source file, relative to the repository
    instances: str  # what one instance is: "axis", "spindle", "channel", "mode group"
    states: tuple[StateDef, ...]
    transitions: tuple[TransitionDef, ...]

    def state(self, name: str) -> StateDef | None:
        for state in self.states:
            if state.name == name:
                return state
        return None


def _enum_states(members: tuple[Enum, ...]) -> tuple[StateDef, ...]:
    return tuple(StateDef(member.name, str(member.value), f"{member.name} = ") for member in members)


def _transitions(*items: tuple[str, str, str]) -> tuple[TransitionDef, ...]:
    return tuple(TransitionDef(*item) for item in items)


R = ReferencingState
_REFERENCING = "vc/core/referencing/referencing.py"


def _referencing(name: str, title: str, states: tuple[ReferencingState, ...],
                 *transitions: tuple[str, str, str]) -> StateMachine:
    return StateMachine(f"referencing.{name}", f"Referencing, {title}", _REFERENCING, "axis",
                        _enum_states(states), _transitions(*transitions))


_ABORT = "abort: reset, an alarm, the traverse key or REF taken away"

STATE_MACHINES: tuple[StateMachine, ...] = (
    StateMachine(
        "mode_group", "Mode group: operating mode and machine function REF (DB11)", "vc/core/nck/mode_group.py",
        "mode group",
        (StateDef("JOG", "JOG (DB11.DBX6.2)", "self.jog_active = "),
         StateDef("JOG REF", "JOG with the machine function REF (DB11.DBX7.2)", "self.ref_active = "),
         StateDef("MDA", "MDA (DB11.DBX6.1)", "self.mda_active = "),
         StateDef("MDA REF", "MDA with the machine function REF", "self.ref_active = "),
         StateDef("AUTO", "AUTOMATIC (DB11.DBX6.0)", "self.auto_active = ")),
        _transitions(("JOG", "MDA", "DB11.DBX0.1"), ("MDA", "JOG", "DB11.DBX0.2"),
                     ("JOG", "AUTO", "DB11.DBX0.0"), ("AUTO", "JOG", "DB11.DBX0.2"),
                     ("MDA", "AUTO", "DB11.DBX0.0"), ("AUTO", "MDA", "DB11.DBX0.1"),
                     ("JOG", "JOG REF", "DB11.DBX1.2 in JOG"), ("JOG REF", "JOG", "DB11.DBX1.2 = 0"),
                     ("MDA", "MDA REF", "DB11.DBX1.2 in MDA"), ("MDA REF", "MDA", "DB11.DBX1.2 = 0"),
                     ("JOG REF", "MDA", "DB11.DBX0.1: REF ends with JOG"),
                     ("JOG REF", "AUTO", "DB11.DBX0.0: REF ends with JOG"))),
    StateMachine(
        "channel", "Channel state (DB21.DBX35.5-35.7)", "vc/core/channel/channel.py", "channel",
        _enum_states(tuple(ChannelState)),
        _transitions(("RESET", "ACTIVE", "NC start"), ("ACTIVE", "INTERRUPTED", "NC stop, an alarm"),
                     ("RESET", "INTERRUPTED", "NC start, and an alarm of the first block in the same cycle"),
                     ("INTERRUPTED", "ACTIVE", "NC start"), ("ACTIVE", "RESET", "program end, reset"),
                     ("INTERRUPTED", "RESET", "reset"))),
    StateMachine(
        "program", "Program state (DB21.DBX35.0-35.4)", "vc/core/channel/channel.py", "channel",
        _enum_states(tuple(ProgramState)),
        _transitions(("ABORTED", "RUNNING", "NC start"), ("RUNNING", "ABORTED", "program end, reset"),
                     ("ABORTED", "STOPPED", "NC start, and an alarm of the first block in the same cycle"),
                     ("RUNNING", "WAITING", "read-in disable DB21.DBX6.1"), ("WAITING", "RUNNING", "read-in enabled"),
                     ("RUNNING", "STOPPED", "NC stop, an alarm"), ("STOPPED", "RUNNING", "NC start"),
                     ("STOPPED", "INTERRUPTED", "another mode selected"),
                     ("INTERRUPTED", "RUNNING", "back in the mode, NC start"),
                     ("STOPPED", "ABORTED", "reset"), ("INTERRUPTED", "ABORTED", "reset"))),
    _referencing(
        "incremental_cam", "incremental measuring system with reference cam (MD34200 = 1, MD34000 = 1)",
        (R.IDLE, R.P1_TO_CAM, R.P1_BRAKE, R.P2_LEAVE_CAM, R.P2_BRAKE_OFF_CAM, R.P2_RETURN_TO_CAM, R.P2_ZERO_MARK,
         R.P3_STOP, R.P3_TO_POINT, R.SETTLE, R.DONE),
        ("IDLE", "P1_TO_CAM", "start off the cam"), ("IDLE", "P2_LEAVE_CAM", "start on the cam"),
        ("DONE", "P1_TO_CAM", "a referenced axis referenced again"),
        ("P1_TO_CAM", "P1_BRAKE", "the cam rises"), ("P1_BRAKE", "P2_LEAVE_CAM", "standstill on the cam"),
        ("P2_LEAVE_CAM", "P2_ZERO_MARK", "the cam falls, MD34050 = 0"),
        ("P2_LEAVE_CAM", "P2_BRAKE_OFF_CAM", "the cam falls, MD34050 = 1"),
        ("P2_LEAVE_CAM", "P1_TO_CAM", "the cam fell before creep speed: phase 1 again"),
        ("P2_BRAKE_OFF_CAM", "P2_RETURN_TO_CAM", "standstill off the cam"),
        ("P2_RETURN_TO_CAM", "P2_ZERO_MARK", "the cam rises"),
        ("P2_ZERO_MARK", "P3_TO_POINT", "zero mark"),
        ("P2_ZERO_MARK", "P3_STOP", "zero mark, reference point within the braking distance"),
        ("P3_STOP", "P3_TO_POINT", "standstill"), ("P3_TO_POINT", "SETTLE", "at the reference point"),
        ("SETTLE", "DONE", "exact stop fine: referenced"),
        ("P1_TO_CAM", "IDLE", f"{_ABORT}, 20000"), ("P1_BRAKE", "IDLE", f"{_ABORT}, 20001"),
        ("P2_LEAVE_CAM", "IDLE", f"{_ABORT}, 20005"), ("P2_ZERO_MARK", "IDLE", f"{_ABORT}, 20002"),
        ("P3_TO_POINT", "IDLE", _ABORT)),
    _referencing(
        "incremental_no_cam", "incremental measuring system without reference cam (MD34000 = 0)",
        (R.IDLE, R.P2_ZERO_MARK, R.P3_STOP, R.P3_TO_POINT, R.SETTLE, R.DONE),
        ("IDLE", "P2_ZERO_MARK", "start"), ("P2_ZERO_MARK", "P3_TO_POINT", "zero mark"),
        ("P2_ZERO_MARK", "P3_STOP", "zero mark, reference point within the braking distance"),
        ("P3_STOP", "P3_TO_POINT", "standstill"), ("P3_TO_POINT", "SETTLE", "at the reference point"),
        ("SETTLE", "DONE", "exact stop fine: referenced"), ("P2_ZERO_MARK", "IDLE", f"{_ABORT}, 20002"),
        ("P3_TO_POINT", "IDLE", _ABORT)),
    _referencing(
        "distance_coded", "distance-coded reference marks (MD34200 = 3 / 8)",
        (R.IDLE, R.DC_SEARCH, R.DC_REVERSE, R.DC_BRAKE, R.TO_TARGET, R.SETTLE, R.DONE),
        ("IDLE", "DC_SEARCH", "start"), ("DC_SEARCH", "DC_BRAKE", "2 (4) plausible marks"),
        ("DC_SEARCH", "DC_REVERSE", "the cam at the end of the range, or implausible marks"),
        ("DC_REVERSE", "DC_SEARCH", "standstill: the other way"), ("DC_BRAKE", "TO_TARGET", "standstill, MD34330 = 0"),
        ("DC_BRAKE", "DONE", "standstill, MD34330 = 1: referenced"), ("TO_TARGET", "SETTLE", "at the target"),
        ("SETTLE", "DONE", "exact stop fine: referenced"), ("DC_SEARCH", "IDLE", f"{_ABORT}, 20003, 20004"),
        ("TO_TARGET", "IDLE", _ABORT)),
    _referencing(
        "absolute", "absolute encoder (MD30240 = 4)", (R.IDLE, R.TO_TARGET, R.SETTLE, R.DONE),
        ("IDLE", "TO_TARGET", "start, calibrated, MD34330 = 0"),
        ("IDLE", "DONE", "calibration without motion (MD34210 = 1), or MD34330 = 1"),
        ("TO_TARGET", "SETTLE", "at the reference position"), ("SETTLE", "DONE", "exact stop fine: referenced"),
        ("TO_TARGET", "IDLE", _ABORT)),
    _referencing(
        "follow_up", "in follow-up mode (MD34104 = 1)", (R.IDLE, R.FOLLOW_UP, R.DONE),
        ("IDLE", "FOLLOW_UP", "start in follow-up mode"), ("FOLLOW_UP", "DONE", "the slide crossed the marks"),
        ("FOLLOW_UP", "IDLE", "follow-up mode ended"), ("DONE", "FOLLOW_UP", "G74 on a referenced axis")),
    StateMachine(
        "spindle_mode", "Spindle modes (DB31.DBX84.3-84.7)", "vc/core/spindle/spindle.py", "spindle",
        _enum_states(tuple(SpindleMode)),
        _transitions(("CONTROL", "OSCILLATION", "gear change"), ("POSITIONING", "OSCILLATION", "gear change"),
                     ("OSCILLATION", "CONTROL", "gear changed (16.3)"),
                     ("CONTROL", "POSITIONING", "SPOS / SPOSA / M19"), ("POSITIONING", "CONTROL", "M3 / M4 / M5"),
                     ("CONTROL", "AXIS", "M70"), ("POSITIONING", "AXIS", "M70"), ("AXIS", "CONTROL", "M3 / M4 / M5"),
                     ("AXIS", "POSITIONING", "SPOS in axis mode"),
                     ("CONTROL", "SYNCHRONOUS", "COUPON: following spindle"),
                     ("POSITIONING", "SYNCHRONOUS", "COUPON on a positioned spindle"),
                     ("SYNCHRONOUS", "CONTROL", "COUPOF"))),
    StateMachine(
        "gear_change", "Gear stage change dialog (DB31.DBX82.3, 16.3)", "vc/core/spindle/gear_change.py", "spindle",
        (StateDef("NONE", "no gear change", "The dialog (:class:`GearChange`)"), *_enum_states(tuple(GearState))),
        _transitions(("NONE", "REQUESTED", "M40 S / M41..M45 with another stage"),
                     ("NONE", "AT_STANDSTILL", "requested at standstill (REQUESTED lasts less than a cycle)"),
                     ("NONE", "TO_POSITION", "change at a fixed position (MD35010 bit 1)"),
                     ("TO_POSITION", "POSITION_DELAY", "at the change position"),
                     ("POSITION_DELAY", "REQUESTED", "MD35310 elapsed"),
                     ("REQUESTED", "AT_STANDSTILL", "stationary (61.4)"),
                     ("AT_STANDSTILL", "NONE", "gear changed (16.3)"),
                     ("REQUESTED", "NONE", "gear changed before standstill, reset"),
                     ("TO_POSITION", "NONE", "position not reached (22020), reset"))),
    StateMachine(
        "coupling", "Synchronous spindle coupling of a following spindle", "vc/core/spindle/coupling_state.py",
        "spindle",
        (StateDef("UNCOUPLED", "follows no leading spindle", "defined ──COUPON"), *_enum_states(tuple(CouplingPhase))),
        _transitions(("UNCOUPLED", "SYNCHRONISING", "COUPON, the configured pair at NC start"),
                     ("UNCOUPLED", "SYNCHRONOUS", "COUPON with both spindles at standstill: synchronous at once"),
                     ("SYNCHRONISING", "SYNCHRONOUS", "synchronism reached"),
                     ("SYNCHRONOUS", "UNCOUPLED", "COUPOF, reset"), ("SYNCHRONISING", "UNCOUPLED", "COUPOF, reset"))),
    StateMachine(
        "esr.drive", "Drive-autonomous ESR of an axis (DB31.DBX95.2)", "vc/core/retraction/drive_esr.py", "axis",
        _enum_states(tuple(DriveReaction)),
        _transitions(("ARMED", "REACTING", "$AN_ESR_TRIGGER with $AA_ESR_ENABLE = 1"),
                     ("REACTING", "DONE", "the reaction ended"),
                     ("DONE", "ARMED", "$AA_ESR_ENABLE 1 -> 0 -> 1 (acknowledged)"))),
    StateMachine(
        "esr.retract", "Fast retraction and NC-controlled ESR retract of a channel", "vc/core/retraction/esr.py",
        "channel",
        (StateDef("IDLE", "no retract motion", "def start_channel_reaction"),
         StateDef("RETRACTING", "the retract axes move to their POLF / LIFTFAST positions", "self.motion = ")),
        _transitions(("IDLE", "RETRACTING", "$AC_ESR_TRIGGER, LIFTFAST in G33, POLFA"),
                     ("RETRACTING", "IDLE", "at the retract positions"))),
    StateMachine(
        "esr.stop", "NC-controlled ESR stop axes of a channel (MD21380, MD21381)", "vc/core/retraction/esr.py",
        "channel",
        (StateDef("IDLE", "no stop reaction", "class _StopAxes"),
         StateDef("RUNNING_ON", "the path runs on for MD21380", "brake_at: int"),
         StateDef("BRAKING", "the stop axes brake within MD21381", "stopped_by: int")),
        _transitions(("IDLE", "RUNNING_ON", "$AC_ESR_TRIGGER (a stop axis, or G33 with LFON)"),
                     ("IDLE", "BRAKING", "$AC_ESR_TRIGGER with MD21380 = 0"),
                     ("RUNNING_ON", "BRAKING", "MD21380 elapsed"), ("BRAKING", "IDLE", "the stop axes stand"))),
    StateMachine(
        "command_axis", "Command axis: POS[ax]= of a synchronized action, a single axis (seed 003 §9.3.2)",
        "vc/core/axis/command_axis.py", "axis", _enum_states(tuple(CommandState)),
        _transitions(("IDLE", "TRAVERSING", "POS[ax]= of a synchronized action"),
                     ("TRAVERSING", "IDLE", "at its end point; channel reset, DB31.DBX2.2; another owner took it"),
                     ("TRAVERSING", "ESR_STOPPED", "its single-axis ESR stop or retraction"),
                     ("IDLE", "ESR_STOPPED", "its ESR stop after the motion ended within MD37510"),
                     ("ESR_STOPPED", "IDLE", "the channel's reset, DB31.DBX2.2"))),
    StateMachine(
        "manual_retraction", "Manual retraction along the tool axis (DB21.DBX377.4, 377.5)",
        "vc/core/nck/manual_retraction.py", "channel",
        (StateDef("NO_DATA", "no retract data", "NO DATA ──"),
         StateDef("DATA", "retract data kept (377.5)", "▶ DATA (377.5 = 1)"),
         StateDef("ACTIVE", "retraction selected (377.4)", "▶ ACTIVE (377.4 = 1)")),
        _transitions(("NO_DATA", "DATA", "reset / power failure in G33, G331, G332"),
                     ("DATA", "ACTIVE", "RETRAC (DB21.DBX396.0) in JOG"),
                     ("ACTIVE", "DATA", "reset, another mode, REF"),
                     ("DATA", "NO_DATA", "a program starts"), ("ACTIVE", "NO_DATA", "a program starts"))),
)

BY_NAME: dict[str, StateMachine] = {machine.name: machine for machine in STATE_MACHINES}
