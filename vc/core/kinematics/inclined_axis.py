"""Inclined (angular) axis control of the GSK 988TD (seed 000): pure mapping and decisions.

Two slides of the machine are not at 90 degrees: the inclined axis (Y in the seed) stands at
the angle theta to the position it would have on an orthogonal machine; the orthogonal axis
(X) is a normal linear axis.  Programs, absolute and relative displays and the Cartesian
interface signals use the orthogonal (Cartesian) system; the machine position display, the
drives and the inclined-class signals use the inclined machine system (seed 000 L5, L38-41,
L297-324).

Positions (seed 000 L11-22), C = 2 for a diameter-programmed orthogonal axis, else 1::

    Ya = Yp / cos(theta)                    Yp = Ya cos(theta)           (inverse: derived)
    Xa = Xp - C Yp tan(theta)               Xp = Xa + C Yp tan(theta)

All positions here are Cartesian *machine* coordinates: the NC core applies work offsets
before :func:`to_machine` and after :func:`to_program`.  With the PLC signal NOZAGC
(G63.5) = 1 only the inclined axis is converted, the orthogonal axis keeps still when the
inclined axis moves (L54-55, L194-204, L386-396): the mapping then works on increments,
:func:`machine_increment`, and program and machine positions drift apart until the next
manual reference return (L378).

Feeds (L26-36): the seed prints F_ay = F_p / cos(theta) and F_ax = F_p - F_p tan(theta).
Read as velocity components, the derivative of the position formulas:
F_ay = F_py / cos(theta), F_ax = F_px - F_py tan(theta).  Taken literally, L33 would run the
orthogonal axis at 1577 mm/min for a pure Y move at 1000 mm/min, although its position changes
by only 0.577 mm per mm of Y.  The NC core measures F along the Cartesian path and moves the
machine axes by their increments (``machine_increment``), which gives the derivative form.

The parameters (L398-464) are GSK numbers; the project carries them as machine data
MD62800-62808 (vc/config/md_dictionary.py): 8200 #0 AAC, 8200 #2 AZR, 8201 #0-2 AOT/AO2/AO3,
8209 #0 ARF, 8210 theta (0.001 degree IS-B, 0.0001 degree IS-C; function invalid for
85 <= |theta| <= 95, L449), 8211/8212 the axis numbers with the fallback of L45-49 or the
invalid function of L460 (MD62807 chooses).

Decisions for the NC core: which motion a G28/G30 leg and a manual reference return make
(ARF, AZR), where a stroke limit is checked (AOT/AO2/AO3), the referencing order (the
inclined axis first, alarm otherwise), and the functions that cannot run with this one.
"""

from __future__ import annotations

import math
from collections.abc import Collection, Iterable
from dataclasses import dataclass
from enum import IntEnum, StrEnum
from typing import NamedTuple

from vc.config import md_dictionary as MD
from vc.config.machine_data import MachineData
from vc.config.model import ChannelConfig
from vc.core.kinematics.transform_alarm import (
    INCLINED_CONFIGURATION,
    INCLINED_G28_BLOCK,
    INCLINED_INCOMPATIBLE,
    INCLINED_ORDER,
    TransformAlarm,
)

DEAD_BAND = (85.0, 95.0)  # |theta| in this closed band makes the function invalid (seed 000 L449)
IS_B_DEGREES = 0.001  # unit of parameter 8210 with increment system IS-B (L448)
IS_C_DEGREES = 0.0001  # ... with IS-C


class AxisPair(NamedTuple):
    """The two axes of the inclined-axis control, in the seed's order: X (orthogonal), Y (inclined)."""

    orthogonal: float
    inclined: float

    def plus(self, other: AxisPair) -> AxisPair:
        return AxisPair(self.orthogonal + other.orthogonal, self.inclined + other.inclined)



class AxisFallback(IntEnum):
    """What unusable axis numbers 8211/8212 mean (MD62807); the seed says both (spec 9.2)."""

    INVALID = 0  # L460: the function is invalid
    M_SERIES = 1  # L45-48: inclined = basic axis Y, orthogonal = basic axis Z
    T_SERIES = 2  # L45-49: inclined = basic axis X, orthogonal = basic axis Z


class Role(StrEnum):
    INCLINED = "inclined"
    ORTHOGONAL = "orthogonal"


