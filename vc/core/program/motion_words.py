"""The motion words of a block: G words, F, the I / J / K and R words, the axis words' blocks.

G0 / G1 / G2 / G3 / G33 / G331 / G332 and the other G codes (``g_word``), the feed F, the circle
(G2 / G3 with I J K or CR= / R), thread cutting (G33) and tapping (G331 / G332), the reference
point return (G28 / G30), stored stroke limit 2 (G22 / G23), PRESETON and the argument words of
a five-axis block.  The ``..._block`` functions check what stands together once the whole block
is read (``interpreter._finish`` calls them).
"""

from __future__ import annotations

from collections.abc import Callable

from vc.config import md_dictionary as MD
from vc.core.axis.stroke_limits import StrokeCommand
from vc.core.interpolation.circle import CENTRE_WORDS, CIRCLE_END_POINT, PLANES, ArcTolerance, plan_arc
from vc.core.interpolation.thread_cutting import ThreadCommand
from vc.core.program.block_plan import (
    EXACT_STOP_COARSE,
    EXACT_STOP_FINE,
    INTERPOLATION_END,
    ModalState,
    Tapping,
)
from vc.core.program.commands import PolygonCommand, SpindleCommand
from vc.core.program.decoder import ALARM_NO_TRANSVERSE_AXIS, BlockDecoder
from vc.core.program.five_axis_program import FIVE_AXIS_ADDRESSES, FIVE_AXIS_G_CODES, TILTED_PLANE, FiveAxisWords
from vc.core.program.program import Call, Word

PITCH_OF_GEOMETRY_AXIS = ("I", "J", "K")  # the pitch word of geometry axis 1, 2, 3 (seed 003 L17668-17675)


def g_word(decoder: BlockDecoder, value: float) -> None:
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
        feed_type(modal, code in (95, 99), "")
    elif code in (96, 961, 97, 971):
        # constant cutting speed G96 (F in mm/rev, as G95) / G961 (F in mm/min, as G94); G97 / G971
        # cancel it and keep the last speed, F per revolution / per minute (seed 003 L7654-7745)
        feed_type(modal, code in (96, 97), f"G{code:g}" if code in (96, 961) else "")
    elif code == 51.2:
        decoder.plan.polygon = PolygonCommand(True)
    elif code == 50.2:
        decoder.plan.polygon = PolygonCommand(False)
    elif code in FIVE_AXIS_G_CODES and decoder.plan.five_axis is not None:
        decoder.plan.five_axis.codes.append(code)  # the channel's five-axis control checks and applies them
    else:
        decoder.unknown(f"G{value:g}")


def diameter_programming(decoder: BlockDecoder, keyword: str) -> None:
    """DIAMON / DIAM90 / DIAMOF (G group 29, channel-modal): the transverse axis (MD20100) in diameter
    or radius (seed 003 §8.1, L10283-10415); DIAMCYCOF is the radius programming of cycles and acts as
    DIAMOF here [control].  Without a transverse axis DIAMON / DIAM90 raise 16510 [control]."""
    if keyword in ("DIAMON", "DIAM90") and decoder.transverse_axis() is None:
        decoder.fail(ALARM_NO_TRANSVERSE_AXIS, decoder.channel.name, decoder.block.label, keyword)
        return
    decoder.modal.diameter = "DIAMOF" if keyword == "DIAMCYCOF" else keyword


def feed_type(modal: ModalState, per_revolution: bool, constant_cutting: str) -> None:
    """A G word of group 15: a change of the feed type wants a new F, the old one is in the other
    unit (else alarm 10860) [control]."""
    if per_revolution != modal.per_revolution:
        modal.feed = None
    modal.per_revolution = per_revolution
    modal.constant_cutting = constant_cutting


def f_word(decoder: BlockDecoder, value: float) -> None:
    decoder.feed_word = value


def radius_word(decoder: BlockDecoder, value: float) -> None:
    decoder.radius_word = value


