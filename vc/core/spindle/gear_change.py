"""Gear stages of a spindle (seed 003 §13.4): which gear, and the NC/PLC gear-change dialog.

Gear selection (:func:`select_gear`): M41..M45 name the gear; M40 chooses it from the
programmed speed with the switching thresholds MD35110 / MD35120 (§13.8.9, L18481-18510,
L21275-21357).

The dialog (:class:`GearChange`), one change at a time per spindle (spec B.4.5-B.4.8), one
method per state; ``state`` None: no change runs::

    None ─M40 S / M41..M45 with another gear, MD35010 bit 1─▶ TO_POSITION
      │  ─... without bit 1─▶ REQUESTED
    TO_POSITION ─ position to MD35012 with the current gear (84.5), exact stop fine ─▶ POSITION_DELAY
       │          not reached (or no drive enable): alarm 22020, no dialog ─▶ None
    POSITION_DELAY ─ MD35310 elapsed ─▶ REQUESTED
    REQUESTED ── 82.0-82.2 = set gear, 82.3 = 1, oscillation mode (84.6); the spindle brakes
       │         (with MD35410 when 18.5 is already set, else with MD35200)
       ▼ stationary (61.4)
    AT_STANDSTILL ── oscillates while the PLC enables it: 18.5 by the NC (MD35400 alternately
       │             MD35440 in M3 and MD35450 in M4 direction), 18.4 + 18.6 / 18.7 by the PLC
       ▼ 16.3 gear changed (accepted from REQUESTED on)
    None: the reported gear 16.0-16.2 becomes active (its parameter set and limits), 82.3 = 0,
          alarm 22010 when it is not the set gear (MD11410 bit 3 = 0), control mode again

A change the PLC does not acknowledge within MD10192 raises alarm 65830; a reset or the
spindle reset DB31.DBX2.2 ends it without alarm and takes the gear the PLC reports.  With
MD35010 bit 3 the NC simulates the dialog: nothing is output, the set gear becomes active at
standstill.  In reset state the PLC may set the gear without a request (L18597-18625).

Observers see the dialog as ``GEAR_CHANGE_STATES``, with NONE while no change runs.

The spindle owns its modes: :class:`GearChange` tells it through ``outcome`` when the dialog
opens (oscillation mode), when the change position was not reached and when the change ended
(control mode with the new gear's data), and it owns the positioning to the change position.
"""

from __future__ import annotations

from dataclasses import dataclass
from enum import Enum

from vc.config import md_dictionary as MD
from vc.config.machine_data import MachineData, MdDef
from vc.core.alarms import AlarmList
from vc.core.axis.axis import MachineAxis
from vc.core.nc_memory import NcMemory
from vc.core.program.commands import SpindleCommand
from vc.core.referencing.buffered_positions import lose_calibration
from vc.core.spindle.positioning import Positioning
from vc.core.spindle.signals import SpindleInputs
from vc.core.state_machine import Instance, StateMachine, StateValue, states, transitions

GEAR_CHANGE_WITH_OSCILLATION = 1 << 0  # MD35010 bit 0
GEAR_CHANGE_AT_POSITION = 1 << 1  # MD35010 bit 1
GEAR_CHANGE_SIMULATED = 1 << 3  # MD35010 bit 3
ALARM_GEAR_CHANGE_NOT_POSSIBLE = 22000
ALARM_WRONG_GEAR = 22010
ALARM_CATCH_UP_IMPOSSIBLE = 22011  # the programmed stage cannot be caught up (L20054-20055)
ALARM_POSITION_NOT_REACHED = 22020
ALARM_NOT_ACKNOWLEDGED = 65830  # project number: the seed names none (spec B.5) [control: an alarm follows]
SUPPRESS_WRONG_GEAR = 1 << 3  # MD11410 bit 3
CATCH_UP_AFTER_SUPPRESSION = 1 << 2  # MD35035 bit 2: the programmed stage is engaged afterwards
_STABLE_CYCLES = 10  # a gear reported in reset state is taken once it stood this long (L18603-18606)


