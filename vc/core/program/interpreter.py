"""Block decoding: modal G-code state and what one block asks the channel to do.

``decode`` turns a parsed block into a :class:`BlockPlan` (axis end points, dwell,
program stop or end) or an alarm, using the modal state it updates.  The words this
control understands are dispatched through ``_WORD_HANDLERS`` / ``_KEYWORD_HANDLERS``;
a word without a handler raises alarm 12550 "name not defined or option/function not
available", as on a control without the function.  Later NC functions add handlers.

The word handlers live by what they program: ``motion_words`` (G words, F, circle, thread,
tapping, G28 / G30, G22, PRESETON, five-axis arguments), ``spindle_words`` (spindles,
couplings, polygon turning), ``retract_words`` (fast retraction, ESR, system variables,
synchronized actions), ``positioning_words`` (POS / POSA / FA / WAITP / FINEA of positioning axes)
and ``aux_words`` (the M, S, T, D, DL, H and F functions for the PLC);
``block_plan`` holds what they produce, ``decoder`` what they share.
"""

from __future__ import annotations

import re
from collections.abc import Callable, Collection, Mapping

from vc.config import md_dictionary as MD
from vc.config.model import ChannelConfig
from vc.core.axis.axis import MachineAxis
from vc.core.program import aux_words
from vc.core.program.block_plan import (
    BlockPlan,
    DecodeAlarm,
    ModalState,
    end_point_limit_alarm,
)
from vc.core.program.commands import SYNCHRONISM_THRESHOLDS, OutputTime, SpindleCommand
from vc.core.program.decoder import BlockDecoder
from vc.core.program.fixed_stop_words import FIXED_STOP_WORDS, fixed_stop_word
from vc.core.program.motion_words import (
    PITCH_OF_GEOMETRY_AXIS,
    circle_block,
    diameter_programming,
    f_word,
    five_axis_word,
    g_word,
    pitch_word,
    preseton,
    radius_word,
    reference_return_block,
    stroke_limit_block,
    tapping_block,
    thread_cutting_block,
)
from vc.core.program.positioning_words import motion_end_keyword, positioning_assignment, positioning_block, waitp
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
from vc.core.program.retract_words import RETRACT_CALLS, RETRACT_KEYWORDS, retract_assignment, synchronized_action
from vc.core.program.spindle_words import (
    constant_cutting_speed,
    coupling_call,
    polygon_block,
    s_word,
    spcon,
    spindle_limit,
    spindle_m,
    spos,
    synchronism_threshold,
    waitc,
    waits,
)


def _m_function(decoder: BlockDecoder, value: float, extension: int | None, quick: bool = False) -> None:
    """An M function (``M8``, ``M2=3``, ``M=QU(8)``): a spindle's function for that spindle, a program
    flow function, and in every case to the PLC (``aux_words``).  An M19 that MD22000 .. MD22030
    assign to a group is only an auxiliary function: the NC does not position (L16397-16403)."""
    if not (value == aux_words.M19 and aux_words.user_m19(decoder.channel, extension or 0)) and \
            spindle_m(decoder, value, extension):
        number = extension if extension is not None else decoder.channel.md.int(MD.SPIND_DEF_MASTER_SPIND)
        aux_words.output(decoder, "M", number, value, quick)
        return
    if not extension and value == round(value):
        aux_words.program_flow(decoder, round(value))
    aux_words.output(decoder, "M", extension or 0, value, quick)


def _m_word(decoder: BlockDecoder, value: float) -> None:
    _m_function(decoder, value, None)


def _s_function(decoder: BlockDecoder, value: float, number: int | None = None, quick: bool = False) -> None:
    """S: the spindle's speed, and to the PLC with the spindle number (seed 003 L20215)."""
    s_word(decoder, value, number)
    if decoder.alarm is None:
        spindle = number if number is not None else decoder.channel.md.int(MD.SPIND_DEF_MASTER_SPIND)
        aux_words.output(decoder, "S", spindle, value, quick)


def _s_word(decoder: BlockDecoder, value: float) -> None:
    _s_function(decoder, value)


def _output_word(kind: str) -> Callable[[BlockDecoder, float], None]:
    """T, D and H as words (``T5``, ``D1``, ``H12``): only to the PLC."""
    return lambda decoder, value: aux_words.output(decoder, kind, 0, value)


def _diameter_keyword(keyword: str) -> Callable[[BlockDecoder], None]:
    return lambda decoder: diameter_programming(decoder, keyword)


