"""The five-axis functions of a channel (Syntec, seed 001): G43.4, G43 / G49, G68.2 / G69, G53.1.

The kinematic chain is the channel's MD63000-63055 (``vc/core/kinematics/five_axis.py``); the
linear axes are the geometry axes (MD20050), the rotary axes those of MD63000.  This module
decides, the transforms compute:

* ``apply`` checks a block's five-axis words and sets the modal state (``FiveAxisModal``);
* ``program_positions`` is where the geometry axes stand in program coordinates, the start of
  incremental words;
* ``plan`` turns a block into a :class:`~vc.core.interpolation.tool_path.ToolPathSegment` while a transform is
  active, or refuses it with an alarm before anything moves;
* ``quantity`` is the tool tip and direction for traces and scenarios.

Program coordinates and machine positions (``to_machine``):

* G43.4 (RTCP type 1, seed 001 L42): the program point is the tool tip in workpiece coordinates
  (in the tilted plane while G68.2 is active); the rotary axes are programmed as machine angles.
  Every IPO cycle, M = tool_center_point(tip, angles, L): the tip follows its straight path while
  the rotary axes turn, both linear in the path parameter (five-axis simultaneous interpolation,
  Pr3054 = 0, seed 001 L31).
* G68.2 without G43.4: the program point lies in the tilted plane; the rotary axes stand (they
  are turned by G53.1 only) and the program point goes through the same chain with the angles
  where they stand, so X Y Z move in the plane as the table has been tilted.  With G43 the
  point is the tool tip (L = the H length), without it the spindle face.
* G43 alone: the tool length along the tool, M = P + L t; no rotary compensation.

Choices where the seed is silent are marked [INF] (interpretation) or [control] (what the
SINUMERIK does) and listed in docs/kinematics.md section 4.
"""

from __future__ import annotations

import math
from collections.abc import Collection, Sequence

from vc.config import md_dictionary as MD
from vc.config.model import ChannelConfig
from vc.core.axis.axis import MachineAxis
from vc.core.axis.indexing import ALARM_HIRTH_NOT_AN_INDEX_POSITION
from vc.core.interpolation.tool_path import ToolPathSegment
from vc.core.kinematics.five_axis import (
    NO_ROTATION,
    Kinematics,
    MachinePosition,
    RotaryAngles,
    ToolPose,
    forward,
    leaving_range,
    parameters_from_machine_data,
    resolve,
    tool_axes,
    tool_center_point,
)
from vc.core.kinematics.geometry import Vec3
from vc.core.kinematics.tilted_plane import align_tool, euler_frame
from vc.core.kinematics.transform_alarm import FIVE_AXIS_PROGRAM, ROTARY_RANGE, TransformAlarm
from vc.core.program.block_plan import BlockPlan, DecodeAlarm, end_point_limit_alarm, software_limit_alarm
from vc.core.program.five_axis_program import (
    ALIGN_TOOL,
    LENGTH_CANCEL,
    LENGTH_COMPENSATION,
    TILTED_PLANE,
    TILTED_PLANE_CANCEL,
    TOOL_CENTER_POINT,
    FiveAxisModal,
    FiveAxisWords,
)

# Words each five-axis G code takes (seed 001 L42-46, L59-60).
_ARGUMENTS = {TOOL_CENTER_POINT: "HLER", LENGTH_COMPENSATION: "H", TILTED_PLANE: "IJK", ALIGN_TOOL: "P"}
# Codes that change what program coordinates mean: incremental words in their block are refused.
_SWITCHING = {TOOL_CENTER_POINT, LENGTH_COMPENSATION, LENGTH_CANCEL, TILTED_PLANE, TILTED_PLANE_CANCEL}


