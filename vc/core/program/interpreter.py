"""Block decoding: modal G-code state and what one block asks the channel to do.

``decode`` turns a parsed block into a :class:`BlockPlan` (axis end points, dwell,
program stop or end) or an alarm, using the modal state it updates.  The words this
control understands are dispatched through ``_WORD_HANDLERS`` / ``_KEYWORD_HANDLERS``;
a word without a handler raises alarm 12550 "name not defined or option/function not
available", as on a control without the function.  Later NC functions add handlers.
"""

from __future__ import annotations

import re
from collections.abc import Callable, Collection, Mapping
from dataclasses import dataclass, field

from vc.config import md_dictionary as MD
from vc.config.model import ChannelConfig
from vc.core.axis.axis import MachineAxis
from vc.core.axis.stroke_limits import StrokeCommand
from vc.core.interpolation.circle import CENTRE_WORDS, CIRCLE_END_POINT, PLANES, Arc, ArcTolerance, plan_arc
from vc.core.interpolation.thread_cutting import ThreadCommand
from vc.core.program.commands import (
    LFPOS,
    LFTXT,
    LFWP,
    MAX_DELAY_S,
    SYNCHRONISM_THRESHOLDS,
    CouplingCommand,
    DriveEsrCommand,
    PolygonCommand,
    RetractProgramming,
    SpindleCommand,
    block_change_of,
    esrr_command,
    esrs_command,
    kind_of,
)
from vc.core.program.five_axis_program import (
    FIVE_AXIS_ADDRESSES,
    FIVE_AXIS_G_CODES,
    TILTED_PLANE,
    FiveAxisModal,
    FiveAxisWords,
)
from vc.core.program.program import (
    Assignment,
    Block,
    Call,
    Item,
    Keyword,
    Label,
    SynchronizedAction,
    ValueFunction,
    Word,
)
from vc.core.program.sync_actions import SyncAction, SyncActionError, VariableWrite, parse_actions, parse_condition

POLYGON_OUT_OF_RANGE = 65840  # project numbers: seed 002 names no alarms (spec 7.5 TV-PG-7)
POLYGON_OWN_BLOCK = 65842

# Block-end condition of a motion block (G60 exact stop with its window, or G64 continuous path).
EXACT_STOP_FINE = "G601"
EXACT_STOP_COARSE = "G602"
INTERPOLATION_END = "G603"


@dataclass(slots=True)
class ModalState:
    """Modal G-code state of a channel; ``reset()`` restores the values after reset / program start."""

    rapid: bool = True  # group 1: G0 (reset value) / G1
    absolute: bool = True  # G90 / G91
    block_end: str = EXACT_STOP_FINE  # G60 + G601 / G602 / G603; G64 ends at interpolation end
    feed: float | None = None  # F: path feed in mm/min (G94) or mm per master spindle revolution (G95)
    per_revolution: bool = False  # group 15: G94 (reset value) / G95, the ISO G98 / G99 of seed 002 alike
    polygon: bool = False  # G51.2 (polygon turning) until G50.2 (seed 002)
    five_axis: FiveAxisModal = field(default_factory=FiveAxisModal)  # G43.4 / G43 / G68.2 (seed 001)
    # group 1 thread modes: "G33" (thread cutting), "G331"/"G332" (tapping); "" after G0/G1
    thread: str = ""
    plane: str = "G17"  # G17 / G18 / G19 working plane; reset value G17 (MD20150 as delivered) [control]
    circle: str = ""  # group 1 circular interpolation: "G2" (clockwise) / "G3"; "" after G0/G1/G33/G331
    thread_lead: ThreadCommand | None = None  # the last G33 lead: it holds for G33 blocks without one
    retract: RetractProgramming = field(default_factory=RetractProgramming)  # LFON, DILF, ALF, POLF ...

    def reset(self) -> None:
        self.rapid = True
        self.absolute = True
        self.block_end = EXACT_STOP_FINE
        self.feed = None
        self.per_revolution = False
        self.polygon = False
        self.five_axis.reset()
        self.thread = ""
        self.plane = "G17"
        self.circle = ""
        self.thread_lead = None
        self.retract.reset()


@dataclass(frozen=True, slots=True)
class Tapping:
    """G331 / G332: the drilling axis and the spindle interpolated with it (seed 003 L17640-17664).

    The spindle turns ``pitch`` mm per revolution of the drilling axis: G331 in the direction of
    the pitch's sign (+ = M3, right-hand thread), G332 against it; the path feed is S x |pitch|
    (L8573, L8581)."""

    function: str  # "G331" or "G332"
    axis: str  # machine axis of the drilling (geometry) axis
    spindle: str  # machine axis of the master spindle
    pitch: float  # mm/rev, signed
    travel: float = 0.0  # mm of the drilling axis, signed; known when the block starts to move

    def spindle_degrees(self, travel: float) -> float:
        """How far the spindle turns while the drilling axis travels ``travel`` mm."""
        direction = (1.0 if self.pitch > 0 else -1.0) * (1.0 if self.function == "G331" else -1.0)
        return direction * abs(travel) / abs(self.pitch) * 360.0

    @property
    def spindle_per_mm(self) -> float:
        """Spindle degrees per mm of the drilling axis's travel, signed (0 before the block moves)."""
        return self.spindle_degrees(self.travel) / self.travel if self.travel else 0.0