class Motion(StrEnum):
    """How the inclined axis travels on a leg where the seed lets a parameter choose."""

    CARTESIAN = "Cartesian"  # a straight line of the program system: the orthogonal axis compensates
    INCLINED = "inclined"  # the inclined machine axis alone: the orthogonal axis keeps still


@dataclass(frozen=True, slots=True)
class InclinedAxisSettings:
    """The parameters as set, before they are checked against the channel's axes."""

    enabled: bool  # 8200 #0 AAC
    reference_keeps_orthogonal_still: bool  # 8200 #2 AZR
    limits_cartesian: tuple[bool, bool, bool]  # 8201 #0 AOT, #1 AO2, #2 AO3
    g28_cartesian: bool  # 8209 #0 ARF
    angle: float  # 8210 in degrees
    inclined_axis: int  # 8211, channel axis number (1-based), 0 = not set
    orthogonal_axis: int  # 8212
    fallback: AxisFallback  # MD62807
    orthogonal_diameter: bool  # MD62808: C = 2


@dataclass(frozen=True, slots=True)
class InclinedAxisParameters:
    """A checked, active inclined-axis control of one channel."""

    angle: float  # theta in degrees, outside the dead band
    inclined_axis: int  # channel axis number, 1-based
    orthogonal_axis: int
    diameter_factor: int = 1  # C: 2 for a diameter-programmed orthogonal axis
    reference_keeps_orthogonal_still: bool = False  # AZR
    limits_cartesian: tuple[bool, bool, bool] = (False, False, False)  # AOT, AO2, AO3
    g28_cartesian: bool = False  # ARF


@dataclass(frozen=True, slots=True)
class InclinedAxisOff:
    """The control is switched off (AAC = 0) or its parameters make it invalid; ``reason`` says which."""

    reason: str


# ------------------------------------------------------------------------------ parameters


def settings_from_gsk(p8200: int, p8201: int, p8209: int, p8210: int, p8211: int, p8212: int, *,
                      fallback: AxisFallback = AxisFallback.INVALID, orthogonal_diameter: bool = False,
                      angle_unit: float = IS_B_DEGREES) -> InclinedAxisSettings:
    """The GSK parameter values as the seed's parameter list prints them (bit words, 0.001 degree)."""
    return InclinedAxisSettings(
        enabled=bool(p8200 & 0b001),
        reference_keeps_orthogonal_still=bool(p8200 & 0b100),
        limits_cartesian=(bool(p8201 & 0b001), bool(p8201 & 0b010), bool(p8201 & 0b100)),
        g28_cartesian=bool(p8209 & 0b001),
        angle=p8210 * angle_unit,
        inclined_axis=p8211,
        orthogonal_axis=p8212,
        fallback=fallback,
        orthogonal_diameter=orthogonal_diameter,
    )


def settings_from_machine_data(md: MachineData) -> InclinedAxisSettings:
    """The channel's MD62800-62808."""
    limits = tuple(md.bool(MD.INCL_AXIS_LIMITS_CARTESIAN, index) for index in range(3))
    return InclinedAxisSettings(
        enabled=md.bool(MD.INCL_AXIS_ENABLE),
        reference_keeps_orthogonal_still=md.bool(MD.INCL_AXIS_REF_ORTHO_STILL),
        limits_cartesian=(limits[0], limits[1], limits[2]),
        g28_cartesian=md.bool(MD.INCL_AXIS_G28_CARTESIAN),
        angle=md.float(MD.INCL_AXIS_ANGLE),
        inclined_axis=md.int(MD.INCL_AXIS_INCLINED),
        orthogonal_axis=md.int(MD.INCL_AXIS_ORTHOGONAL),
        fallback=AxisFallback(md.int(MD.INCL_AXIS_FALLBACK)),
        orthogonal_diameter=md.bool(MD.INCL_AXIS_ORTHO_DIAMETER),
    )