class FiveAxisControl:
    """The five-axis functions of one channel; without a usable chain every five-axis word is
    refused with alarm 12550 (function not available), as on a control without the option."""

    def __init__(self, config: ChannelConfig, axes: dict[str, MachineAxis]):
        self._channel = config.name
        self._md = config.md
        self._axes = axes
        self._geometry_names = config.geometry_names
        self.linear = [axes[name] for name in config.geometry_axes if name in axes]
        numbers = [config.md.int(MD.FIVE_AXIS_ROTARY_AXES, index) for index in range(2)]
        names = [config.axes[number - 1] for number in numbers if 0 < number <= len(config.axes)]
        self.rotary = [axes[name] for name in names if name in axes]
        chain = resolve(parameters_from_machine_data(config.md))
        usable = isinstance(chain, Kinematics) and len(self.linear) == 3 and \
            len(self.rotary) == chain.mechanism.rotary_axes
        self.kinematics: Kinematics | None = chain if usable and isinstance(chain, Kinematics) else None
        # a rotary axis of the chain with a Hirth joint: no transformation, no frame (seed 003 L14066, L14077)
        self._hirth_axis = next((axis.name for axis in self.rotary if axis.index is not None and axis.index.hirth), "")
        self._pose_key: tuple[float, ...] = ()
        self._pose: ToolPose | None = None

    # ------------------------------------------------------------------ positions
    def tool_length(self, modal: FiveAxisModal) -> float:
        """The length of the H number while G43.4 or G43 is active (H0: none)."""
        if not modal.tool_length_active or modal.length_offset == 0:
            return 0.0
        return self._md.float(MD.TOOL_LENGTH_OFFSETS, modal.length_offset - 1)

    def _angles(self, values: Sequence[float]) -> RotaryAngles:
        return RotaryAngles(*values)

    def to_machine(self, modal: FiveAxisModal, point: Vec3, angles: RotaryAngles) -> Vec3:
        """The linear machine position for the program point ``point`` at the rotary ``angles``."""
        kinematics = self.kinematics
        assert kinematics is not None
        length = self.tool_length(modal)
        if modal.tool_center_point or modal.plane is not None:
            workpiece = modal.plane.to_workpiece(point) if modal.plane is not None else point
            # Work offsets are not part of this core: the table's zero is the machine rotary
            # origin (Pr3055 = 0 and Pr3055 = 1 coincide).
            return tool_center_point(kinematics, workpiece, angles, length, NO_ROTATION)
        return point + self._tool_direction(angles) * length

    def to_program(self, modal: FiveAxisModal, linear: Vec3, angles: RotaryAngles) -> Vec3:
        """The program point of the linear machine position ``linear`` at the rotary ``angles``."""
        kinematics = self.kinematics
        assert kinematics is not None
        length = self.tool_length(modal)
        if modal.tool_center_point or modal.plane is not None:
            tip = forward(kinematics, MachinePosition(linear, angles), length, NO_ROTATION).tip
            return modal.plane.to_plane(tip) if modal.plane is not None else tip
        return linear - self._tool_direction(angles) * length

    def _tool_direction(self, angles: RotaryAngles) -> Vec3:
        """The tool (tip -> holder) in machine coordinates: turned by a head, not by a table."""
        kinematics = self.kinematics
        assert kinematics is not None
        return tool_axes(kinematics, angles).apply(kinematics.tool)

    def program_positions(self, modal: FiveAxisModal) -> dict[str, float]:
        """Where the geometry axes stand in program coordinates while a transform is active."""
        if self.kinematics is None or not modal.transformed:
            return {}
        point = self.to_program(modal, self._setpoint(), self._angles([axis.setpoint for axis in self.rotary]))
        return dict(zip((axis.name for axis in self.linear), (point.x, point.y, point.z), strict=True))

    def _setpoint(self) -> Vec3:
        return Vec3(*(axis.setpoint for axis in self.linear))

    # ------------------------------------------------------------------ the block's words
    def apply(self, plan: BlockPlan, modal: FiveAxisModal, label: str,
              limits_checked_elsewhere: Collection[str] = ()) -> DecodeAlarm | None:
        """Check the block's five-axis words and set the modal state; an alarm refuses the block.
        A block that leaves no transform in force (G49, G69) has machine end points: their software
        limits are checked here, the interpreter leaves blocks with five-axis words to this control."""
        words = plan.five_axis
        if words is None:
            return None
        if self.kinematics is None:
            return DecodeAlarm(12550, (self._channel, label, f"G{words.codes[0]:g}"))
        if TOOL_CENTER_POINT in words.codes and words.arguments.get("L") == 2.0:
            # STO, smooth tool orientation (Pr3051, seed 001 L30-31, L42-46), is not part of this
            # control: refused like a function whose option is missing [control]
            return DecodeAlarm(12550, (self._channel, label, "G43.4 L2"))
        if self._hirth_axis and {TOOL_CENTER_POINT, TILTED_PLANE} & set(words.codes):
            # the transformation G43.4 and the frame G68.2 would turn it off its index positions
            return DecodeAlarm(ALARM_HIRTH_NOT_AN_INDEX_POSITION, (self._channel, label, self._hirth_axis),
                               self._hirth_axis)
        refusal = self._refusal(plan, words)
        if refusal:
            return self._refuse(label, refusal)
        arguments = words.arguments
        for code in words.codes:
            if code == TOOL_CENTER_POINT:
                refusal = self._tool_center_point(modal, arguments)
            elif code == LENGTH_COMPENSATION:
                modal.tool_center_point, modal.length_compensation = False, True
                self._length_offset(modal, arguments)
            elif code == LENGTH_CANCEL:
                modal.tool_center_point = modal.length_compensation = False
            elif code == TILTED_PLANE:
                origin = Vec3(*(words.origin.get(axis, 0.0) for axis in self._geometry_names[:3]))
                modal.plane = euler_frame(origin, arguments.get("I", 0.0), arguments.get("J", 0.0),
                                          arguments.get("K", 0.0))
            elif code == TILTED_PLANE_CANCEL:
                modal.plane = None
            elif code == ALIGN_TOOL and modal.plane is None:
                refusal = "G53.1 without G68.2 (G53.1 must follow G68.2)"
            if refusal:
                return self._refuse(label, refusal)
        if modal.transformed or ALIGN_TOOL in words.codes:
            return None  # program coordinates: ``plan`` checks the machine path
        return end_point_limit_alarm(plan, self._channel, label, self._axes, limits_checked_elsewhere)

    def _refuse(self, label: str, text: str) -> DecodeAlarm:
        return DecodeAlarm(FIVE_AXIS_PROGRAM, (self._channel, label, text))

    @staticmethod
    def _refusal(plan: BlockPlan, words: FiveAxisWords) -> str:
        """What makes the block as a whole impossible, "" if nothing."""
        codes = set(words.codes)
        for address, value in words.arguments.items():
            if not any(address in _ARGUMENTS.get(code, "") for code in codes):
                return f"{address}{value:g} without the G code it belongs to"
        if LENGTH_CANCEL in codes and codes & {TOOL_CENTER_POINT, LENGTH_COMPENSATION}:
            return "G49 with G43 / G43.4 in one block"
        if TILTED_PLANE in codes and TILTED_PLANE_CANCEL in codes:
            return "G68.2 with G69 in one block"
        if ALIGN_TOOL in codes and (plan.targets or len(codes) > 1):
            return "G53.1 stands in a block of its own"  # [INF] it only turns the rotary axes
        number = words.arguments.get("H")
        count = MD.TOOL_LENGTH_OFFSETS.length
        if number is not None and (number != int(number) or not 0 <= number <= count):
            return f"H{number:g}: tool offset numbers are 0 .. {count}"
        if words.incremental_axes and codes & _SWITCHING:
            # [INF] the start of an incremental word would change with the block's own switch
            return "incremental positions in a block that switches G43.4 / G43 / G49 / G68.2 / G69"
        return ""

    def _tool_center_point(self, modal: FiveAxisModal, arguments: dict[str, float]) -> str:
        """G43.4 [H_] [L0] (seed 001 L42); L2 (STO) is refused in ``apply``, L0 switches it off."""
        smoothing = arguments.get("L")
        if smoothing not in (None, 0.0):
            return f"G43.4 L{smoothing:g}: L is 0 or 2"
        if "E" in arguments or "R" in arguments:
            return "E and R belong to G43.4 L2"
        modal.tool_center_point, modal.length_compensation = True, False
        self._length_offset(modal, arguments)
        return ""

    @staticmethod
    def _length_offset(modal: FiveAxisModal, arguments: dict[str, float]) -> None:
        """H (checked in ``_refusal``); without H the number in force stays [control]."""
        number = arguments.get("H")
        if number is not None:
            modal.length_offset = int(number)

    # ------------------------------------------------------------------ the block's motion
    def plan(self, plan: BlockPlan, modal: FiveAxisModal, label: str) -> ToolPathSegment | DecodeAlarm | None:
        """The block's motion through the transform; None: an ordinary block (path.py moves it).

        Fills ``plan.targets`` with the machine end positions of the chain's axes, so that the
        block end waits for all of them in their exact stop windows.
        """
        aligning = plan.five_axis is not None and ALIGN_TOOL in plan.five_axis.codes
        if self.kinematics is None or not (modal.transformed or aligning):
            return None  # an ordinary block, its end points checked by the interpreter
        chain = self.linear + self.rotary
        others = sorted(set(plan.targets) - {axis.name for axis in chain})
        if others:
            return self._refuse(label, f"axis {others[0]} with G43.4 / G43 / G68.2 active")
        linear, angles = self._setpoint(), self._angles([axis.setpoint for axis in self.rotary])
        start = self.to_program(modal, linear, angles)
        if aligning:
            assert modal.plane is not None and plan.five_axis is not None
            written = plan.five_axis.arguments.get("P", 0.0)
            chosen = align_tool(self.kinematics, modal.plane, angles, int(written) if written == int(written) else -1)
            if isinstance(chosen, TransformAlarm):  # COR-149 (P) or COR-153 (no solution in range)
                return DecodeAlarm(chosen.number, (self._channel, label, f"{written:g}"))
            target_angles, end = chosen, start
            plan.rapid = True  # [INF] G53.1 positions the rotary axes at rapid traverse
        else:
            rotary_targets = [plan.targets.get(axis.name, axis.setpoint) for axis in self.rotary]
            target_angles = self._angles(rotary_targets)
            if target_angles != angles and not modal.tool_center_point:
                # [INF] with G68.2 (or G43 alone) the rotary axes are turned by G53.1, not programmed
                return self._refuse(label, "rotary axes programmed without G43.4")
            end = Vec3(*(plan.targets.get(axis.name, value) for axis, value in
                         zip(self.linear, (start.x, start.y, start.z), strict=True)))
            range_alarm = self._range_alarm(label, angles, target_angles)
            if range_alarm is not None:
                return range_alarm
        segment = self._segment(modal, plan, (linear, angles), (start, end), target_angles,
                                keep_linear=aligning and not modal.tool_center_point)
        limit_alarm = self._limit_alarm(label, chain, segment.samples)
        if limit_alarm is not None:
            return limit_alarm
        ends = segment.samples[-1]  # a segment of no length stands at its start
        plan.targets = {axis.name: end_position for axis, end_position in zip(chain, ends, strict=True)}
        return segment

    def _segment(self, modal: FiveAxisModal, plan: BlockPlan, machine: tuple[Vec3, RotaryAngles],
                 program: tuple[Vec3, Vec3], target_angles: RotaryAngles, keep_linear: bool) -> ToolPathSegment:
        """The tool path: program point and rotary angles linear in the path parameter."""
        linear, angles = machine
        start, end = program
        first = (angles.first, target_angles.first)
        second = (angles.second, target_angles.second)
        single = len(self.rotary) == 1
        arc, names = plan.arc, [axis.name for axis in self.linear]

        def program_at(fraction: float) -> Vec3:
            if arc is None or fraction >= 1.0:
                return start + (end - start) * fraction
            point = arc.point(fraction)  # G2 / G3: the tip on the arc in program coordinates
            return Vec3(*(point.get(name, value) for name, value in zip(names, (start.x, start.y, start.z),
                                                                          strict=True)))

        def positions_at(fraction: float) -> list[float]:
            turned = RotaryAngles(first[0] + (first[1] - first[0]) * fraction,
                                  second[0] + (second[1] - second[0]) * fraction)
            point = linear if keep_linear else self.to_machine(modal, program_at(fraction), turned)
            return [point.x, point.y, point.z, turned.first] + ([] if single else [turned.second])

        # F is the velocity of the tool tip; when the tip stands (a pure orientation change) it is
        # the rotary axes' velocity in degrees/min [control: as for an ordinary rotary-axis block].
        length = arc.length if arc is not None else end.distance(start)
        if length < 1e-9:
            length = math.hypot(first[1] - first[0], second[1] - second[0])
        feed = math.inf if plan.feed_per_revolution else plan.feed / 60.0  # G95: the channel sets it per cycle
        return ToolPathSegment.plan(self.linear + self.rotary, positions_at, length, feed, plan.rapid)

    def _range_alarm(self, label: str, start: RotaryAngles, end: RotaryAngles) -> DecodeAlarm | None:
        """Alarm 65852 when a rotary axis would leave its Pr3009-3012 range on the way (seed 001 L13-15)."""
        kinematics = self.kinematics
        assert kinematics is not None
        number = leaving_range(kinematics, start, end)
        if not number:
            return None
        axis = kinematics.first if number == 1 else kinematics.second
        assert axis is not None
        low, high = axis.travel_range
        name = self.rotary[number - 1].name
        return DecodeAlarm(ROTARY_RANGE, (self._channel, label, name, f"{low:g} -> {high:g}"), name)

    def _limit_alarm(self, label: str, axes: list[MachineAxis], path: list[list[float]]) -> DecodeAlarm | None:
        """Alarm 10720 when a point of ``path`` (positions of ``axes``) lies beyond a software limit."""
        for positions in path:
            for axis, position in zip(axes, positions, strict=True):
                alarm = software_limit_alarm(self._channel, label, axis, position)
                if alarm is not None:
                    return alarm
        return None

    # ------------------------------------------------------------------ what scenarios see
    def tool_pose(self, modal: FiveAxisModal) -> ToolPose:
        """Tool tip and direction in workpiece coordinates by the forward kinematics from the
        actual machine positions, with the tool length in force (none: the spindle face)."""
        key = (*(axis.actual for axis in self.linear + self.rotary), self.tool_length(modal))
        if key == self._pose_key and self._pose is not None:
            return self._pose  # traces read the tip several times a cycle
        linear = Vec3(*key[:3]) if len(self.linear) == 3 else Vec3(0.0, 0.0, 0.0)
        if self.kinematics is None:
            pose = ToolPose(linear, Vec3(0.0, 0.0, 1.0))
        else:
            angles = self._angles(key[3:-1])
            pose = forward(self.kinematics, MachinePosition(linear, angles), key[-1], NO_ROTATION)
        self._pose_key, self._pose = key, pose
        return pose

    def quantity(self, name: str, modal: FiveAxisModal) -> float:
        """What scenarios read of the tool: CHAN1.toolTipX .. toolDirZ, CHAN1.tcpActive (their
        meanings: CHANNEL_QUANTITY_MEANINGS in vc/simulation/observables.py)."""
        if name == "tcpActive":
            return 1.0 if modal.tool_center_point else 0.0
        pose = self.tool_pose(modal)
        vector = pose.tip if name.startswith("toolTip") else pose.direction
        return {"X": vector.x, "Y": vector.y, "Z": vector.z}[name[-1]]