@dataclass(slots=True)
class BlockPlan:
    targets: dict[str, float] = field(default_factory=dict)  # machine axis -> end position
    rapid: bool = True
    feed: float = 0.0  # mm/min, or mm/rev with feed_per_revolution
    feed_per_revolution: bool = False  # G95 / G99: the channel multiplies F by the spindle speed each cycle
    dwell: float = 0.0  # seconds
    program_stop: bool = False  # M0
    program_end: bool = False  # M2 / M30
    block_end: str = EXACT_STOP_FINE
    reference_axes: tuple[str, ...] = ()  # G74: machine axes to reference
    preset: dict[str, float] = field(default_factory=dict)  # PRESETON: machine axis -> new actual value
    delete_drf: bool = False  # DRFOF: the DRF offsets of the channel's axes are deleted (seed 003 L36470)
    spindles: dict[str, SpindleCommand] = field(default_factory=dict)  # machine axis -> its part of the block
    couplings: list[CouplingCommand] = field(default_factory=list)
    # CPSYNCOP[Sn]=.. and the other synchronism thresholds: machine axis of the FS -> MD number -> value
    coupling_thresholds: dict[str, dict[int, float]] = field(default_factory=dict)
    feeds: dict[str, float] = field(default_factory=dict)  # FA[Sn]: machine axis -> deg/min (0 = MD)
    position_control: dict[str, bool] = field(default_factory=dict)  # SPCON / SPCOF: machine axis -> on
    dwell_revolutions: float = 0.0  # G4 S: revolutions of the spindle ``dwell_spindle``
    dwell_spindle: str = ""  # the machine axis of the spindle whose revolutions G4 S / G4 S<n>= counts
    spindle_waits: list[str] = field(default_factory=list)  # WAITS: machine axes of the spindles waited for
    polygon: PolygonCommand | None = None
    five_axis: FiveAxisWords | None = None  # G43.4 / G43 / G49 / G68.2 / G69 / G53.1 and their words
    tapping: Tapping | None = None  # G331 / G332 with a drilling axis
    thread: ThreadCommand | None = None  # G33 with axes: thread cutting slaved to the master spindle
    variables: list[VariableWrite] = field(default_factory=list)  # $AC_.. / $AA_.. / $AN_.. assignments
    sync_actions: list[SyncAction] = field(default_factory=list)  # ID= / IDS= synchronized actions
    drive_esr: list[DriveEsrCommand] = field(default_factory=list)  # ESRS / ESRR
    single_axis_retract: list[tuple[str, int, float | None]] = field(default_factory=list)  # POLFA
    machine_coordinates: bool = False  # G53: the axis words are machine positions, in rapid (seed 000 L154-158)
    reference_return: int = 0  # G28 = 1, G30 = 2: via the axis words (intermediate point) to reference point n
    return_targets: dict[str, float] = field(default_factory=dict)  # G28 / G30: machine axis -> reference point
    path_length: float | None = None  # the length F is measured along where a transform makes it differ
    arc: Arc | None = None  # G2 / G3: the path in program coordinates (``targets`` hold its end point)
    stroke_limit: StrokeCommand | None = None  # G22 (with the box corners it sets) / G23


@dataclass(frozen=True, slots=True)
class DecodeAlarm:
    number: int
    parameters: tuple[object, ...]
    axis: str = ""


SOFTWARE_LIMIT = 10720
LIMIT_TOLERANCE = 1e-9  # mm: an end point a transform computes onto the limit is on it, not beyond


def software_limit_alarm(channel: str, label: str, axis: MachineAxis, position: float) -> DecodeAlarm | None:
    """Alarm 10720 when ``position`` of ``axis`` lies beyond its software limit switches MD36100 /
    MD36110 (active once referenced): the check before a block moves, for ordinary end points, for
    the Cartesian position of the inclined pair and for the points of a transformed path."""
    if not axis.software_limits_active:
        return None
    if position > axis.dyn.limit_plus + LIMIT_TOLERANCE:
        return DecodeAlarm(SOFTWARE_LIMIT, (channel, axis.name, label, "+"), axis.name)
    if position < axis.dyn.limit_minus - LIMIT_TOLERANCE:
        return DecodeAlarm(SOFTWARE_LIMIT, (channel, axis.name, label, "-"), axis.name)
    return None


def end_point_limit_alarm(plan: BlockPlan, channel: str, label: str, axes: Mapping[str, MachineAxis],
                          limits_checked_elsewhere: Collection[str] = ()) -> DecodeAlarm | None:
    """10720 for the first machine end point of an ordinary block beyond its software limits;
    ``limits_checked_elsewhere`` are axes a transform checks in its own coordinates."""
    for name, target in plan.targets.items():
        if name not in limits_checked_elsewhere:
            alarm = software_limit_alarm(channel, label, axes[name], target)
            if alarm is not None:
                return alarm
    return None


class _Decoder:
    def __init__(self, block: Block, modal: ModalState, channel: ChannelConfig, axes: dict[str, MachineAxis],
                 program_positions: Mapping[str, float], limits_checked_elsewhere: Collection[str]):
        self.block = block
        self.modal = modal
        self.channel = channel
        self.axes = axes
        self.program_positions = program_positions  # where a transform puts an axis in program coordinates
        self.limits_checked_elsewhere = limits_checked_elsewhere  # a transform checks their software limits
        if any(isinstance(item, Word) and item.address == "G" and item.value == 53 for item in block.items):
            self.program_positions = {}  # G53: machine coordinates; incremental words count from the setpoint
        self.plan = BlockPlan()
        self.alarm: DecodeAlarm | None = None
        self.dwell_requested = False
        self.reference_requested = False  # G74
        self.other_g_words = False  # G words besides G74 (a G74 block stands alone)
        self.dwell_value: float | None = None
        self.feed_word: float | None = None
        self.polygon_block = any(isinstance(item, Word) and item.address == "G" and round(item.value * 10) in (512, 502)
                                 for item in block.items)
        self.polygon_words: dict[str, float] = {}
        self.five_axis_codes = {round(item.value * 10) / 10 for item in block.items
                                if isinstance(item, Word) and item.address == "G"} & FIVE_AXIS_G_CODES
        if self.five_axis_codes:
            self.plan.five_axis = FiveAxisWords()
        self.pitch_words: dict[str, float] = {}  # I / J / K: thread pitch (G33, G331) or circle centre (G2, G3)
        self.radius_word: float | None = None  # R / CR=: circle radius (G2, G3)
        self.start_angle: float | None = None  # SF= of a G33 block

    def fail(self, number: int, *parameters: object, axis: str = "") -> None:
        if self.alarm is None:
            self.alarm = DecodeAlarm(number, parameters, axis)

    def unknown(self, text: str) -> None:
        self.fail(12550, self.channel.name, self.block.label, text)

    def spindle(self, number: int | None) -> SpindleCommand | None:
        """The command of spindle ``number`` (None: the channel's master spindle, MD20090)."""
        if number is None:
            number = self.channel.md.int(MD.SPIND_DEF_MASTER_SPIND)
        for name, axis in self.axes.items():
            if axis.config.spindle_number == number:
                return self.plan.spindles.setdefault(name, SpindleCommand())
        self.fail(16105, self.channel.name, self.block.label, number)
        return None

    def spindle_axis(self, text: object) -> str | None:
        """The machine axis of ``S<n>`` (or of a spindle's axis name) in a coupling call."""
        name = str(text).strip().upper()
        if len(name) > 1 and name[0] == "S" and name[1:].isdigit():
            command_count = len(self.plan.spindles)
            found = self.spindle(int(name[1:]))
            if found is None:
                return None
            axis = next(a for a, c in self.plan.spindles.items() if c is found)
            if len(self.plan.spindles) > command_count and found == SpindleCommand():
                del self.plan.spindles[axis]  # only looked up: no spindle function in the block
            return axis
        machine_axis = self.machine_axis(name)
        if machine_axis is not None and self.axes[machine_axis].is_spindle:
            return machine_axis
        self.fail(16105, self.channel.name, self.block.label, name)
        return None

    def machine_axis(self, name: str) -> str | None:
        """The machine axis of this channel that ``name`` (geometry, channel or machine axis name) means."""
        machine_axis = self.channel.axis_for_program_name(name)
        return machine_axis if machine_axis in self.axes else None

    def axis_value(self, name: str, value: object) -> None:
        machine_axis = self.machine_axis(name)
        if machine_axis is None:
            self.unknown(name)
            return
        axis = self.axes[machine_axis]
        if axis.is_spindle and not axis.axis_mode:
            # the axis name of a spindle switches it to axis mode: an implicit M70 (L17421-17462)
            self.plan.spindles.setdefault(machine_axis, SpindleCommand()).axis_mode = True
        if isinstance(value, ValueFunction) and value.name in ("AC", "IC"):
            absolute, number = value.name == "AC", value.value
        elif isinstance(value, float):
            absolute, number = self.modal.absolute, value
        else:
            self.unknown(f"{name}={value}")
            return
        start = self.plan.targets.get(machine_axis, self.program_positions.get(machine_axis, axis.setpoint))
        self.plan.targets[machine_axis] = number if absolute else start + number
        if not absolute and self.plan.five_axis is not None:
            self.plan.five_axis.incremental_axes = True


