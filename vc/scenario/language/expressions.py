"""Expressions in scenario files: conditions and ``${...}`` placeholders, one bounded reader.

Conditions (``wait: {until: ...}``, ``expect``, invariants, ``when`` events) are parsed once and
evaluated every cycle.  Grammar (lowest precedence first; keywords and function names in any
letter case)::

    expression  := or
    or          := and ( "or" and )*
    and         := not ( "and" not )*
    not         := "not" not | comparison
    comparison  := sum [ ( "==" | "!=" | "<" | "<=" | ">" | ">=" ) sum ]
    sum         := product ( ( "+" | "-" ) product )*
    product     := unary ( ( "*" | "/" ) unary )*
    unary       := ( "-" | "+" ) unary | primary
    primary     := NUMBER | "true" | "false" | NAME [ "[" WHOLE NUMBER "]" ] | "(" expression ")"
                 | "abs" "(" expression ")"
                 | "alarm" "(" NUMBER [ "," NAME ] ")"

``NAME`` is a signal symbol (with its group's index: ``CHAN1.auxMFuncs[2].in.value``), an
absolute address, a plant I/O name, ``<axis>.<quantity>``, a machine datum (``X1.MD34090[1]``) or
``time`` (see :mod:`vc.scenario.language.quantities`).  Comparisons and ``and``/``or``/``not`` give 1 or 0; a
condition holds when its value is not 0.  Only one comparison per level: write
``0 < X1.position and X1.position < 5`` (chained comparisons read differently in different
languages, so they are refused with that hint).  ``alarm(21614, X1)`` is 1 while alarm 21614 of
axis (or channel) X1 is present.

The arithmetic of a placeholder (:mod:`vc.scenario.language.placeholders`, :data:`Grammar.ARITHMETIC`) is
the ``sum`` of this grammar: names (varied keys), numbers, ``+ - * /``, signs, parentheses, and
an index of any whole-number value after a name or another index (``X1.plant.ref_cam[side + 1]``).

Parsing never uses ``eval``: a tokenizer and a recursive-descent parser build a tree; a
condition's tree is compiled into nested closures, so an invariant costs a few function calls per
IPO cycle.  Errors carry the 1-based column inside the text.

Bounds (:mod:`vc.input_limits`), the same for both grammars: a text holds at most
``MAX_EXPRESSION_CHARACTERS`` characters; parentheses, brackets, ``not``, signs and ``abs`` nest at
most ``MAX_EXPRESSION_NESTING`` deep and the tree is at most ``MAX_EXPRESSION_DEPTH`` deep, since
checking, compiling and evaluating recurse along it; a number is finite and at most
``MAX_MAGNITUDE``.  A comparison of a value that is not finite (a NaN or an infinity read from a
signal or made by arithmetic) cannot be judged: evaluating it raises :class:`EvaluationError`, as
a division by zero does, and a division whose result is not finite does too.  Without that,
``!=`` would hold for a NaN and ``<`` for minus infinity.
"""

from __future__ import annotations

import math
import operator
import re
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from dataclasses import dataclass
from enum import Enum
from typing import Protocol

from interfaces.errors import VcError
from interfaces.signals import UnknownSignalError
from vc.input_limits import (
    MAX_EXPRESSION_CHARACTERS,
    MAX_EXPRESSION_DEPTH,
    MAX_EXPRESSION_NESTING,
    MAX_MAGNITUDE,
)
from vc.scenario.language.quantities import NameResolver, Quantity

Number = int | float
Evaluator = Callable[[], Number]


class ExpressionError(VcError, ValueError):
    """A syntax or name problem in an expression, at a 1-based column of its text."""

    def __init__(self, message: str, column: int | None = None):
        super().__init__(message)
        self.message = message
        self.column = column

    def __str__(self) -> str:
        return self.message if self.column is None else f"{self.message} at column {self.column}"


class EvaluationError(VcError, ArithmeticError):
    """A condition could not be evaluated in this cycle (division by zero, a value not finite)."""


# ---------------------------------------------------------------------------------- tokens

_TOKEN = re.compile(
    r"""
    (?P<space>\s+)
  | (?P<number>(?:[0-9]+(?:\.[0-9]*)?|\.[0-9]+)(?:[eE][-+]?[0-9]+)?(?![A-Za-z_0-9.]))
  | (?P<name>[A-Za-z_][A-Za-z_0-9]*(?:\.[A-Za-z_0-9]+)*)
  | (?P<member>(?<=\])\.[A-Za-z_][A-Za-z_0-9]*(?:\.[A-Za-z_0-9]+)*)
  | (?P<op>==|!=|<=|>=|<|>|\+|-|\*|/|\(|\)|\[|\]|,)
    """,
    re.VERBOSE,
)

