"""The spindle words of a block: M3 / M4 / M5 / M19 / M40..M45 / M70, S, SPOS / SPOSA, SPCON /
SPCOF, WAITS; the coupling calls (COUPDEF, COUPON ... COUPRES, WAITC) and the synchronism
thresholds (docs/sync_spindle.md); polygon turning G51.2 / G50.2 with P Q R A (seed 002).

They fill the block plan's :class:`~vc.core.program.commands.SpindleCommand` and
:class:`~vc.core.program.commands.CouplingCommand` entries, which the channel hands to its spindles
and couplings.
"""

from __future__ import annotations

from vc.config import md_dictionary as MD
from vc.core.program.commands import (
    SYNCHRONISM_THRESHOLDS,
    CouplingCommand,
    PolygonCommand,
    SpindleCommand,
    block_change_of,
    kind_of,
)
from vc.core.program.decoder import BlockDecoder
from vc.core.program.program import Call, ValueFunction

POLYGON_OUT_OF_RANGE = 65840  # project numbers: seed 002 names no alarms (spec 7.5 TV-PG-7)
POLYGON_OWN_BLOCK = 65842


_SPINDLE_M = {3, 4, 5, 19, 40, 41, 42, 43, 44, 45, 70}
IMPLICIT_M19 = 1 << 19  # MD35035 bit 19: SPOS / SPOSA output M19
_POSITION_MODES = ("AC", "IC", "DC", "ACP", "ACN")


def spindle_m(decoder: BlockDecoder, value: float, number: int | None) -> bool:
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


def s_word(decoder: BlockDecoder, value: float, number: int | None = None) -> None:
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


def spindle_limit(decoder: BlockDecoder, index: str, value: object) -> None:
    """LIMS=<rev/min> (the master spindle) / LIMS[<n>]=: the speed limit of G96 / G961 / G97, up to
    four in a block (seed 003 L7780-7790); a negative value raises 14820 (L7853-7855)."""
    number = int(index[1:] if index[:1] == "S" else index) if index.lstrip("S").isdigit() else None
    if (index and number is None) or not isinstance(value, float):
        decoder.fail(12080, decoder.channel.name, decoder.block.label, f"LIMS[{index}]={value}" if index
                     else f"LIMS={value}")  # [control]
        return
    if value < 0.0:
        decoder.fail(14820, decoder.channel.name, decoder.block.label)
        return
    if number is None:
        number = decoder.channel.md.int(MD.SPIND_DEF_MASTER_SPIND)
    axis = next((name for name, axis in decoder.axes.items() if axis.config.spindle_number == number), None)
    if axis is None:
        decoder.fail(16105, decoder.channel.name, decoder.block.label, number)
        return
    decoder.plan.spindle_limits[axis] = value


def constant_cutting_speed(decoder: BlockDecoder) -> None:
    """G96 / G961 selected: the master spindle's S of the block is the cutting speed in m/min
    (L7661-7668), which the first selection must program (10900); a transverse axis must be defined
    in MD20100 (10870, L7846-7851)."""
    modal, plan, channel = decoder.modal, decoder.plan, decoder.channel
    master = channel.md.int(MD.SPIND_DEF_MASTER_SPIND)
    axis = next((name for name, axis in decoder.axes.items() if axis.config.spindle_number == master), None)
    command = plan.spindles.get(axis) if axis is not None else None
    if axis is not None and command is not None and command.speed is not None and not decoder.dwell_requested:
        modal.cutting_speed = command.speed
        command.speed = None
        if command == SpindleCommand():
            del plan.spindles[axis]  # the S was the cutting speed alone
    if decoder.transverse_axis() is None:
        decoder.fail(10870, channel.name, decoder.block.label)
        return
    if modal.cutting_speed is None:
        decoder.fail(10900, channel.name, decoder.block.label)
        return
    plan.constant_cutting = modal.constant_cutting
    plan.cutting_speed = modal.cutting_speed


def spos(decoder: BlockDecoder, name: str, index: str, value: object) -> None:
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
        axis = next(axis for axis, other in decoder.plan.spindles.items() if other is command)
        implicit = decoder.channel.md.int(MD.SPOS_TO_VDI) & 1 or \
            decoder.axes[axis].config.md.int(MD.SPIND_FUNCTION_MASK) & IMPLICIT_M19
        if implicit and command.m_function is None:
            # MD20850 bit 0 / MD35035 bit 19: SPOS / SPOSA output M19 to the PLC (L16406-16446), in
            # DB31.DBB86 and in the channel's auxiliary functions (aux_words)
            command.m_function = 19


def coupling_call(decoder: BlockDecoder, call: Call) -> None:
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


def synchronism_threshold(decoder: BlockDecoder, name: str, index: str, value: object) -> None:
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


def waitc(decoder: BlockDecoder, call: Call) -> None:
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


def waits(decoder: BlockDecoder, call: Call | None) -> None:
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


def spcon(decoder: BlockDecoder, call: Call | None, on: bool) -> None:
    """SPCON / SPCON(n) / SPCOF: position control of a spindle on or off (L22100, L23918-23921)."""
    numbers = [None] if call is None or not call.arguments else list(call.arguments)
    for number in numbers:
        axis = decoder.spindle_axis(f"S{number:g}" if isinstance(number, float) else
                                    f"S{decoder.channel.md.int(MD.SPIND_DEF_MASTER_SPIND)}")
        if axis is not None:
            decoder.plan.position_control[axis] = on


def polygon_block(decoder: BlockDecoder) -> None:
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