def _g_word(decoder: _Decoder, value: float) -> None:
    code = round(value * 10) / 10
    modal = decoder.modal
    if code != 74:
        decoder.other_g_words = True
    if code in (0, 1, 2, 3, 33, 331, 332):
        modal.circle = f"G{code:g}" if code in (2, 3) else ""  # one G group: the last motion word holds
    if code == 0:
        modal.rapid = True
        modal.thread = ""
    elif code in (1, 2, 3):
        modal.rapid = False
        modal.thread = ""
    elif code == 33:
        modal.rapid = False
        modal.thread = "G33"
    elif code in (17, 18, 19):
        modal.plane = f"G{code:g}"
    elif code in (331, 332):
        modal.rapid = False
        modal.thread = f"G{code:g}"
    elif code == 4:
        decoder.dwell_requested = True
    elif code == 74:
        decoder.reference_requested = True
    elif code == 53:
        decoder.plan.machine_coordinates = True
    elif code in (28, 30):
        decoder.plan.reference_return = 1 if code == 28 else 2
    elif code in (22, 23):
        decoder.plan.stroke_limit = StrokeCommand(code == 22, {})
    elif code == 90:
        modal.absolute = True
    elif code == 91:
        modal.absolute = False
    elif code in (60, 601):
        modal.block_end = EXACT_STOP_FINE
    elif code == 602:
        modal.block_end = EXACT_STOP_COARSE
    elif code in (603, 64):
        # G64 without look-ahead blending: the block ends when interpolation ends.
        modal.block_end = INTERPOLATION_END
    elif code in (94, 95, 98, 99):
        # G94 / G95, or G98 / G99 as the GSK programs of seed 002 write them (L241): a change of the
        # feed type wants a new F, the old one is in the other unit (else alarm 10860) [control]
        per_revolution = code in (95, 99)
        if per_revolution != modal.per_revolution:
            modal.feed = None
        modal.per_revolution = per_revolution
    elif code == 51.2:
        decoder.plan.polygon = PolygonCommand(True)
    elif code == 50.2:
        decoder.plan.polygon = PolygonCommand(False)
    elif code in FIVE_AXIS_G_CODES and decoder.plan.five_axis is not None:
        decoder.plan.five_axis.codes.append(code)  # the channel's five-axis control checks and applies them
    else:
        decoder.unknown(f"G{value:g}")


_SPINDLE_M = {3, 4, 5, 19, 40, 41, 42, 43, 44, 45, 70}
_POSITION_MODES = ("AC", "IC", "DC", "ACP", "ACN")


def spindle_m(decoder: _Decoder, value: float, number: int | None) -> bool:
    """M3/M4/M5/M19/M40..M45/M70 for a spindle; False when ``value`` is no spindle function."""
    code = round(value)
    if value != code or code not in _SPINDLE_M:
        return False
    command = decoder.spindle(number)
    if command is None:
        return True
    command.m_function = code
    if code in (3, 4, 5):
        command.direction = code
    elif code == 19:
        # M19 positions to SD43240 M19_SPOS with SD43250 (L16381-16391); the setting data are not
        # part of this control: 0 degrees, shortest way [control: their defaults]
        command.position = ("DC", 0.0)
        command.wait_for_position = True
    elif code == 70:
        command.axis_mode = True
    else:
        command.gear = code
    return True


def _s_word(decoder: _Decoder, value: float, number: int | None = None) -> None:
    command = decoder.spindle(number)
    if command is None:
        return
    if decoder.modal.polygon and number is None:
        # during polygon turning S is signed: its sign is the master's direction, 0 stops (seed 002 L41-47)
        command.speed = abs(value)
        if command.direction is None:
            command.direction = 3 if value > 0 else (4 if value < 0 else 5)
        return
    command.speed = value


def _spos(decoder: _Decoder, name: str, index: str, value: object) -> None:
    """SPOS[n]= / SPOSA[n]= with AC, IC, DC, ACP, ACN (L16335-16349); plain = DC."""
    number = int(index) if index.isdigit() else None
    if index and number is None:
        decoder.unknown(f"{name}[{index}]")
        return
    if isinstance(value, ValueFunction) and value.name in _POSITION_MODES:
        mode, degrees = value.name, value.value
    elif isinstance(value, float):
        mode, degrees = "DC", value
    else:
        decoder.unknown(f"{name}={value}")
        return
    command = decoder.spindle(number)
    if command is not None:
        command.position = (mode, degrees)
        command.wait_for_position = name == "SPOS"
        if decoder.channel.md.int(MD.SPOS_TO_VDI) & 1 and command.m_function is None:
            command.m_function = 19  # MD20850 bit 0: SPOS / SPOSA output M19 to the PLC (L16406-16420)


def _m_word(decoder: _Decoder, value: float) -> None:
    if spindle_m(decoder, value, None):
        return
    if value == 0:
        decoder.plan.program_stop = True
    elif value == 1:
        pass  # optional stop, not activated
    elif value in (2, 30):
        decoder.plan.program_end = True
    else:
        decoder.unknown(f"M{value:g}")


def _f_word(decoder: _Decoder, value: float) -> None:
    decoder.feed_word = value


def _radius_word(decoder: _Decoder, value: float) -> None:
    decoder.radius_word = value


