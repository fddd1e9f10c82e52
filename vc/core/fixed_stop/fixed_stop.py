"""Travel to fixed stop of one axis (seed 003 chapter 17, L37062-38125): FXS / FXST / FXSW.

A tailstock quill, a sleeve or a steady rest travels with a reduced torque until it presses against
the workpiece, then holds it with the clamping torque for as long as the program wants::

    OFF ──FXS[ax]=1, MD37060 bit 0 = 1──▶ WAIT_ENABLE: DB31.DBX62.4 = 1, the torque limited at once
    OFF ──FXS[ax]=1, MD37060 bit 0 = 0──▶ APPROACH
    WAIT_ENABLE ──the PLC enables DB31.DBX3.1──▶ APPROACH: the block's motion starts
    APPROACH ──following error > MD37030 (MD37040 = 0 / 2) or the sensor DB31.DBX1.2 (1 / 2),
               MD37060 bit 1 = 1──▶ DETECTED: DBX62.5 = 1, the rest of the path deleted
    APPROACH ──the same, MD37060 bit 1 = 0──▶ CLAMPED
    DETECTED ──the PLC acknowledges DB31.DBX1.1──▶ CLAMPED: the block changes
    APPROACH ──the end point reached (20091), the pulses or DBX3.1 taken away (20094), RESET──▶ FAILED
    CLAMPED ──outside the window SD43520 (20093); DBX3.1 or the pulses taken away (20094)──▶ FAILED
    WAIT_ENABLE, APPROACH, DETECTED ──RESET──▶ FAILED (the function is aborted, L37703-37710)
    CLAMPED ──RESET──▶ CLAMPED (the clamp stays, L37711-37712)
    WAIT_ENABLE, APPROACH, DETECTED, CLAMPED ──FXS[ax]=0──▶ DESELECTING: DBX62.4 / 62.5 = 0
    DESELECTING ──the PLC took DBX3.1 (MD37060 bit 0) and DBX1.1 (bit 1) away──▶ OFF: position control again
    DESELECTING ──the pulses taken away while waiting──▶ DESELECTING with the torque limit 0 (L37482-37486)
    FAILED ──the PLC took DBX3.1 away (MD37060 bit 0), else at once──▶ OFF

While it is selected the drive's torque is limited to SD43510 (FXST, default MD37010), changed on the
ramp MD37012.  At the stop the NC holds the position setpoint MD37030 beyond the point it detected
the stop at, so that the drive pushes with its limited torque (L37345-37349), and watches the window
SD43520 (FXSW, default MD37020) around that point; the axis's controller enable DBX2.1 and its
disable DBX1.3 do not act there (L37292-37298), nor does the standstill monitoring (L37771-37773).
The states are $AA_FXS (``aa_fxs``) and the failures' $VA_FXS_INFO (``info``) of L37867-37915.
The function at rest costs nothing: its cycle runs only while it is not OFF.
"""

from __future__ import annotations

from enum import Enum

from interfaces.signal_groups import FixedStopStatus
from vc.config import md_dictionary as MD
from vc.core.alarms import AlarmList
from vc.core.axis.axis import MachineAxis
from vc.core.axis.owner import Owner
from vc.core.interface_map import SignalTable
from vc.core.state_machine import Instance, StateMachine, states, transitions

NOT_POSSIBLE, NOT_REACHED, STILL_ACTIVE, WINDOW_LEFT, ABORTED = 20090, 20091, 20092, 20093, 20094
# $VA_FXS_INFO (L37898-37915)
INFO_NONE, INFO_NO_MOTION, INFO_END_REACHED, INFO_RESET, INFO_WINDOW, INFO_TORQUE, INFO_ENABLE = range(7)


class State(Enum):
    OFF = "not at the fixed stop ($AA_FXS 0)"
    WAIT_ENABLE = "selected (DBX62.4), waiting for the PLC's enable DBX3.1 ($AA_FXS 3)"
    APPROACH = "travelling with the torque limit until the stop is detected ($AA_FXS 3)"
    DETECTED = "stop detected (DBX62.5), waiting for the PLC's acknowledgement DBX1.1 ($AA_FXS 4)"
    CLAMPED = "at the stop with the clamping torque, the window watched ($AA_FXS 1)"
    DESELECTING = "FXS=0: DBX62.4 / 62.5 = 0, waiting for the PLC to take DBX3.1 / 1.1 away ($AA_FXS 5)"
    FAILED = "not reached or aborted, waiting for the PLC to take DBX3.1 away ($AA_FXS 2)"


AA_FXS = {State.OFF: 0, State.WAIT_ENABLE: 3, State.APPROACH: 3, State.DETECTED: 4, State.CLAMPED: 1,
          State.DESELECTING: 5, State.FAILED: 2}
