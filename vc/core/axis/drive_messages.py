"""The drive's messages to the PLC: DB31.DBX94.0-94.6 and 95.0 (seed 003 §18.2, L38355-38371).

The seed prints the signals without saying when the drive gives them; the real drive (SINAMICS
with the 840D sl) derives them from its speed, torque, temperature and DC-link voltage against
thresholds of its own parameters, which the machine file gives under the axis's ``drive:``
(vc/config/model.py ``DriveParameters``) [control]::

    DBX94.0 motor temperature pre-warning   temperature > p0604 (the plant's motor temperature)
    DBX94.2 ramp-up completed               the speed setpoint stands and n act came within p2163 of
                                            it; a ramp of the setpoint takes it away again
    DBX94.3 |Md| < Mdx                      torque < p2174; falls once the torque stood >= p2174
                                            for p2176 ms, comes back at once
    DBX94.4 |n act| < n min                 motor speed < p2161 (5 rev/min while p2161 is 0)
    DBX94.5 |n act| < n x                   motor speed < p2155
    DBX94.6 n act = n set                   |n act - n set| <= p2163
    DBX95.0 Vdc < warning threshold         DC-link voltage < p2172 (a machine with a DC link)

Speeds are the motor's, in rev/min: the axis's velocity through the gear of its active parameter
set (MD31050 / MD31060) and the leadscrew pitch MD31030 (``motor_speed``).  The torque is the
drive's in percent of its maximum: blocked by a fixed stop it is the torque limit (FXST, or 100 %
without one); otherwise the acceleration's, 50 % at MD32300 [INF: the harness has no load or
friction model; a drive is commissioned with about half its torque for the axis's acceleration].

Cost: the axis evaluates the messages in its control cycle only, which it skips while it rests;
at rest every message stands where the last cycle left it, the temperature and the DC link write
their bit when they change.  An axis whose drive reports no messages (``messages: 0``, the
default of the packaged machines) has no ``DriveMessages`` at all [INF].
"""

from __future__ import annotations

from collections.abc import Callable

from interfaces.signal_groups import DriveMessageStatus
from vc.config import md_dictionary as MD
from vc.config.model import AxisConfig
from vc.core.interface_map import SignalTable

ACCELERATION_TORQUE = 50.0  # percent of the drive's maximum torque that MD32300's acceleration takes [INF]
FACTORY_MINIMUM_SPEED = 5.0  # rev/min: SINAMICS p2161's factory setting, taken while p2161 is 0 [control]
AMBIENT_TEMPERATURE = 40.0  # degC: the motor's temperature until a scenario sets another [INF]


def motor_speed(config: AxisConfig, load_velocity_per_minute: float, stage: int) -> float:
    """Load-side velocity (mm/min or deg/min) -> motor rev/min with the axis's gear ratio of the
    parameter set ``stage`` (MD31050 / MD31060 load / motor revolutions, "the current total gear
    ratio", seed 003 L41971-41975; MD31030 leadscrew pitch) [control]."""
    md = config.md
    ratio = md.int(MD.DRIVE_AX_RATIO_NUMERA, stage) / md.int(MD.DRIVE_AX_RATIO_DENOM, stage)
    if config.is_rotary:
        return load_velocity_per_minute / 360.0 * ratio
    return load_velocity_per_minute / md.float(MD.LEADSCREW_PITCH) * ratio