def resolve(settings: InclinedAxisSettings, axis_count: int,
            basic_axes: tuple[int, int, int]) -> InclinedAxisParameters | InclinedAxisOff:
    """Check ``settings`` against a channel with ``axis_count`` axes.

    ``basic_axes`` are the channel axis numbers of the basic axes X, Y, Z (GSK parameter
    1022 = 1, 2, 3; MD20050 here), 0 where there is none; the fallback of L45-49 picks from them.
    """
    if not settings.enabled:
        return InclinedAxisOff("8200 #0 AAC = 0: inclined-axis control is off")
    if not -180.0 <= settings.angle <= 180.0:
        return InclinedAxisOff(f"8210 = {settings.angle:g} degrees is outside -180 .. 180 (L449)")
    low, high = DEAD_BAND
    if low <= abs(settings.angle) <= high:
        return InclinedAxisOff(f"8210 = {settings.angle:g} degrees lies in the dead band {low:g} .. {high:g}:"
                               " the function is invalid (L449)")
    axes = _axis_numbers(settings, axis_count, basic_axes)
    if isinstance(axes, InclinedAxisOff):
        return axes
    return InclinedAxisParameters(
        angle=settings.angle,
        inclined_axis=axes[0],
        orthogonal_axis=axes[1],
        diameter_factor=2 if settings.orthogonal_diameter else 1,
        reference_keeps_orthogonal_still=settings.reference_keeps_orthogonal_still,
        limits_cartesian=settings.limits_cartesian,
        g28_cartesian=settings.g28_cartesian,
    )


def _axis_numbers(settings: InclinedAxisSettings, axis_count: int,
                  basic_axes: tuple[int, int, int]) -> tuple[int, int] | InclinedAxisOff:
    inclined, orthogonal = settings.inclined_axis, settings.orthogonal_axis
    if 1 <= inclined <= axis_count and 1 <= orthogonal <= axis_count and inclined != orthogonal:
        return inclined, orthogonal
    unusable = f"8211 = {inclined}, 8212 = {orthogonal} with {axis_count} axes"
    # Seed conflict (spec 9.2): L45-49 falls back to the series table, L460 makes the
    # function invalid.  MD62807 chooses; the default is the parameter table's "invalid".
    if settings.fallback is AxisFallback.INVALID:
        return InclinedAxisOff(f"{unusable}: the function is invalid (L460)")
    basic_x, basic_y, basic_z = basic_axes
    inclined = basic_y if settings.fallback is AxisFallback.M_SERIES else basic_x
    orthogonal = basic_z
    if not (1 <= inclined <= axis_count and 1 <= orthogonal <= axis_count) or inclined == orthogonal:
        return InclinedAxisOff(f"{unusable}, and the {settings.fallback.name} fallback (L45-49) finds no"
                               f" basic axes: inclined {inclined}, orthogonal {orthogonal}")
    return inclined, orthogonal


def parameters_for_channel(channel: ChannelConfig) -> InclinedAxisParameters | InclinedAxisOff:
    """The inclined-axis control of a configured channel (MD62800-62808, basic axes from MD20050)."""
    basic = tuple(channel.md.int(MD.AXCONF_GEOAX_ASSIGN_TAB, index) for index in range(3))
    return resolve(settings_from_machine_data(channel.md), len(channel.axes), (basic[0], basic[1], basic[2]))


# ------------------------------------------------------------------------------ positions and feeds


def to_machine(p: InclinedAxisParameters, program: AxisPair) -> AxisPair:
    """Cartesian -> inclined machine position: Ya = Yp / cos(theta), Xa = Xp - C Yp tan(theta) (L11-22)."""
    theta = math.radians(p.angle)
    return AxisPair(orthogonal=program.orthogonal - p.diameter_factor * program.inclined * math.tan(theta),
                    inclined=program.inclined / math.cos(theta))


def to_program(p: InclinedAxisParameters, machine: AxisPair) -> AxisPair:
    """Inclined machine -> Cartesian position, the inverse of :func:`to_machine`.

    The absolute display after G53 (L160-189: G53 Y100 from 0 shows X -50.000 Y 86.603) and
    the Cartesian stroke check read positions this way.
    """
    theta = math.radians(p.angle)
    inclined = machine.inclined * math.cos(theta)
    return AxisPair(orthogonal=machine.orthogonal + p.diameter_factor * inclined * math.tan(theta),
                    inclined=inclined)