# Operators from other languages, with the way to write them here.
_FOREIGN = (
    ("&&", "write and"), ("||", "write or"), ("<>", "write !="), ("=", "compare with =="),
    ("!", "write not, or != to compare"), ("&", "write and"), ("|", "write or"),
)

KEYWORDS = frozenset({"and", "or", "not", "true", "false"})
FUNCTIONS = ("abs", "alarm")


@dataclass(frozen=True, slots=True)
class Token:
    kind: str  # "number", "name", "member" (".in.value" after an index), "op", "end"
    text: str
    column: int  # 1-based


def tokenize(text: str) -> list[Token]:
    tokens: list[Token] = []
    position = 0
    while position < len(text):
        match = _TOKEN.match(text, position)
        if match is None or text.startswith("<>", position):
            raise ExpressionError(_unexpected_character(text, position), position + 1)
        kind = match.lastgroup
        assert kind is not None
        if kind != "space":
            tokens.append(Token(kind, match.group(), position + 1))
        position = match.end()
    tokens.append(Token("end", "", len(text) + 1))
    return tokens


def _unexpected_character(text: str, position: int) -> str:
    for foreign, hint in _FOREIGN:
        if text.startswith(foreign, position):
            return f"unexpected '{foreign}' ({hint})"
    if text[position].isdigit():
        return "a number must not run into a name (leave a space or an operator between them)"
    return f"unexpected '{text[position]}'"


# ---------------------------------------------------------------------------------- tree


@dataclass(frozen=True, slots=True)
class Literal:
    value: Number
    column: int


@dataclass(frozen=True, slots=True)
class Name:
    text: str
    column: int


@dataclass(frozen=True, slots=True)
class Unary:
    op: str  # "-" or "not"
    operand: Node
    column: int


@dataclass(frozen=True, slots=True)
class Binary:
    op: str
    left: Node
    right: Node
    column: int


@dataclass(frozen=True, slots=True)
class Abs:
    operand: Node
    column: int


@dataclass(frozen=True, slots=True)
class Index:
    """``target[index]`` of an arithmetic expression: an item of a list (a placeholder's varied value)."""

    target: Node
    index: Node
    column: int


@dataclass(frozen=True, slots=True)
class AlarmCall:
    number: int
    place: str  # axis or channel name; "" = anywhere
    column: int
    place_column: int = 0


Node = Literal | Name | Unary | Binary | Abs | Index | AlarmCall

_COMPARISONS = ("==", "!=", "<", "<=", ">", ">=")


class Grammar(Enum):
    """What a text may hold: a whole condition, or the arithmetic of a ``${...}`` placeholder."""

    CONDITION = "condition"
    ARITHMETIC = "arithmetic"


_NESTED = {Grammar.CONDITION: "parentheses, brackets, not, signs and abs",
           Grammar.ARITHMETIC: "parentheses, brackets and signs"}


