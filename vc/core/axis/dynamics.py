"""The dynamics of a machine axis from its machine data, in internal units (seed 003 axes).

Internal units: mm, mm/s, mm/s^2 for linear axes; degrees, deg/s, deg/s^2 for rotary axes and
spindles.  Machine data come in the control's units (mm/min, rev/min, m/s^2): ``dynamics_of``
converts them once; ``jerk_filter_of`` builds the axial jerk filter the axis's data ask for.
``CoupledLoop`` is the position loop a synchronous spindle coupling sets in place of the axis's
own.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from vc.config import md_dictionary as MD
from vc.config.machine_data import MachineData
from vc.config.model import AxisConfig
from vc.core.axis.motion import JerkFilter


@dataclass(frozen=True, slots=True)
class AxisDynamics:
    """Limits and loop parameters in internal units (per second)."""

    max_velocity: float
    max_accel: float
    max_jerk: float  # MD32431: the retract motion's jerk limit (vc/core/retraction/retract_motion.py)
    jog_velocity: float
    jog_rapid_velocity: float
    drf_velocity: float  # the DRF offset's handwheel velocity: JOG velocity x MD32090
    rapid_stop_decel: float
    kv: float
    feedforward: float  # 0 = off, else weighting factor
    drive_time_constant: float
    dyn_match_time: float  # MD32910 where MD32900 enables it: the setpoint's extra delay
    coarse_window: float
    fine_window: float
    standstill_velocity: float
    positioning_time: float
    standstill_tolerance: float
    standstill_delay: float
    clamp_tolerance: float  # MD36050: the clamping monitor's tolerance while DB31.DBX2.3 is set
    servo_disable_delay: float
    limit_minus: float
    limit_plus: float
    limit_minus_2: float  # MD36120 / MD36130: the 2nd software limit switches, chosen by DB31.DBX12.2 / 12.3
    limit_plus_2: float
    brake_rapid_at_limit_switch: bool
    display_velocity_factor: float  # internal per second -> mm/min or rev/min
    # MD12202 / MD12204: the fixed feedrates 1-4 per second (0: not set), given at power-on (fixed_feeds_of)
    fixed_feeds: tuple[float, ...] = ()


def dynamics_of(axis: AxisConfig) -> AxisDynamics:
    md = axis.md
    if axis.is_rotary:
        velocity_unit = 6.0  # rev/min -> deg/s
        accel_unit = 360.0  # rev/s^2 -> deg/s^2
    else:
        velocity_unit = 1.0 / 60.0  # mm/min -> mm/s
        accel_unit = 1000.0  # m/s^2 -> mm/s^2
    max_velocity = md.float(MD.MAX_AX_VELO) * velocity_unit
    emergency_time = md.float(MD.AX_EMERGENCY_STOP_TIME)
    max_accel = md.float(MD.MAX_AX_ACCEL, 0) * accel_unit
    return AxisDynamics(
        max_velocity=max_velocity,
        max_accel=max_accel,
        max_jerk=md.float(MD.MAX_AX_JERK, 0) * accel_unit,  # m/s^3 -> mm/s^3, rev/s^3 -> deg/s^3
        jog_velocity=min(md.float(MD.JOG_VELO) * velocity_unit, max_velocity),
        jog_rapid_velocity=min(md.float(MD.JOG_VELO_RAPID) * velocity_unit, max_velocity),
        drf_velocity=min(md.float(MD.JOG_VELO) * velocity_unit, max_velocity) * md.float(MD.HANDWH_VELO_OVERLAY_FACTOR),
        # MD36610: the rapid-stop ramp takes the axis from MAX_AX_VELO to standstill in this time
        rapid_stop_decel=max_velocity / emergency_time if emergency_time > 0 else math.inf,
        kv=md.float(MD.POSCTRL_GAIN, 0),
        feedforward=md.float(MD.VELO_FFW_WEIGHT, 0) if md.int(MD.FFW_MODE) else 0.0,
        drive_time_constant=md.float(MD.EQUIV_SPEEDCTRL_TIME, 0),
        dyn_match_time=md.float(MD.DYN_MATCH_TIME, 0) if md.bool(MD.DYN_MATCH_ENABLE) else 0.0,
        coarse_window=md.float(MD.STOP_LIMIT_COARSE),
        fine_window=md.float(MD.STOP_LIMIT_FINE),
        standstill_velocity=md.float(MD.STANDSTILL_VELO_TOL) * velocity_unit,
        positioning_time=md.float(MD.POSITIONING_TIME),
        standstill_tolerance=md.float(MD.STANDSTILL_POS_TOL),
        standstill_delay=md.float(MD.STANDSTILL_DELAY_TIME),
        clamp_tolerance=md.float(MD.CLAMP_POS_TOL),
        servo_disable_delay=md.float(MD.SERVO_DISABLE_DELAY_TIME),
        limit_minus=md.float(MD.POS_LIMIT_MINUS),
        limit_plus=md.float(MD.POS_LIMIT_PLUS),
        limit_minus_2=md.float(MD.POS_LIMIT_MINUS2),
        limit_plus_2=md.float(MD.POS_LIMIT_PLUS2),
        brake_rapid_at_limit_switch=md.int(MD.BRAKE_MODE_CHOICE) == 1,
        display_velocity_factor=1.0 / velocity_unit,
    )


def jerk_filter_of(axis: AxisConfig, dyn: AxisDynamics, dt: float, start: float) -> JerkFilter | None:
    """The axial jerk filter (MD32400 .. MD32410) with the delay of dynamic-response matching
    (MD32910), starting at ``start``; None where neither is enabled."""
    md = axis.md
    jerk = md.bool(MD.AX_JERK_ENABLE)
    if not (jerk or dyn.dyn_match_time):
        return None
    jerk_time = md.float(MD.AX_JERK_TIME) if jerk else 0.0
    return JerkFilter(md.int(MD.AX_JERK_MODE), jerk_time, dt, start, dyn.dyn_match_time)


@dataclass(frozen=True, slots=True)
class CoupledLoop:
    """The position loop a synchronous spindle coupling sets on a spindle in place of its own
    (vc/core/spindle/coupling.py, L22997-23006, L23756-23775): Kv, feedforward weight (0 = off) and the
    equivalent speed-control time MD32810 the feedforward's symmetrising models.  The drive itself
    keeps its own lag: MD32810 only tells the control how fast the drive is."""

    kv: float
    feedforward: float
    symmetrising_time: float


def fixed_feeds_of(nck: MachineData, axis: AxisConfig) -> tuple[float, ...]:
    """MD12202 (linear axes, mm/min) or MD12204 (rotary axes, rev/min) per second, within MD32000."""
    unit = 6.0 if axis.is_rotary else 1.0 / 60.0
    top = axis.md.float(MD.MAX_AX_VELO) * unit
    values = nck.floats(MD.PERMANENT_ROT_AX_FEED if axis.is_rotary else MD.PERMANENT_FEED)
    return tuple(min(value * unit, top) for value in values)


def fixed_feed(feeds: tuple[float, ...], selection: int) -> float:
    """The fixed feedrate the selection bits name (the lowest set bit, bit 0 = value 1), 0.0 for none."""
    if not selection:
        return 0.0
    index = (selection & -selection).bit_length() - 1
    return feeds[index] if index < len(feeds) else 0.0