def machine_increment(p: InclinedAxisParameters, program_increment: AxisPair, nozagc: bool) -> AxisPair:
    """The machine travel of a programmed (or jogged) travel.

    NOZAGC = 0: both components are converted (L202-204).  NOZAGC = 1: only the inclined
    component; the orthogonal axis travels its own programmed amount (L198-200).
    """
    theta = math.radians(p.angle)
    compensation = 0.0 if nozagc else p.diameter_factor * program_increment.inclined * math.tan(theta)
    return AxisPair(orthogonal=program_increment.orthogonal - compensation,
                    inclined=program_increment.inclined / math.cos(theta))


def reference_lost(program_increment: AxisPair, nozagc: bool) -> bool:
    """True when a travel leaves program and machine positions inconsistent: an inclined
    travel with NOZAGC = 1, after which a manual reference return is mandatory (L378)."""
    return nozagc and program_increment.inclined != 0.0


# ------------------------------------------------------------------------------ reference returns


def reference_return_motion(p: InclinedAxisParameters) -> Motion:
    """Manual reference return of the inclined axis: AZR = 0 moves the orthogonal axis too (L62,
    L410-412), AZR = 1 keeps it still (L68).

    Seed conflict: L52-53 says the orthogonal axis moves with AZR = "1"; the parameter table
    L410-412 and the cases L62/L68 say the opposite.  Two of three places are followed.
    """
    return Motion.INCLINED if p.reference_keeps_orthogonal_still else Motion.CARTESIAN


def g28_leg_motion(p: InclinedAxisParameters) -> Motion:
    """G28/G30 from the intermediate point to the reference point: ARF = 1 Cartesian, 0 inclined (L431-441)."""
    return Motion.CARTESIAN if p.g28_cartesian else Motion.INCLINED


def move_inclined_axis(p: InclinedAxisParameters, machine: AxisPair, inclined_target: float,
                       motion: Motion) -> AxisPair:
    """Where both machine axes end when the inclined axis travels to the machine position
    ``inclined_target`` in ``motion``.

    Cartesian: the program position of the orthogonal axis stays, so its machine position
    changes by -C dYp tan(theta) = -C dYa sin(theta).  Inclined: it keeps still.
    """
    travel = inclined_target - machine.inclined
    if motion is Motion.INCLINED:
        return AxisPair(machine.orthogonal, inclined_target)
    shift = p.diameter_factor * travel * math.sin(math.radians(p.angle))
    return AxisPair(machine.orthogonal - shift, inclined_target)


@dataclass(frozen=True, slots=True)
class ReturnPath:
    """Machine positions of a G28/G30 reference return of one axis of the pair."""

    intermediate: AxisPair  # at the intermediate point
    reference: AxisPair  # at the reference point
    motion: Motion  # how the leg intermediate -> reference interpolates


def return_path(p: InclinedAxisParameters, machine: AxisPair, role: Role, intermediate: float,
                reference: float, nozagc: bool) -> ReturnPath:
    """G28/G30 of one axis of the pair from ``machine`` via the Cartesian intermediate
    coordinate ``intermediate`` to its machine reference position ``reference`` (1240).

    Up to the intermediate point the move is an ordinary programmed move and acts on the
    orthogonal axis (L72-74); from there ARF chooses (L76-84).  The orthogonal axis does not
    act on the inclined one, so its return is a plain machine move.

    Seed ambiguity (spec 6.7 TV-IA-8): the ARF = 0 example prints the intermediate point at
    machine X 0.000 with absolute X 0.000, which the mapping of L72-74 cannot produce
    (it gives machine X 57.735).  The text of L72-74 and L439-441 is followed; the example's
    last leg (machine X kept, Y to its reference) is reproduced.
    """
    start = to_program(p, machine)
    if role is Role.ORTHOGONAL:
        via = AxisPair(machine.orthogonal + intermediate - start.orthogonal, machine.inclined)
        return ReturnPath(via, AxisPair(reference, via.inclined), Motion.INCLINED)
    via = machine.plus(machine_increment(p, AxisPair(0.0, intermediate - start.inclined), nozagc))
    motion = g28_leg_motion(p)
    return ReturnPath(via, move_inclined_axis(p, via, reference, motion), motion)


