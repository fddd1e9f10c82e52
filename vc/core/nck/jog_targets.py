"""JOG to a fixed point and JOG to a position of the machine axes: the PLC's selection and the NC's
feedback (seed 003 §16.9 L34236, §16.10 L34607; the motion: ``vc/core/axis/jog_target.py``).

DB31.DBX13.0..13.2 (the fixed point's number, binary) and DB31.DBX13.3 (JOG to position) are read
when the PLC changed the axis's DB31 or the mode changed; DB31.DBX75.0..75.2 / 75.6 acknowledge
the selection active, DB31.DBX75.3..75.5 / 75.7 report the axis on its fixed point / position.
An axis costs nothing while it has no fixed point (MD30610 = 0) and no selection: only the axes
``watched`` (fixed points configured, or a selection active) are followed each cycle.
"""

from __future__ import annotations

from collections.abc import Sequence

from interfaces.image import ProcessImage
from interfaces.signal_groups import JogTargetRequests, JogTargetStatus
from vc.config import md_dictionary as MD
from vc.config.machine_data import MachineData
from vc.core.alarms import AlarmList
from vc.core.axis.axis import MachineAxis
from vc.core.axis.jog import FREE_JOG, JogLimits
from vc.core.axis.jog_target import REVERSE_ALLOWED, JogTarget
from vc.core.axis.owner import Owner
from vc.core.interface_map import SignalTable

_NOTHING_REPORTED = JogTargetStatus()


class JogTargets:
    """JOG to a fixed point / to a position of every machine axis that is no spindle (a spindle
    switched to positioning for it is not built)."""

    def __init__(self, nck: MachineData, axis_table: SignalTable, image: ProcessImage, axes: Sequence[MachineAxis]):
        self._image = image
        self._read = axis_table.codec(JogTargetRequests).read
        self._encode = axis_table.codec(JogTargetStatus).encode
        reverse = bool(nck.int(MD.JOG_MODE_MASK) & REVERSE_ALLOWED)
        self.of: dict[str, JogTarget] = {}
        for axis in axes:
            if axis.is_spindle:
                continue
            md = axis.config.md
            points = md.floats(MD.FIX_POINT_POS)[:md.int(MD.NUM_FIX_POINT_POS)]
            self.of[axis.name] = JogTarget(points, md.float(MD.JOG_POSITION), md.float(MD.STOP_LIMIT_FINE), reverse)
        self._reported: dict[str, JogTargetStatus] = {name: _NOTHING_REPORTED for name in self.of}
        # the axes followed each cycle: fixed points configured (reported wherever the axis stands) or a selection
        self._with_fixed_points = frozenset(name for name, target in self.of.items() if target.fixed_points)
        self._watched = set(self._with_fixed_points)
        self._selected_for: tuple[bool, bool] | None = None  # (JOG, emergency stop) the selections were read in

    def cycle(self, axes: Sequence[MachineAxis], jog_mode: bool, emergency_stop: bool, latched: set[str] | None,
              cycle: int, alarms: AlarmList) -> None:
        """Take the PLC's selections (when they or the mode changed), follow the watched axes, report."""
        selected_for = (jog_mode, emergency_stop)
        reselect = selected_for != self._selected_for
        if not reselect and latched is None and not self._watched:
            return  # at rest: nothing selected, nothing changed
        self._selected_for = selected_for
        may_activate = jog_mode and not emergency_stop
        for axis in axes:
            target = self.of.get(axis.name)
            if target is None:
                continue
            name = axis.name
            if reselect or (latched is not None and axis.area_key in latched):
                requests = self._read(self._image.area(axis.area_key))
                if target.select(requests.fixed_point, requests.to_position, may_activate) and \
                        axis.owner is Owner.JOG:
                    self._end_motion(axis)  # another fixed point while travelling to one (L34338-34342)
                    alarms.raise_alarm(17812, cycle, axis.channel, name, channel=axis.channel, axis=name)
                if target.target is not None:
                    self._watched.add(name)
                elif name not in self._with_fixed_points:
                    self._watched.discard(name)
            elif name not in self._watched:
                continue
            referenced = axis.referenced
            if target.target is not None:
                target.follow(axis.actual, referenced)
                inputs = axis.inputs
                if not referenced and jog_mode and (inputs.key_plus != inputs.key_minus or axis.handwheel_rest):
                    alarms.raise_alarm(17810, cycle, axis.channel, name, channel=axis.channel, axis=name)
            self._report(axis, target, referenced)

    def jog_limits(self, axis: MachineAxis) -> JogLimits:
        """Where JOG may take ``axis`` this cycle (towards its target, or free)."""
        target = self.of.get(axis.name)
        if target is None or target.target is None:
            return FREE_JOG
        return target.jog_limits(axis.setpoint, axis.referenced)

    def _report(self, axis: MachineAxis, target: JogTarget, referenced: bool) -> None:
        """DB31.DBX75.0..75.7, written when it changed."""
        status = JogTargetStatus(fixed_point_selected=target.fixed_point,
                                 fixed_point_reached=target.fixed_point_at(axis.actual, referenced),
                                 to_position_active=target.to_position, position_reached=target.position_reached)
        if status != self._reported[axis.name]:
            self._reported[axis.name] = status
            self._encode(self._image.area(axis.area_key), status)

    @staticmethod
    def _end_motion(axis: MachineAxis) -> None:
        """The motion of the traverse keys and the handwheel ends; a new press starts again."""
        inputs = axis.inputs
        axis.jog.keys.end_motion(inputs.key_plus or inputs.key_minus)
        axis.jog.handwheel_rest = 0.0
