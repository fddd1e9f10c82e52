"""What the traverse keys command in JOG: continuous or incremental, jog or continuous mode
(seed 003 §16.4 continuous JOG L32600-32800, §16.5 incremental JOG L32804-33101).

The PLC selects per machine axis the machine function of JOG (DB31.DBX5.0..5.6,
``vc/core/nck/jog_functions.py``): INC1 .. INC10000 or INCvar make the traverse keys travel an
increment (MD11330 / SD41010 x MD31090), "continuous" (or none) lets them traverse as long as
they command it.  Two data choose how the keys command, for every axis of the NC:

* continuous JOG, SD41050 JOG_CONT_MODE_LEVELTRIGGRD (L32789-32791): 1, jog mode, the axis runs
  while the key is held and brakes when it is released (L32614-32618); 0, continuous mode, a press
  starts it and it runs on after the release until the same key is pressed again, the other key is
  pressed, RESET, JOG is left or a limit is reached (L32624-32673);
* incremental JOG, MD11300 JOG_INC_MODE_LEVELTRIGGRD (L33093-33095): 1, jog mode, the key held
  travels the increment; released before it is done the axis stops and keeps the rest, the same key
  pressed again travels it on; the other key does nothing until the increment is done or ended
  (L32814-32820); 0, continuous mode, a press travels the whole increment, a second press of the
  same key or the other key ends it (L32832-32852).

An increment ends (its rest is dropped, the axis brakes) on RESET (the channel's reset brakes the
axis: another owner takes it), DB31.DBX2.2 "delete distance to go" (L32826-32828), a limit reached
(the software limit switches, an actuated hardware limit switch in its direction), a change of the
selected increment (L32861), the drive's enables removed (L32862) and JOG left (mode change, an
alarm that stops the axes) [control: the seed says the NC keeps JOG while an axis travels
(L32872); the harness's mode group takes the PLC's mode change, so the increment is ended].

States::

    IDLE ──key, continuous──▶ CONTINUOUS ──jog mode: key released; continuous mode: a key pressed again──▶ IDLE
    IDLE ──key, INC──▶ INCREMENT ──the increment travelled──▶ AT_END (key still held) / IDLE
    INCREMENT ──jog mode: key released──▶ INCREMENT_HELD ──the same key again──▶ INCREMENT
    INCREMENT ──continuous mode: a key pressed again──▶ IDLE
    CONTINUOUS, INCREMENT, INCREMENT_HELD ──RESET, DBX2.2, a limit, the increment changed, the enables
        removed, JOG left──▶ AT_END (key still held) / IDLE
    AT_END ──the key held released──▶ IDLE (the other key pressed meanwhile starts at once)
"""

from __future__ import annotations

from dataclasses import dataclass
from enum import Enum

from vc.core.axis.owner import Owner
from vc.core.state_machine import Instance, StateMachine, states, transitions


@dataclass(frozen=True, slots=True)
class JogSelection:
    """The machine function of JOG for one axis this cycle: the increment (axis units, 0 =
    continuous JOG) and whether the keys command in jog mode (held) or continuous mode (pressed)."""

    increment: float = 0.0
    continuous_held: bool = True  # SD41050 = 1
    increment_held: bool = True  # MD11300 = 1


CONTINUOUS_JOG = JogSelection()


class JogKeyState(Enum):
    IDLE = "no motion commanded by the traverse keys"
    CONTINUOUS = "continuous JOG: the axis runs (key held, or in continuous mode after its press)"
    INCREMENT = "incremental JOG: the axis travels the increment"
    INCREMENT_HELD = "incremental JOG in jog mode: the key released before the increment was done, the rest kept"
    AT_END = "the increment done or ended, the key still held: a new motion needs a new press"


_MOVING = (JogKeyState.CONTINUOUS, JogKeyState.INCREMENT, JogKeyState.INCREMENT_HELD)