class DriveMessages:
    """The messages of one axis's drive, and their thresholds."""

    def __init__(self, config: AxisConfig, table: SignalTable, area: bytearray, dt: float,
                 parameter_set: Callable[[], int] = lambda: 0):
        self.config = config
        self._encode = table.codec(DriveMessageStatus).encode
        self._area = area
        self._dt = dt
        self._parameter_set = parameter_set  # a spindle's gear stage selects its gear ratio
        drive = config.drive
        self.temperature_limit = drive.p0604
        self.minimum_speed = drive.p2161 if drive.p2161 > 0.0 else FACTORY_MINIMUM_SPEED
        self.threshold_speed = drive.p2155
        self.speed_tolerance = drive.p2163
        self.link_threshold = drive.p2172
        self.torque_threshold = drive.p2174
        self._torque_delay = max(1, round(drive.p2176 / 1000.0 / dt))  # cycles
        self._max_accel = 0.0  # set by the axis (its dynamics in load units/s^2)
        self.temperature = AMBIENT_TEMPERATURE
        self.link_voltage: float | None = None  # None: no DC link model, the link stands at its nominal voltage
        self.torque = 0.0  # percent of the maximum
        self.speed = 0.0  # n act, motor rev/min (signed)
        self.speed_setpoint = 0.0  # n set, motor rev/min (signed)
        self._previous_setpoint = 0.0
        self._ramp_up_complete = True
        self._torque_cycles = 0  # cycles the torque has stood at or above the threshold
        self._written: tuple[bool, ...] = ()

    def set_max_accel(self, max_accel: float) -> None:
        self._max_accel = max_accel

    # ------------------------------------------------------------------ the plant's side
    def set_temperature(self, celsius: float) -> None:
        """The motor's temperature (the plant's sensor; a scenario's ``motor_temperature`` fault)."""
        self.temperature = celsius
        self._write()

    def set_link_voltage(self, volts: float) -> None:
        """The DC link's voltage (a machine with ``dc_link:``, while it is off its supply or charging)."""
        self.link_voltage = volts
        self._write()

    # ------------------------------------------------------------------ IPO cycle
    def update(self, velocity: float, velocity_setpoint: float, acceleration: float, servo_on: bool,
               torque_limit: float | None, blocked: bool) -> None:
        """One control cycle of the axis: ``velocity`` / ``velocity_setpoint`` load units per second,
        ``acceleration`` of the drive per s^2; ``blocked``: the slide stands against a fixed stop."""
        stage = self._parameter_set()
        speed = motor_speed(self.config, velocity * 60.0, stage)
        setpoint = motor_speed(self.config, velocity_setpoint * 60.0, stage) if servo_on else 0.0
        limit = 100.0 if torque_limit is None else torque_limit
        if not servo_on:
            torque = 0.0
        elif blocked:
            torque = limit
        else:
            share = abs(acceleration) / self._max_accel if self._max_accel > 0.0 else 0.0
            torque = min(limit, ACCELERATION_TORQUE * share)
        tolerance = self.speed_tolerance
        steady = abs(setpoint - self._previous_setpoint) <= tolerance * self._dt  # the setpoint no longer ramps
        if not steady:
            self._ramp_up_complete = False
        elif abs(speed - setpoint) <= tolerance:
            self._ramp_up_complete = True
        self._previous_setpoint = setpoint
        self._torque_cycles = self._torque_cycles + 1 if torque >= self.torque_threshold else 0
        self.speed, self.speed_setpoint, self.torque = speed, setpoint, torque
        self._write()

    # ------------------------------------------------------------------ outputs
    def _write(self) -> None:
        speed = abs(self.speed)
        status = (self.temperature > self.temperature_limit, self._ramp_up_complete,
                  self._torque_cycles < self._torque_delay, speed < self.minimum_speed, speed < self.threshold_speed,
                  abs(self.speed - self.speed_setpoint) <= self.speed_tolerance,
                  self.link_voltage is not None and self.link_voltage < self.link_threshold)
        if status == self._written:
            return
        self._written = status
        temperature, ramp_up, torque_below, below_minimum, below_threshold, at_setpoint, link_low = status
        self._encode(self._area, DriveMessageStatus(
            motor_temperature_warning=temperature, ramp_up_complete=ramp_up, torque_below_threshold=torque_below,
            speed_below_minimum=below_minimum, speed_below_threshold=below_threshold, speed_at_setpoint=at_setpoint,
            dc_link_below_warning=link_low))

    def publish(self) -> None:
        """Power-on: the messages of the motor at rest."""
        self._write()