def _preseton(decoder: _Decoder, call: Call) -> None:
    """PRESETON(axis, value, ...): set the actual value of machine axes where they stand.

    The axes lose their reference (seed 003 L758-761: G74 references them again).  Pairs of a
    machine axis (or channel axis name) and a value; like the real control's it stands in a
    block of its own, which is checked in ``_finish`` [control].
    """
    arguments = call.arguments
    if not arguments or len(arguments) % 2:
        decoder.fail(12080, decoder.channel.name, decoder.block.label, "PRESETON")
        return
    for name, value in zip(arguments[::2], arguments[1::2], strict=True):
        machine_axis = decoder.machine_axis(str(name))
        if machine_axis is None or decoder.axes[machine_axis].is_spindle or not isinstance(value, float):
            decoder.fail(12080, decoder.channel.name, decoder.block.label, f"PRESETON({name},{value})")
            return
        decoder.plan.preset[machine_axis] = value


def _coupling_call(decoder: _Decoder, call: Call) -> None:
    """COUPDEF(FS, LS, TRNom, TRDenom, BlockChange, CouplingType), COUPON(FS, LS[, POSFS]),
    COUPONC(FS, LS), COUPOF(FS[, LS]), COUPOFS(FS[, LS]), COUPDEL(FS[, LS]), COUPRES(FS[, LS])
    (seed 003 L22497-22657)."""
    arguments = list(call.arguments)
    name, label = call.name, decoder.block.label
    needs_leading = name in ("COUPDEF", "COUPON", "COUPONC")
    if len(arguments) < (2 if needs_leading else 1):
        decoder.fail(12080, decoder.channel.name, label, name)
        return
    following = decoder.spindle_axis(arguments[0])
    leading = decoder.spindle_axis(arguments[1]) if len(arguments) > 1 and arguments[1] != "" else ""
    if following is None or leading is None:
        return
    if following == leading:
        decoder.fail(16785, decoder.channel.name, label, following)  # [control] identical spindles
        return
    rest = arguments[2:]
    if name == "COUPDEF":
        numbers = [value if isinstance(value, float) else None for value in rest[:2]] + [None, None]
        texts = [str(value) if value != "" else None for value in rest[2:4]] + [None, None]
        if any(value not in ("", None) and not isinstance(value, float) for value in rest[:2]) or \
                (numbers[1] is not None and numbers[1] == 0.0) or \
                (texts[0] is not None and block_change_of(texts[0]) is None) or \
                (texts[1] is not None and kind_of(texts[1]) is None):
            decoder.fail(16795, decoder.channel.name, label)  # [control] string cannot be interpreted
            return
        decoder.plan.couplings.append(CouplingCommand(name, following, leading, numbers[0], numbers[1], texts[0],
                                                      texts[1]))
    elif name == "COUPON" and rest:
        offset = rest[0]
        if not isinstance(offset, float) or not 0.0 <= offset < 360.0:
            decoder.fail(12080, decoder.channel.name, label, f"COUPON POSFS {offset}")
            return
        decoder.plan.couplings.append(CouplingCommand(name, following, leading, offset=offset))
    else:
        decoder.plan.couplings.append(CouplingCommand(name, following, leading))


def _synchronism_threshold(decoder: _Decoder, name: str, index: str, value: object) -> None:
    """CPSYNCOP[FS]= / CPSYNFIP / CPSYNCOV / CPSYNFIV / CPSYNCOP2 / CPSYNFIP2: a threshold of the
    synchronism monitoring of the following spindle FS, a REAL >= 0 in degrees (rev/min for the
    ..V keywords; stage 2: 0 = off), L29655-29850.  The coupling takes it at the FS's next COUPON."""
    if not index or not isinstance(value, float) or value < 0.0:
        text = f"{value:g}" if isinstance(value, float) else str(value)
        decoder.fail(12080, decoder.channel.name, decoder.block.label,
                     f"{name}[{index}]={text}" if index else f"{name}={text}")  # [control]
        return
    following = decoder.spindle_axis(index)
    if following is not None:
        decoder.plan.coupling_thresholds.setdefault(following, {})[SYNCHRONISM_THRESHOLDS[name].number] = value


def _waitc(decoder: _Decoder, call: Call) -> None:
    """WAITC(FS[, condition][, FS2[, condition]]): wait for the synchronism condition (L22659-22690)."""
    arguments = list(call.arguments)
    while arguments:
        following = decoder.spindle_axis(arguments.pop(0))
        condition = str(arguments.pop(0)) if arguments else ""
        if following is None:
            return
        if condition and block_change_of(condition) is None:
            decoder.fail(16795, decoder.channel.name, decoder.block.label)
            return
        decoder.plan.couplings.append(CouplingCommand("WAITC", following, block_change=condition or None))


def _waits(decoder: _Decoder, call: Call | None) -> None:
    """WAITS / WAITS(n, m, ...): the block change waits until the spindles (the master spindle
    without arguments) stand on their SPOSA position or, after M5, stand still (seed 003 L23963
    uses it after SPOSA[2]=0) [control: the 840D command, its page is not in the seed]."""
    numbers = [float(decoder.channel.md.int(MD.SPIND_DEF_MASTER_SPIND))] if call is None or not call.arguments \
        else list(call.arguments)
    for number in numbers:
        axis = decoder.spindle_axis(f"S{number:g}" if isinstance(number, float) else number)
        if axis is None:
            return
        decoder.plan.spindle_waits.append(axis)


def _spcon(decoder: _Decoder, call: Call | None, on: bool) -> None:
    """SPCON / SPCON(n) / SPCOF: position control of a spindle on or off (L22100, L23918-23921)."""
    numbers = [None] if call is None or not call.arguments else list(call.arguments)
    for number in numbers:
        axis = decoder.spindle_axis(f"S{number:g}" if isinstance(number, float) else
                                    f"S{decoder.channel.md.int(MD.SPIND_DEF_MASTER_SPIND)}")
        if axis is not None:
            decoder.plan.position_control[axis] = on


# ---------------------------------------------------------------------------- retraction and ESR words
# System variables a part program (or a synchronized action) may write; True: indexed by an axis.
PROGRAM_VARIABLES = {"$AC_LIFTFAST": False, "$AC_ESR_TRIGGER": False, "$AN_ESR_TRIGGER": False,
                     "$AA_ESR_ENABLE": True, "$AA_ESR_TRIGGER": True, "$AA_COUP_CORR": True}
_SPINDLE_VARIABLES = {"$AA_COUP_CORR"}  # indexed by a spindle: S<n> or its axis name (L31543-31551)
_RETRACT_TARGET_MODES = {"LFTXT": LFTXT, "LFWP": LFWP, "LFPOS": LFPOS}
_MAX_ESR_AXES = 5  # ESRS / ESRR: at most 5 axes per call (L41926, L41958)


