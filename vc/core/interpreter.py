"""Block decoding: modal G-code state and what one block asks the channel to do.

``decode`` turns a parsed block into a :class:`BlockPlan` (axis end points, dwell,
program stop or end) or an alarm, using the modal state it updates.  The words this
control understands are dispatched through ``_WORD_HANDLERS`` / ``_KEYWORD_HANDLERS``;
a word without a handler raises alarm 12550 "name not defined or option/function not
available", as on a control without the function.  Later NC functions add handlers.
"""

from __future__ import annotations

import re
from collections.abc import Callable
from dataclasses import dataclass, field

from vc.config import md_dictionary as MD
from vc.config.model import ChannelConfig
from vc.core.axis import MachineAxis
from vc.core.coupling_types import block_change_of, kind_of
from vc.core.program import Assignment, Block, Call, Item, Keyword, Label, ValueFunction, Word

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
    feed: float | None = None  # F in mm/min (path feed)
    polygon: bool = False  # G51.2 (polygon turning) until G50.2 (seed 002)

    def reset(self) -> None:
        self.rapid = True
        self.absolute = True
        self.block_end = EXACT_STOP_FINE
        self.feed = None
        self.polygon = False


@dataclass(slots=True)
class SpindleCommand:
    """What one block asks of one spindle (seed 003 chapter 13)."""

    speed: float | None = None  # S, rev/min
    direction: int | None = None  # M3, M4 or M5
    gear: int | None = None  # M40 .. M45
    position: tuple[str, float] | None = None  # SPOS / SPOSA / M19: (AC|IC|DC|ACP|ACN, degrees)
    wait_for_position: bool = True  # SPOS and M19 hold the block; SPOSA does not
    axis_mode: bool = False  # M70, or the spindle programmed by its axis name
    m_function: int | None = None  # the M function shown in DB31.DBB86


@dataclass(frozen=True, slots=True)
class CouplingCommand:
    """COUPDEF, COUPON, COUPONC, COUPOF, COUPOFS, COUPDEL, COUPRES or WAITC (seed 003 §14.2)."""

    function: str
    following: str  # machine axis of the FS
    leading: str = ""  # machine axis of the LS ("" where the call names none)
    numerator: float | None = None  # COUPDEF ratio
    denominator: float | None = None
    block_change: str | None = None  # COUPDEF "NOC" / "FINE" / "COARSE" / "IPOSTOP"; WAITC's condition
    kind: str | None = None  # COUPDEF "DV" / "AV" / "VV"
    offset: float | None = None  # COUPON's POSFS


@dataclass(frozen=True, slots=True)
class PolygonCommand:
    """G51.2 P Q R A (start) or G50.2 (cancel), seed 002 L21-51."""

    start: bool
    p: float = 0.0  # master (workpiece) rotation factor = number of tools
    q: float = 0.0  # slave (tool) rotation factor = number of sides, its sign the direction
    r: float = 0.0  # master offset angle before the synchronisation (relative)
    a: float = 0.0  # helix lead per master revolution


@dataclass(slots=True)
class BlockPlan:
    targets: dict[str, float] = field(default_factory=dict)  # machine axis -> end position
    rapid: bool = True
    feed: float = 0.0  # mm/min
    dwell: float = 0.0  # seconds
    program_stop: bool = False  # M0
    program_end: bool = False  # M2 / M30
    block_end: str = EXACT_STOP_FINE
    reference_axes: tuple[str, ...] = ()  # G74: machine axes to reference
    preset: dict[str, float] = field(default_factory=dict)  # PRESETON: machine axis -> new actual value
    spindles: dict[str, SpindleCommand] = field(default_factory=dict)  # machine axis -> its part of the block
    couplings: list[CouplingCommand] = field(default_factory=list)
    feeds: dict[str, float] = field(default_factory=dict)  # FA[Sn]: machine axis -> deg/min (0 = MD)
    position_control: dict[str, bool] = field(default_factory=dict)  # SPCON / SPCOF: machine axis -> on
    dwell_revolutions: float = 0.0  # G4 S: revolutions of the master spindle
    polygon: PolygonCommand | None = None


@dataclass(frozen=True, slots=True)
class DecodeAlarm:
    number: int
    parameters: tuple[object, ...]
    axis: str = ""


class _Decoder:
    def __init__(self, block: Block, modal: ModalState, channel: ChannelConfig, axes: dict[str, MachineAxis]):
        self.block = block
        self.modal = modal
        self.channel = channel
        self.axes = axes
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
        start = self.plan.targets.get(machine_axis, axis.setpoint)
        self.plan.targets[machine_axis] = number if absolute else start + number


