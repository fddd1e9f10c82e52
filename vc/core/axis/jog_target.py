"""JOG to a fixed point and JOG to a position of one machine axis (seed 003 §16.9 L34236-34607,
§16.10 L34607-34880).

In JOG the PLC selects a fixed point by its number (DB31.DBX13.0..13.2, binary, 1..MD30610 of the
positions MD30600[0..3]) or "JOG to position" (DB31.DBX13.3, the position SD43320); a fixed point
selected wins (L34667).  The NC acknowledges the selection (DB31.DBX75.0..75.2 / 75.6) and from then
on the traverse keys and the handwheel move the axis only towards the target, continuously or by
increments, and it stops exactly on it (L34310-34312, L34672-34674); an increment that reaches it
first is done (L34376-34378, L34732-34734).  Away from the target only with MD10735 bit 2
(L34426-34432); the key pressed the other way does nothing [control: the channel's message "JOG:
direction locked" is not built].  The target is a position of the machine coordinate system
(frames are ignored, L34523-34525).  The axis must be referenced: a key pressed without it raises
alarm 17810 and nothing moves (L34270, L34392-34394).  Another fixed point selected while the axis
travels to one ends the motion with alarm 17812 (L34338-34342); a new press travels on.

Reached: the axis stands within the exact stop window MD36010 on a fixed point (DB31.DBX75.3..75.5,
whatever brought it there, L34314-34320 and the example's initial state L34568-34572) or on the
position of JOG to position while it is active (DB31.DBX75.7, L34676-34678).  JOG left, or an
emergency stop, withdraws the selection [control: the seed says it can be activated only in JOG and
not during an emergency stop, L34266, L34300-34304; the harness drops it there too].

States::

    OFF ──a fixed point / JOG to position selected in JOG──▶ TOWARDS ──the axis on the target──▶ REACHED
    REACHED ──the axis left the target (moved away with MD10735 bit 2, or by another motion)──▶ TOWARDS
    TOWARDS, REACHED ──another target selected──▶ TOWARDS / REACHED (a motion to the old one ends: 17812)
    TOWARDS, REACHED ──the selection withdrawn, JOG left, emergency stop──▶ OFF
"""

from __future__ import annotations

from enum import Enum

from vc.core.axis.jog import FREE_JOG, JogLimits
from vc.core.state_machine import Instance, StateMachine, states, transitions

_TINY = 1e-9
REVERSE_ALLOWED = 1 << 2  # MD10735 JOG_MODE_MASK bit 2: away from the target too (L34426-34432)
_NOWHERE = JogLimits(plus=False, minus=False)  # not referenced: JOG to a target does not travel


class JogTargetState(Enum):
    OFF = "no fixed point and no JOG to position active"
    TOWARDS = "JOG to a fixed point / to a position active: the keys and the handwheel travel towards it"
    REACHED = "the axis stands on the target selected (exact stop fine): it travels no further towards it"


class JogTarget:
    """JOG to a fixed point or to a position of one axis (see the module docstring)."""

    def __init__(self, fixed_points: tuple[float, ...], jog_position: float, fine_window: float,
                 reverse_allowed: bool):
        self.fixed_points = fixed_points  # MD30600[0 .. MD30610 - 1]
        self.jog_position = jog_position  # SD43320
        self.fine_window = fine_window  # MD36010
        self.reverse_allowed = reverse_allowed
        self.state = JogTargetState.OFF
        self.fixed_point = 0  # the fixed point active (1..4), 0 none
        self.to_position = False  # JOG to position active
        self.target: float | None = None  # the position travelled to, None when OFF

    def select(self, fixed_point: int, to_position: bool, may_activate: bool) -> bool:
        """The PLC's selection this cycle (``may_activate``: in JOG, no emergency stop).  A fixed
        point beyond MD30610 is not taken [control: the seed names no alarm for it].  Returns True
        when the fixed point changed from one to another (alarm 17812 if the axis travels)."""
        if not may_activate or fixed_point > len(self.fixed_points):
            fixed_point = 0
        to_position = may_activate and to_position and not fixed_point  # a fixed point wins (L34667)
        changed = bool(fixed_point and self.fixed_point and fixed_point != self.fixed_point)
        self.fixed_point, self.to_position = fixed_point, to_position
        if fixed_point:
            self.target = self.fixed_points[fixed_point - 1]
        elif to_position:
            self.target = self.jog_position
        else:
            self.target = None
            self.state = JogTargetState.OFF
        return changed

    def follow(self, actual: float, referenced: bool) -> None:
        """TOWARDS / REACHED from the actual position (exact stop fine window MD36010)."""
        target = self.target
        if target is None:
            return
        on_target = referenced and abs(actual - target) <= self.fine_window
        self.state = JogTargetState.REACHED if on_target else JogTargetState.TOWARDS

    def fixed_point_at(self, actual: float, referenced: bool) -> int:
        """The fixed point (1..4) the axis stands on within MD36010, 0 none (DB31.DBX75.3..75.5)."""
        if referenced:
            window = self.fine_window
            for number, position in enumerate(self.fixed_points, 1):
                if abs(actual - position) <= window:
                    return number
        return 0

    @property
    def position_reached(self) -> bool:
        """DB31.DBX75.7: JOG to position active and the axis on SD43320."""
        return self.to_position and self.state is JogTargetState.REACHED

    def jog_limits(self, setpoint: float, referenced: bool) -> JogLimits:
        """Where JOG may take the axis this cycle: towards the target and no further (away from it only
        with MD10735 bit 2); nowhere without the reference point; free with no target."""
        target = self.target
        if target is None:
            return FREE_JOG
        if not referenced:
            return _NOWHERE
        reverse = self.reverse_allowed
        return JogLimits(plus=reverse or target > setpoint + _TINY, minus=reverse or target < setpoint - _TINY,
                         target=target)


JOG_TARGET_STATES: StateMachine[JogTarget] = StateMachine(
    __name__, "jog_target", "JOG to a fixed point and JOG to a position (seed 003 §16.9, §16.10)",
    Instance.AXIS, states(*JogTargetState),
    transitions(("OFF", "TOWARDS", "a fixed point (DB31.DBX13.0..13.2) or JOG to position (DB31.DBX13.3)"
                 " selected in JOG"),
                ("OFF", "REACHED", "selected while the axis stands on the target"),
                ("TOWARDS", "REACHED", "the axis on the target (exact stop fine MD36010)"),
                ("REACHED", "TOWARDS", "the axis left the target, or another target selected"),
                ("TOWARDS", "OFF", "the selection withdrawn, JOG left, emergency stop"),
                ("REACHED", "OFF", "the selection withdrawn, JOG left, emergency stop")),
    read=lambda target: target.state)
