"""Manual retraction along the tool axis (seed 003 §16.12, L35304-35807).

A part program in AUTOMATIC or MDA that is aborted by a channel reset or by power failure
while a thread block runs (G33, or tapping G331 / G332) leaves the tool in the workpiece.
The NC keeps the retract data of that block (tool axis, spindle, the thread's pitch) in its
memory, which survives the power cycle, and shows DB21.DBX377.5.
In JOG the PLC selects the function; then only the tool axis moves, with the traverse keys,
and the spindle turns with it by the thread's pitch, so the tap unscrews itself.

One channel's states (:class:`RetractionState`)::

    NO_DATA ──reset / power failure in G33, G331, G332──▶ DATA (377.5 = 1)
    DATA ──PI service RETRAC: JOG, channel in reset, tool axis and spindle
           referenced or restored──▶ ACTIVE (377.4 = 1)
    ACTIVE ──channel or mode-group reset, another mode, REF──▶ DATA (377.4 = 0; reselect from
           where the axes stand now, L35608-35656)
    DATA, ACTIVE ──NC start that starts a program in AUTOMATIC / MDA──▶ NO_DATA (377.5 = 0, L35683-35693)

While ACTIVE: the tool axis only in its plus direction unless MD10735 bit 8 = 1 (L35390-35400);
the channel's other geometry axes stand (they place the tool in the thread) [INF: seed 003
L35547-35549 lets only the retract axis retract, L35533 leaves the axes not involved free];
software limits as in JOG (L35531-35533); NC stop pauses, NC start continues (L35534-35535);
the spindle start keys DB31.DBX30.1 / 30.2 do nothing (L35582-35588).  The tool axis is the
geometry axis of the WCS (L35530-35531): its keys retract while the PLC shows the WCS
(DB19.DBX0.7 = 1, selected after 377.4, L35486-35488); in the MCS (0.7 = 0) they do not move it
[control: the real PLC routes the panel's keys to the geometry axis in the WCS and to the machine
axis in the MCS, and a machine-axis traverse of an axis taking part in the retraction is refused;
the harness has no frames, so WCS and MCS positions are equal].

The selection: the real PLC calls the PI service "RETRAC" with FB4 (L35481-35483).  Here the
PLC sets DB21.DBX396.0 (project-specific, rising edge) and the NC answers DB21.DBX397.0 (done)
or 397.1 (refused) until the PLC takes the request away, FB4's REQ / DONE / ERROR handshake.
"""

from __future__ import annotations

from dataclasses import dataclass
from enum import Enum

from interfaces.signal_groups import RETRACTION_REQUEST, RetractionStatus
from vc.core.axis.axis import MachineAxis
from vc.core.axis.jog import FREE_JOG, JogLimits
from vc.core.axis.owner import Owner
from vc.core.channel.channel import Channel
from vc.core.channel.program_run import ChannelState, Mode
from vc.core.interface_map import SignalTable
from vc.core.nc_memory import NcMemory, RetractData
from vc.core.state_machine import Instance, StateMachine, states, transitions

BOTH_DIRECTIONS = 1 << 8  # MD10735 bit 8: retraction in plus and minus direction (L35396-35400)
THREAD_FUNCTIONS = ("G33", "G331", "G332")
STANDING = JogLimits(plus=False, minus=False)


class RetractionState(Enum):
    NO_DATA = "no retract data"
    DATA = "retract data kept (377.5)"
    ACTIVE = "retraction selected (377.4)"


MANUAL_RETRACTION_STATES: StateMachine[ManualRetraction] = StateMachine(
    __name__, "manual_retraction", "Manual retraction along the tool axis (DB21.DBX377.4, 377.5)", Instance.CHANNEL,
    states(*RetractionState),
    transitions(("NO_DATA", "DATA", "reset / power failure in G33, G331, G332"),
                ("DATA", "ACTIVE", "RETRAC (DB21.DBX396.0) in JOG"),
                ("ACTIVE", "DATA", "reset, another mode, REF"),
                ("DATA", "NO_DATA", "a program starts"), ("ACTIVE", "NO_DATA", "a program starts")),
    read=lambda retraction: retraction.state)