def _g_word(decoder: _Decoder, value: float) -> None:
    code = round(value * 10) / 10
    modal = decoder.modal
    if code != 74:
        decoder.other_g_words = True
    if code == 0:
        modal.rapid = True
    elif code == 1:
        modal.rapid = False
    elif code == 4:
        decoder.dwell_requested = True
    elif code == 74:
        decoder.reference_requested = True
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
    elif code == 51.2:
        decoder.plan.polygon = PolygonCommand(True)
    elif code == 50.2:
        decoder.plan.polygon = PolygonCommand(False)
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


def _spcon(decoder: _Decoder, call: Call | None, on: bool) -> None:
    """SPCON / SPCON(n) / SPCOF: position control of a spindle on or off (L22100, L23918-23921)."""
    numbers = [None] if call is None or not call.arguments else list(call.arguments)
    for number in numbers:
        axis = decoder.spindle_axis(f"S{number:g}" if isinstance(number, float) else
                                    f"S{decoder.channel.md.int(MD.SPIND_DEF_MASTER_SPIND)}")
        if axis is not None:
            decoder.plan.position_control[axis] = on


_WORD_HANDLERS: dict[str, Callable[[_Decoder, float], None]] = {"G": _g_word, "M": _m_word, "F": _f_word,
                                                                  "S": _s_word}
_ADDRESS_EXTENSION = re.compile(r"([MS])(\d+)$")  # M2=3, S2=500: the function of spindle 2
_KEYWORD_HANDLERS: dict[str, Callable[[_Decoder], None]] = {
    "SPCON": lambda decoder: _spcon(decoder, None, True),
    "SPCOF": lambda decoder: _spcon(decoder, None, False),
}
_CALL_HANDLERS: dict[str, Callable[[_Decoder, Call], None]] = {
    "PRESETON": _preseton, "WAITC": _waitc,
    "SPCON": lambda decoder, call: _spcon(decoder, call, True),
    "SPCOF": lambda decoder, call: _spcon(decoder, call, False),
    **{name: _coupling_call for name in ("COUPDEF", "COUPON", "COUPONC", "COUPOF", "COUPOFS", "COUPDEL",
                                         "COUPRES")},
}


def decode(
    block: Block, modal: ModalState, channel: ChannelConfig, axes: dict[str, MachineAxis]
) -> tuple[BlockPlan, DecodeAlarm | None]:
    """Decode ``block`` (updating ``modal``) into what the channel must do, or an alarm."""
    decoder = _Decoder(block, modal, channel, axes)
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
    elif isinstance(item, Label):
        pass


def _assignment(decoder: _Decoder, item: Assignment) -> None:
    if item.name in ("SPOS", "SPOSA"):
        _spos(decoder, item.name, item.index, item.value)
        return
    if item.name == "FA" and item.index and isinstance(item.value, float):
        # FA[Sn]: the velocity of SPOS offset changes on a coupled FS, deg/min; 0 = MD (L23925-23940)
        axis = decoder.spindle_axis(item.index)
        if axis is not None:
            decoder.plan.feeds[axis] = item.value
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
        # G4 S<n>: n revolutions of the master spindle (L23907-23963).
        master = next(iter(plan.spindles.values()), None) if len(plan.spindles) == 1 else None
        if decoder.feed_word is None and master is not None and master.speed is not None and \
                master == SpindleCommand(speed=master.speed) and master.speed > 0 and not plan.targets:
            plan.dwell_revolutions = master.speed
            plan.spindles.clear()
            return
        if decoder.feed_word is None or decoder.feed_word < 0 or plan.targets:
            decoder.fail(12080, channel.name, decoder.block.label, "G4")
        plan.dwell = decoder.feed_word or 0.0
        return
    if decoder.feed_word is not None:
        modal.feed = decoder.feed_word
    plan.rapid = modal.rapid
    plan.block_end = modal.block_end
    if plan.targets and not modal.rapid:
        if modal.feed is None:
            decoder.fail(10860, channel.name, decoder.block.label)
        elif modal.feed <= 0.0:
            decoder.fail(14800, channel.name, decoder.block.label)
        else:
            plan.feed = modal.feed
    for name, target in plan.targets.items():
        axis = decoder.axes[name]
        if not axis.software_limits_active:
            continue
        if target > axis.dyn.limit_plus:
            decoder.fail(10720, channel.name, name, decoder.block.label, "+", axis=name)
        elif target < axis.dyn.limit_minus:
            decoder.fail(10720, channel.name, name, decoder.block.label, "-", axis=name)
