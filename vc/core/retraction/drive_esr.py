"""Drive-autonomous extended stop and retract (ESR), seed 003 §22.2 (L41550-42088).

The drive itself stops or retracts the axis when the NC-wide trigger ``$AN_ESR_TRIGGER`` reaches
it, whatever the NC does meanwhile (the NC may be the very thing that failed).  Its configuration
is drive parameters, written from the part program by ESRS / ESRR (L41912-41993):

* p0888 = 1 extended stop, 2 extended retract, 3 generator operation (L41602-41720);
* p0892: stop - the time the drive keeps its speed setpoint of the trigger moment, then brakes;
  retract - the time of running up to p0893 and running at it, then braking (L41628-41693);
* p0893: retract speed, a motor speed: ESRR's velocity converted with the gear ratio (L41971-41975);
* p0891 = 0: braking on the OFF3 ramp (p1135), 1: on the ramp-function generator's ramp p1121.
  The harness's drives have one ramp, the rapid-stop ramp MD36610 (MAX_AX_VELO in that time) [INF].

The trigger must stand at least 2 IPO cycles (PROFIdrive, L41793-41809): the drive sees it in the
second cycle.  Timeline of one axis (figures 22-1, 22-2, 22-4)::

    ARMED ──$AA_ESR_ENABLE = 1, trigger 2 cycles──▶ REACTING (r0887.12 = r0887.13 = 1, DB31.DBX95.2)
    REACTING ──stop: p0892, then the ramp; retract: p0892 at p0893, then the ramp──▶ DONE (r0887.13 = 0)

While it reacts the drive moves the axis on its own: DB31.DBX92.4 "drive-autonomous motion active"
(L38352) is 1 in REACTING [INF: the harness's only drive-autonomous motion is this reaction].
    DONE ──$AA_ESR_ENABLE 1 -> 0 (acknowledge)──▶ ACKNOWLEDGED: 95.2 = 0
    REACTING ──enable 1 -> 0──▶ ack pending: 95.2 falls when the reaction ends (red path of fig. 22-4)
    ACKNOWLEDGED ──enable 0 -> 1 and $AN_ESR_TRIGGER = 0──▶ ARMED

Observers see the reaction as ``DRIVE_ESR_STATES`` (ARMED, REACTING, DONE: the acknowledgement
arms the drive again).

Generator operation (p0888 = 3, set up in the drive: the axis's ``drive:`` parameters) turns the
motor's kinetic energy into the DC link's when the supply fails (L41700-41769, vc/core/retraction/dc_link.py):
from the trigger T1 until T2 = T1 + p0892 the drive holds its speed setpoint, and its Vdc_min
controller brakes the motor whenever the link falls to p1248 (DB31.DBX95.1, r0056.15); at T2 it
brakes on the ramp.  DB31.DBX95.3 (r2199.0) shows the motor below the minimum speed p2161, where
the generator gives no more energy.  Braking for the link is no harder than the rapid-stop ramp
MD36610 [INF]; friction and the motor's losses are not modelled (all kinetic energy reaches the link).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from enum import Enum

from interfaces.signal_groups import DriveEsrStatus
from vc.config.model import EXTENDED_RETRACT, EXTENDED_STOP, GENERATOR_OPERATION, SPEED_HYSTERESIS
from vc.core.axis.axis import MachineAxis
from vc.core.axis.drive_messages import motor_speed
from vc.core.axis.motion import ramp
from vc.core.axis.owner import Owner
from vc.core.interface_map import SignalTable
from vc.core.program.commands import DriveEsrCommand
from vc.core.state_machine import Instance, StateMachine, states, transitions

TRIGGER_CYCLES = 2  # $AN_ESR_TRIGGER must stand this many IPO cycles to reach the drive (L41806-41809)
STAT_REACTION = 1 << 2  # $AA_ESR_STAT bit 2 = r0887.12 = DB31.DBX95.2
STAT_DC_LINK_UNDERVOLTAGE = 1 << 3  # bit 3 = r0056.15 = DB31.DBX95.1 (L41837-41870)
STAT_BELOW_MINIMUM_SPEED = 1 << 4  # bit 4 = r2199.0 = DB31.DBX95.3
REACTIONS = (EXTENDED_STOP, EXTENDED_RETRACT, GENERATOR_OPERATION)


class DriveEsrReaction(Enum):
    ARMED = "armed"
    REACTING = "reacting"
    DONE = "done"


DRIVE_ESR_STATES: StateMachine[DriveEsr] = StateMachine(
    __name__, "esr.drive", "Drive-autonomous ESR of an axis (DB31.DBX95.2)", Instance.AXIS,
    states(*DriveEsrReaction),
    transitions(("ARMED", "REACTING", "$AN_ESR_TRIGGER with $AA_ESR_ENABLE = 1"),
                ("REACTING", "DONE", "the reaction ended"),
                ("DONE", "ARMED", "$AA_ESR_ENABLE 1 -> 0 -> 1 (acknowledged)")),
    read=lambda drive: drive.reaction)


class DriveEsr:
    """The drive-autonomous ESR of one axis: its drive parameters, enable, reaction and feedback."""

    def __init__(self, axis: MachineAxis, table: SignalTable, area: bytearray, dt: float,
                 parameter_set: Callable[[], int] = lambda: 0):
        self.axis = axis
        self._parameter_set = parameter_set  # the active gear stage's parameter set (a spindle's gear)
        self._encode = table.codec(DriveEsrStatus).encode
        self._area = area
        self._dt = dt
        self.p0888 = 0  # configuration: 0 = none
        self.p0891 = 0  # braking ramp: OFF3
        self.p0892 = 0.0  # s
        self.p0893 = 0.0  # retract speed, motor rev/min (signed)
        self.retract_velocity = 0.0  # the same on the load side, per second (mm/s, deg/s)
        self.enabled = False  # $AA_ESR_ENABLE
        self._acknowledge_pending = False
        self.reaction: DriveEsrReaction = DriveEsrReaction.ARMED
        self._triggered = False  # r0887.12: reaction triggered (until acknowledged)
        self._elapsed = 0
        self._hold_velocity = 0.0  # stop: the speed setpoint of the trigger moment
        drive = axis.config.drive
        self.threshold = drive.p1248  # V: the Vdc_min controller's setpoint
        self._inertia = drive.p0341 * drive.p0342  # kg m^2 at the motor, load included
        self._minimum_speed = drive.p2161  # rev/min
        self._vdc_min_active = False  # r0056.15
        self._below_minimum_speed = False  # r2199.0
        self._watched_velocity: float | None = None
        self.watches_speed = drive.p2161 > 0.0  # r2199.0 is worth a look each cycle
        if drive.generator:
            self.p0888, self.p0892 = GENERATOR_OPERATION, drive.p0892

    # ------------------------------------------------------------------ configuration (ESRS / ESRR)
    def configure(self, command: DriveEsrCommand) -> None:
        self.p0888 = command.configuration
        self.p0892 = command.delay
        self.retract_velocity = command.velocity / 60.0
        self.p0893 = self._motor_speed(command.velocity)

    def _motor_speed(self, load_velocity_per_minute: float) -> float:
        """Load-side velocity (mm/min or deg/min) -> motor rev/min with the axis's gear ratio of the
        active gear stage (MD31050 / MD31060 load / motor revolutions, "the current total gear ratio",
        L41971-41975; MD31030 leadscrew pitch) [control]."""
        return motor_speed(self.axis.config, load_velocity_per_minute, self._parameter_set())

    # ------------------------------------------------------------------ $AA_ESR_ENABLE
    def set_enable(self, enabled: bool) -> None:
        """1 -> 0 acknowledges a triggered reaction (at once, or when it ends); 0 -> 1 arms again."""
        if self.enabled and not enabled and self.triggered:
            if self.reaction is DriveEsrReaction.DONE:
                self.triggered = False
                self.reaction = DriveEsrReaction.ARMED
            else:
                self._acknowledge_pending = True
        self.enabled = enabled

    @property
    def triggered(self) -> bool:
        return self._triggered

    @triggered.setter
    def triggered(self, value: bool) -> None:
        # DB31.DBX95.2 follows r0887.12 where it changes, not every IPO cycle
        self._triggered = value
        self._write_status()

    @property
    def reacting(self) -> bool:
        return self.reaction is DriveEsrReaction.REACTING

    @property
    def status(self) -> int:
        """$AA_ESR_STAT: bit 2 reaction triggered, bit 3 DC-link undervoltage, bit 4 below p2161."""
        return ((STAT_REACTION if self.triggered else 0)
                | (STAT_DC_LINK_UNDERVOLTAGE if self._vdc_min_active else 0)
                | (STAT_BELOW_MINIMUM_SPEED if self._below_minimum_speed else 0))

    # ------------------------------------------------------------------ generator operation
    @property
    def buffering(self) -> bool:
        """The generator reaction runs: the Vdc_min controller may brake the motor for the link."""
        return self.reaction is DriveEsrReaction.REACTING and self.p0888 == GENERATOR_OPERATION \
            and self.axis.owner is Owner.RETRACT

    def feed(self, energy: float) -> float:
        """The Vdc_min controller: brake the motor so that the link gets ``energy`` (J), down to
        the minimum speed p2161 and no harder than the rapid-stop ramp; returns the energy given."""
        self._set_vdc_min_active(energy > 0.0)
        if energy <= 0.0:
            return 0.0
        axis, inertia = self.axis, self._inertia
        radians_per_unit = abs(self._motor_speed(60.0)) * 2.0 * math.pi / 60.0  # motor rad/s per load unit/s
        velocity = axis.command_velocity
        omega = abs(velocity) * radians_per_unit
        slowest = max(0.0, (self._minimum_speed - SPEED_HYSTERESIS) * 2.0 * math.pi / 60.0,
                      omega - axis.dyn.rapid_stop_decel * self._dt * radians_per_unit)  # never through standstill
        if omega <= slowest:
            return 0.0
        given = min(energy, 0.5 * inertia * (omega * omega - slowest * slowest))
        new_velocity = math.copysign(math.sqrt(omega * omega - 2.0 * given / inertia) / radians_per_unit, velocity)
        axis.set_path_setpoint(axis.setpoint + (new_velocity - velocity) * self._dt, new_velocity)
        return given

    def watch_speed(self) -> None:
        """r2199.0 = |n_act| < p2161, the drive's comparison of its actual speed, reported as
        DB31.DBX95.3 while ESR is enabled for the drive: the seed names the bit "ESR, generator
        operation: below the minimum speed" (L41862-41872) [INF]."""
        velocity = self.axis.velocity if self.enabled else None
        if velocity == self._watched_velocity:
            return  # most cycles: the motor stands or runs at its speed
        self._watched_velocity = velocity
        below = velocity is not None and abs(self._motor_speed(velocity * 60.0)) < self._minimum_speed
        if below != self._below_minimum_speed:
            self._below_minimum_speed = below
            self._write_status()

    def _set_vdc_min_active(self, active: bool) -> None:
        if active != self._vdc_min_active:
            self._vdc_min_active = active
            self._write_status()

    def _write_status(self) -> None:
        self._encode(self._area, DriveEsrStatus(response_initiated=self._triggered,
                                                dc_link_undervoltage=self._vdc_min_active,
                                                below_minimum_speed=self._below_minimum_speed,
                                                autonomous_motion=self.reaction is DriveEsrReaction.REACTING))

    # ------------------------------------------------------------------ IPO cycle
    def cycle(self, trigger_cycles: int) -> None:
        """``trigger_cycles``: for how many cycles $AN_ESR_TRIGGER has stood at 1."""
        if self.reaction is DriveEsrReaction.ARMED and not self.triggered and self.enabled and self.p0888 in REACTIONS \
                and trigger_cycles >= TRIGGER_CYCLES:
            self._start()
        if self.reaction is DriveEsrReaction.REACTING:
            self._react()

    def _start(self) -> None:
        axis = self.axis
        self.reaction = DriveEsrReaction.REACTING
        self.triggered = True
        self._elapsed = 0
        self._hold_velocity = axis.command_velocity
        axis.take(Owner.RETRACT)

    def _react(self) -> None:
        axis, dyn, dt = self.axis, self.axis.dyn, self._dt
        self._elapsed += 1
        within_delay = self._elapsed * dt <= self.p0892 + 1e-9
        if axis.owner is not Owner.RETRACT:
            within_delay = False  # the NC braked it meanwhile (rapid stop): the reaction has ended
        if self.p0888 == EXTENDED_STOP:
            target = self._hold_velocity if within_delay else 0.0
        elif self.p0888 == GENERATOR_OPERATION:
            target = axis.command_velocity if within_delay else 0.0  # as the Vdc_min controller left it
        else:
            target = self.retract_velocity if within_delay else 0.0
        velocity = ramp(axis.command_velocity, target, dyn.rapid_stop_decel, dt)
        if axis.owner is Owner.RETRACT:
            axis.set_path_setpoint(axis.setpoint + velocity * dt, velocity)
        if not within_delay and (velocity == 0.0 or axis.owner is not Owner.RETRACT):
            if axis.owner is Owner.RETRACT:
                axis.release()
            self.reaction = DriveEsrReaction.DONE
            self._write_status()  # DB31.DBX92.4: the drive's own motion has ended
            self._set_vdc_min_active(False)
            if self._acknowledge_pending:
                self._acknowledge_pending = False
                self.triggered = False
                self.reaction = DriveEsrReaction.ARMED