def select_gear(md: MachineData, speed: float, current: int) -> int | None:
    """The gear M40 chooses for ``speed`` (rev/min), or None to keep the current one.

    The current gear stays while the speed lies in its switching window [MD35120, MD35110]
    (L18489-18491); otherwise the first gear whose window holds the speed, searched upwards
    (the seed's example L21662-21679).  Beyond every window: above all -> the highest gear,
    below gear 1's lower threshold -> gear 1; S0 changes nothing unless MD35120[1] = 0
    (L21335-21357).
    """
    gears = md.int(MD.NUM_GEAR_STEPS)
    low, high = MD.GEAR_STEP_MIN_VELO, MD.GEAR_STEP_MAX_VELO
    if speed == 0.0:
        return 1 if md.float(low, 1) == 0.0 and current != 1 else None
    if 1 <= current <= gears and md.float(low, current) <= speed <= md.float(high, current):
        return None
    for gear in range(1, gears + 1):
        if md.float(low, gear) <= speed <= md.float(high, gear):
            return gear
    if speed > max(md.float(high, gear) for gear in range(1, gears + 1)):
        return gears
    return 1


class GearState(Enum):
    TO_POSITION = "to the gear-change position"
    POSITION_DELAY = "waiting MD35310 at the gear-change position"
    REQUESTED = "change requested, braking"
    AT_STANDSTILL = "at standstill, waiting for the PLC"


GEAR_CHANGE_STATES: StateMachine[GearChange] = StateMachine(
    __name__, "gear_change", "Gear stage change dialog (DB31.DBX82.3, 16.3)", Instance.SPINDLE,
    states(("NONE", "no gear change"), *GearState),
    transitions(("NONE", "REQUESTED", "M40 S / M41..M45 with another stage"),
                ("NONE", "AT_STANDSTILL", "requested at standstill (REQUESTED lasts less than a cycle)"),
                ("NONE", "TO_POSITION", "change at a fixed position (MD35010 bit 1)"),
                ("TO_POSITION", "POSITION_DELAY", "at the change position"),
                ("POSITION_DELAY", "REQUESTED", "MD35310 elapsed"),
                ("REQUESTED", "AT_STANDSTILL", "stationary (61.4)"),
                ("AT_STANDSTILL", "NONE", "gear changed (16.3)"),
                ("REQUESTED", "NONE", "gear changed before standstill, reset"),
                ("TO_POSITION", "NONE", "position not reached (22020), reset")),
    read=lambda change: _state_of(change))


def _state_of(change: GearChange) -> StateValue:
    state = change.state
    return "NONE" if state is None else state  # NONE: no change runs


@dataclass(frozen=True, slots=True)
class Oscillation:
    """The NC's oscillation for meshing (MD35400 speed, MD35410 acceleration, MD35440 / MD35450
    times in the M3 / M4 direction, MD35430 start direction), in internal units."""

    speed: float  # deg/s
    accel: float  # deg/s^2
    cycles_cw: int
    cycles_ccw: int
    start_direction: int  # MD35430: 0..2 = against the last rotation, 3 = M3, 4 = M4

    @classmethod
    def of(cls, md: MachineData, dt: float) -> Oscillation:
        return cls(md.float(MD.SPIND_OSCILL_DES_VELO) * 6.0, md.float(MD.SPIND_OSCILL_ACCEL) * 360.0,
                   max(1, round(md.float(MD.SPIND_OSCILL_TIME_CW) / dt)),
                   max(1, round(md.float(MD.SPIND_OSCILL_TIME_CCW) / dt)), md.int(MD.SPIND_OSCILL_START_DIR))

    def first_direction(self, last_rotation: int) -> int:
        if self.start_direction == 3:
            return 1
        if self.start_direction == 4:
            return -1
        return -last_rotation if last_rotation else 1

    def step(self, change: GearChange, last_rotation: int) -> float:
        """The NC's oscillation velocity command for this cycle; alternates the direction."""
        if change.oscillation_direction == 0:
            change.oscillation_direction = self.first_direction(last_rotation)
            change.oscillation_cycles = 0
        change.oscillation_cycles += 1
        limit = self.cycles_cw if change.oscillation_direction > 0 else self.cycles_ccw
        if change.oscillation_cycles > limit:
            change.oscillation_direction = -change.oscillation_direction
            change.oscillation_cycles = 1
        return change.oscillation_direction * self.speed