class TraverseKeys:
    """The traverse keys of one axis in JOG (see the module docstring); ``AxisJog`` moves the axis."""

    def __init__(self) -> None:
        self.state = JogKeyState.IDLE
        self.direction = 0  # the direction of the key that started the motion
        self.way = 0  # INCREMENT: the direction the axis travels (against the key's with MD31090 < 0)
        self.increment = 0.0  # INCREMENT / INCREMENT_HELD: the increment selected when it started
        self.rest = 0.0  # INCREMENT / INCREMENT_HELD: the distance still to travel (sign = way)
        self._plus = False  # the keys as last seen, for their edges
        self._minus = False

    @property
    def busy(self) -> bool:
        """Its cycle must run in JOG even with no key pressed: a motion to end, or a key to see released."""
        return self.state is not JogKeyState.IDLE or self._plus or self._minus

    @property
    def travelling_increment(self) -> bool:
        return self.state is JogKeyState.INCREMENT

    def command(self, owner: Owner, plus: bool, minus: bool, selection: JogSelection, ended: bool,
                may_go_plus: bool, may_go_minus: bool) -> int:
        """One IPO cycle: the keys as JOG follows them (``plus`` / ``minus``: False outside JOG);
        ``ended``: the motion must end (DBX2.2, the enables removed, JOG left); ``may_go_*``: JOG may
        start that way (no actuated limit switch, not resting on a software limit).  Returns the
        direction of continuous JOG (0: none); an increment leaves its distance in ``rest``."""
        rise_plus, rise_minus = plus and not self._plus, minus and not self._minus
        self._plus, self._minus = plus, minus
        held = (1 if plus else -1) if plus != minus else 0
        state = self.state
        # jog mode of continuous JOG follows the keys' level alone (a drive that is not ready holds it)
        level_only = state is JogKeyState.CONTINUOUS and selection.continuous_held
        if state in _MOVING and not level_only and (
                ended or (owner is not Owner.JOG and owner is not Owner.NONE)
                or (state is not JogKeyState.CONTINUOUS and selection.increment != self.increment)):
            self._end(held)  # RESET (another owner brakes it), DBX2.2, the increment changed ...
            return 0
        if state is JogKeyState.IDLE:
            if ended and (selection.increment or not selection.continuous_held):
                return 0
            return self._start(selection, held, rise_plus, rise_minus, may_go_plus, may_go_minus)
        if state is JogKeyState.CONTINUOUS:
            return self._continuous(selection, held, rise_plus or rise_minus, may_go_plus, may_go_minus)
        if state is JogKeyState.INCREMENT:
            if not (may_go_plus if self.way > 0 else may_go_minus):
                self._end(held)  # an actuated limit switch ahead: the first active limit ends it
            else:
                self._increment(selection, held, rise_plus or rise_minus)
        elif state is JogKeyState.INCREMENT_HELD:
            if held == self.direction:
                self.state = JogKeyState.INCREMENT  # the same key again: on with the rest (L32816)
        elif held != self.direction:  # AT_END: the key released (the other one may start at once)
            self.state = JogKeyState.IDLE
            if not ended or (selection.continuous_held and not selection.increment):
                return self._start(selection, held, rise_plus, rise_minus, may_go_plus, may_go_minus)
        return 0

    def increment_travelled(self, held: bool) -> None:
        """The axis is at the end of the increment, or it cannot go on (a limit): it is done."""
        self._end(self.direction if held else 0)

    def end_motion(self, held: bool) -> None:
        """The motion ends from outside (another fixed point selected, L34338-34342): a key still held
        must be released before the next press."""
        self._end(self.direction if held else 0)

    def _start(self, selection: JogSelection, held: int, rise_plus: bool, rise_minus: bool,
               may_go_plus: bool, may_go_minus: bool) -> int:
        """IDLE: a press starts a motion; in jog mode of continuous JOG the key's level moves the axis."""
        pressed = (1 if rise_plus else -1) if rise_plus != rise_minus and held else 0
        if selection.increment:
            way = pressed if selection.increment > 0.0 else -pressed  # MD31090 < 0 reverses it (L33086-33088)
            if pressed == held and pressed and (may_go_plus if way > 0 else may_go_minus):
                self.state, self.direction, self.way = JogKeyState.INCREMENT, pressed, way
                self.increment = selection.increment
                self.rest = pressed * selection.increment
            return 0
        if selection.continuous_held:
            if held and (may_go_plus if held > 0 else may_go_minus):
                self.state, self.direction = JogKeyState.CONTINUOUS, held
                return held
            return 0
        if pressed == held and pressed and (may_go_plus if pressed > 0 else may_go_minus):
            self.state, self.direction = JogKeyState.CONTINUOUS, pressed
            return pressed
        return 0

    def _continuous(self, selection: JogSelection, held: int, pressed: bool, may_go_plus: bool,
                    may_go_minus: bool) -> int:
        """CONTINUOUS: jog mode follows the key's level; continuous mode runs until a key is pressed again."""
        if selection.increment:
            self._end(held)  # INC selected: a new press travels an increment
            return 0
        if selection.continuous_held:
            if held and (may_go_plus if held > 0 else may_go_minus):
                self.direction = held
                return held
            self.state = JogKeyState.IDLE  # released (or both keys): it brakes
            return 0
        if pressed or not (may_go_plus if self.direction > 0 else may_go_minus):
            self._end(held)  # the same or the other key pressed again, or a limit (L32656-32673)
            return 0
        return self.direction

    def _increment(self, selection: JogSelection, held: int, pressed: bool) -> None:
        """INCREMENT: jog mode pauses on the release; continuous mode ends on a second press."""
        if selection.increment_held:
            if held != self.direction:
                self.state = JogKeyState.INCREMENT_HELD  # released: it stops, the rest kept (L32814-32816)
        elif pressed:
            self._end(held)  # the same key again or the other key (L32834-32846)

    def _end(self, held: int) -> None:
        """The motion ends; a key still held must be released before the next one."""
        self.state = JogKeyState.AT_END if held else JogKeyState.IDLE
        self.direction = held or self.direction
        self.rest = 0.0
        self.increment = 0.0


JOG_KEY_STATES: StateMachine[TraverseKeys] = StateMachine(
    __name__, "jog_keys", "The traverse keys in JOG: continuous and incremental (seed 003 §16.4, §16.5)",
    Instance.AXIS, states(*JogKeyState),
    transitions(("IDLE", "CONTINUOUS", "a traverse key, continuous JOG (held in jog mode, pressed in continuous"
                 " mode)"),
                ("CONTINUOUS", "IDLE", "jog mode: the key released; continuous mode: a key pressed again; a limit,"
                 " RESET, JOG left"),
                ("CONTINUOUS", "AT_END", "continuous mode: a key pressed again and still held"),
                ("IDLE", "INCREMENT", "a traverse key pressed, INC1 .. INC10000 / INCvar selected"),
                ("INCREMENT", "INCREMENT_HELD", "jog mode: the key released before the increment is done"),
                ("INCREMENT_HELD", "INCREMENT", "the same key pressed again"),
                ("INCREMENT", "AT_END", "the increment travelled, the key still held; ended with the key held"),
                ("INCREMENT", "IDLE", "the increment travelled; continuous mode: a key pressed again; RESET,"
                 " DBX2.2, a limit, the increment changed, the enables removed, JOG left"),
                ("INCREMENT_HELD", "IDLE", "RESET, DBX2.2, the increment changed, the enables removed, JOG left"),
                ("INCREMENT_HELD", "AT_END", "ended while the other key is held"),
                ("AT_END", "IDLE", "the key held released")),
    read=lambda keys: keys.state)
