"""The retraction and ESR words of a block (docs/retraction.md): LFON / LFOF, LFTXT / LFWP / LFPOS,
DILF=, ALF=, SF=, POLF[ax]=, POLFMASK / POLFMLIN, POLFA, ESRS / ESRR, the system variables a
program writes ($AC_LIFTFAST, $AA_ESR_ENABLE[ax] ...) and the synchronized actions ID= / IDS= that
write them.

The modal ones go into the modal state's :class:`~vc.core.program.commands.RetractProgramming`;
the others into the block plan, for the channel's ESR.
"""

from __future__ import annotations

from vc.core.program.commands import (
    LFPOS,
    LFTXT,
    LFWP,
    MAX_DELAY_S,
    esrr_command,
    esrs_command,
)
from vc.core.program.decoder import BlockDecoder
from vc.core.program.fixed_stop_words import fixed_stop_action
from vc.core.program.program import Assignment, Call, SynchronizedAction, ValueFunction
from vc.core.program.sync_actions import (
    COMMAND_AXIS_WORDS,
    FIXED_STOP_WORDS,
    SyncAction,
    SyncActionError,
    VariableWrite,
    parse_actions,
    parse_condition,
)

# System variables a part program (or a synchronized action) may write; True: indexed by an axis.
PROGRAM_VARIABLES = {"$AC_LIFTFAST": False, "$AC_ESR_TRIGGER": False, "$AN_ESR_TRIGGER": False,
                     "$AA_ESR_ENABLE": True, "$AA_ESR_TRIGGER": True, "$AA_COUP_CORR": True}
_SPINDLE_VARIABLES = {"$AA_COUP_CORR"}  # indexed by a spindle: S<n> or its axis name (L31543-31551)
_RETRACT_TARGET_MODES = {"LFTXT": LFTXT, "LFWP": LFWP, "LFPOS": LFPOS}
_MAX_ESR_AXES = 5  # ESRS / ESRR: at most 5 axes per call (L41926, L41958)


def _variable_write(decoder: BlockDecoder, name: str, index: str, value: object) -> VariableWrite | None:
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


def _command_axis_word(decoder: BlockDecoder, name: str, index: str, value: float) -> VariableWrite | None:
    """``POS[Z]=100`` / ``FA[Z]=2000`` of a synchronized action, with the axis as a machine axis of the
    channel (12550 for another name); FA above 0 (12080)."""
    if name == "FA" and value <= 0.0:
        decoder.fail(12080, decoder.channel.name, decoder.block.label, f"FA[{index}]={value}")
        return None
    machine_axis = decoder.machine_axis(index)
    if machine_axis is None:
        decoder.unknown(index)
        return None
    return VariableWrite(name, machine_axis, value)


def _retract_keyword(decoder: BlockDecoder, name: str) -> None:
    """LFON / LFOF (G group 45) and LFTXT / LFWP / LFPOS (G group 46), seed 003 L8238-8262."""
    retract = decoder.modal.retract
    if name in ("LFON", "LFOF"):
        retract.enabled = name == "LFON"
    else:
        retract.target_mode = _RETRACT_TARGET_MODES[name]


def retract_assignment(decoder: BlockDecoder, item: Assignment) -> bool:
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


def _retract_axes(decoder: BlockDecoder, call: Call) -> tuple[str, ...] | None:
    axes = []
    for argument in call.arguments:
        machine_axis = decoder.machine_axis(str(argument)) if argument != "" else None
        if machine_axis is None:
            decoder.fail(12080, decoder.channel.name, decoder.block.label, f"{call.name}({argument})")
            return None
        axes.append(machine_axis)
    return tuple(axes)


def _polf_mask(decoder: BlockDecoder, call: Call) -> None:
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


def _polfa(decoder: BlockDecoder, call: Call) -> None:
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


def _esr_drive(decoder: BlockDecoder, call: Call) -> None:
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


def synchronized_action(decoder: BlockDecoder, item: SynchronizedAction) -> None:
    """ID= / IDS= ... DO ...: the condition is read by the channel in every IPO cycle."""
    try:
        condition = parse_condition(item.condition)
        actions = parse_actions(item.actions)
    except SyncActionError as error:
        decoder.fail(12080, decoder.channel.name, decoder.block.label, str(error))
        return
    writes = [_command_axis_word(decoder, action.name, action.index, action.value) if action.name in COMMAND_AXIS_WORDS
              else fixed_stop_action(decoder, action.name, action.index, action.value)
              if action.name in FIXED_STOP_WORDS
              else _variable_write(decoder, action.name, action.index, action.value) for action in actions]
    if all(write is not None for write in writes):
        decoder.plan.sync_actions.append(SyncAction(item.number, item.static, item.mode, condition,
                                                    tuple(write for write in writes if write is not None),
                                                    decoder.block.text))


RETRACT_KEYWORDS = {name: (lambda decoder, name=name: _retract_keyword(decoder, name))
                     for name in ("LFON", "LFOF", "LFTXT", "LFWP", "LFPOS")}
RETRACT_CALLS = {"POLFMASK": _polf_mask, "POLFMLIN": _polf_mask, "POLFA": _polfa, "ESRS": _esr_drive,
                  "ESRR": _esr_drive}
