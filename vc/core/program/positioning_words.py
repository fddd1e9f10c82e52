"""The words of positioning axes in a part program (seed 003 chapter 9).

``POS[ax]=`` (type 1: the block ends when the axis has reached its end, L11832-11845) and
``POSA[ax]=`` (type 2: the program goes on, the axis travels across block boundaries, L11852-11858),
absolute or incremental by AC( ) / IC( ) or the modal G90 / G91 (L11741-11754); ``FA[ax]=`` the
axis's own feed in mm/min or deg/min, modal, 0.001 .. 999 999.999, at most five in a block
(L8838-8871); the motion-end conditions ``FINEA`` / ``COARSEA`` / ``IPOENDA`` written ``FINEA[ax]`` or
``FINEA=ax`` (L11729-11737, L10112-10122); ``WAITP(ax, ...)`` in a block of its own (L11771-11788).

Each axis has one type in a block (L11708-11709): an axis both as path axis and as positioning axis
is refused (12080).  ``positioning_block`` checks what stands together once the block is read.
"""

from __future__ import annotations

from vc.config.model import ChannelConfig
from vc.core.program.block_plan import MOTION_ENDS, PositioningMotion
from vc.core.program.decoder import BlockDecoder
from vc.core.program.program import Assignment, Block, Call, Keyword, Label, Word

POSITIONING_WORDS = ("POS", "POSA")
MAX_AXIS_FEEDS = 5  # FA words in one block (L8853)
MIN_AXIS_FEED, MAX_AXIS_FEED = 0.001, 999_999.999  # mm/min, deg/min (L8869-8871)


def _positioning_axis(decoder: BlockDecoder, word: str, name: str) -> str | None:
    """The machine axis ``name`` means, a machine axis of this channel that is no spindle; else 12550."""
    machine_axis = decoder.machine_axis(name)
    if machine_axis is None or decoder.axes[machine_axis].is_spindle:
        decoder.unknown(f"{word}[{name}]")
        return None
    return machine_axis


def positioning_assignment(decoder: BlockDecoder, item: Assignment) -> bool:
    """``POS[ax]=``, ``POSA[ax]=``, ``FA[ax]=`` of an axis and ``FINEA=ax``; False: not such a word
    (``FA[S2]`` of a spindle is the coupling's, ``spindle_words``)."""
    if item.name in POSITIONING_WORDS and item.index:
        machine_axis = _positioning_axis(decoder, item.name, item.index)
        if machine_axis is None:
            return True
        given = {name: motion.target for name, motion in decoder.plan.positioning.items()}
        target = decoder.end_point(machine_axis, f"{item.name}[{item.index}]", item.value, given)
        if target is not None:
            decoder.plan.positioning[machine_axis] = PositioningMotion(target, item.name == "POS")
        return True
    if item.name == "FA" and item.index:
        machine_axis = decoder.machine_axis(item.index)
        if machine_axis is None or decoder.axes[machine_axis].is_spindle:
            return False
        if not isinstance(item.value, float) or not MIN_AXIS_FEED <= item.value <= MAX_AXIS_FEED:
            decoder.fail(12080, decoder.channel.name, decoder.block.label, f"FA[{item.index}]={item.value}")
            return True
        decoder.plan.axis_feeds[machine_axis] = item.value
        return True
    if item.name in MOTION_ENDS and not item.index and isinstance(item.value, str):
        _motion_end(decoder, item.name, item.value)
        return True
    return False


def motion_end_keyword(decoder: BlockDecoder, item: Keyword) -> bool:
    """``FINEA[ax]``, ``COARSEA[ax]``, ``IPOENDA[ax]``; False: not such a word."""
    if item.name in MOTION_ENDS and item.index:
        _motion_end(decoder, item.name, item.index)
        return True
    return False


def _motion_end(decoder: BlockDecoder, condition: str, name: str) -> None:
    machine_axis = _positioning_axis(decoder, condition, name)
    if machine_axis is not None:
        decoder.plan.motion_ends[machine_axis] = condition


def waitp(decoder: BlockDecoder, call: Call) -> None:
    """WAITP(ax, ...): the block waits until these axes have reached their end (L11771-11792)."""
    axes: list[str] = []
    for argument in call.arguments:
        machine_axis = _positioning_axis(decoder, "WAITP", str(argument)) if isinstance(argument, str) and argument \
            else None
        if machine_axis is None:
            decoder.fail(12080, decoder.channel.name, decoder.block.label, f"WAITP({argument})")
            return
        axes.append(machine_axis)
    if not axes:
        decoder.fail(12080, decoder.channel.name, decoder.block.label, "WAITP()")  # the axes must be named
        return
    decoder.plan.positioning_waits = tuple(axes)


def positioning_block(decoder: BlockDecoder) -> None:
    """What stands together: one type per axis (L11708-11709), WAITP alone (L11775), five FA (L8853)."""
    plan, channel, label = decoder.plan, decoder.channel, decoder.block.label
    both = next((name for name in plan.positioning if name in plan.targets), None)
    if both is not None:
        decoder.fail(12080, channel.name, label, f"{both}: path axis and positioning axis")
    elif len(plan.axis_feeds) > MAX_AXIS_FEEDS:
        decoder.fail(12080, channel.name, label, "FA")
    elif plan.positioning_waits and sum(not isinstance(item, Label) for item in decoder.block.items) > 1:
        decoder.fail(12080, channel.name, label, "WAITP")  # [control] WAITP stands in a block of its own


def named_axes(block: Block, channel: ChannelConfig) -> set[str]:
    """The machine axes a block may name (as an address, an assignment or its index, an argument):
    a POSA axis still on its way among them makes the block wait before it is decoded, as the
    control's implicit WAITP (L11761-11764: the axis is programmed again only once it has arrived)."""
    names: set[str] = set()
    for item in block.items:
        if isinstance(item, Word):
            names.add(item.address)
        elif isinstance(item, (Assignment, Keyword)):
            names.update((item.name, item.index))
        elif isinstance(item, Call):
            names.update(str(argument) for argument in item.arguments)
    machine_axes = (channel.axis_for_program_name(name) for name in names if name)
    return {axis for axis in machine_axes if axis is not None}
