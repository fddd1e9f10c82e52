"""The auxiliary functions of a block: M, S, T, D, DL, H and F as they go to the PLC.

Every M function goes to the PLC (seed 003 L20662-20680): the spindle functions M3 / M4 / M5 /
M19 / M40..M45 / M70 with the spindle number as extended address (L16445, L17479, L20215), the
program flow functions M0 / M1 / M2 / M17 / M30 at the block end, every other M as programmed
(``M8``, ``M2=10``: M10 with extended address 2, ``M=QU(8)``: M8 quick).  S goes out with the
spindle number, T, D, DL and H as programmed, F (the path feed) only when MD22240 asks for it
(L8893-8897).  When each goes out and whether the block waits for the PLC follows the control:
the type's MD22200 .. MD22252, for the functions of MD22000 .. MD22030 their MD22035, quick with
QU; the implicit M19 of SPOS (MD20850 / MD35035 bit 19) and M70 of a spindle programmed as an
axis (MD35035 bit 20) are quick and go out during the motion whatever their data say (L16451,
L17488).

A block may hold 5 M, 3 S, 3 H and one T, D, DL and F function (more: alarm 14770, as a value
that is no auxiliary function's: a fraction, a negative number); two functions of one group
(MD22000; M0 / M1 / M2 / M17 / M30 are one group) raise 14760 [control].
"""

from __future__ import annotations

import re
from collections import Counter

from vc.config import md_dictionary as MD
from vc.config.model import ChannelConfig
from vc.core.program.commands import AuxiliaryFunction, OutputTime
from vc.core.program.decoder import BlockDecoder
from vc.core.program.program import Assignment, ValueFunction
from vc.core.program.spindle_words import IMPLICIT_M19

ALARM_GROUP_REPEATED = 14760
ALARM_PROGRAMMED_INCORRECTLY = 14770

PROGRAM_STOP, OPTIONAL_STOP = 0, 1
M19 = 19
PROGRAM_END = (2, 17, 30)
PROGRAM_FLOW = (PROGRAM_STOP, OPTIONAL_STOP, *PROGRAM_END)  # M0, M1, M2, M17, M30
PROGRAM_FLOW_GROUP = -1  # M0, M1, M2, M17, M30: one predefined group [control]
IMPLICIT_M70 = 1 << 20  # MD35035: the transition to axis mode outputs M70
LIMITS = {"M": 5, "S": 3, "H": 3, "T": 1, "D": 1, "DL": 1, "F": 1}  # functions of a type per block
MAX_EXTENSION = 99
MAX_VALUE = 2_147_483_647  # M, T, D: a DINT
_SYNC_TYPE = {"M": MD.AUXFU_M_SYNC_TYPE, "S": MD.AUXFU_S_SYNC_TYPE, "T": MD.AUXFU_T_SYNC_TYPE,
              "H": MD.AUXFU_H_SYNC_TYPE, "F": MD.AUXFU_F_SYNC_TYPE, "D": MD.AUXFU_D_SYNC_TYPE,
              "DL": MD.AUXFU_DL_SYNC_TYPE}
_WHOLE_NUMBERS = ("M", "T", "D")
# MD22035 bits
_QUICK, _NO_OUTPUT, _BEFORE, _DURING, _AT_END = 1 << 1, 1 << 3, 1 << 5, 1 << 6, 1 << 7
# M2=10, H3=5.5, DL=2, T=QU(5): an auxiliary function written as an assignment
AUXILIARY_ASSIGNMENT = re.compile(r"^(M|H|T|D|DL)(\d{0,2})$")


def output(decoder: BlockDecoder, kind: str, extension: int, value: float, quick: bool = False,
           implicit: bool = False) -> None:
    """Add the auxiliary function to the block's output, with when it goes out (module docstring)."""
    if extension < 0 or extension > MAX_EXTENSION or (kind in _WHOLE_NUMBERS and (
            value != int(value) or not 0 <= value <= MAX_VALUE)):
        decoder.fail(ALARM_PROGRAMMED_INCORRECTLY, decoder.channel.name, decoder.block.label)
        return
    if implicit:
        decoder.plan.aux_functions.append(AuxiliaryFunction(kind, extension, value, OutputTime.DURING_MOTION, True))
        return
    time, configured_quick = output_time(decoder.channel, kind, extension, value)
    decoder.plan.aux_functions.append(AuxiliaryFunction(kind, extension, value, time, quick or configured_quick))


def output_time(channel: ChannelConfig, kind: str, extension: int, value: float) -> tuple[OutputTime, bool]:
    """When a function goes out and whether it is quick: its entry of MD22010 .. MD22035 where one
    matches, the program flow functions at the block end, the others by the type's MD22200 ..."""
    spec = _assigned_spec(channel, kind, extension, value)
    if spec is not None:
        if spec & _NO_OUTPUT:
            return OutputTime.NOT_OUTPUT, False
        for bit, time in ((_BEFORE, OutputTime.BEFORE_MOTION), (_DURING, OutputTime.DURING_MOTION),
                          (_AT_END, OutputTime.AT_BLOCK_END)):
            if spec & bit:
                return time, bool(spec & _QUICK)
        return OutputTime(channel.md.int(_SYNC_TYPE[kind])), bool(spec & _QUICK)
    if kind == "M" and extension == 0 and value in PROGRAM_FLOW:
        return OutputTime.AT_BLOCK_END, False
    return OutputTime(channel.md.int(_SYNC_TYPE[kind])), False