def _variable_write(decoder: _Decoder, name: str, index: str, value: object) -> VariableWrite | None:
    """``$AA_ESR_ENABLE[X]=1`` and the like, with the axis index as a machine axis."""
    label = decoder.block.label
    if name not in PROGRAM_VARIABLES:
        decoder.unknown(name)
        return None
    if PROGRAM_VARIABLES[name] != bool(index) or not isinstance(value, float):
        decoder.fail(12080, decoder.channel.name, label, f"{name}[{index}]={value}" if index else f"{name}={value}")
        return None
    machine_axis = ""
    if index:
        spindle = name in _SPINDLE_VARIABLES
        found = decoder.spindle_axis(index) if spindle else decoder.machine_axis(index)
        if found is None:
            if not spindle:
                decoder.unknown(index)  # spindle_axis raised 16105 itself
            return None
        machine_axis = found
    return VariableWrite(name, machine_axis, value)


def _retract_keyword(decoder: _Decoder, name: str) -> None:
    """LFON / LFOF (G group 45) and LFTXT / LFWP / LFPOS (G group 46), seed 003 L8238-8262."""
    retract = decoder.modal.retract
    if name in ("LFON", "LFOF"):
        retract.enabled = name == "LFON"
    else:
        retract.target_mode = _RETRACT_TARGET_MODES[name]


def _retract_assignment(decoder: _Decoder, item: Assignment) -> bool:
    """DILF=, ALF=, SF=, POLF[ax]= and the system variables; False: not one of these."""
    name, value, label, channel = item.name, item.value, decoder.block.label, decoder.channel.name
    retract = decoder.modal.retract
    if name.startswith("$"):
        write = _variable_write(decoder, name, item.index, value)
        if write is not None:
            decoder.plan.variables.append(write)
        return True
    if name in ("DILF", "ALF", "SF") and not item.index:
        if not isinstance(value, float) or value < 0.0 or (name == "ALF" and value not in range(1, 9)) or \
                (name == "SF" and value >= 360.0):
            decoder.fail(12080, channel, label, f"{name}={value}")  # [control] ALF 1..8, SF 0..<360
        elif name == "DILF":
            retract.distance = value
        elif name == "ALF":
            retract.direction = int(value)
        else:
            decoder.start_angle = value
        return True
    if name == "POLF" and item.index:
        machine_axis = decoder.machine_axis(item.index)
        if machine_axis is None:
            decoder.unknown(item.index)
        elif isinstance(value, ValueFunction) and value.name in ("IC", "AC"):
            retract.positions[machine_axis] = (value.value, value.name == "IC")
        elif isinstance(value, float):
            retract.positions[machine_axis] = (value, False)
        else:
            decoder.fail(12080, channel, label, f"POLF[{item.index}]={value}")
        return True
    return False


def _retract_axes(decoder: _Decoder, call: Call) -> tuple[str, ...] | None:
    axes = []
    for argument in call.arguments:
        machine_axis = decoder.machine_axis(str(argument)) if argument != "" else None
        if machine_axis is None:
            decoder.fail(12080, decoder.channel.name, decoder.block.label, f"{call.name}({argument})")
            return None
        axes.append(machine_axis)
    return tuple(axes)


def _polf_mask(decoder: _Decoder, call: Call) -> None:
    """POLFMASK(ax, ...) axial, POLFMLIN(ax, ...) linear retraction; () disables the set (L8314-8325).
    An axis is in one of the two sets at a time [control]."""
    axes = _retract_axes(decoder, call)
    if axes is None:
        return
    retract = decoder.modal.retract
    if call.name == "POLFMASK":
        retract.axial = axes
        retract.linear = tuple(axis for axis in retract.linear if axis not in axes)
    else:
        retract.linear = axes
        retract.axial = tuple(axis for axis in retract.axial if axis not in axes)


def _polfa(decoder: _Decoder, call: Call) -> None:
    """POLFA(ax, type[, value], ...): single-axis retract, type 0 off, 1 absolute, 2 incremental
    (L11511-11578; types 0 and 2 [INF] as the spec reads them)."""
    arguments = list(call.arguments)
    while arguments:
        name, kind, value = [*arguments, "", "", ""][:3]
        del arguments[:3]
        machine_axis = decoder.machine_axis(str(name))
        if machine_axis is None or kind not in (0.0, 1.0, 2.0) or (value != "" and not isinstance(value, float)):
            decoder.fail(12080, decoder.channel.name, decoder.block.label, f"POLFA({name},{kind},{value})")
            return
        decoder.plan.single_axis_retract.append((machine_axis, int(kind), value if isinstance(value, float) else None))


def _esr_drive(decoder: _Decoder, call: Call) -> None:
    """ESRS(ax, time, ...) / ESRR(ax, distance, velocity, ...): drive parameters of drive-autonomous ESR
    (L41912-41993); at most 5 axes, stop time 0 .. 20 s, velocity above 0."""
    width = 2 if call.name == "ESRS" else 3
    arguments = list(call.arguments)
    label = decoder.block.label
    if not arguments or len(arguments) % width or len(arguments) > width * _MAX_ESR_AXES:
        decoder.fail(12080, decoder.channel.name, label, call.name)
        return
    for start in range(0, len(arguments), width):
        name, *numbers = arguments[start:start + width]
        machine_axis = decoder.machine_axis(str(name))
        if machine_axis is None or not all(isinstance(number, float) for number in numbers):
            decoder.fail(12080, decoder.channel.name, label, f"{call.name}({name})")
            return
        values = [float(number) for number in numbers]
        if (call.name == "ESRS" and not 0.0 <= values[0] <= MAX_DELAY_S) or (call.name == "ESRR" and values[1] <= 0.0):
            decoder.fail(12080, decoder.channel.name, label, f"{call.name}({name})")
            return
        decoder.plan.drive_esr.append(esrs_command(machine_axis, values[0]) if call.name == "ESRS"
                                      else esrr_command(machine_axis, values[0], values[1]))


def _synchronized_action(decoder: _Decoder, item: SynchronizedAction) -> None:
    """ID= / IDS= ... DO ...: the condition is read by the channel in every IPO cycle."""
    try:
        condition = parse_condition(item.condition)
        actions = parse_actions(item.actions)
    except SyncActionError as error:
        decoder.fail(12080, decoder.channel.name, decoder.block.label, str(error))
        return
    writes = [_variable_write(decoder, action.name, action.index, action.value) for action in actions]
    if all(write is not None for write in writes):
        decoder.plan.sync_actions.append(SyncAction(item.number, item.static, item.mode, condition,
                                                    tuple(write for write in writes if write is not None),
                                                    decoder.block.text))


