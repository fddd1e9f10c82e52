"""Constant cutting speed G96 / G961 (seed 003 §7.2.2, L7654-7870): the master spindle's speed from
the programmed cutting speed and the radius of the transverse axis.

    OFF ──G96 / G961 S.. (a block without rapid motion)──▶ FOLLOWING
    OFF ──G96 / G961 S.. in a rapid block──▶ HELD
    FOLLOWING ──rapid block (G0)──▶ HELD ──machining block (G1, G2, G3 ...)──▶ FOLLOWING
    FOLLOWING, HELD ──G97 / G971 / G94 / G95, reset, program end──▶ OFF

FOLLOWING: every IPO cycle n = v / (2 pi r), v the cutting speed (m/min), r the distance of the
transverse axis (MD20100) from the turning centre, its position 0 (L7678-7712): the setpoint, without
DRF and overlays (L7700-7702, L7756).  n is limited by LIMS / SD43230 (L7773-7797) and the gear stage's
maximum, and raised to its minimum (MD35140, L7812-7818); the spindle's speed signals are not changed by
this internal setting (L7760-7761), so the limits are applied here, before the speed control sees the
value.  No gear stage changes (L7754).  The speed is the spindle's S at 100 % override: the spindle
override acts on it (L7755, L9026), and a reset with MD35040 = 1 keeps it (L16209-16211).

HELD: a rapid block (G96 acts where F acts, L7748-7749).  MD20750 ALLOW_G0_IN_G96 = 0: the speed stays
as it was; = 1: it is set for the rapid block's end point at its start, so the spindle reaches it while
the axes travel [control].  The next machining block follows again, and with MD35500 it starts only
once the spindle has reached the speed (L7758-7759).

G97 / G971 end it and keep the last speed (L7735-7738); DB31.DBX84.0 of the master spindle shows it
(L17412).  Observers see it as ``CUTTING_SPEED_STATES``.
"""

from __future__ import annotations

import math
from enum import Enum

from vc.config import md_dictionary as MD
from vc.config.model import ChannelConfig
from vc.core.axis.axis import MachineAxis
from vc.core.program.block_plan import BlockPlan
from vc.core.spindle.spindle import Spindle
from vc.core.state_machine import Instance, StateMachine, states, transitions


class CuttingSpeedState(Enum):
    OFF = "off"  # G94 / G95 / G97 / G971: the spindle turns at its S
    FOLLOWING = "following"  # G96 / G961 in a machining block: the speed follows the radius
    HELD = "held"  # G96 / G961 in a rapid block: the speed does not follow the axis


M_PER_MIN_TO_MM = 1000.0  # the cutting speed is programmed in m/min, the radius is in mm


class ConstantCuttingSpeed:
    """G96 / G961 of one channel (see the module docstring)."""

    def __init__(self, config: ChannelConfig, axes_by_name: dict[str, MachineAxis],
                 spindles: dict[str, Spindle]):
        self._config = config
        self._axes_by_name = axes_by_name
        self._spindles = spindles  # machine axis -> spindle, filled by the NCK
        self.state = CuttingSpeedState.OFF
        self.following = False  # state is FOLLOWING: the channel calls cycle() (nothing else costs a cycle)
        self.cutting_speed = 0.0  # m/min
        self._spindle: Spindle | None = None  # the master spindle it sets
        self._transverse: MachineAxis | None = None
        self._limits: dict[str, float] = {}  # LIMS by machine axis of the spindle, rev/min (SD43230 until then)

    def block(self, plan: BlockPlan, master: str | None) -> None:
        """A decoded block: its LIMS, and G96 / G961 as it selects, keeps or ends them."""
        for name, limit in plan.spindle_limits.items():
            self._limits[name] = limit  # into SD43230; kept after reset and program end (L7792-7829)
        if not plan.constant_cutting:
            if self.state is not CuttingSpeedState.OFF:
                self.end()  # G97 / G971 / G94 / G95: the last speed stays (L7735-7738)
            return
        spindle = self._spindles.get(master or "")
        transverse = self._axes_by_name.get(self._config.transverse_axis() or "")
        if spindle is None or transverse is None:
            self.end()  # no master spindle in this channel: nothing to set
            return
        if spindle is not self._spindle:
            self.end()  # another master spindle: the old one keeps its speed (L7835-7838)
            self._spindle = spindle
            spindle.show_constant_cutting_speed(True)
        self._transverse = transverse
        if plan.cutting_speed != self.cutting_speed or self.state is CuttingSpeedState.OFF:
            spindle.show_speed(plan.cutting_speed)  # DB31.DBD88: the S programmed, the cutting speed
        self.cutting_speed = plan.cutting_speed
        rapid = plan.rapid and bool(plan.targets)
        if rapid:
            self._set_state(CuttingSpeedState.HELD)
            end = plan.targets.get(transverse.name)
            if self._config.md.bool(MD.ALLOW_G0_IN_G96) and end is not None:
                self._set_speed(spindle, end)  # the G0 logic: the end point's speed from the start
        else:
            self._set_state(CuttingSpeedState.FOLLOWING)
            self.cycle()  # the speed of the start point before the block's interlocks are judged

    def cycle(self) -> None:
        """FOLLOWING: the master spindle's speed from the transverse axis's setpoint."""
        spindle, transverse = self._spindle, self._transverse
        assert spindle is not None and transverse is not None
        self._set_speed(spindle, transverse.setpoint)

    def _set_speed(self, spindle: Spindle, position: float) -> None:
        radius = abs(position)
        speed = self.cutting_speed * M_PER_MIN_TO_MM / (2.0 * math.pi * radius) if radius > 0.0 else math.inf
        limit = self._limits.get(spindle.name)
        if limit is None:
            limit = spindle.md.float(MD.SPIND_MAX_VELO_LIMS)
        control = spindle.speed_control
        maximum = control.max_speed(spindle.position_control)
        if limit > 0.0:
            maximum = min(maximum, limit)
        speed = max(min(speed, maximum), min(control.min_speed(), maximum))
        if speed != spindle.speed:
            spindle.speed = speed
            spindle.quiet = False

    def _set_state(self, state: CuttingSpeedState) -> None:
        self.state = state
        self.following = state is CuttingSpeedState.FOLLOWING

    def end(self) -> None:
        """G97 / G971, reset, program end: the spindle keeps the speed it has (L7735-7738, L16209-16211)."""
        self._set_state(CuttingSpeedState.OFF)
        if self._spindle is not None:
            self._spindle.show_constant_cutting_speed(False)
            self._spindle = None
        self.cutting_speed = 0.0


CUTTING_SPEED_STATES: StateMachine[ConstantCuttingSpeed] = StateMachine(
    __name__, "constant_cutting_speed", "Constant cutting speed G96 / G961 (DB31.DBX84.0)", Instance.CHANNEL,
    states(*CuttingSpeedState),
    transitions(("OFF", "FOLLOWING", "G96 / G961 S.."), ("OFF", "HELD", "G96 / G961 S.. in a rapid block"),
                ("FOLLOWING", "HELD", "rapid block (G0)"), ("HELD", "FOLLOWING", "machining block"),
                ("FOLLOWING", "OFF", "G97 / G971 / G94 / G95, reset, program end"),
                ("HELD", "OFF", "G97 / G971 / G94 / G95, reset, program end")),
    read=lambda cutting: cutting.state)