_SELECTED = (State.WAIT_ENABLE, State.APPROACH, State.DETECTED, State.CLAMPED)


class FixedStop:
    """Travel to fixed stop of one axis whose MD37000 allows it (see the module docstring)."""

    def __init__(self, axis: MachineAxis, table: SignalTable, area: bytearray, dt: float, alarms: AlarmList):
        self.axis = axis
        self.name = axis.name
        self._encode = table.codec(FixedStopStatus).encode
        self._area = area
        self._dt = dt
        self._alarms = alarms
        md = axis.config.md
        self.control = md.int(MD.FIXED_STOP_CONTROL)
        self.threshold = md.float(MD.FIXED_STOP_THRESHOLD)
        self.by_sensor = md.int(MD.FIXED_STOP_BY_SENSOR)
        self.alarm_mask = md.int(MD.FIXED_STOP_ALARM_MASK)
        self.ack_mask = md.int(MD.FIXED_STOP_ACKN_MASK)
        self._ramp_time = md.float(MD.FIXED_STOP_TORQUE_RAMP_TIME)
        self._default_torque = md.float(MD.FIXED_STOP_TORQUE_DEF)
        self._default_window = md.float(MD.FIXED_STOP_WINDOW_DEF)
        self.state: State = State.OFF
        self.torque = self._default_torque  # SD43510: the clamping torque, percent
        self.window = self._default_window  # SD43520: the monitoring window
        self.info = INFO_NONE  # $VA_FXS_INFO
        self.stop_position = 0.0  # where the stop was detected: the centre of the window
        self._direction = 1.0  # the direction the axis pushes in
        self._torque_step = 0.0  # per IPO cycle while the torque ramps (MD37012)
        self._ramp_target = self.torque
        self._pulses = True  # the pulses as last seen at the stop (MD37002)
        self._single_axis = False  # the approach runs on the axis's own motion (POS / POSA, an action's POS)
        self._outputs: tuple[bool, bool] | None = None
        self._write_outputs()

    # ------------------------------------------------------------------ what the channel asks
    @property
    def aa_fxs(self) -> int:
        """$AA_FXS: the state as the program reads it (L37867-37893); after a failure 2 until the
        next FXS or a reset, so that the program can branch on it (L37917-37941)."""
        if self.state is State.OFF and self.info != INFO_NONE:
            return AA_FXS[State.FAILED]
        return AA_FXS[self.state]

    @property
    def busy(self) -> bool:
        return self.state is not State.OFF

    @property
    def at_stop(self) -> bool:
        """Detected or clamped: a new motion or selection is refused (20092)."""
        return self.state in (State.DETECTED, State.CLAMPED)

    @property
    def holds_motion(self) -> bool:
        """The block's motion waits: for the PLC's enable, or for the deselection's acknowledgement."""
        return self.state in (State.WAIT_ENABLE, State.DESELECTING)

    @property
    def motion_ended(self) -> bool:
        """The approach is over: the channel deletes the rest of the block's path (L37306)."""
        return self.state in (State.DETECTED, State.CLAMPED, State.FAILED)

    @property
    def block_may_change(self) -> bool:
        """The block changes at the stop only once the PLC acknowledged (MD37060 bit 1), after a
        failure or a deselection only once the PLC took its enable away (L37309-37320, L37398-37404)."""
        return self.state in (State.OFF, State.APPROACH, State.CLAMPED)

    @property
    def single_axis(self) -> bool:
        """The axis approaches on its own motion (a command or positioning axis), not the path's:
        the program's blocks do not wait for it (L37775-37778)."""
        return self._single_axis or (self.state is not State.OFF and self.axis.owner is Owner.COMMAND)

    def select(self, cycle: int) -> bool:
        """FXS[ax]=1.  False: refused with 20092 (it is at the stop or still selected)."""
        if self.state is not State.OFF:
            self._alarm(STILL_ACTIVE, cycle)
            return False
        self.info = INFO_NONE
        self._single_axis = False
        self._set_state(State.WAIT_ENABLE if self.ack_mask & 1 and not self.axis.inputs.fixed_stop_enable
                        else State.APPROACH)
        self.axis.torque_limit = self.torque  # from the block's start, also while approaching (L37237-37247)
        self._torque_step = 0.0
        return True

    def deselect(self) -> None:
        """FXS[ax]=0 (L37428-37449); after a failure it clears $AA_FXS."""
        self.info = INFO_NONE
        if self.state in _SELECTED:
            self._set_state(State.DESELECTING)

    def set_torque(self, percent: float) -> None:
        """FXST[ax]= (SD43510): before the block's motion (L37166-37170), on the ramp MD37012."""
        self.torque = percent
        if self.state is not State.OFF:
            self._ramp_to(percent)

    def set_window(self, width: float) -> None:
        """FXSW[ax]= (SD43520): at the stop the window is centred anew on the actual position (L37179-37181)."""
        self.window = width
        if self.state is State.CLAMPED:
            self.stop_position = self.axis.actual

    def motion_finished(self, cycle: int) -> None:
        """The block's end point was reached without a stop: 20091, the block changes (L37963-37967)."""
        if self.state is State.APPROACH:
            self.info = INFO_END_REACHED
            if self.alarm_mask & 1:
                self._alarm(NOT_REACHED, cycle)
            self._fail()

    def reset(self) -> None:
        """NC reset aborts the function until the stop is reached; a clamp stays (L37703-37712)."""
        if self.state is State.OFF:
            self.info = INFO_NONE
        elif self.state in (State.WAIT_ENABLE, State.APPROACH, State.DETECTED):
            self.info = INFO_RESET
            self._fail()
        self.torque = self._default_torque if self.state is State.OFF else self.torque
        self.window = self._default_window if self.state is State.OFF else self.window

    # ------------------------------------------------------------------ the cycle
    def cycle(self, cycle: int) -> None:
        """After position control, while the function is not OFF."""
        axis = self.axis
        if self._torque_step:
            self._ramp()
        inputs = axis.inputs
        state = self.state
        if state is State.WAIT_ENABLE:
            self._wait_enable(inputs.fixed_stop_enable)
        elif state is State.APPROACH:
            self._approach(cycle)
        elif state is State.DETECTED:
            self._detected(cycle)
        elif state is State.CLAMPED:
            self._clamped(cycle)
        elif state is State.DESELECTING:
            self._deselecting()
        elif state is State.FAILED:
            self._failed()
        self._write_outputs()

    def _wait_enable(self, enabled: bool) -> None:
        """The block's motion waits for the PLC's enable DBX3.1 (MD37060 bit 0, L37221-37232)."""
        if enabled:
            self._set_state(State.APPROACH)

    def _approach(self, cycle: int) -> None:
        """Moving with the torque limit: detect the stop (L37273-37290); the PLC or the drive may abort."""
        axis = self.axis
        if self._aborted(cycle):
            return
        error = axis.following_error
        by_error = self.by_sensor != 1 and abs(error) > self.threshold
        by_sensor = self.by_sensor != 0 and axis.inputs.fixed_stop_sensor
        if not (by_error or by_sensor):
            if axis.owner is Owner.COMMAND:
                self._single_axis = True
            elif self._single_axis and axis.owner is Owner.NONE:
                self.motion_finished(cycle)  # its own motion reached the end point without a stop: 20091
            return
        self._direction = 1.0 if error >= 0.0 else -1.0
        if by_sensor and not by_error:
            self._direction = 1.0 if axis.command_velocity >= 0.0 else -1.0
        self.stop_position = axis.actual
        self._pulses = self._pulses_present
        axis.hold_at_fixed_stop(axis.actual + self._direction * self.threshold)
        self._set_state(State.DETECTED if self.ack_mask & 2 else State.CLAMPED)

    def _detected(self, cycle: int) -> None:
        """At the stop, the block change waits for the PLC's DBX1.1 (MD37060 bit 1, L37317-37320)."""
        if self._aborted(cycle) or self._window_left(cycle):
            return
        if self.axis.inputs.fixed_stop_ack:
            self._set_state(State.CLAMPED)

    def _clamped(self, cycle: int) -> None:
        """Holding with the clamping torque; the window watched (20093, L37335-37337).  With
        MD37002 bit 0 the pulses may go (the drive holds nothing) and come back: the torque then
        jumps to the clamping torque, or with bit 1 it rises on the ramp MD37012 (L37461-37480)."""
        if self._aborted(cycle) or self._window_left(cycle):
            return
        pulses = self._pulses_present
        if pulses and not self._pulses and self.control & 2:
            self.axis.torque_limit = 0.0
            self._ramp_to(self.torque)
        self._pulses = pulses

    @property
    def _pulses_present(self) -> bool:
        axis = self.axis
        return axis.inputs.pulse_enable and not axis.pulses_cancelled

    def _deselecting(self) -> None:
        """The signals are reset; position control again once the PLC acknowledged (L37436-37449).
        The pulses taken away while waiting set the torque limit to 0, and it stays 0 when they
        come back until the deselection is done (L37482-37486)."""
        axis = self.axis
        inputs = axis.inputs
        if (self.ack_mask & 1 and inputs.fixed_stop_enable) or (self.ack_mask & 2 and inputs.fixed_stop_ack):
            if not self._pulses_present:
                self._torque_step = 0.0
                axis.torque_limit = 0.0
            return
        self._release()
        self._set_state(State.OFF)

    def _failed(self) -> None:
        """Torque limit off, DBX62.4 = 0; off once the PLC took DBX3.1 away (L37395-37406)."""
        if not (self.ack_mask & 1 and self.axis.inputs.fixed_stop_enable):
            self._set_state(State.OFF)

    def _aborted(self, cycle: int) -> bool:
        """The PLC took its enable away (MD37060 bit 0) or the pulses went (MD37002 bit 0 = 0): 20094."""
        inputs = self.axis.inputs
        enable_lost = bool(self.ack_mask & 1) and not inputs.fixed_stop_enable
        pulses_lost = not self._pulses_present and not self.control & 1
        if not (enable_lost or pulses_lost):
            return False
        self.info = INFO_ENABLE if enable_lost else INFO_TORQUE
        if not self.alarm_mask & 2:
            self._alarm(ABORTED, cycle)
        self._fail()
        return True

    def _window_left(self, cycle: int) -> bool:
        if abs(self.axis.actual - self.stop_position) <= self.window:
            return False
        self.info = INFO_WINDOW
        self._alarm(WINDOW_LEFT, cycle)
        self._fail()
        return True

    # ------------------------------------------------------------------ helpers
    def _fail(self) -> None:
        self._release()
        self._set_state(State.FAILED)

    def _release(self) -> None:
        """Torque limit off, the axis back in position control where it stands."""
        self._torque_step = 0.0
        self.axis.leave_fixed_stop()

    def _set_state(self, state: State) -> None:
        self.state = state
        self.axis.at_fixed_stop = state in (State.DETECTED, State.CLAMPED, State.DESELECTING)
        self.axis.fixed_stop_waits = state is State.WAIT_ENABLE

    def _ramp_to(self, percent: float) -> None:
        """A new torque limit: at once, or linearly within MD37012 (L37172-37176)."""
        current = self.axis.torque_limit
        if self._ramp_time <= 0.0 or current is None:
            self.axis.torque_limit = percent
            self._torque_step = 0.0
            return
        self._torque_step = (percent - current) * self._dt / self._ramp_time
        self._ramp_target = percent

    def _ramp(self) -> None:
        axis = self.axis
        current = axis.torque_limit if axis.torque_limit is not None else self._ramp_target
        following = current + self._torque_step
        if (self._torque_step > 0.0) == (following >= self._ramp_target):
            following, self._torque_step = self._ramp_target, 0.0
        axis.torque_limit = following

    def _alarm(self, number: int, cycle: int) -> None:
        self._alarms.raise_alarm(number, cycle, self.name, channel=self.axis.channel, axis=self.name)

    def _write_outputs(self) -> None:
        outputs = (self.state in _SELECTED, self.state in (State.DETECTED, State.CLAMPED))
        if outputs != self._outputs:
            self._outputs = outputs
            self._encode(self._area, FixedStopStatus(active=outputs[0], reached=outputs[1]))