def _thread_cutting(decoder: _Decoder) -> None:
    """G33 <axes> I|J|K<lead> [SF=]: the lead belongs to the geometry axis its address names; a block
    without one keeps the last lead [control]."""
    plan, modal, channel, label = decoder.plan, decoder.modal, decoder.channel, decoder.block.label
    words = decoder.pitch_words
    if len(words) > 1:
        decoder.fail(12080, channel.name, label, "G33 lead")
        return
    if words:
        address, lead = next(iter(words.items()))
        index = _PITCH_OF_GEOMETRY_AXIS.index(address)
        lead_axis = channel.geometry_axes[index] if index < len(channel.geometry_axes) else ""
        if lead <= 0.0 or not lead_axis:
            decoder.fail(12080, channel.name, label, f"G33 {address}{lead:g}")
            return
        command = ThreadCommand(lead, lead_axis, decoder.start_angle or 0.0)
    elif modal.thread_lead is not None:
        previous = modal.thread_lead
        command = ThreadCommand(previous.lead, previous.lead_axis,
                                previous.start_angle if decoder.start_angle is None else decoder.start_angle)
    else:
        decoder.fail(12080, channel.name, label, "G33 without lead")
        return
    modal.thread_lead = command
    plan.thread = command
    plan.block_end = INTERPOLATION_END  # thread blocks join without exact stop: one thread [control]


_RETRACT_KEYWORDS = {name: (lambda decoder, name=name: _retract_keyword(decoder, name))
                     for name in ("LFON", "LFOF", "LFTXT", "LFWP", "LFPOS")}
_RETRACT_CALLS = {"POLFMASK": _polf_mask, "POLFMLIN": _polf_mask, "POLFA": _polfa, "ESRS": _esr_drive,
                  "ESRR": _esr_drive}


def _pitch_word(address: str) -> Callable[[_Decoder, float], None]:
    def handler(decoder: _Decoder, value: float) -> None:
        decoder.pitch_words[address] = value
    return handler


_PITCH_OF_GEOMETRY_AXIS = ("I", "J", "K")  # the pitch word of geometry axis 1, 2, 3 (seed 003 L17668-17675)
_WORD_HANDLERS: dict[str, Callable[[_Decoder, float], None]] = {"G": _g_word, "M": _m_word, "F": _f_word,
                                                                  "S": _s_word, "R": _radius_word,
                                                                  **{address: _pitch_word(address)
                                                                     for address in _PITCH_OF_GEOMETRY_AXIS}}
_ADDRESS_EXTENSION = re.compile(r"([MS])(\d+)$")  # M2=3, S2=500: the function of spindle 2
_KEYWORD_HANDLERS: dict[str, Callable[[_Decoder], None]] = {
    "SPCON": lambda decoder: _spcon(decoder, None, True),
    "SPCOF": lambda decoder: _spcon(decoder, None, False),
    "WAITS": lambda decoder: _waits(decoder, None),
    "DRFOF": lambda decoder: setattr(decoder.plan, "delete_drf", True),
    **_RETRACT_KEYWORDS,
}
_CALL_HANDLERS: dict[str, Callable[[_Decoder, Call], None]] = {
    "PRESETON": _preseton, "WAITC": _waitc, "WAITS": _waits,
    "SPCON": lambda decoder, call: _spcon(decoder, call, True),
    "SPCOF": lambda decoder, call: _spcon(decoder, call, False),
    **{name: _coupling_call for name in ("COUPDEF", "COUPON", "COUPONC", "COUPOF", "COUPOFS", "COUPDEL",
                                         "COUPRES")},
    **_RETRACT_CALLS,
}


def decode(
    block: Block, modal: ModalState, channel: ChannelConfig, axes: dict[str, MachineAxis],
    program_positions: Mapping[str, float] | None = None, limits_checked_elsewhere: Collection[str] = (),
) -> tuple[BlockPlan, DecodeAlarm | None]:
    """Decode ``block`` (updating ``modal``) into what the channel must do, or an alarm.

    ``program_positions``: where a transform (G43.4, G68.2) puts axes in program coordinates;
    incremental words count from there instead of from the machine setpoint.
    ``limits_checked_elsewhere``: axes whose software limits a transform checks in its own
    coordinates (the inclined pair, where its AOT bit says).
    """
    decoder = _Decoder(block, modal, channel, axes, program_positions or {}, limits_checked_elsewhere)
    if block.error:
        decoder.fail(12080, channel.name, block.label, block.error)
        return decoder.plan, decoder.alarm
    for item in block.items:
        _decode_item(decoder, item)
    _finish(decoder)
    return decoder.plan, decoder.alarm


def _decode_item(decoder: _Decoder, item: Item) -> None:
    if isinstance(item, Word):
        if decoder.polygon_block and item.address in "PQRA":
            decoder.polygon_words[item.address] = item.value
            return
        if decoder.plan.five_axis is not None and _five_axis_word(decoder, decoder.plan.five_axis, item):
            return
        handler = _WORD_HANDLERS.get(item.address)
        if handler is not None:
            handler(decoder, item.value)
        else:
            decoder.axis_value(item.address, item.value)
    elif isinstance(item, Assignment):
        _assignment(decoder, item)
    elif isinstance(item, Keyword):
        keyword_handler = _KEYWORD_HANDLERS.get(item.name)
        if keyword_handler is None:
            decoder.unknown(item.name)
        else:
            keyword_handler(decoder)
    elif isinstance(item, Call):
        call_handler = _CALL_HANDLERS.get(item.name)
        if call_handler is None:
            decoder.unknown(item.name)
        else:
            call_handler(decoder, item)
    elif isinstance(item, SynchronizedAction):
        _synchronized_action(decoder, item)
    elif isinstance(item, Label):
        pass


def _five_axis_word(decoder: _Decoder, words: FiveAxisWords, item: Word) -> bool:
    """The arguments of a five-axis block (H L E R P I J K) and G68.2's origin X Y Z; True: taken."""
    if item.address in FIVE_AXIS_ADDRESSES:
        words.arguments[item.address] = item.value
        return True
    if TILTED_PLANE in decoder.five_axis_codes and item.address in decoder.channel.geometry_names:
        words.origin[item.address] = item.value  # the plane's origin, not a motion
        return True
    return False


def _assignment(decoder: _Decoder, item: Assignment) -> None:
    if item.name in ("SPOS", "SPOSA"):
        _spos(decoder, item.name, item.index, item.value)
        return
    if _retract_assignment(decoder, item):
        return
    if item.name == "FA" and item.index and isinstance(item.value, float):
        # FA[Sn]: the velocity of SPOS offset changes on a coupled FS, deg/min; 0 = MD (L23925-23940)
        axis = decoder.spindle_axis(item.index)
        if axis is not None:
            decoder.plan.feeds[axis] = item.value
        return
    if item.name in SYNCHRONISM_THRESHOLDS:
        _synchronism_threshold(decoder, item.name, item.index, item.value)
        return
    extended = _ADDRESS_EXTENSION.match(item.name)
    if extended and not item.index and isinstance(item.value, float) and \
            decoder.channel.axis_for_program_name(item.name) is None:
        address, number = extended.group(1), int(extended.group(2))
        if address == "S":
            _s_word(decoder, item.value, number)
        elif not spindle_m(decoder, item.value, number):
            decoder.unknown(f"{item.name}={item.value:g}")
        return
    if item.name == "S" and not item.index and isinstance(item.value, float):
        _s_word(decoder, item.value)
        return
    if item.name == "CR" and not item.index and isinstance(item.value, float):
        decoder.radius_word = item.value  # the SINUMERIK's circle radius (the ISO dialect's R)
        return
    if item.index:
        decoder.unknown(f"{item.name}[{item.index}]")
    else:
        decoder.axis_value(item.name, item.value)