def preseton(decoder: BlockDecoder, call: Call) -> None:
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
        if decoder.refuse_hirth(machine_axis, str(name)):
            return  # its actual value is the joint's position (L14070)
        decoder.plan.preset[machine_axis] = value


def pitch_word(address: str) -> Callable[[BlockDecoder, float], None]:
    def handler(decoder: BlockDecoder, value: float) -> None:
        decoder.pitch_words[address] = value
    return handler


def five_axis_word(decoder: BlockDecoder, words: FiveAxisWords, item: Word) -> bool:
    """The arguments of a five-axis block (H L E R P I J K) and G68.2's origin X Y Z; True: taken."""
    if item.address in FIVE_AXIS_ADDRESSES:
        words.arguments[item.address] = item.value
        return True
    if TILTED_PLANE in decoder.five_axis_codes and item.address in decoder.channel.geometry_names:
        words.origin[item.address] = item.value  # the plane's origin, not a motion
        return True
    return False


def thread_cutting_block(decoder: BlockDecoder) -> None:
    """G33 <axes> I|J|K<lead> [SF=]: the lead belongs to the geometry axis its address names; a block
    without one keeps the last lead [control]."""
    plan, modal, channel, label = decoder.plan, decoder.modal, decoder.channel, decoder.block.label
    words = decoder.pitch_words
    if len(words) > 1:
        decoder.fail(12080, channel.name, label, "G33 lead")
        return
    if words:
        address, lead = next(iter(words.items()))
        index = PITCH_OF_GEOMETRY_AXIS.index(address)
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
    master = _master_spindle(decoder)
    if master is not None and decoder.refuse_positioning_only(master, master):
        return  # an auxiliary spindle cuts no thread (L10850)
    modal.thread_lead = command
    plan.thread = command
    plan.block_end = INTERPOLATION_END  # thread blocks join without exact stop: one thread [control]


MAX_PITCH = 2000.0  # mm/rev: the range of the pitch, 0.001 .. 2000 either sign (seed 003 L17675)
MIN_PITCH = 0.001


def tapping_block(decoder: BlockDecoder) -> None:
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
    pitch = decoder.pitch_words.get(PITCH_OF_GEOMETRY_AXIS[index]) if index < len(PITCH_OF_GEOMETRY_AXIS) else None
    if pitch is None or not MIN_PITCH <= abs(pitch) <= MAX_PITCH or \
            set(decoder.pitch_words) - {PITCH_OF_GEOMETRY_AXIS[index]}:
        decoder.fail(12080, channel.name, label, f"{function} pitch")  # [control] missing or out of range
        return
    spindle = _master_spindle(decoder)
    if spindle is None:
        decoder.fail(16105, channel.name, label, channel.md.int(MD.SPIND_DEF_MASTER_SPIND))
        return
    if decoder.refuse_positioning_only(spindle, spindle):
        return  # no tapping with an auxiliary spindle (L10850)
    command = plan.spindles.setdefault(spindle, SpindleCommand())
    if command.direction is not None or command.position is not None or command.gear is not None:
        decoder.fail(12080, channel.name, label, function)  # [control] M3/M4/M5, SPOS or M4x with G331
        return
    command.axis_mode = True  # position control, interpolated with the drilling axis (L17614-17616)
    plan.tapping = Tapping(function, axis, spindle, pitch)


def _master_spindle(decoder: BlockDecoder) -> str | None:
    """The machine axis of the channel's master spindle (MD20090), None if it has none."""
    number = decoder.channel.md.int(MD.SPIND_DEF_MASTER_SPIND)
    return next((name for name, each in decoder.axes.items() if each.config.spindle_number == number), None)


def reference_return_block(decoder: BlockDecoder) -> bool:
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


def circle_block(decoder: BlockDecoder) -> None:
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


def stroke_limit_block(decoder: BlockDecoder) -> None:
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