FIXED_STOP_STATES: StateMachine[FixedStop] = StateMachine(
    __name__, "fixed_stop", "Travel to fixed stop (DB31.DBX62.4 / 62.5)", Instance.AXIS,
    states(*State),
    transitions(("OFF", "WAIT_ENABLE", "FXS[ax]=1, MD37060 bit 0"), ("OFF", "APPROACH", "FXS[ax]=1"),
                ("WAIT_ENABLE", "APPROACH", "DB31.DBX3.1"),
                ("APPROACH", "DETECTED", "following error > MD37030 or sensor DBX1.2, MD37060 bit 1"),
                ("APPROACH", "CLAMPED", "following error > MD37030 or sensor DBX1.2"),
                ("DETECTED", "CLAMPED", "DB31.DBX1.1"),
                ("APPROACH", "FAILED", "end point reached (20091), DBX3.1 or pulses off (20094), RESET"),
                ("WAIT_ENABLE", "FAILED", "RESET"), ("DETECTED", "FAILED", "RESET, DBX3.1 off (20094)"),
                ("CLAMPED", "FAILED", "window SD43520 left (20093), DBX3.1 or pulses off (20094)"),
                ("WAIT_ENABLE", "DESELECTING", "FXS[ax]=0"), ("APPROACH", "DESELECTING", "FXS[ax]=0"),
                ("DETECTED", "DESELECTING", "FXS[ax]=0"), ("CLAMPED", "DESELECTING", "FXS[ax]=0"),
                ("DESELECTING", "OFF", "DBX3.1 / 1.1 taken away (MD37060)"),
                ("FAILED", "OFF", "DBX3.1 taken away (MD37060 bit 0)")),
    read=lambda fixed_stop: fixed_stop.state)