class _Parser:
    def __init__(self, text: str, grammar: Grammar):
        self.text = text
        self.grammar = grammar
        self.tokens = tokenize(text)
        self.index = 0
        self.nesting = 0  # parentheses, brackets, not, signs and abs around the current token

    @property
    def token(self) -> Token:
        return self.tokens[self.index]

    def advance(self) -> Token:
        token = self.tokens[self.index]
        self.index += 1
        return token

    def is_keyword(self, word: str) -> bool:
        return self.grammar is Grammar.CONDITION and self.token.kind == "name" and self.token.text.lower() == word

    def is_op(self, *ops: str) -> bool:
        return self.token.kind == "op" and self.token.text in ops

    def unexpected(self) -> ExpressionError:
        token = self.token
        if token.kind == "end":
            return ExpressionError("unexpected end of the expression", token.column)
        return ExpressionError(f"unexpected '{token.text}'", token.column)

    def parse(self) -> Node:
        if self.token.kind == "end":
            raise ExpressionError("the expression is empty", 1)
        node = self.parse_top()
        if self.token.kind != "end":
            if self.is_op(*_COMPARISONS) and self.grammar is Grammar.CONDITION:
                raise ExpressionError(
                    f"a comparison cannot follow another ('{self.token.text}'); join them with and",
                    self.token.column)
            raise self.unexpected()
        return node

    def parse_top(self) -> Node:
        """The whole of the grammar: a condition, or a sum."""
        return self.parse_or() if self.grammar is Grammar.CONDITION else self.parse_sum()

    def parse_or(self) -> Node:
        node = self.parse_and()
        while self.is_keyword("or"):
            column = self.advance().column
            node = Binary("or", node, self.parse_and(), column)
        return node

    def parse_and(self) -> Node:
        node = self.parse_not()
        while self.is_keyword("and"):
            column = self.advance().column
            node = Binary("and", node, self.parse_not(), column)
        return node

    def parse_not(self) -> Node:
        if self.is_keyword("not"):
            column = self.advance().column
            with self.nested(column):
                return Unary("not", self.parse_not(), column)
        return self.parse_comparison()

    def parse_comparison(self) -> Node:
        node = self.parse_sum()
        if self.is_op(*_COMPARISONS):
            token = self.advance()
            node = Binary(token.text, node, self.parse_sum(), token.column)
        return node

    def parse_sum(self) -> Node:
        node = self.parse_product()
        while self.is_op("+", "-"):
            token = self.advance()
            node = Binary(token.text, node, self.parse_product(), token.column)
        return node

    def parse_product(self) -> Node:
        node = self.parse_unary()
        while self.is_op("*", "/"):
            token = self.advance()
            node = Binary(token.text, node, self.parse_unary(), token.column)
        return node

    def parse_unary(self) -> Node:
        if self.is_op("-", "+"):
            sign = self.advance()
            with self.nested(sign.column):
                operand = self.parse_unary()
            return Unary("-", operand, sign.column) if sign.text == "-" else operand
        return self.parse_primary()

    def parse_primary(self) -> Node:
        token = self.token
        if token.kind == "number":
            self.advance()
            return Literal(_number(token), token.column)
        if self.is_op("("):
            self.advance()
            with self.nested(token.column):
                node = self.parse_top()
            self.expect_close(token, ")")
            return self.indexes(node) if self.grammar is Grammar.ARITHMETIC else node
        if token.kind != "name":
            raise self.unexpected()
        if self.grammar is Grammar.ARITHMETIC:
            self.advance()
            if self.is_op("("):
                raise ExpressionError(f"'{token.text}(' calls a function; a placeholder holds varied keys, numbers,"
                                      " + - * / and parentheses", token.column)
            return self.indexes(Name(token.text, token.column))
        word = token.text.lower()
        if word in ("true", "false"):
            self.advance()
            return Literal(1 if word == "true" else 0, token.column)
        if word in ("and", "or", "not"):
            raise self.unexpected()
        self.advance()
        if self.is_op("["):
            return self.element(token)
        if not self.is_op("("):
            return Name(token.text, token.column)
        opening = self.advance()
        if word == "abs":
            with self.nested(token.column):
                operand = self.parse_or()
            self.expect_close(opening, ")")
            return Abs(operand, token.column)
        if word == "alarm":
            return self.parse_alarm(token, opening)
        raise ExpressionError(f"unknown function '{token.text}' (known: {', '.join(FUNCTIONS)})",
                              token.column)

    def element(self, name: Token) -> Name:
        """``X1.MD34090[1]`` or ``CHAN1.auxMFuncs[2].in.value`` in a condition: an element of an array
        datum or of an indexed signal group is one name."""
        text = name.text
        while self.is_op("["):
            opening = self.advance()
            number = self.token
            if number.kind != "number" or not number.text.isdigit() or len(number.text) > 9:
                raise ExpressionError("an index in a condition is a whole number, e.g. X1.MD34090[1]",
                                      number.column)
            self.advance()
            self.expect_close(opening, "]")
            text = f"{text}[{int(number.text)}]"
            if self.token.kind == "member":  # the signal's name goes on after its group's index
                text += self.advance().text
        return Name(text, name.column)

    def indexes(self, node: Node) -> Node:
        """``target[index][index]...`` of the arithmetic grammar."""
        while self.is_op("["):
            opening = self.advance()
            with self.nested(opening.column):
                index = self.parse_sum()
            self.expect_close(opening, "]")
            node = Index(node, index, opening.column)
        return node

    @contextmanager
    def nested(self, column: int) -> Iterator[None]:
        """One level deeper into parentheses, brackets, not, a sign or abs (the parser recurses per level)."""
        if self.nesting == MAX_EXPRESSION_NESTING:
            raise ExpressionError(f"more than {MAX_EXPRESSION_NESTING} {_NESTED[self.grammar]} inside one another",
                                  column)
        self.nesting += 1
        try:
            yield
        finally:
            self.nesting -= 1

    def parse_alarm(self, name: Token, opening: Token) -> AlarmCall:
        number = self.token
        if number.kind != "number" or not number.text.isdigit() or len(number.text) > 9:
            raise ExpressionError("alarm(...) takes an alarm number, e.g. alarm(3000) or alarm(21614, X1)",
                                  number.column)
        self.advance()
        place, place_column = "", 0
        if self.is_op(","):
            self.advance()
            if self.token.kind != "name" or "." in self.token.text:
                raise ExpressionError("the second argument of alarm(...) is an axis or channel name",
                                      self.token.column)
            place_column = self.token.column
            place = self.advance().text
        self.expect_close(opening, ")")
        return AlarmCall(int(number.text), place, name.column, place_column)

    def expect_close(self, opening: Token, closing: str) -> None:
        if self.is_op(closing):
            self.advance()
            return
        if self.token.kind == "end":
            raise ExpressionError(f"this '{opening.text}' is not closed", opening.column)
        raise self.unexpected()