def _assigned_entry(channel: ChannelConfig, kind: str, extension: int, value: float) -> int | None:
    """The index of the first entry of MD22000 .. MD22030 that names the function, or None."""
    md = channel.md
    groups = md.value(MD.AUXFU_ASSIGN_GROUP)
    assert isinstance(groups, tuple)
    if not any(groups):
        return None  # no user-defined auxiliary function (the delivery state)
    for index, group in enumerate(groups):
        if not group:
            continue
        if md.str(MD.AUXFU_ASSIGN_TYPE, index).upper() != kind:
            continue
        assigned_extension = md.int(MD.AUXFU_ASSIGN_EXTENSION, index)
        assigned_value = md.int(MD.AUXFU_ASSIGN_VALUE, index)
        if assigned_extension in (-1, extension) and (assigned_value == -1 or assigned_value == value):
            return index
    return None


def user_m19(channel: ChannelConfig, extension: int) -> bool:
    """M19 is the machine builder's auxiliary function, no spindle positioning (L16397-16403)."""
    return _assigned_entry(channel, "M", extension, M19) is not None


def _assigned_spec(channel: ChannelConfig, kind: str, extension: int, value: float) -> int | None:
    index = _assigned_entry(channel, kind, extension, value)
    return None if index is None else channel.md.int(MD.AUXFU_ASSIGN_SPEC, index)


def group_of(channel: ChannelConfig, function: AuxiliaryFunction) -> int:
    """The function's group: its MD22000 entry's, the program flow group, else 0 (none)."""
    index = _assigned_entry(channel, function.kind, function.extension, function.value)
    if index is not None:
        return channel.md.int(MD.AUXFU_ASSIGN_GROUP, index)
    if function.kind == "M" and function.extension == 0 and function.value in PROGRAM_FLOW:
        return PROGRAM_FLOW_GROUP
    return 0


def program_flow(decoder: BlockDecoder, code: int) -> None:
    """M0 stops at the block end, M1 too with "activate M01", M2 / M17 / M30 end the program."""
    plan = decoder.plan
    if code == PROGRAM_STOP:
        plan.program_stop = True
    elif code == OPTIONAL_STOP:
        plan.optional_stop = True
    elif code in PROGRAM_END:
        plan.program_end = True  # M17 in the main program ends it like M2 [control]


def quick_value(decoder: BlockDecoder, value: object) -> tuple[float, bool] | None:
    """The value of ``X=QU(v)`` (quick) or of ``X=v``; None (alarm 14770) for anything else."""
    if isinstance(value, ValueFunction) and value.name == "QU":
        return value.value, True
    if isinstance(value, float):
        return value, False
    decoder.fail(ALARM_PROGRAMMED_INCORRECTLY, decoder.channel.name, decoder.block.label)
    return None


def is_auxiliary_assignment(decoder: BlockDecoder, item: Assignment) -> bool:
    """``M2=10``, ``H3=5``, ``DL=2``, ``T=QU(5)``: an auxiliary function (not an axis of that name)."""
    return not item.index and AUXILIARY_ASSIGNMENT.match(item.name) is not None and \
        decoder.channel.axis_for_program_name(item.name) is None


def check_block(decoder: BlockDecoder) -> None:
    """At most LIMITS of a type per block (14770), one function of a group (14760)."""
    functions = decoder.plan.aux_functions
    if not functions:
        return
    counts = Counter(function.kind for function in functions)
    if any(count > LIMITS[kind] for kind, count in counts.items()):
        decoder.fail(ALARM_PROGRAMMED_INCORRECTLY, decoder.channel.name, decoder.block.label)
        return
    groups = [group for function in functions if (group := group_of(decoder.channel, function))]
    if len(groups) != len(set(groups)):
        decoder.fail(ALARM_GROUP_REPEATED, decoder.channel.name, decoder.block.label)


def implicit_spindle_function(decoder: BlockDecoder, axis: str, code: int) -> None:
    """M19 of SPOS / SPOSA (MD20850 bit 0 or MD35035 bit 19) and M70 of a spindle programmed as an
    axis (MD35035 bit 20), with the spindle number as extended address (L16406-16455, L17466-17490)."""
    spindle = decoder.axes[axis].config
    mask = spindle.md.int(MD.SPIND_FUNCTION_MASK)
    wanted = (mask & IMPLICIT_M19 or decoder.channel.md.int(MD.SPOS_TO_VDI) & 1) if code == 19 \
        else mask & IMPLICIT_M70
    if wanted and not any(function.kind == "M" and function.extension == spindle.spindle_number
                          and function.value == code for function in decoder.plan.aux_functions):
        output(decoder, "M", spindle.spindle_number, code, implicit=True)