_WORD_HANDLERS: dict[str, Callable[[BlockDecoder, float], None]] = {"G": g_word, "M": _m_word, "F": f_word,
                                                                  "S": _s_word, "R": radius_word,
                                                                  **{kind: _output_word(kind) for kind in "TDH"},
                                                                  **{address: pitch_word(address)
                                                                     for address in PITCH_OF_GEOMETRY_AXIS}}
_ADDRESS_EXTENSION = re.compile(r"(S)(\d+)$")  # S2=500: the speed of spindle 2
_KEYWORD_HANDLERS: dict[str, Callable[[BlockDecoder], None]] = {
    "SPCON": lambda decoder: spcon(decoder, None, True),
    "SPCOF": lambda decoder: spcon(decoder, None, False),
    "WAITS": lambda decoder: waits(decoder, None),
    "DRFOF": lambda decoder: setattr(decoder.plan, "delete_drf", True),
    **{keyword: _diameter_keyword(keyword) for keyword in ("DIAMON", "DIAM90", "DIAMOF", "DIAMCYCOF")},
    **RETRACT_KEYWORDS,
}
_CALL_HANDLERS: dict[str, Callable[[BlockDecoder, Call], None]] = {
    "PRESETON": preseton, "WAITC": waitc, "WAITS": waits, "WAITP": waitp,
    "SPCON": lambda decoder, call: spcon(decoder, call, True),
    "SPCOF": lambda decoder, call: spcon(decoder, call, False),
    **{name: coupling_call for name in ("COUPDEF", "COUPON", "COUPONC", "COUPOF", "COUPOFS", "COUPDEL",
                                         "COUPRES")},
    **RETRACT_CALLS,
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
    decoder = BlockDecoder(block, modal, channel, axes, program_positions or {}, limits_checked_elsewhere)
    if block.error:
        decoder.fail(12080, channel.name, block.label, block.error)
        return decoder.plan, decoder.alarm
    for item in block.items:
        _decode_item(decoder, item)
    _finish(decoder)
    return decoder.plan, decoder.alarm


def _decode_item(decoder: BlockDecoder, item: Item) -> None:
    if isinstance(item, Word):
        if decoder.polygon_block and item.address in "PQRA":
            decoder.polygon_words[item.address] = item.value
            return
        if decoder.plan.five_axis is not None and five_axis_word(decoder, decoder.plan.five_axis, item):
            return
        handler = _WORD_HANDLERS.get(item.address)
        if handler is not None:
            handler(decoder, item.value)
        else:
            decoder.axis_value(item.address, item.value)
    elif isinstance(item, Assignment):
        _assignment(decoder, item)
    elif isinstance(item, Keyword) and item.index:
        if not motion_end_keyword(decoder, item):
            decoder.unknown(f"{item.name}[{item.index}]")
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
        synchronized_action(decoder, item)
    elif isinstance(item, Label):
        pass


def _assignment(decoder: BlockDecoder, item: Assignment) -> None:
    if item.name in ("SPOS", "SPOSA"):
        spos(decoder, item.name, item.index, item.value)
        return
    if retract_assignment(decoder, item):
        return
    if item.name in FIXED_STOP_WORDS and item.index:
        fixed_stop_word(decoder, item)
        return
    if positioning_assignment(decoder, item):
        return
    if item.name == "FA" and item.index and isinstance(item.value, float):
        # FA[Sn]: the velocity of SPOS offset changes on a coupled FS, deg/min; 0 = MD (L23925-23940)
        axis = decoder.spindle_axis(item.index)
        if axis is not None:
            decoder.plan.feeds[axis] = item.value
        return
    if item.name in SYNCHRONISM_THRESHOLDS:
        synchronism_threshold(decoder, item.name, item.index, item.value)
        return
    if aux_words.is_auxiliary_assignment(decoder, item):
        _auxiliary_assignment(decoder, item)
        return
    extended = _ADDRESS_EXTENSION.match(item.name)
    if extended and not item.index and isinstance(item.value, (float, ValueFunction)) and \
            decoder.channel.axis_for_program_name(item.name) is None:
        speed = aux_words.quick_value(decoder, item.value)
        if speed is not None:
            _s_function(decoder, speed[0], int(extended.group(2)), speed[1])
        return
    if item.name == "S" and not item.index and isinstance(item.value, (float, ValueFunction)):
        speed = aux_words.quick_value(decoder, item.value)
        if speed is not None:
            _s_function(decoder, *speed)
        return
    if item.name == "LIMS":
        spindle_limit(decoder, item.index, item.value)
        return
    if item.name == "CR" and not item.index and isinstance(item.value, float):
        decoder.radius_word = item.value  # the SINUMERIK's circle radius (the ISO dialect's R)
        return
    if item.index:
        decoder.unknown(f"{item.name}[{item.index}]")
    else:
        decoder.axis_value(item.name, item.value)


def _auxiliary_assignment(decoder: BlockDecoder, item: Assignment) -> None:
    """``M2=10``, ``M=QU(8)``, ``H3=5.5``, ``T=QU(5)``, ``D=2``, ``DL=1``: an auxiliary function with its
    extended address (the digits after the letter), quick with QU."""
    match = aux_words.AUXILIARY_ASSIGNMENT.match(item.name)
    assert match is not None
    kind, digits = match.group(1), match.group(2)
    written = aux_words.quick_value(decoder, item.value)
    if written is None:
        return
    value, quick = written
    extension = int(digits) if digits else None
    if kind == "M":
        _m_function(decoder, value, extension, quick)
    else:
        aux_words.output(decoder, kind, extension or 0, value, quick)


def _finish(decoder: BlockDecoder) -> None:
    modal, plan, channel = decoder.modal, decoder.plan, decoder.channel
    if modal.constant_cutting:
        constant_cutting_speed(decoder)  # the S of the block is the cutting speed (G4 S: revolutions)
    for axis, command in plan.spindles.items():
        if command.position is not None:
            aux_words.implicit_spindle_function(decoder, axis, 19)  # SPOS / SPOSA (L16406-16455)
        if command.axis_mode and command.m_function != 70:
            aux_words.implicit_spindle_function(decoder, axis, 70)  # programmed as an axis (L17466-17490)
    aux_words.check_block(decoder)
    if plan.positioning or plan.axis_feeds or plan.positioning_waits:
        positioning_block(decoder)
    if plan.polygon is not None:
        polygon_block(decoder)
        return
    if plan.preset:
        if plan.targets or decoder.reference_requested or decoder.dwell_requested or plan.program_stop or \
                plan.program_end or plan.spindles:
            decoder.fail(12080, channel.name, decoder.block.label, "PRESETON")
        return
    if plan.stroke_limit is not None:
        stroke_limit_block(decoder)
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
    if plan.reference_return and not reference_return_block(decoder):
        return
    if decoder.feed_word is not None:
        modal.feed = decoder.feed_word
        if channel.md.int(MD.AUXFU_F_SYNC_TYPE) != OutputTime.NOT_OUTPUT:
            aux_words.output(decoder, "F", 0, decoder.feed_word)  # the path feed (seed 003 L7390-7395)
    # G53 (seed 000 L156) and G28 / G30 move in rapid whatever the modal motion is [control]
    plan.rapid = modal.rapid or plan.machine_coordinates or bool(plan.reference_return)
    plan.block_end = modal.block_end
    tapping = modal.thread in ("G331", "G332") and bool(plan.targets)
    if tapping:
        tapping_block(decoder)
    elif modal.circle and not plan.machine_coordinates and not plan.reference_return:
        circle_block(decoder)
    elif decoder.pitch_words and not modal.thread:
        decoder.unknown(next(iter(decoder.pitch_words)))  # I / J / K outside a thread: no such axis
    if decoder.radius_word is not None and plan.arc is None and decoder.alarm is None:
        decoder.unknown("R")  # a radius outside G2 / G3: no such axis
    thread_cutting = modal.thread == "G33" and bool(plan.targets)
    if thread_cutting:
        thread_cutting_block(decoder)  # the master spindle's turning sets the feed, not F
    if plan.drive_esr and (plan.targets or plan.spindles or plan.variables or plan.sync_actions):
        decoder.fail(12080, channel.name, decoder.block.label, "ESRS/ESRR")  # in a block of its own (L41922)
    if (plan.targets or plan.arc) and not plan.rapid and not tapping and not thread_cutting:
        if modal.feed is None:
            decoder.fail(10860, channel.name, decoder.block.label)
        elif modal.feed <= 0.0:
            decoder.fail(14800, channel.name, decoder.block.label)
        elif modal.per_revolution and any(decoder.refuse_hirth(axis, axis) for axis in plan.targets):
            return  # a Hirth axis never with a feed per revolution (G95, seed 003 L14073)
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