def reference_order_alarm(p: InclinedAxisParameters, channel_axis: int,
                          inclined_at_reference_point: bool) -> TransformAlarm | None:
    """May ``channel_axis`` start its (manual or first automatic) reference return now?

    The orthogonal axis needs the inclined axis at its reference point first, ZPx = 1
    (L62-66, L321, L375, L380); otherwise alarm, the orthogonal axis does not move.
    """
    if channel_axis != p.orthogonal_axis or inclined_at_reference_point:
        return None
    return TransformAlarm(INCLINED_ORDER, "seed 000 L62-66, L321, L375, L380")


def g28_block_alarm(p: InclinedAxisParameters, commanded_axes: Collection[int],
                    inclined_at_reference_point: bool) -> TransformAlarm | None:
    """The order rule for G28/G30 blocks (L88-100): ``G28 Y_;`` then ``G28 X_;`` is right.

    Both axes in one block, or the orthogonal axis while the inclined axis is not at its
    reference point (it was not returned first), raise the alarm on the orthogonal move.
    """
    if p.orthogonal_axis not in commanded_axes:
        return None
    if p.inclined_axis in commanded_axes:
        return TransformAlarm(INCLINED_G28_BLOCK, "seed 000 L88-100")
    return reference_order_alarm(p, p.orthogonal_axis, inclined_at_reference_point)


# ------------------------------------------------------------------------------ stroke limits


class StrokeLimit(IntEnum):
    FIRST = 1  # stored stroke limit 1 (I and II): 8201 #0 AOT
    SECOND = 2  # stored stroke limit 2 (G22/G23): 8201 #1 AO2
    THIRD = 3  # stored stroke limit 3: 8201 #2 AO3


def stroke_check_position(p: InclinedAxisParameters, limit: StrokeLimit, machine: AxisPair) -> AxisPair:
    """The position ``limit`` is checked at: the Cartesian (virtual orthogonal machine) position
    when its bit AOT/AO2/AO3 is 1, else the inclined machine position, where a box becomes a
    rhombus in Cartesian terms (L264-277, L414-429)."""
    return to_program(p, machine) if p.limits_cartesian[limit - 1] else machine


# ------------------------------------------------------------------------------ incompatibilities


class ConflictingFunction(StrEnum):
    """Functions that cannot run together with inclined-axis control (L368-370)."""

    AXIS_SYNCHRONOUS_CONTROL = "feed axis synchronous control"
    POLYGON_TURNING = "polygon turning"
    HYPOTHETICAL_AXIS = "hypothetical axis control"
    PMC_AXIS = "PMC axis control"
    SUPERIMPOSED_CONTROL = "superimposed control"


def incompatibility_alarms(active: Iterable[ConflictingFunction]) -> tuple[TransformAlarm, ...]:
    """One alarm for each function in ``active`` while inclined-axis control is on."""
    return tuple(TransformAlarm(INCLINED_INCOMPATIBLE, "seed 000 L368-370", function.value) for function in active)


def rigid_tapping_alarm(p: InclinedAxisParameters, tapping_axis: int) -> TransformAlarm | None:
    """The inclined axis cannot be the tapping axis of rigid tapping (L364-366)."""
    if tapping_axis != p.inclined_axis:
        return None
    return TransformAlarm(INCLINED_INCOMPATIBLE, "seed 000 L364-366", "rigid tapping on the inclined axis")


def configuration_alarms(p: InclinedAxisParameters, inclined_is_rotary: bool, orthogonal_is_rotary: bool,
                         same_increment_system: bool) -> tuple[TransformAlarm, ...]:
    """Both axes linear and in the same increment system (L379-381)."""
    alarms: list[TransformAlarm] = []
    for role, axis, rotary in ((Role.INCLINED, p.inclined_axis, inclined_is_rotary),
                               (Role.ORTHOGONAL, p.orthogonal_axis, orthogonal_is_rotary)):
        if rotary:
            alarms.append(TransformAlarm(INCLINED_CONFIGURATION, "seed 000 L381",
                                         f"the {role.value} axis {axis} is a rotary axis; only linear axes can be"
                                         " inclined or orthogonal axes"))
    if not same_increment_system:
        alarms.append(TransformAlarm(INCLINED_CONFIGURATION, "seed 000 L379",
                                     f"the inclined axis {p.inclined_axis} and the orthogonal axis"
                                     f" {p.orthogonal_axis} use different increment systems"))
    return tuple(alarms)
