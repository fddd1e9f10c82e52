"""Motion-synchronous actions: ``ID[S]=<n> WHENEVER|WHEN|EVERY|FROM <condition> DO <actions>``.

The ESR triggers of seed 003 §22.4.1 (L42180-42195) are static synchronized actions: checked in
every IPO cycle, independent of the block being executed, and (IDS) kept beyond reset and program
end [control].  The condition language is the part the retraction functions need::

    condition  := or_expr
    or_expr    := and_expr { OR and_expr }
    and_expr   := not_expr { AND not_expr }
    not_expr   := [NOT] comparison
    comparison := bit_expr [ (== | <> | > | < | >= | <=) bit_expr ]
    bit_expr   := term { (B_AND | B_OR | B_XOR | + | -) term }
    term       := number | 'H<hex>' | 'B<binary>' | $VARIABLE[ '[' index ']' ] | '(' or_expr ')'

An action is ``$VARIABLE[ [index] ]=<number>``, or ``POS[<axis>]=<number>`` / ``FA[<axis>]=<number>``
that move the axis as a command axis (vc/core/axis/command_axis.py), or ``FXS[<axis>]=0|1`` /
``FXST[<axis>]=<%>`` / ``FXSW[<axis>]=<width>`` of travel to fixed stop (vc/core/fixed_stop/, seed 003
L37125-37131); several are separated by blanks.  Modes: WHENEVER
does the actions in every cycle the condition holds, EVERY on each rising edge, WHEN once, FROM
once the condition held once, in every cycle from then on [control].

A condition or action that cannot be read raises the control's alarm 12080 when the block is
executed; reading an unknown variable raises 12550 at that time as well.
"""

from __future__ import annotations

import re
from collections.abc import Callable
from dataclasses import dataclass

from interfaces.errors import VcError
from vc.core.program.program import number, tokenize
from vc.input_limits import MAX_EXPRESSION_DEPTH, MAX_EXPRESSION_NESTING, MAX_MAGNITUDE

Reader = Callable[[str, str], float]  # (variable, index) -> value; KeyError for an unknown variable
COMMAND_AXIS_WORDS = ("POS", "FA")  # the words of a command axis an action may write (L11211-11236)
FIXED_STOP_WORDS = ("FXS", "FXST", "FXSW")  # travel to fixed stop, in a block or an action (L37125-37131)
_AXIS_WORDS = COMMAND_AXIS_WORDS + FIXED_STOP_WORDS

_TOKEN = re.compile(r"\s*(?:(?P<number>\d+\.?\d*|\.\d+)|'(?P<literal>[HB][0-9A-F]+)'|(?P<variable>\$[A-Z0-9_]+)"
                    r"|(?P<word>[A-Z_][A-Z0-9_]*)|(?P<symbol>==|<>|>=|<=|[<>()\[\]=+\-]))", re.IGNORECASE)
_COMPARISONS: dict[str, Callable[[float, float], bool]] = {
    "==": lambda a, b: a == b, "<>": lambda a, b: a != b, ">": lambda a, b: a > b,
    "<": lambda a, b: a < b, ">=": lambda a, b: a >= b, "<=": lambda a, b: a <= b,
}
_BIT_OPERATORS: dict[str, Callable[[float, float], float]] = {
    "B_AND": lambda a, b: float(int(a) & int(b)), "B_OR": lambda a, b: float(int(a) | int(b)),
    "B_XOR": lambda a, b: float(int(a) ^ int(b)), "+": lambda a, b: a + b, "-": lambda a, b: a - b,
}

Expression = Callable[[Reader], float]


def _either(a: float, b: float) -> float:
    return float(bool(a) or bool(b))


def _both(a: float, b: float) -> float:
    return float(bool(a) and bool(b))


def _combine(operator: Callable[[float, float], float], left: Expression, right: Expression) -> Expression:
    def expression(read: Reader) -> float:
        return operator(left(read), right(read))
    return expression


class SyncActionError(VcError, ValueError):
    """The text of a synchronized action cannot be read (alarm 12080)."""


@dataclass(frozen=True, slots=True)
class VariableWrite:
    """``$AC_ESR_TRIGGER=1``, ``$AA_ESR_ENABLE[X]=0``, ``POS[Z1]=100``: an action (or a program assignment)."""

    name: str
    index: str  # "" or the index as written (an axis name, an input number)
    value: float


def _tokens(text: str) -> list[tuple[str, str]]:
    return [(kind, token.upper()) for kind, token in tokenize(_TOKEN, text, SyncActionError)]