def _number(token: Token) -> Number:
    """A number of the text: finite and at most MAX_MAGNITUDE (``1e400`` would be infinite)."""
    text = token.text
    if text.isdigit() and len(text) <= 16:
        return int(text)
    value = float(text)
    if not abs(value) <= MAX_MAGNITUDE:
        shown = text if len(text) <= 24 else f"{text[:12]}...({len(text)} characters)"
        raise ExpressionError(f"the number {shown} is beyond {MAX_MAGNITUDE:g}, the largest an expression may hold",
                              token.column)
    return int(text) if text.isdigit() else value


def parse(text: str, grammar: Grammar = Grammar.CONDITION) -> Node:
    """Parse ``text`` into a tree; raises :class:`ExpressionError` with the column.  Every bound of
    the module docstring is checked here, before anything evaluates the tree."""
    if len(text) > MAX_EXPRESSION_CHARACTERS:
        raise ExpressionError(f"{len(text):,} characters; an expression holds at most"
                              f" {MAX_EXPRESSION_CHARACTERS:,}", MAX_EXPRESSION_CHARACTERS + 1)
    root = _Parser(text, grammar).parse()
    deepest, column = _depth(root)
    if deepest > MAX_EXPRESSION_DEPTH:
        raise ExpressionError(f"more than {MAX_EXPRESSION_DEPTH} operators one inside the other (split the"
                              " expression, or group long chains with parentheses)", column)
    return root


def _children(node: Node) -> tuple[Node, ...]:
    if isinstance(node, Unary | Abs):
        return (node.operand,)
    if isinstance(node, Binary):
        return (node.left, node.right)
    if isinstance(node, Index):
        return (node.target, node.index)
    return ()


def _depth(root: Node) -> tuple[int, int]:
    """How deep the tree is, and the column of its deepest operator (without recursing)."""
    deepest, column = 0, root.column
    pending = [(root, 1)]
    while pending:
        node, depth = pending.pop()
        children = _children(node)
        if children and depth > deepest:
            deepest, column = depth, node.column
        pending.extend((child, depth + 1) for child in children)
    return deepest, column


def walk(node: Node) -> Iterator[Node]:
    """Every node of the tree, parents before their children, left to right."""
    pending = [node]
    while pending:
        current = pending.pop()
        yield current
        pending.extend(reversed(_children(current)))


def to_text(node: Node) -> str:
    """The tree written back as text, fully parenthesised (for tests and messages)."""
    if isinstance(node, Literal):
        return repr(node.value)
    if isinstance(node, Name):
        return node.text
    if isinstance(node, Unary):
        return f"(not {to_text(node.operand)})" if node.op == "not" else f"(-{to_text(node.operand)})"
    if isinstance(node, Binary):
        return f"({to_text(node.left)} {node.op} {to_text(node.right)})"
    if isinstance(node, Abs):
        return f"abs({to_text(node.operand)})"
    if isinstance(node, Index):
        return f"{to_text(node.target)}[{to_text(node.index)}]"
    return f"alarm({node.number}, {node.place})" if node.place else f"alarm({node.number})"


# ---------------------------------------------------------------------------------- resolved