@dataclass(slots=True)
class _Following:
    """The spindle coupled to the tool axis while it retracts: it turns ``ratio`` degrees per mm.

    Counted from cycle to cycle, so that a zero mark the restored spindle synchronises on (and
    the shift of its coordinates) does not move it."""

    tool: MachineAxis
    spindle: MachineAxis
    ratio: float  # spindle degrees per mm of the tool axis
    last_tool_setpoint: float


class ManualRetraction:
    """Manual retraction of one channel (see the module docstring)."""

    def __init__(self, channel: Channel, memory: NcMemory, table: SignalTable, area: bytearray,
                 jog_mode_mask: int):
        self.channel = channel
        self._memory = memory
        self._request_signal = table.bit(RETRACTION_REQUEST)
        self._encode = table.codec(RetractionStatus).encode
        self._area = area
        self.both_directions = bool(jog_mode_mask & BOTH_DIRECTIONS)
        self.active = False
        self.paused = False  # NC stop during the retraction, until NC start
        self.wcs_shown = False  # DB19.DBX0.7: the keys traverse in the WCS
        self._request = False
        self._answer: bool | None = None  # True done, False refused, None no request
        self._following: _Following | None = None
        self._written: tuple[bool, bool, bool, bool] | None = None  # the outputs last written

    @property
    def data(self) -> RetractData | None:
        return self._memory.retract.get(self.channel.name)

    @property
    def state(self) -> RetractionState:
        if self.active:
            return RetractionState.ACTIVE
        return RetractionState.NO_DATA if self.data is None else RetractionState.DATA

    # ------------------------------------------------------------------ the abort
    def keep_data(self) -> None:
        """A reset or power failure ends the program: keep the retract data if a thread block was
        running (or stopped in the middle).  Called before the channel forgets its block."""
        channel = self.channel
        plan = channel.block_in_progress
        if plan is None or channel.modal.thread not in THREAD_FUNCTIONS or not plan.targets:
            return
        if plan.tapping is not None:
            tool_axis, spindle, ratio = plan.tapping.axis, plan.tapping.spindle, plan.tapping.spindle_per_mm
        elif plan.thread is not None and plan.thread.lead_axis in plan.targets:
            # G33: the tool axis is the axis the lead names (K: Z), the spindle the master spindle the
            # thread follows, 360 / lead degrees per mm; the sign from the spindle's sense of rotation
            # and the block's travel along the tool axis [INF]
            tool_axis = plan.thread.lead_axis
            thread = channel.thread_in_progress
            spindle = thread.spindle.name if thread is not None else channel.master_spindle() or ""
            if not spindle:
                return
            start = thread.starts[thread.axes.index(channel.axes_by_name[tool_axis])] \
                if thread is not None and channel.axes_by_name[tool_axis] in thread.axes \
                else channel.axes_by_name[tool_axis].setpoint
            turning = thread.direction if thread is not None else (-1 if channel.axes_by_name[spindle].velocity < 0
                                                                   else 1)
            travel = -1 if plan.targets[tool_axis] < start else 1
            ratio = turning * travel * 360.0 / plan.thread.lead
        else:
            return
        self._memory.retract[channel.name] = RetractData(tool_axis, spindle, ratio)

    # ------------------------------------------------------------------ commands
    def commands(self, mode: Mode, reference_function: bool, reset: bool) -> None:
        """Cancel, select (PI service RETRAC), pause and continue; one IPO cycle."""
        request = self._request_signal.get(self._area)
        if not (request or self._request or reset or self.active):
            return  # no selection asked for, none running: the usual IPO cycle
        request_edge = request and not self._request
        self._request = request
        if reset or (self.active and (mode is not Mode.JOG or reference_function)):
            self._cancel()
        if request_edge:
            self._answer = self._select(mode, reference_function)
        elif not request:
            self._answer = None
        edges = self.channel.edges
        if self.active and edges.nc_stop:
            self.paused = True
        elif self.active and edges.nc_start:
            self.paused = False

    def _select(self, mode: Mode, reference_function: bool) -> bool:
        """The preconditions of L35430-35443; the data are restored on top of where the axes stand now."""
        data = self.data
        channel = self.channel
        if data is None or mode is not Mode.JOG or reference_function or channel.state is not ChannelState.RESET:
            return False
        axes = channel.axes_by_name
        retract_axes = [axes[data.tool_axis]] + ([axes[data.spindle]] if data.spindle else [])
        if not all(axis.encoder.referenced or axis.encoder.restored for axis in retract_axes):
            return False
        if data.spindle:
            # the thread's axis group again: the spindle in position control (L35497-35500)
            channel.spindles[data.spindle].enter_retraction()
            if data.spindle_per_mm:
                tool, spindle = axes[data.tool_axis], axes[data.spindle]
                self._following = _Following(tool, spindle, data.spindle_per_mm, tool.setpoint)
        self.active = True
        self.paused = False
        return True

    def _cancel(self) -> None:
        """Channel reset: JOG and reset, the retract data stay for a new selection (L35608-35640)."""
        self.active = False
        self.paused = False

    def program_started(self) -> None:
        """NC start in AUTOMATIC / MDA started a program: the retract data are deleted (L35683-35693)."""
        self.active = False
        self._memory.retract.pop(self.channel.name, None)

    # ------------------------------------------------------------------ JOG
    def jog_limits(self, axis: MachineAxis) -> JogLimits:
        """What JOG may do with ``axis``: the tool axis plus only (MD10735 bit 8), as fast as the
        spindle can follow; the other geometry axes not at all; NC stop pauses."""
        data = self.data
        if not self.active or data is None:
            return FREE_JOG
        if axis.name == data.tool_axis:
            if not self.wcs_shown:
                return STANDING  # MCS: the retraction is a traverse of the WCS geometry axis [control]
            following = self._following
            if following is None:
                return JogLimits(not self.paused, not self.paused and self.both_directions)
            ratio, dyn = abs(following.ratio), following.spindle.dyn
            return JogLimits(not self.paused, not self.paused and self.both_directions,
                             dyn.max_velocity / ratio, dyn.max_accel / ratio)
        if axis.name in self.channel.config.geometry_axes:
            return STANDING  # the tool stays on the thread's axis
        return FREE_JOG

    def handwheel_priority(self, receivers: list[tuple[int, MachineAxis]]) -> list[tuple[int, MachineAxis]]:
        """Which of the turning handwheels' (number, axis) assignments count this cycle (L35590-35598):
        none while the tool axis is moved by its keys; else only the handwheels of the highest
        rank among those turning - the tool axis, then the spindle, then the axes not involved."""
        data = self.data
        if not self.active or data is None or not receivers:
            return receivers
        tool = self.channel.axes_by_name[data.tool_axis]
        if tool.owner is Owner.JOG and tool.inputs.key_plus != tool.inputs.key_minus:
            return []

        def rank(axis: MachineAxis) -> int:
            return 0 if axis is tool else 1 if axis.name == data.spindle else 2

        best: dict[int, int] = {}
        for number, axis in receivers:
            best[number] = min(best.get(number, 2), rank(axis))
        top = min(best.values())
        return [(number, axis) for number, axis in receivers if best[number] == top]

    def follow(self) -> None:
        """The spindle turns with the tool axis by the thread's pitch while the tool axis moves,
        also while it brakes after a cancel."""
        following = self._following
        if following is None:
            return
        tool, spindle = following.tool, following.spindle
        moving = tool.owner in (Owner.JOG, Owner.BRAKE)
        if moving and spindle.owner is not Owner.JOG:
            spindle.take(Owner.JOG)  # a reset brakes the JOG axes: the spindle stays with the tool axis
        travel, following.last_tool_setpoint = tool.setpoint - following.last_tool_setpoint, tool.setpoint
        if spindle.owner is Owner.JOG:
            spindle.set_path_setpoint(spindle.setpoint + following.ratio * travel,
                                      following.ratio * tool.command_velocity if moving else 0.0)
            if not moving:
                spindle.release()
        if not moving and not self.active:
            self._following = None

    # ------------------------------------------------------------------ outputs
    def write_outputs(self) -> None:
        data_available = self.channel.name in self._memory.retract
        done, error = self._answer is True, self._answer is False
        status = (data_available, self.active, done, error)
        if status == self._written:
            return
        self._written = status
        self._encode(self._area, RetractionStatus(data_available=data_available, active=self.active, done=done,
                                                  error=error))
