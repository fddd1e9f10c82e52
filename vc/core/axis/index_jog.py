"""JOG of an indexing axis to its index positions (seed 003 §11.2.2, L13405-13490).

Once the axis's active measuring system is referenced (L13405-13407; before that it jogs as any
axis, ``vc/core/axis/jog.py``) JOG stops it on an index position (``vc/core/axis/indexing.py``):

* continuous JOG, the traverse key held (jog mode, SD41050 = 1, "the usual mode", L13420-13448): the
  axis runs while the key is held; released, it runs on to the nearest index position ahead at
  which it can stop (its distance, the speed and the axis's dynamics decide which, L13424-13430);
* a change of direction before it arrives: it still goes to that position, and the other key must be
  pressed again (L13450-13454);
* incremental JOG (an INC machine function selected, whichever, L13463-13473): a key pressed takes
  the axis to the next index position in its direction; released on the way, the axis stops at
  once, between two positions, and a new press takes it on to that position;
* the software limit switches: it goes at most to the last index position before them (L13993-13997).

The latched mode of SD41050 = 0 (a second press stops it) is not built: the traverse keys of this
NC are level-triggered.  The handwheel moves an indexing axis as any axis (L13999-14002).

A Hirth axis (MD30505, §11.5 L14030-14060) never stops between two positions: INC JOG released on
the way, the feed stop, the channel's feed disable and JOG left run it on to the index position ahead
(continuous JOG runs out to the next one it can stop on) at the speed it has; the handwheel does not
move it (L14070-14080, ``MachineAxis.add_handwheel_travel``).

States::

    IDLE ──key, continuous──▶ CONTINUOUS ──key released (or the other key)──▶ TO_INDEX_POSITION
    IDLE ──key, INC──▶ TO_INDEX_POSITION ──INC: key released (stops at once)──▶ IDLE
    CONTINUOUS ──at the last index position before a software limit switch──▶ ARRIVED
    TO_INDEX_POSITION ──on the index position──▶ ARRIVED ──keys released──▶ IDLE
    TO_INDEX_POSITION ──the same key again (continuous)──▶ CONTINUOUS
    CONTINUOUS, TO_INDEX_POSITION ──JOG no longer allowed: braked where it is──▶ IDLE
    CONTINUOUS, TO_INDEX_POSITION ──another owner took the axis (e-stop, an alarm)──▶ IDLE
"""

from __future__ import annotations

from enum import Enum

from vc.core.axis.indexing import IndexPositions
from vc.core.axis.jog import JoggedAxis, JogLimits
from vc.core.axis.motion import ramp, stopping_velocity
from vc.core.axis.owner import Owner
from vc.core.state_machine import Instance, StateMachine, states, transitions

_TINY = 1e-9


class IndexJogState(Enum):
    IDLE = "no JOG motion of the indexing axis"
    CONTINUOUS = "the traverse key held: the axis runs"
    TO_INDEX_POSITION = "on its way to an index position, braking to stop on it"
    ARRIVED = "on the index position, the key still held"