class GearOutcome(Enum):
    """What a cycle of the change asks of the spindle, which switches its modes itself."""

    NONE = "nothing"
    TO_POSITION = "the change begins at the change position: positioning to MD35012"
    DIALOG = "the dialog opened: oscillation mode"
    ABORTED = "the gear-change position was not reached: control mode, M5"
    CHANGED = "the change ended (16.3, a reset, simulated): control mode with the new gear's data"


class GearChange:
    """The gear stages of one spindle and their change (see the module docstring).

    ``state`` is None while no change runs; the other fields of the change (``target``..) keep
    the values of the last one until the next starts."""

    def __init__(self, axis: MachineAxis, inputs: SpindleInputs, channel: str, dt: float,
                 suppress_alarm_mask: int, gear_wait_s: float, memory: NcMemory, alarms: AlarmList):
        """``memory`` and ``alarms``: where a change that recalibrates an absolute motor encoder
        writes MD34210 and raises 25022, also when a reset ends the change."""
        self._axis = axis
        self._inputs = inputs
        self._channel = channel
        self._name = axis.name
        self._number = axis.config.spindle_number
        self._md = md = axis.config.md
        self._dt = dt
        self._memory = memory
        self._alarms = alarms
        self._suppress_wrong_gear = bool(suppress_alarm_mask & SUPPRESS_WRONG_GEAR)
        self._wait_cycles = max(1, round(gear_wait_s / dt))
        self.gears = md.int(MD.NUM_GEAR_STEPS)
        self.change_enable = md.int(MD.GEAR_STEP_CHANGE_ENABLE)
        self.oscillation = Oscillation.of(md, dt)
        self.automatic_gear = True  # M40 is the default after reset (L21331)
        self.gear = 1  # active gear stage (its parameter set and limits)
        self.acknowledged_gear = 1  # shown in DBX82.0-82.2 outside a change
        self.dialog_forced = False  # stage 0 reported at program start: the next change talks to the PLC
        self.suppressed_gear: int | None = None  # programmed while changes were suppressed ($P_GEAR)
        self._reported_since = 0
        self._last_report = 0  # the last gear report taken in reset state (DBX16.0-16.2)
        # the running change
        self.state: GearState | None = None
        self.outcome = GearOutcome.NONE  # of the last cycle (or start)
        self.target = 0  # the set gear
        self.started_cycle = 0
        self.simulated = False  # MD35010 bit 3: the NC does not talk to the PLC
        self.stops_spindle = False  # requested in positioning or axis mode: M5 afterwards (L18657-18675)
        self.delay_cycles = 0  # MD35310 still to wait at the change position
        self.oscillation_direction = 0  # +1 M3, -1 M4: the NC's oscillation
        self.oscillation_cycles = 0  # time in the present oscillation direction
        self.acknowledged_timeout = False  # alarm 65830 raised

    # ------------------------------------------------------------------ gear stage data
    def gear_float(self, md_def: MdDef) -> float:
        """A machine datum of the active gear stage."""
        return self._md.float(md_def, self.gear)

    def ratio(self, gear: int) -> float:
        """Load revolutions per motor revolution in ``gear`` (MD31050 / MD31060)."""
        md = self._md
        return md.int(MD.DRIVE_AX_RATIO_DENOM, gear) / md.int(MD.DRIVE_AX_RATIO_NUMERA, gear)

    def apply_parameter_set(self, index: int) -> None:
        """The gear's (or axis mode's) parameter set ``index``: Kv, and with a motor encoder the
        zero-mark spacing of the new ratio (§13.4.4, L18960-18995) and the spindle speed at which
        the encoder reaches its limit frequency MD36300 (§13.8.7: a motor speed, the same in every
        gear stage)."""
        axis, md = self._axis, self._md
        axis.set_loop_gain(md.float(MD.POSCTRL_GAIN, min(index, 5)))
        for encoder in axis.encoders:
            if not md.bool(MD.ENC_IS_DIRECT, encoder.index):
                axis.set_encoder_turn(encoder, abs(360.0 * self.ratio(index)))

    @property
    def changes_enabled(self) -> bool:
        return bool(self.change_enable & (GEAR_CHANGE_WITH_OSCILLATION | GEAR_CHANGE_AT_POSITION))

    @property
    def at_position(self) -> bool:
        """MD35010 bit 1: the change takes place at the position MD35012."""
        return bool(self.change_enable & GEAR_CHANGE_AT_POSITION)

    @property
    def dialog_open(self) -> bool:
        """82.3 is set: the PLC may (and must) change the gear."""
        return not self.simulated and self.state in (GearState.REQUESTED, GearState.AT_STANDSTILL)

    @property
    def brakes_into_oscillation(self) -> bool:
        """The spindle brakes into (or turns in) the oscillation with MD35410 (L18372-18374)."""
        return self.state in (GearState.REQUESTED, GearState.AT_STANDSTILL) \
            and (self._inputs.oscillation_enable or self.state is GearState.AT_STANDSTILL)

    @property
    def settled(self) -> bool:
        """No change runs and no new gear report waits to be taken."""
        return self.state is None and self._inputs.gear_reported == self._last_report

    def take_report(self, reported: int) -> None:
        """DBX16.0-16.2 as the PLC writes them this cycle; a new value must stand still to be taken."""
        if reported != self._inputs.gear_reported:
            self._reported_since = 0
        self._inputs.gear_reported = reported

    # ------------------------------------------------------------------ program commands
    def programmed(self, command: SpindleCommand, suppressed: bool) -> int | None:
        """The stage a block asks for (M41..M45, S with M40) unless it is already active, or None.
        ``suppressed`` (dry run, program test): the stage is only remembered for a catch-up."""
        if command.gear is not None:
            self.automatic_gear = command.gear == 40
        target = self.requested(command)
        if command.gear is not None or (self.automatic_gear and command.speed is not None):
            # the block programs a stage: it replaces one a suppressed block left to catch up
            self.suppressed_gear = target if suppressed else None
        return target

    def requested(self, command: SpindleCommand) -> int | None:
        if not self.changes_enabled:
            return None  # a fixed ratio: the data of gear stage 1 (MD35010 = 0, L18245-18256)
        # the PLC reported stage 0 (gearbox disengaged) at program start: the next change runs the
        # dialog whatever the active stage is (L18758-18766)
        current = 0 if self.dialog_forced else self.gear
        if command.gear is not None and command.gear >= 41:
            wanted = min(command.gear - 40, self.gears)
            return wanted if wanted != self.gear or current == 0 else None
        if self.automatic_gear and command.speed is not None:
            chosen = select_gear(self._md, command.speed, current)
            return chosen if chosen is not None and (chosen != self.gear or current == 0) else None
        return None

    def for_axis_mode(self) -> int | None:
        """MD35014: the stage axis mode needs, when a change to it is due (L19886-19891)."""
        used = self._md.int(MD.GEAR_STEP_USED_IN_AXISMODE)
        return used if used and used != self.gear and self.state is None and self.changes_enabled else None

    def reset(self) -> None:
        """Channel reset or M2 / M30: M40 again (L21331), nothing to catch up."""
        self.automatic_gear = True
        self.suppressed_gear = None

    def catch_up_target(self) -> int | None:
        """Dry run / program test deselected: the stage programmed meanwhile, to be engaged now with
        MD35035 bit 2 (L20019-20035); without it the active stage stays (L20005-20007)."""
        target, self.suppressed_gear = self.suppressed_gear, None
        if target is None or not self._md.int(MD.SPIND_FUNCTION_MASK) & CATCH_UP_AFTER_SUPPRESSION:
            return None
        return target

    def changes_to(self, target: int) -> bool:
        """Engaging ``target`` now takes a change (none runs; another stage, or stage 0 reported)."""
        return self.state is None and (target != self.gear or self.dialog_forced)

    # ------------------------------------------------------------------ the change
    def start(self, target: int, cycle: int, stops_spindle: bool) -> None:
        """A change to ``target`` begins: at the change position (the spindle positions to
        :meth:`change_position`) or with the dialog."""
        self.dialog_forced = False
        self.target = target
        self.started_cycle = cycle
        self.simulated = bool(self.change_enable & GEAR_CHANGE_SIMULATED)
        self.stops_spindle = stops_spindle
        self.delay_cycles = 0
        self.oscillation_direction = 0
        self.oscillation_cycles = 0
        self.acknowledged_timeout = False
        self.outcome = GearOutcome.NONE
        if self.at_position:
            self.state = GearState.TO_POSITION
            self.outcome = GearOutcome.TO_POSITION
        else:
            self._open_dialog()

    def change_position(self) -> float:
        """MD35012 of the active gear, degrees."""
        return self.gear_float(MD.GEAR_STEP_CHANGE_POSITION)

    def _open_dialog(self) -> None:
        self.state = GearState.REQUESTED
        self.outcome = GearOutcome.DIALOG

    def cycle(self, cycle: int, alarms: AlarmList, stationary: bool, position_control: bool,
              positioning: Positioning | None, last_rotation: int) -> float | None:
        """The velocity the change commands this cycle (None: the change does not command); the
        spindle then acts on ``outcome``.  ``stationary``: the spindle stands (61.4)."""
        self.outcome = GearOutcome.NONE
        if self.dialog_open and not self.acknowledged_timeout and cycle - self.started_cycle > self._wait_cycles:
            self.acknowledged_timeout = True
            alarms.raise_alarm(ALARM_NOT_ACKNOWLEDGED, cycle, self._channel, self._number,
                               f"{self._wait_cycles * self._dt:g}", channel=self._channel, axis=self._name)
        state = self.state
        if state is GearState.TO_POSITION:
            return self._to_position(cycle, alarms, positioning)
        if state is GearState.POSITION_DELAY:
            return self._position_delay()
        if state is GearState.REQUESTED:
            if not stationary:
                return self._requested(cycle, alarms)
            self.state = GearState.AT_STANDSTILL
        return self._at_standstill(cycle, alarms, position_control, last_rotation)

    def _to_position(self, cycle: int, alarms: AlarmList, positioning: Positioning | None) -> float | None:
        """Positioning to MD35012 with the current gear, then exact stop fine."""
        axis = self._axis
        if positioning is None:
            return None
        if not axis.drive_ready:
            return self._position_not_reached(cycle, alarms)
        if positioning.done and abs(axis.distance_to_end_point) <= axis.dyn.fine_window:
            self.state = GearState.POSITION_DELAY
            self.delay_cycles = round(self.gear_float(MD.SPIND_POSIT_DELAY_TIME) / self._dt)
        elif positioning.done and cycle - self.started_cycle > self._wait_cycles:
            return self._position_not_reached(cycle, alarms)
        return None

    def _position_delay(self) -> float | None:
        """MD35310 at the change position, then the dialog."""
        self.delay_cycles -= 1
        if self.delay_cycles <= 0:
            self._open_dialog()
        return None

    def _position_not_reached(self, cycle: int, alarms: AlarmList) -> float:
        """No dialog when the gear-change position is not reached: it protects the gearbox (L19697-19701)."""
        alarms.raise_alarm(ALARM_POSITION_NOT_REACHED, cycle, self._channel, "", self._number,
                           channel=self._channel, axis=self._name)
        self.state = None
        self.outcome = GearOutcome.ABORTED
        return 0.0

    def _requested(self, cycle: int, alarms: AlarmList) -> float | None:
        """82.3 set, the spindle brakes (the ramp chooses the acceleration); 16.3 is accepted already."""
        inp = self._inputs
        if self.dialog_open and inp.gear_done:
            self.finish(inp.gear_reported, alarms, cycle)
            return None
        # at the change position the spindle stands in position control, braking or not
        return 0.0

    def _at_standstill(self, cycle: int, alarms: AlarmList, position_control: bool, last_rotation: int) -> float | None:
        """Stationary: oscillation while the PLC enables it, until 16.3 (or at once when simulated)."""
        inp = self._inputs
        if self.simulated:
            self.finish(self.target, alarms, cycle)
            return 0.0
        if self.dialog_open and inp.gear_done:
            self.finish(inp.gear_reported, alarms, cycle)
            return None
        if position_control and not inp.oscillation_enable:
            # at the change position the spindle stands in position control; oscillation is not
            # needed there, "but in principle it can still be enabled" (L19593-19603)
            return 0.0
        if not inp.oscillation_enable or inp.rapid_stop or self._axis.inputs.feed_stop:
            self.oscillation_direction = 0
            return 0.0
        if inp.oscillation_by_plc:
            if inp.oscillation_cw == inp.oscillation_ccw:
                return 0.0
            return self.oscillation.speed if inp.oscillation_cw else -self.oscillation.speed
        return self.oscillation.step(self, last_rotation)

    def finish(self, reported: int, alarms: AlarmList | None, cycle: int) -> None:
        """The PLC reported the gear (16.3), a reset ended the change (``alarms`` None), or the NC
        simulated it: the reported gear becomes active."""
        self.state = None
        self.outcome = GearOutcome.CHANGED
        axis, md = self._axis, self._md
        previous = self.gear
        self.gear = max(0, min(reported, self.gears))
        self.acknowledged_gear = self.gear
        self._last_report = self._inputs.gear_reported
        if alarms is not None and self.gear != self.target and not self._suppress_wrong_gear:
            alarms.raise_alarm(ALARM_WRONG_GEAR, cycle, self._channel, "", self._number, self.gear, self.target,
                               channel=self._channel, axis=self._name)
        motor_encoder = not md.bool(MD.ENC_IS_DIRECT, axis.encoder.index)
        if motor_encoder and previous != self.gear and not axis.encoder.absolute:
            axis.encoder.referenced = False  # a new ratio between motor and spindle (L19281-19284)
        if self.ratio(previous) != self.ratio(self.gear):
            for encoder in axis.encoders:
                if encoder.absolute and not md.bool(MD.ENC_IS_DIRECT, encoder.index) \
                        and self._memory.view(self._name, md).int(MD.ENC_REFP_STATE, encoder.index):
                    # the stage between the load and an absolute motor encoder changed its ratio: the
                    # encoder must be calibrated again (seed 003 L1992-1996, L2025-2040)
                    lose_calibration(axis, encoder.index, self._memory, self._alarms, cycle)

    def accept_reported_gear(self) -> bool:
        """Reset state: the PLC may set the gear without a request (L18597-18625); the NC takes a
        new report once it stood still and acknowledges it in DBX82.0-82.2.  Only a report that
        changed counts: a PLC that never writes the bits (a spindle without a gearbox) leaves the
        gear alone [control: the gear stage of the last change, gear 1 after power-on].  True: a
        new gear was taken (the spindle applies its data)."""
        inp = self._inputs
        if self.state is not None or inp.gear_done or inp.gear_reported == self._last_report \
                or not self.changes_enabled:
            return False
        self._reported_since += 1
        if self._reported_since >= _STABLE_CYCLES and inp.gear_reported <= self.gears:
            self._last_report = inp.gear_reported
            self.gear = inp.gear_reported
            self.acknowledged_gear = self.gear
            return True
        return False