def _polygon(decoder: _Decoder) -> None:
    """G51.2 P Q R A / G50.2 stand in blocks of their own; P 1..999, Q -999..999 but not 0,
    R 0..9999999 (seed 002 L21-51, L29-31); a re-issue while synchronous is the channel's to judge
    (parameter ECN)."""
    plan, words, label = decoder.plan, decoder.polygon_words, decoder.block.label
    command = plan.polygon
    assert command is not None
    alone = not (plan.targets or plan.spindles or plan.couplings or decoder.dwell_requested or plan.program_end
                 or plan.program_stop or decoder.feed_word is not None or plan.feeds)
    if not alone or (not command.start and words):
        decoder.fail(POLYGON_OWN_BLOCK, decoder.channel.name, label)
        return
    if not command.start:
        decoder.modal.polygon = False
        return
    p, q, r, a = (words.get(key, 0.0) for key in "PQRA")
    if "P" not in words or "Q" not in words or not (1 <= p <= 999 and p == int(p)) or \
            not (-999 <= q <= 999 and q == int(q)) or q == 0 or not 0.0 <= r <= 9999999:
        decoder.fail(POLYGON_OUT_OF_RANGE, decoder.channel.name, label, f"P{p:g} Q{q:g} R{r:g}")
        return
    plan.polygon = PolygonCommand(True, p, q, r, a)
    decoder.modal.polygon = True


MAX_PITCH = 2000.0  # mm/rev: the range of the pitch, 0.001 .. 2000 either sign (seed 003 L17675)
MIN_PITCH = 0.001


def _tapping(decoder: _Decoder) -> None:
    """G331 / G332 <geometry axis> <I|J|K pitch> [S]: one geometry axis to the thread end, with the
    pitch word of that axis (L17651-17675); the master spindle goes into position control (axis
    mode) and is interpolated with it."""
    plan, channel, label = decoder.plan, decoder.channel, decoder.block.label
    function = decoder.modal.thread
    drilling = [(index, name) for index, name in enumerate(channel.geometry_axes) if name and name in plan.targets]
    others = [name for name in plan.targets if name not in channel.geometry_axes]
    if len(drilling) != 1 or others:
        decoder.fail(12080, channel.name, label, function)  # [control] one drilling axis per tapping block
        return
    index, axis = drilling[0]
    pitch = decoder.pitch_words.get(_PITCH_OF_GEOMETRY_AXIS[index]) if index < len(_PITCH_OF_GEOMETRY_AXIS) else None
    if pitch is None or not MIN_PITCH <= abs(pitch) <= MAX_PITCH or \
            set(decoder.pitch_words) - {_PITCH_OF_GEOMETRY_AXIS[index]}:
        decoder.fail(12080, channel.name, label, f"{function} pitch")  # [control] missing or out of range
        return
    number = channel.md.int(MD.SPIND_DEF_MASTER_SPIND)
    spindle = next((name for name, each in decoder.axes.items() if each.config.spindle_number == number), None)
    if spindle is None:
        decoder.fail(16105, channel.name, label, number)
        return
    command = plan.spindles.setdefault(spindle, SpindleCommand())
    if command.direction is not None or command.position is not None or command.gear is not None:
        decoder.fail(12080, channel.name, label, function)  # [control] M3/M4/M5, SPOS or M4x with G331
        return
    command.axis_mode = True  # position control, interpolated with the drilling axis (L17614-17616)
    plan.tapping = Tapping(function, axis, spindle, pitch)


def _reference_return(decoder: _Decoder) -> bool:
    """G28 / G30 <axes>: in rapid to the intermediate point (the axis words, program coordinates,
    G90 / G91), then each axis to its reference point: MD34100[0] for G28, MD34100[1] for G30 (the
    reference point values of the ISO dialect) [control].  Only axis words may stand with it.

    Axes that have not been referenced since power-on run the reference point approach like G74,
    in the order of the manual reference return (seed 000 L74).  False: nothing more to decode.
    """
    plan, channel, label = decoder.plan, decoder.channel, decoder.block.label
    function = "G28" if plan.reference_return == 1 else "G30"
    if not plan.targets or plan.machine_coordinates or decoder.dwell_requested or plan.spindles or \
            plan.program_stop or plan.program_end or any(decoder.axes[name].is_spindle for name in plan.targets):
        decoder.fail(12080, channel.name, label, function)
        return False
    if not all(decoder.axes[name].referenced for name in plan.targets):
        plan.reference_axes = tuple(plan.targets)
        plan.targets = {}
        return False
    index = plan.reference_return - 1
    plan.return_targets = {name: decoder.axes[name].config.md.float(MD.REFP_SET_POS, index) for name in plan.targets}
    return True


