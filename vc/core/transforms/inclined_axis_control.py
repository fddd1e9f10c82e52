"""The inclined-axis control of a channel on the NC core (GSK 988TD, seed 000).

The formulas and decisions are the pure functions of ``vc/core/kinematics/inclined_axis.py``;
this module applies them to the channel's two machine axes:

* ``program_positions``: where the pair stands in program (Cartesian) coordinates, the start of
  incremental words; ``program_position`` the same from the actual values, for the absolute
  position display (seed 000 L38-41);
* ``plan``: a decoded block's Cartesian targets become machine end points: G0 / G1 through the
  mapping of the increment with NOZAGC as the PLC sets it (L194-204), G53 as machine positions
  (L154-158), G28 / G30 through ``return_path`` with ARF (L72-84); a G2 / G3 arc is mapped point
  by point (``path_positions``) like G1 (L194-204).  F is measured along the
  Cartesian path, stored stroke limit 1 (MD36100 / MD36110) is checked where AOT says
  (L264-286), and the order rules and the functions that cannot run with this one refuse the
  block with their alarm (L88-100, L364-370);
* ``follow``: every IPO cycle; a JOG of the inclined axis with NOZAGC = 0, or its reference
  return with AZR = 0, is a Cartesian motion: the orthogonal axis travels -C sin(theta) per unit
  of inclined travel (L52-53, L62, L313);
* ``leg_finished``: a motion of a block has reached its end point.

Program and machine positions agree through ``to_program`` except after motions that leave the
orthogonal axis uncompensated (NOZAGC = 1, a G28 leg in the inclined system): ``drift`` is the
orthogonal program position minus its Cartesian position.  The display keeps the program
position (L246-260) until the orthogonal axis is referenced again (L378) or G53 sets machine
positions (L160-189).  After the inclined axis has moved with NOZAGC = 1 a manual reference
return is mandatory (L378): the orthogonal axis loses its reference (DB31.DBX60.4 / 60.5 = 0,
NC start locked by MD20700) until it is referenced again, after the inclined axis as always; its
machine position is still exact, so its software limits stay active [control: how the SINUMERIK
asks for a reference return].
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Collection, Mapping

from interfaces.bit_access import Bit
from vc.config import md_dictionary as MD
from vc.config.model import ChannelConfig
from vc.core.alarms import AlarmList
from vc.core.axis.axis import MachineAxis
from vc.core.axis.jog import FREE_JOG, JogLimits
from vc.core.axis.owner import Owner
from vc.core.interface_map import SignalTable
from vc.core.interpolation.circle import Arc
from vc.core.kinematics.inclined_axis import (
    AxisPair,
    ConflictingFunction,
    InclinedAxisOff,
    InclinedAxisParameters,
    Motion,
    Role,
    StrokeLimit,
    configuration_alarms,
    g28_block_alarm,
    incompatibility_alarms,
    machine_increment,
    parameters_for_channel,
    reference_lost,
    reference_return_motion,
    return_path,
    rigid_tapping_alarm,
    stroke_check_position,
    to_program,
)
from vc.core.kinematics.transform_alarm import INCLINED_G28_BLOCK, INCLINED_ORDER
from vc.core.program.block_plan import BlockPlan, DecodeAlarm, software_limit_alarm

ARC_CHECK_POINTS_MIN = 32  # points of an arc checked against the stroke limits before it moves ...
ARC_CHECK_POINTS_MAX = 512  # ... about one per mm of its path


def at_reference_point(axis: MachineAxis, point: int = 0) -> bool:
    """ZPx: referenced and standing on reference point ``point`` (MD34100[point]) within the exact
    stop fine window (seed 000 L321, L375)."""
    reference = axis.config.md.float(MD.REFP_SET_POS, point)
    return axis.referenced and axis.at_rest and abs(axis.actual - reference) <= axis.dyn.fine_window


class InclinedAxisControl:
    def __init__(self, config: ChannelConfig, parameters: InclinedAxisParameters, axes: dict[str, MachineAxis],
                 nozagc: Bit, area: bytearray, dt: float):
        self.parameters = parameters
        self._channel = config.name
        self._geometry = {name for name in config.geometry_axes if name}
        self._axes = axes
        self.inclined = axes[config.axes[parameters.inclined_axis - 1]]
        self.orthogonal = axes[config.axes[parameters.orthogonal_axis - 1]]
        self._nozagc = nozagc
        self._area = area
        self._dt = dt
        self.drift = 0.0  # orthogonal program position minus its Cartesian position
        self._leg_drifts: list[float] = []  # the drift after each motion of the running block
        self._block_loses_reference = False  # the running block moves the inclined axis with NOZAGC = 1
        self._block_start_inclined = 0.0  # the inclined axis's setpoint when that block was planned
        # the planned block's start, machine and program, and NOZAGC then: the mapping of its path
        self._path_start = (AxisPair(0.0, 0.0), AxisPair(0.0, 0.0), False)
        self._carrying = False  # the orthogonal axis travels with a manual motion of the inclined axis
        # The planned block moves the orthogonal axis only because the inclined axis moves: the
        # orthogonal axis's interlock, a Cartesian-class signal, does not hold that motion (L308).
        self.orthogonal_only_carried = False
        theta = math.radians(parameters.angle)
        self._shift_per_travel = -parameters.diameter_factor * math.sin(theta)
        self._inclined_per_program_y = 1.0 / math.cos(theta)  # Ya = Yp / cos(theta)
        # The JOG keys act in the Cartesian system (L313): the programmed velocity F_p becomes
        # F_p / cos(theta) on the inclined slide (L32), with and without NOZAGC.
        dyn, factor = self.inclined.dyn, 1.0 / abs(math.cos(theta))
        self.inclined.dyn = dataclasses.replace(
            dyn, jog_velocity=min(dyn.jog_velocity * factor, dyn.max_velocity),
            jog_rapid_velocity=min(dyn.jog_rapid_velocity * factor, dyn.max_velocity))

    @property
    def nozagc(self) -> bool:
        """NOZAGC (GSK G63.5) from the PLC: 1 = the orthogonal axis is not compensated (L54-55, L386-396)."""
        return self._nozagc.get(self._area)

    # ------------------------------------------------------------------ positions
    def _program(self, machine: AxisPair) -> AxisPair:
        cartesian = to_program(self.parameters, machine)
        return AxisPair(cartesian.orthogonal + self.drift, cartesian.inclined)

    def _setpoints(self) -> AxisPair:
        return AxisPair(self.orthogonal.setpoint, self.inclined.setpoint)

    def program_positions(self) -> dict[str, float]:
        """The commanded program positions of the pair: where incremental words start."""
        program = self._program(self._setpoints())
        return {self.orthogonal.name: program.orthogonal, self.inclined.name: program.inclined}

    @property
    def machine_axes(self) -> tuple[str, str]:
        """The machine axes of the pair: orthogonal, inclined."""
        return self.orthogonal.name, self.inclined.name

    def machine_targets(self, program_targets: dict[str, float]) -> dict[str, float]:
        """ESR / fast retraction: the pair's machine end points for program end points of one or both
        (keyed by machine axis); an axis without one keeps its program position: it leaves the path
        with the other, or, standing where it is to stay, is left out."""
        start = self._setpoints()
        program_start = self._program(start)
        orthogonal, inclined = self.machine_axes
        increment = AxisPair(program_targets.get(orthogonal, program_start.orthogonal) - program_start.orthogonal,
                             program_targets.get(inclined, program_start.inclined) - program_start.inclined)
        end = start.plus(machine_increment(self.parameters, increment, self.nozagc))
        return {axis.name: finish for axis, begin, finish in ((self.orthogonal, start.orthogonal, end.orthogonal),
                                                              (self.inclined, start.inclined, end.inclined))
                if axis.name in program_targets or finish != begin or axis.command_velocity != 0.0}

    def program_position(self, axis: str) -> float | None:
        """The absolute (program) position of ``axis`` from the actual values; None for other axes."""
        program = self._program(AxisPair(self.orthogonal.actual, self.inclined.actual))
        if axis == self.orthogonal.name:
            return program.orthogonal
        if axis == self.inclined.name:
            return program.inclined
        return None

    # ------------------------------------------------------------------ blocks
    def plan(self, plan: BlockPlan, label: str) -> DecodeAlarm | None:
        """Map the block's targets of the pair onto the machine axes, or refuse the block."""
        self._leg_drifts = []
        self._block_loses_reference = False
        self.orthogonal_only_carried = False
        if plan.polygon is not None and plan.polygon.start:
            alarm = incompatibility_alarms((ConflictingFunction.POLYGON_TURNING,))[0]
            return DecodeAlarm(alarm.number, (self._channel, label, alarm.detail))
        if plan.tapping is not None and plan.tapping.axis == self.inclined.name:
            tapping = rigid_tapping_alarm(self.parameters, self.parameters.inclined_axis)
            assert tapping is not None
            return DecodeAlarm(tapping.number, (self._channel, label, f"{tapping.detail} {self.inclined.name}"
                                                                      f" ({plan.tapping.function})"))
        pair = self.machine_axes
        commanded = [name for name in pair if name in plan.targets or name in plan.reference_axes]
        if commanded and plan.reference_return:
            refusal = self._return_order(plan, commanded, label)
            if refusal is not None or plan.reference_axes:
                return refusal  # unreferenced: the reference point approach keeps the order rule itself
            return self._plan_return(plan, label)
        if plan.reference_axes or not any(name in plan.targets for name in pair):
            return None
        start = self._setpoints()
        if plan.machine_coordinates:
            end = AxisPair(plan.targets.get(self.orthogonal.name, start.orthogonal),
                           plan.targets.get(self.inclined.name, start.inclined))
            drift = 0.0  # the display shows the Cartesian position of the new machine position (L160-189)
        else:
            program_start = self._program(start)
            program_end = AxisPair(plan.targets.get(self.orthogonal.name, program_start.orthogonal),
                                   plan.targets.get(self.inclined.name, program_start.inclined))
            increment = AxisPair(program_end.orthogonal - program_start.orthogonal,
                                 program_end.inclined - program_start.inclined)
            end = start.plus(machine_increment(self.parameters, increment, self.nozagc))
            drift = program_end.orthogonal - to_program(self.parameters, end).orthogonal
            plan.path_length = self._program_length(plan, increment)
            self._path_start = (start, program_start, self.nozagc)
        refusal = self._stroke_limit(end, label)
        if refusal is None and plan.arc is not None and not plan.machine_coordinates:
            refusal = self._arc_stroke_limit(plan.arc, label)
        if refusal is not None:
            return refusal
        self.orthogonal_only_carried = not plan.machine_coordinates and self.orthogonal.name not in plan.targets
        self._set_targets(plan.targets, start, end)
        self._leg_drifts = [drift]
        self._expect_reference_loss(start, not plan.machine_coordinates and
                                    reference_lost(AxisPair(0.0, end.inclined - start.inclined), self.nozagc))
        return None

    def path_positions(self, program: Mapping[str, float]) -> dict[str, float]:
        """A point of the planned block's path in program coordinates (G2 / G3, cycle by cycle) as
        machine positions: the pair's increment from the block's start goes through
        ``machine_increment`` with NOZAGC as the block was planned, as for G0 / G1 (L194-204);
        the other axes are as given."""
        start, program_start, nozagc = self._path_start
        orthogonal, inclined = self.machine_axes
        increment = AxisPair(program.get(orthogonal, program_start.orthogonal) - program_start.orthogonal,
                             program.get(inclined, program_start.inclined) - program_start.inclined)
        machine = start.plus(machine_increment(self.parameters, increment, nozagc))
        return {**program, orthogonal: machine.orthogonal, inclined: machine.inclined}

    def stroke_point(self, limit: int, machine: dict[str, float]) -> dict[str, float]:
        """Machine positions in the coordinates stored stroke limit ``limit`` (2 or 3) is checked in:
        the pair's Cartesian position when AO2 / AO3 is 1, else as they are (L264-291, L424-429)."""
        orthogonal, inclined = self.machine_axes
        pair = AxisPair(machine.get(orthogonal, self.orthogonal.setpoint),
                        machine.get(inclined, self.inclined.setpoint))
        checked = stroke_check_position(self.parameters, StrokeLimit(limit), pair)
        return {**machine, orthogonal: checked.orthogonal, inclined: checked.inclined}

    def geometry_travel(self, axis: MachineAxis) -> float:
        """The travel of ``axis`` per unit of travel of the geometry axis it is (a handwheel on the
        geometry axis moves it in the WCS): program Y is the inclined axis x cos(theta) (L11-22);
        the orthogonal axis follows as in JOG."""
        return self._inclined_per_program_y if axis is self.inclined else 1.0

    def jog_travel(self, axis: MachineAxis) -> dict[str, float]:
        """The machine travel of the axes per unit of JOG travel of ``axis``: the inclined axis carries
        the orthogonal one with NOZAGC = 0 (L313, L377)."""
        if axis is self.inclined and not self.nozagc:
            return {axis.name: 1.0, self.orthogonal.name: self._shift_per_travel}
        return {axis.name: 1.0}

    def _arc_stroke_limit(self, arc: Arc, label: str) -> DecodeAlarm | None:
        """Stored stroke limit 1 along an arc of the pair, at points at most 1 mm apart (at least 32,
        at most 512), where AOT says."""
        if not set(arc.plane_axes) & set(self.machine_axes):
            return None
        count = max(ARC_CHECK_POINTS_MIN, min(ARC_CHECK_POINTS_MAX, math.ceil(arc.length)))
        orthogonal, inclined = self.machine_axes
        for point in arc.points(count):
            machine = self.path_positions(point)
            refusal = self._stroke_limit(AxisPair(machine[orthogonal], machine[inclined]), label)
            if refusal is not None:
                return refusal
        return None

    def _expect_reference_loss(self, start: AxisPair, lost: bool) -> None:
        """The planned block moves the inclined axis without compensation (``lost``): the orthogonal
        axis loses its reference once the inclined axis has left ``start``."""
        self._block_loses_reference = lost
        self._block_start_inclined = start.inclined

    def _set_targets(self, targets: dict[str, float], start: AxisPair, end: AxisPair) -> None:
        """The pair's end points; an axis of the pair that neither is programmed nor moves stays out
        of the block, so it keeps its exact-stop state."""
        for axis, begin, finish in ((self.orthogonal, start.orthogonal, end.orthogonal),
                                    (self.inclined, start.inclined, end.inclined)):
            if axis.name in targets or finish != begin:
                targets[axis.name] = finish

    def _return_order(self, plan: BlockPlan, commanded: Collection[str], label: str) -> DecodeAlarm | None:
        """G28 / G30: the inclined axis first, and not both in one block (L88-100)."""
        numbers = {self.parameters.orthogonal_axis if name == self.orthogonal.name else self.parameters.inclined_axis
                   for name in commanded}
        alarm = g28_block_alarm(self.parameters, numbers,
                                at_reference_point(self.inclined, plan.reference_return - 1))
        if alarm is None:
            return None
        if alarm.number == INCLINED_G28_BLOCK:
            return DecodeAlarm(alarm.number, (self._channel, label, self.orthogonal.name, self.inclined.name),
                               self.orthogonal.name)
        assert alarm.number == INCLINED_ORDER
        return DecodeAlarm(alarm.number, (self._channel, self.orthogonal.name, self.inclined.name),
                           self.orthogonal.name)

    def _plan_return(self, plan: BlockPlan, label: str) -> DecodeAlarm | None:
        """G28 / G30 of one axis of the pair: the intermediate point, then the reference point, each
        a leg of its own (``return_path``).  The seed's ARF = 0 example (TV-IA-8) is followed in its
        text, not in its printed intermediate point (docs/kinematics.md 1.7)."""
        start = self._setpoints()
        program_start = self._program(start)
        if self.inclined.name in plan.targets:
            role, axis = Role.INCLINED, self.inclined
            intermediate = plan.targets[axis.name]
        else:
            role, axis = Role.ORTHOGONAL, self.orthogonal
            intermediate = plan.targets[axis.name] - self.drift  # the Cartesian coordinate of the program one
        path = return_path(self.parameters, start, role, intermediate, plan.return_targets[axis.name], self.nozagc)
        refusal = self._stroke_limit(path.intermediate, label)
        if refusal is not None:
            return refusal
        if role is Role.INCLINED:
            # Both legs keep the orthogonal program position: the Cartesian leg compensates, the
            # inclined leg and NOZAGC leave the orthogonal axis where it is (L80, L134-150).
            kept = program_start.orthogonal
            self._leg_drifts = [kept - to_program(self.parameters, point).orthogonal
                                for point in (path.intermediate, path.reference)]
            # up to the intermediate point an ordinary programmed move: with NOZAGC = 1 uncompensated
            self._expect_reference_loss(start, reference_lost(
                AxisPair(0.0, intermediate - program_start.inclined), self.nozagc))
        else:
            self._leg_drifts = [self.drift, 0.0]  # at its reference point the relation holds again [INF]
        self._set_targets(plan.targets, start, path.intermediate)
        self._set_targets(plan.return_targets, path.intermediate, path.reference)
        for name in set(plan.targets) ^ set(plan.return_targets):  # an axis of one leg stands in the other
            moved = self.orthogonal if name == self.orthogonal.name else self.inclined
            plan.targets.setdefault(name, start.orthogonal if moved is self.orthogonal else start.inclined)
            plan.return_targets.setdefault(name, plan.targets[name])
        return None

    def _program_length(self, plan: BlockPlan, increment: AxisPair) -> float | None:
        """The Cartesian length of the block's path: F is the tangential velocity in the program
        system (L28); the machine axes get F_ay = F_py / cos(theta), F_ax = F_px - F_py tan(theta)."""
        squares = increment.orthogonal ** 2 + increment.inclined ** 2
        for name, target in plan.targets.items():
            if name in self._geometry and name not in (self.orthogonal.name, self.inclined.name):
                squares += (target - self._axes[name].setpoint) ** 2
        return math.sqrt(squares) if squares > 0.0 else None

    def _stroke_limit(self, machine: AxisPair, label: str) -> DecodeAlarm | None:
        """Stored stroke limit 1 = the software limit switches MD36100 / MD36110 of both axes,
        checked before the move at the Cartesian position when AOT = 1, else at the machine
        position (L264-286, L414-423)."""
        position = stroke_check_position(self.parameters, StrokeLimit.FIRST, machine)
        for axis, value in ((self.orthogonal, position.orthogonal), (self.inclined, position.inclined)):
            alarm = software_limit_alarm(self._channel, label, axis, value)
            if alarm is not None:
                return alarm
        return None

    def leg_finished(self) -> None:
        """A motion of the block has reached its end point: the program position it leaves."""
        if self._leg_drifts:
            self.drift = self._leg_drifts.pop(0)
        if self._block_loses_reference and not self._leg_drifts:
            self._block_loses_reference = False
            self.orthogonal.require_reference_return()

    def reset(self) -> None:
        self._leg_drifts = []
        if self._block_loses_reference and self.inclined.setpoint != self._block_start_inclined:
            self.orthogonal.require_reference_return()  # interrupted on the way: the inclined axis has moved
        self._block_loses_reference = False  # a block still waiting (e.g. for a gear change) took nothing

    # ------------------------------------------------------------------ manual motion
    def follow(self) -> None:
        """One IPO cycle of a manual motion of the pair (after JOG and referencing, before the
        position control loops)."""
        inclined, orthogonal = self.inclined, self.orthogonal
        if orthogonal.owner is Owner.REF:
            self.drift = 0.0  # the orthogonal reference return sets program and machine in relation again
        if inclined.command_velocity == 0.0 and not self._carrying:
            return  # nothing moves that could carry the orthogonal axis: the usual idle cycle
        travel = inclined.command_velocity * self._dt
        if inclined.owner is Owner.JOG:
            cartesian = not self.nozagc
        elif inclined.owner is Owner.REF:
            cartesian = reference_return_motion(self.parameters) is Motion.CARTESIAN
        else:
            cartesian = self._carrying and inclined.owner is Owner.BRAKE
        if inclined.owner is Owner.JOG and not cartesian and travel:
            # NOZAGC = 1: the orthogonal program position stays although its Cartesian one moves
            self.drift += self._shift_per_travel * travel
            if orthogonal.referenced and reference_lost(AxisPair(0.0, travel), self.nozagc):
                orthogonal.require_reference_return()
        if cartesian and travel:
            self._carry(travel)
        elif self._carrying:
            self._carrying = False
            if orthogonal.owner is Owner.TRANSFORM:
                orthogonal.release()

    def jog_limits(self, axis: MachineAxis) -> JogLimits:
        """JOG of an axis of the pair stops on stored stroke limit 1 where AOT checks it: the
        Cartesian position with AOT = 1, the machine positions with AOT = 0 (L264-286, L414-423).

        The inclined axis jogs in Cartesian mode (NOZAGC = 0) and carries the orthogonal one, so
        the orthogonal axis's limit bounds it too; with AOT = 1 the carried axis's Cartesian
        position does not change, so its machine position is bounded by its own MD36100 / MD36110
        as well: a machine axis never passes its own software limit switch [control].  The jogged
        axis stops on the first limit its motion reaches and raises 10621 there like on its own
        software limit [control]; from there it moves only away.
        """
        if axis is not self.inclined and axis is not self.orthogonal:
            return FREE_JOG
        keys = axis.inputs
        if not (keys.key_plus or keys.key_minus or axis.owner is Owner.JOG or axis.at_software_limit):
            return FREE_JOG  # idle: JOG does nothing with the axis this cycle
        if axis is self.inclined:
            carried = 0.0 if self.nozagc else self._shift_per_travel
            travel = AxisPair(carried, 1.0)  # machine travel of the pair per unit of jogged travel
        else:
            carried, travel = 0.0, AxisPair(1.0, 0.0)
        room = self._stroke_room(travel, carried_orthogonal=carried != 0.0)
        if room is None:
            return FREE_JOG
        accel = min(axis.dyn.max_accel, self.orthogonal.dyn.max_accel / abs(carried)) if carried else math.inf
        return JogLimits(plus=room[1] > 0.0, minus=room[0] < 0.0, accel=accel,
                         window=(axis.setpoint + room[0], axis.setpoint + room[1]))

    def _stroke_room(self, travel: AxisPair, carried_orthogonal: bool = False) -> tuple[float, float] | None:
        """How far (minus, plus) the pair may travel along ``travel`` from its setpoints within
        stored stroke limit 1 of both axes, and, when the orthogonal axis is carried, within its
        machine limits too; None when neither axis has active limits.  The check position is
        linear in the machine position, so one step along ``travel`` gives its rate.  An axis
        already beyond a limit may move only back towards it."""
        machine = self._setpoints()
        start = stroke_check_position(self.parameters, StrokeLimit.FIRST, machine)
        step = stroke_check_position(self.parameters, StrokeLimit.FIRST, machine.plus(travel))
        checks = [(self.orthogonal, start.orthogonal, step.orthogonal),
                  (self.inclined, start.inclined, step.inclined)]
        if carried_orthogonal:
            checks.append((self.orthogonal, machine.orthogonal, machine.orthogonal + travel.orthogonal))
        low, high = -math.inf, math.inf
        for axis, begin, end in checks:
            rate = end - begin
            if abs(rate) < 1e-12 or not axis.software_limits_active:
                continue
            bounds = sorted(((axis.dyn.limit_minus - begin) / rate, (axis.dyn.limit_plus - begin) / rate))
            low, high = max(low, bounds[0]), min(high, bounds[1])
        if math.isinf(low) and math.isinf(high):
            return None
        return min(low, 0.0), max(high, 0.0)

    def _carry(self, travel: float) -> None:
        orthogonal, shift = self.orthogonal, self._shift_per_travel * travel
        if orthogonal.owner is Owner.JOG:
            orthogonal.setpoint += shift  # jogged at the same time: its own travel comes on top
        elif orthogonal.owner in (Owner.NONE, Owner.TRANSFORM):
            if orthogonal.owner is Owner.NONE:
                orthogonal.take(Owner.TRANSFORM)
            orthogonal.set_path_setpoint(orthogonal.setpoint + shift, shift / self._dt)
        else:
            return  # braked or moved by another function: not carried
        self._carrying = True


NOZAGC_SIGNAL = "inclinedAxis.out.noOrthogonalCompensation"  # DB21.DBX398.0, project location of GSK G63.5


def inclined_axis_control(config: ChannelConfig, axes: dict[str, MachineAxis], table: SignalTable,
                          area: bytearray, dt: float, alarms: AlarmList) -> InclinedAxisControl | None:
    """The channel's inclined-axis control at power-on, or None when MD62800-62808 switch it off.
    A rotary axis in the pair raises alarm 65824 and leaves the function off (L379-381)."""
    parameters = parameters_for_channel(config)
    if isinstance(parameters, InclinedAxisOff):
        return None
    inclined = axes[config.axes[parameters.inclined_axis - 1]]
    orthogonal = axes[config.axes[parameters.orthogonal_axis - 1]]
    # one increment system for every axis of this control (MD10200 is not modelled): always the same
    problems = configuration_alarms(parameters, inclined.config.is_rotary, orthogonal.config.is_rotary, True)
    for problem in problems:
        alarms.raise_alarm(problem.number, 0, config.name, problem.detail, channel=config.name)
    if problems:
        return None
    return InclinedAxisControl(config, parameters, axes, table.bit(NOZAGC_SIGNAL), area, dt)