class IndexJog:
    """JOG of one indexing axis (see the module docstring)."""

    def __init__(self, index: IndexPositions, dt: float):
        self.index = index
        self._dt = dt
        self.state = IndexJogState.IDLE
        self.direction = 0  # the direction of the key that started the motion
        self.target: float | None = None  # TO_INDEX_POSITION: the index position it stops on

    @property
    def busy(self) -> bool:
        """Its cycle must run in JOG even with no key pressed (it runs out or waits for a release)."""
        return self.state is not IndexJogState.IDLE

    def cycle(self, axis: JoggedAxis, allowed: bool, channel_feed_disable: bool, limits: JogLimits,
              step: bool) -> None:
        """One IPO cycle of JOG; ``step``: an INC machine function is selected."""
        inp = axis.inputs
        direction = (1 if inp.key_plus else -1) if allowed and inp.key_plus != inp.key_minus else 0
        if direction and ((direction > 0 and (not limits.plus or inp.hw_limit_plus))
                          or (direction < 0 and (not limits.minus or inp.hw_limit_minus))):
            direction = 0  # only away from an actuated limit switch
        state = self.state
        if state is not IndexJogState.IDLE and axis.owner not in (Owner.JOG, Owner.NONE):
            self.state, self.target = IndexJogState.IDLE, None  # an e-stop or an alarm took the axis
            return
        hirth = self.index.hirth
        stop = not allowed or axis.inputs.feed_stop or channel_feed_disable
        if hirth and state is IndexJogState.CONTINUOUS and stop and axis.owner is Owner.JOG:
            self._run_out(axis, limits)  # a Hirth axis: on to the next index position
            state = self.state
        elif state is not IndexJogState.IDLE and not allowed and not hirth:
            # JOG left (another mode, the channel's alarm): it brakes where it is [INF]
            state = self.state = IndexJogState.TO_INDEX_POSITION if axis.owner is Owner.JOG else IndexJogState.IDLE
            self.target = None
        if state is IndexJogState.IDLE:
            self._start(axis, direction, step)
        elif state is IndexJogState.ARRIVED:
            if not direction:
                self.state = IndexJogState.IDLE  # a new motion needs a new press (L13454, L13465)
        elif state is IndexJogState.CONTINUOUS and direction != self.direction:
            self._run_out(axis, limits)
        elif state is IndexJogState.TO_INDEX_POSITION:
            if step and direction != self.direction and not hirth:
                self.target = None  # INC released: stops at once (L13469-13473)
            elif not step and direction == self.direction and not (hirth and stop):
                self.state, self.target = IndexJogState.CONTINUOUS, None
        if self.state is not IndexJogState.IDLE and axis.owner is Owner.JOG:
            self._move(axis, channel_feed_disable, limits)

    def _start(self, axis: JoggedAxis, direction: int, step: bool) -> None:
        if not direction or axis.owner is not Owner.NONE or not axis.drive_ready:
            return
        self.direction = direction
        if step:
            self.target = self._reachable(axis, self.index.ahead(axis.setpoint, direction, axis.dyn.fine_window))
            if self.target is None:
                return
            self.state = IndexJogState.TO_INDEX_POSITION
        else:
            self.state, self.target = IndexJogState.CONTINUOUS, None
        axis.take(Owner.JOG)

    def _run_out(self, axis: JoggedAxis, limits: JogLimits) -> None:
        """The key released: the nearest index position ahead it can stop on (L13424-13430)."""
        velocity = axis.command_velocity
        way = (1 if velocity > 0.0 else -1) if velocity else self.direction
        accel = min(axis.dyn.max_accel, limits.accel)
        # its braking distance, and one cycle's travel more: the ramp brakes only from the next cycle on
        braking = velocity * velocity / (2.0 * accel) + abs(velocity) * self._dt if accel > 0.0 else 0.0
        self.target = self._reachable(axis, self.index.ahead(axis.setpoint, way, braking))
        self.state = IndexJogState.TO_INDEX_POSITION

    def _reachable(self, axis: JoggedAxis, target: float | None) -> float | None:
        """``target`` if JOG may go there: not beyond the software limit switches (L13993-13997)."""
        if target is None or not axis.software_limits_active:
            return target
        minus, plus = axis.software_limits
        return target if minus - _TINY <= target <= plus + _TINY else None

    def _edge(self, axis: JoggedAxis) -> float | None:
        """CONTINUOUS: the last index position before the software limit switch it runs towards."""
        if not axis.software_limits_active:
            return None
        minus, plus = axis.software_limits
        limit = plus if self.direction > 0 else minus
        return self.index.ahead(limit, -self.direction, 0.0)

    def _move(self, axis: JoggedAxis, channel_feed_disable: bool, limits: JogLimits) -> None:
        dyn, dt, inp = axis.dyn, self._dt, axis.inputs
        accel = min(dyn.max_accel, limits.accel)
        speed = min((dyn.jog_rapid_velocity if inp.rapid_key else dyn.jog_velocity) * axis.override, limits.velocity)
        running_out = self.state is IndexJogState.TO_INDEX_POSITION
        if self.index.hirth and running_out and self.target is not None:
            speed = max(speed, abs(axis.command_velocity))  # whatever holds it: on to the position
            if not axis.drive_ready:
                speed = 0.0
        elif inp.feed_stop or channel_feed_disable or not axis.drive_ready:
            speed = 0.0
        goal = self.target if running_out else self._edge(axis)
        way = 1.0 if goal is None or goal > axis.setpoint else -1.0
        if goal is not None and not running_out and (goal - axis.setpoint) * self.direction <= _TINY:
            self._arrive(axis, None)  # on (or past) the last index position before the software limit
            return
        if goal is None:
            wanted = 0.0 if running_out else self.direction * speed  # nothing to stop on, or INC released
        else:
            wanted = way * min(speed, stopping_velocity(abs(goal - axis.setpoint), accel, dt))
        velocity = ramp(axis.command_velocity, wanted, accel, dt)
        axis.command_velocity = velocity
        axis.setpoint += velocity * dt
        if goal is not None and (goal - axis.setpoint) * way <= _TINY:
            self._arrive(axis, goal)
        elif goal is None and running_out and velocity == 0.0:
            axis.release()
            self.state, self.target = IndexJogState.IDLE, None

    def _arrive(self, axis: JoggedAxis, position: float | None) -> None:
        if position is not None:
            axis.setpoint = position  # lands exactly on the index position
        axis.release()
        self.state, self.target = IndexJogState.ARRIVED, None


INDEX_JOG_STATES: StateMachine[IndexJog] = StateMachine(
    __name__, "index_jog", "JOG of an indexing axis to its index positions (seed 003 §11.2.2)",
    Instance.AXIS, states(*IndexJogState),
    transitions(("IDLE", "CONTINUOUS", "a traverse key, continuous JOG"),
                ("IDLE", "TO_INDEX_POSITION", "a traverse key, INC selected: the next index position"),
                ("CONTINUOUS", "TO_INDEX_POSITION", "the key released or the other key: the nearest one it can stop"
                 " on; JOG left: it brakes"),
                ("CONTINUOUS", "ARRIVED", "at the last index position before a software limit switch"),
                ("TO_INDEX_POSITION", "ARRIVED", "on the index position"),
                ("TO_INDEX_POSITION", "CONTINUOUS", "the same key again (continuous JOG)"),
                ("TO_INDEX_POSITION", "IDLE", "INC: the key released, stopped at once; JOG left (braked), another"
                 " owner took the axis"),
                ("ARRIVED", "IDLE", "the keys released; JOG left"),
                ("CONTINUOUS", "IDLE", "another owner took the axis")),
    read=lambda jog: jog.state)