@dataclass(frozen=True, slots=True)
class Expression:
    """A parsed expression whose names are resolved for one machine."""

    text: str
    root: Node
    quantities: dict[str, Quantity]  # name as written -> what it stands for

    @property
    def names(self) -> tuple[Quantity, ...]:
        """The quantities the expression reads, each once, in order of appearance."""
        seen: dict[str, Quantity] = {}
        for quantity in self.quantities.values():
            seen.setdefault(quantity.name, quantity)
        return tuple(seen.values())

    def compile(self, probe: Probe) -> Evaluator:
        """The condition as a function of the probe's current values; a value that is not finite
        where the condition is judged raises :class:`EvaluationError`."""
        evaluator = _compile(self.root, self.quantities, probe)
        if isinstance(self.root, Binary | Unary) and self.root.op in _JUDGED:
            return evaluator  # 1 or 0, or it raises
        return lambda: _judged(evaluator())

    def __str__(self) -> str:
        return self.text


def parse_expression(text: str, resolver: NameResolver | None) -> Expression:
    """Parse ``text`` and resolve its names (skipped when ``resolver`` is None, e.g. because the
    machine did not load).  Raises :class:`ExpressionError`; name problems carry no column since
    the message quotes the name."""
    root = parse(text)
    quantities: dict[str, Quantity] = {}
    if resolver is not None:
        for node in walk(root):
            if isinstance(node, Name) and node.text not in quantities:
                try:
                    quantities[node.text] = resolver.resolve(node.text)
                except UnknownSignalError as error:
                    raise ExpressionError(error.message) from None
            elif isinstance(node, AlarmCall) and node.place:
                try:
                    resolver.place(node.place)
                except KeyError as error:
                    raise ExpressionError(str(error.args[0]), node.place_column) from None
    return Expression(text, root, quantities)


# ---------------------------------------------------------------------------------- compile


class Probe(Protocol):
    """What compiled expressions read: provided by the runner for one target."""

    def reader(self, quantity: Quantity) -> Evaluator: ...

    def alarm_present(self, number: int, place: str, text: str = "") -> bool: ...


_ARITHMETIC: dict[str, Callable[[Number, Number], Number]] = {
    "+": operator.add, "-": operator.sub, "*": operator.mul,
}
_COMPARE: dict[str, Callable[[Number, Number], bool]] = {
    "==": operator.eq, "!=": operator.ne, "<": operator.lt, "<=": operator.le, ">": operator.gt,
    ">=": operator.ge,
}
_JUDGED = frozenset({*_COMPARE, "and", "or", "not"})  # operators whose result is 1 or 0
_isfinite = math.isfinite


def _compile(node: Node, quantities: dict[str, Quantity], probe: Probe) -> Evaluator:
    if isinstance(node, Literal):
        constant = node.value
        return lambda: constant
    if isinstance(node, Name):
        return probe.reader(quantities[node.text])
    if isinstance(node, AlarmCall):
        number, place, present = node.number, node.place, probe.alarm_present
        return lambda: 1 if present(number, place) else 0
    if isinstance(node, Abs):
        inner = _compile(node.operand, quantities, probe)
        return lambda: abs(inner())
    if isinstance(node, Unary):
        operand = _compile(node.operand, quantities, probe)
        if node.op == "not":
            return lambda: 0 if _judged(operand()) else 1
        return lambda: -operand()
    if isinstance(node, Index):  # the parser folds a condition's index into its name
        raise ExpressionError("an index belongs to a placeholder's arithmetic", node.column)
    left = _compile(node.left, quantities, probe)
    right = _compile(node.right, quantities, probe)
    op = node.op
    if op == "and":
        return lambda: 1 if _judged(left()) and _judged(right()) else 0
    if op == "or":
        return lambda: 1 if _judged(left()) or _judged(right()) else 0
    if op in _COMPARE:
        compare = _COMPARE[op]
        return lambda: _compared(compare, op, left(), right())
    if op == "/":
        return lambda: _divide(left(), right())
    arithmetic = _ARITHMETIC[op]
    return lambda: arithmetic(left(), right())


def _judged(value: Number) -> Number:
    """``value`` where it is taken as true (not 0) or false (0): it must be finite."""
    if _isfinite(value):
        return value
    raise EvaluationError(f"a condition cannot hold or fail on {value}: the value is not finite")


def _compared(compare: Callable[[Number, Number], bool], op: str, left: Number, right: Number) -> int:
    if _isfinite(left) and _isfinite(right):
        return 1 if compare(left, right) else 0
    raise EvaluationError(f"cannot compare {left} {op} {right}: a value that is not finite")


def _divide(numerator: Number, denominator: Number) -> float:
    if denominator == 0:
        raise EvaluationError(f"division by zero ({numerator} / 0)")
    quotient = numerator / denominator
    if not _isfinite(quotient):
        raise EvaluationError(f"{numerator} / {denominator} is not finite")
    return quotient