def _circle(decoder: _Decoder) -> None:
    """G2 / G3 in the working plane (``vc/core/interpolation/circle.py``): the end point from the axis words, the
    centre from I J K (incremental from the start point) or the radius from R / CR=; the start
    point is the program position.  The plane's axes join the targets (a full circle names none)."""
    plan, modal, channel, label = decoder.plan, decoder.modal, decoder.channel, decoder.block.label
    words, radius = decoder.pitch_words, decoder.radius_word
    if not plan.targets and not words and radius is None:
        return  # G2 / G3 alone (or with F): only the modal state changes
    function = modal.circle
    indices = PLANES[modal.plane]
    names = [channel.geometry_axes[index] if index < len(channel.geometry_axes) else "" for index in indices]
    plane_words = {CENTRE_WORDS[index] for index in indices[:2]}
    if not names[0] or not names[1] or names[0] not in decoder.axes or names[1] not in decoder.axes:
        decoder.fail(12080, channel.name, label, f"{function}: no geometry axes in {modal.plane}")
        return
    if (radius is None) == (not words):
        # [control] neither centre nor radius, or both: the control cannot tell which circle is meant
        decoder.fail(12080, channel.name, label, f"{function}: centre I J K or radius CR= / R")
        return
    if set(words) - plane_words:
        decoder.fail(12080, channel.name, label, f"{function} {modal.plane}: {sorted(set(words) - plane_words)[0]}"
                                                 " is no centre word of the plane")  # [control]
        return
    starts = [decoder.program_positions.get(name, decoder.axes[name].setpoint) for name in names[:2]]
    ends = [plan.targets.get(name, start) for name, start in zip(names[:2], starts, strict=True)]
    for name, end in zip(names[:2], ends, strict=True):
        plan.targets[name] = end
    geometry = set(channel.geometry_axes)
    linear = [(name, decoder.program_positions.get(name, decoder.axes[name].setpoint), end, name in geometry)
              for name, end in plan.targets.items() if name not in names[:2]]
    centre = None if radius is not None else tuple(words.get(CENTRE_WORDS[index], 0.0) for index in indices[:2])
    md = channel.md
    arc = plan_arc(function == "G3", (names[0], names[1]), (starts[0], starts[1]), (ends[0], ends[1]),
                   (centre[0], centre[1]) if centre is not None else None, radius, linear,
                   ArcTolerance(md.float(MD.CIRCLE_ERROR_CONST), md.float(MD.CIRCLE_ERROR_FACTOR)))
    if isinstance(arc, str):
        decoder.fail(CIRCLE_END_POINT, channel.name, label, arc)
        return
    plan.arc = arc


def _stroke_limit(decoder: _Decoder) -> None:
    """G22 [X_ I_] [Y_ J_] [Z_ K_] / G23 in a block of their own: each geometry axis word and the
    I / J / K of that axis are two corners of the box of stored stroke limit 2 (seed 000 L264-291,
    ``vc/core/axis/stroke_limits.py``); G23 takes no words [control: FANUC / GSK]."""
    plan, channel, label = decoder.plan, decoder.channel, decoder.block.label
    command = plan.stroke_limit
    assert command is not None
    corners: dict[str, tuple[float, float]] = {}
    for index, name in enumerate(channel.geometry_axes[:3]):
        word = CENTRE_WORDS[index]
        if (name in plan.targets) != (word in decoder.pitch_words):
            decoder.fail(12080, channel.name, label, f"G22: {name or word} needs both corners")
            return
        if name in plan.targets:
            corners[name] = (plan.targets[name], decoder.pitch_words[word])
    if set(plan.targets) - set(corners) or plan.spindles or plan.program_end or plan.program_stop or \
            decoder.dwell_requested or (corners and not command.on) or decoder.radius_word is not None:
        decoder.fail(12080, channel.name, label, "G22/G23")
        return
    plan.stroke_limit = StrokeCommand(command.on, corners)
    plan.targets = {}


def _finish(decoder: _Decoder) -> None:
    modal, plan, channel = decoder.modal, decoder.plan, decoder.channel
    if plan.polygon is not None:
        _polygon(decoder)
        return
    if plan.preset:
        if plan.targets or decoder.reference_requested or decoder.dwell_requested or plan.program_stop or \
                plan.program_end or plan.spindles:
            decoder.fail(12080, channel.name, decoder.block.label, "PRESETON")
        return
    if plan.stroke_limit is not None:
        _stroke_limit(decoder)
        return
    if decoder.reference_requested:
        # G74 <axis>=0 ...: reference these axes; the values are not used.  G74 stands in a block of
        # its own (seed 003 L764-781): anything else with it is refused.
        if not plan.targets or decoder.other_g_words or decoder.feed_word is not None or \
                plan.program_stop or plan.program_end or plan.spindles:
            decoder.fail(12080, channel.name, decoder.block.label, "G74")
        plan.reference_axes = tuple(plan.targets)
        plan.targets = {}
        return
    if decoder.dwell_requested:
        # G4 F<seconds>: the F of a dwell block is a time and does not change the modal feed;
        # G4 S<n>: n revolutions of the master spindle, coupled or not (L20367, L23932-23933);
        # G4 S<m>=<n>: n revolutions of spindle m [control].
        counted, turns = next(iter(plan.spindles.items()), ("", None)) if len(plan.spindles) == 1 else ("", None)
        if decoder.feed_word is None and turns is not None and turns.speed is not None and \
                turns == SpindleCommand(speed=turns.speed) and turns.speed > 0 and not plan.targets:
            plan.dwell_revolutions = turns.speed
            plan.dwell_spindle = counted
            plan.spindles.clear()
            return
        if decoder.feed_word is None or decoder.feed_word < 0 or plan.targets:
            decoder.fail(12080, channel.name, decoder.block.label, "G4")
        plan.dwell = decoder.feed_word or 0.0
        return
    if plan.reference_return and not _reference_return(decoder):
        return
    if decoder.feed_word is not None:
        modal.feed = decoder.feed_word
    # G53 (seed 000 L156) and G28 / G30 move in rapid whatever the modal motion is [control]
    plan.rapid = modal.rapid or plan.machine_coordinates or bool(plan.reference_return)
    plan.block_end = modal.block_end
    tapping = modal.thread in ("G331", "G332") and bool(plan.targets)
    if tapping:
        _tapping(decoder)
    elif modal.circle and not plan.machine_coordinates and not plan.reference_return:
        _circle(decoder)
    elif decoder.pitch_words and not modal.thread:
        decoder.unknown(next(iter(decoder.pitch_words)))  # I / J / K outside a thread: no such axis
    if decoder.radius_word is not None and plan.arc is None and decoder.alarm is None:
        decoder.unknown("R")  # a radius outside G2 / G3: no such axis
    thread_cutting = modal.thread == "G33" and bool(plan.targets)
    if thread_cutting:
        _thread_cutting(decoder)  # the master spindle's turning sets the feed, not F
    if plan.drive_esr and (plan.targets or plan.spindles or plan.variables or plan.sync_actions):
        decoder.fail(12080, channel.name, decoder.block.label, "ESRS/ESRR")  # in a block of its own (L41922)
    if (plan.targets or plan.arc) and not plan.rapid and not tapping and not thread_cutting:
        if modal.feed is None:
            decoder.fail(10860, channel.name, decoder.block.label)
        elif modal.feed <= 0.0:
            decoder.fail(14800, channel.name, decoder.block.label)
        else:
            plan.feed = modal.feed
            plan.feed_per_revolution = modal.per_revolution
    # Under a transform the targets are program coordinates: the five-axis control checks the path.
    # A block with five-axis words is checked by that control once it has applied them.
    if plan.five_axis is not None or modal.five_axis.transformed:
        return
    alarm = end_point_limit_alarm(plan, channel.name, decoder.block.label, decoder.axes,
                                  decoder.limits_checked_elsewhere)
    if alarm is not None:
        decoder.fail(alarm.number, *alarm.parameters, axis=alarm.axis)