class _Parser:
    def __init__(self, text: str):
        self.tokens = _tokens(text)
        self.position = 0
        self.nesting = 0  # parentheses and signs around the current term (the parser recurses per level)
        self.operators = 0  # operators so far (evaluating a chain recurses once per operator)

    def operator(self) -> None:
        self.operators += 1
        if self.operators > MAX_EXPRESSION_DEPTH:
            raise SyncActionError(f"more than {MAX_EXPRESSION_DEPTH} operators")

    def peek(self) -> str:
        return self.tokens[self.position][1] if self.position < len(self.tokens) else ""

    def take(self) -> tuple[str, str]:
        if self.position >= len(self.tokens):
            raise SyncActionError("incomplete expression")
        token = self.tokens[self.position]
        self.position += 1
        return token

    def expect(self, symbol: str) -> None:
        if self.take()[1] != symbol:
            raise SyncActionError(f"'{symbol}' expected")

    def at_end(self) -> bool:
        return self.position >= len(self.tokens)

    def or_expr(self) -> Expression:
        left = self.and_expr()
        while self.peek() == "OR":
            self.take()
            self.operator()
            left = _combine(_either, left, self.and_expr())
        return left

    def and_expr(self) -> Expression:
        left = self.not_expr()
        while self.peek() == "AND":
            self.take()
            self.operator()
            left = _combine(_both, left, self.not_expr())
        return left

    def not_expr(self) -> Expression:
        if self.peek() == "NOT":
            self.take()
            inner = self.comparison()
            return lambda read: float(not inner(read))
        return self.comparison()

    def comparison(self) -> Expression:
        left = self.bit_expr()
        operator = _COMPARISONS.get(self.peek())
        if operator is None:
            return left
        self.take()
        self.operator()
        right = self.bit_expr()
        return lambda read: float(operator(left(read), right(read)))

    def bit_expr(self) -> Expression:
        left = self.term()
        while self.peek() in _BIT_OPERATORS:
            operator = _BIT_OPERATORS[self.take()[1]]
            self.operator()
            left = _combine(operator, left, self.term())
        return left

    def term(self) -> Expression:
        kind, text = self.take()
        if kind == "number":
            value = number(text, SyncActionError)
            return lambda read: value
        if kind == "literal":
            whole = int(text[1:], 16 if text[0] == "H" else 2) if len(text) <= 64 else MAX_MAGNITUDE + 1
            if whole > MAX_MAGNITUDE:
                raise SyncActionError(f"{text[:20]}: beyond {MAX_MAGNITUDE:g}")
            literal = float(whole)
            return lambda read: literal
        if kind == "variable":
            name, index = text, self.index()
            return lambda read: read(name, index)
        if text == "(":
            self.descend()
            inner = self.or_expr()
            self.expect(")")
            self.nesting -= 1
            return inner
        if text == "-":
            self.descend()
            operand = self.term()
            self.nesting -= 1
            return lambda read: -operand(read)
        raise SyncActionError(text)

    def descend(self) -> None:
        self.nesting += 1
        if self.nesting > MAX_EXPRESSION_NESTING:
            raise SyncActionError(f"more than {MAX_EXPRESSION_NESTING} parentheses and signs inside one another")

    def index(self) -> str:
        if self.peek() != "[":
            return ""
        self.take()
        kind, text = self.take()
        if kind not in ("number", "word"):
            raise SyncActionError(text)
        self.expect("]")
        return text


def parse_condition(text: str) -> Expression:
    parser = _Parser(text)
    expression = parser.or_expr()
    if not parser.at_end():
        raise SyncActionError(parser.peek())
    return expression


def parse_actions(text: str) -> tuple[VariableWrite, ...]:
    parser = _Parser(text)
    actions = []
    while not parser.at_end():
        kind, name = parser.take()
        if kind != "variable" and not (kind == "word" and name in _AXIS_WORDS and parser.peek() == "["):
            raise SyncActionError(name)
        index = parser.index()
        parser.expect("=")
        sign = -1.0 if parser.peek() == "-" else 1.0
        if sign < 0:
            parser.take()
        value_kind, value = parser.take()
        if value_kind != "number":
            raise SyncActionError(value)
        actions.append(VariableWrite(name, index, sign * number(value, SyncActionError)))
    if not actions:
        raise SyncActionError("DO without an action")
    return tuple(actions)


@dataclass(slots=True)
class SyncAction:
    """One active synchronized action of a channel."""

    number: int
    static: bool
    mode: str
    condition: Expression
    actions: tuple[VariableWrite, ...]
    text: str
    held: bool = False  # the condition held in the previous cycle
    fired: bool = False  # WHEN has acted / FROM has started

    def due(self, read: Reader) -> bool:
        """Evaluate the condition for this cycle; True when the actions are to be done now."""
        holds = bool(self.condition(read))
        rising, self.held = holds and not self.held, holds
        if self.mode == "WHENEVER":
            return holds
        if self.mode == "EVERY":
            return rising
        if self.mode == "WHEN":
            if holds and not self.fired:
                self.fired = True
                return True
            return False
        self.fired = self.fired or holds  # FROM
        return self.fired
