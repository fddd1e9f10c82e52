"""``${...}`` in a scenario: the values of one variant put into its texts before it is checked.

A placeholder holds a varied key (``${X1.MD34050}``, ``${override}``), an item of a varied list
(``${X1.plant.ref_cam[0]}``), or arithmetic of them and numbers: ``+ - * /``, a leading ``-``,
parentheses (``${X1.plant.ref_cam[0] + 7 * side}``).  A text that is only one placeholder takes
the value itself (a number stays a number, a list a list: ``set: {MCP.feedOverride: "${override}"}``);
inside a longer text the value is written out: ``"${X1.plant.ref_cam[0] - 7} +- 0.001"`` becomes
``"273 +- 0.001"``.

The text between the braces is read by the reader of conditions (:mod:`vc.scenario.language.expressions`,
its arithmetic grammar), with its bounds: length, nesting, depth, numbers at most 1e15.  The tree
is evaluated by walking it, and the value of every step must stay finite and within
``MAX_MAGNITUDE`` as well: a product of large numbers or a division by a tiny one is refused
where it is written, never a number of thousands of digits.  Nothing is ever executed.
"""

from __future__ import annotations

import functools
import re
from collections.abc import Mapping, MutableSet, Sequence
from typing import Any

from interfaces.errors import VcError
from vc.input_limits import MAX_MAGNITUDE
from vc.scenario.language.expressions import (
    Binary,
    ExpressionError,
    Grammar,
    Index,
    Literal,
    Name,
    Node,
    Unary,
    parse,
    walk,
)

PLACEHOLDER = re.compile(r"\$\{([^{}]*)\}")
MARKER = "${"

Number = int | float


class PlaceholderError(VcError, ValueError):
    """A placeholder that cannot be filled: its message and its 1-based column in the text."""

    def __init__(self, message: str, column: int):
        super().__init__(message)
        self.message = message
        self.column = column


def has_placeholder(value: object) -> bool:
    return isinstance(value, str) and MARKER in value


def fill(text: str, values: Mapping[str, Any], used: MutableSet[str] | None = None) -> Any:
    """``text`` with its placeholders filled from ``values`` (varied key -> value); the keys read go
    into ``used``.  A text that is one placeholder and nothing else gives the value itself."""
    whole = PLACEHOLDER.fullmatch(text.strip())
    if whole is not None:
        return _evaluate(whole.group(1), values, text.index(MARKER) + 1, used)
    pieces: list[str] = []
    position = 0
    for match in PLACEHOLDER.finditer(text):
        pieces.append(text[position:match.start()])
        pieces.append(shown(_evaluate(match.group(1), values, match.start() + 1, used)))
        position = match.end()
    rest = text[position:]
    if MARKER in rest:
        raise PlaceholderError("'${' without its closing '}'", position + rest.index(MARKER) + 1)
    return "".join(pieces) + rest


def placeholder_names(text: str) -> set[str]:
    """The names the placeholders of ``text`` read (``X1.MD34100`` for ``${X1.MD34100[0] + 1}``);
    a placeholder that cannot be read adds none (filling it reports it)."""
    names: set[str] = set()
    for match in PLACEHOLDER.finditer(text):
        tree = _parsed(match.group(1)) if match.group(1).strip() else None
        if tree is not None and not isinstance(tree, ExpressionError):
            names.update(node.text for node in walk(tree) if isinstance(node, Name))
    return names


def shown(value: Any) -> str:
    """A value as a scenario text would write it: 273, 0.5, true, [250, 260], {axis: X1}."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, float):
        return f"{value:.12g}" if not value.is_integer() or abs(value) >= 1e15 else str(int(value))
    if isinstance(value, Mapping):
        return "{" + ", ".join(f"{key}: {shown(item)}" for key, item in value.items()) + "}"
    if isinstance(value, Sequence) and not isinstance(value, str):
        return "[" + ", ".join(shown(item) for item in value) + "]"
    if value is None:
        return "none"
    return str(value)


def _evaluate(source: str, values: Mapping[str, Any], column: int, used: MutableSet[str] | None) -> Any:
    written = "${" + source + "}"
    if not source.strip():
        raise PlaceholderError(f"{written} is empty: name a varied key, e.g. ${{X1.MD34050}}", column)
    tree = _parsed(source)
    if isinstance(tree, ExpressionError):
        shown_source = written if len(written) <= 60 else f"{written[:40]}...}} ({len(written):,} characters)"
        where = f" at column {tree.column}" if tree.column is not None else ""
        raise PlaceholderError(f"{shown_source} is not a varied key or arithmetic of them (+ - * /):"
                               f" {tree.message}{where}", column)
    return _Evaluation(written, values, column, used).value(tree)


@functools.lru_cache(maxsize=1024)
def _parsed(source: str) -> Node | ExpressionError:
    """Parsed once: every variant of a matrix fills the same placeholders (the tree is only read);
    a text that cannot be read gives its error, once as well."""
    try:
        return parse(source, Grammar.ARITHMETIC)
    except ExpressionError as error:
        return error


class _Evaluation:
    def __init__(self, written: str, values: Mapping[str, Any], column: int, used: MutableSet[str] | None):
        self.written = written if len(written) <= 60 else f"{written[:40]}...}}"
        self.values = values
        self.column = column
        self.used = used

    def fail(self, message: str) -> PlaceholderError:
        return PlaceholderError(f"{self.written}: {message}", self.column)

    def value(self, node: Node) -> Any:
        """The value of ``node``; the tree is at most MAX_EXPRESSION_DEPTH deep (the reader's bound)."""
        if isinstance(node, Literal):
            return node.value
        if isinstance(node, Name):
            return self.lookup(node.text)
        if isinstance(node, Index):
            return self.item(node)
        if isinstance(node, Unary):
            return -self.number(self.value(node.operand), "-")
        if isinstance(node, Binary):
            left = self.number(self.value(node.left), node.op)
            right = self.number(self.value(node.right), node.op)
            if node.op == "+":
                return self.bounded(left + right)
            if node.op == "-":
                return self.bounded(left - right)
            if node.op == "*":
                return self.bounded(left * right)
            if right == 0:
                raise self.fail("division by zero")
            return self.bounded(left / right)
        raise self.fail("only varied keys, numbers, + - * / and parentheses are allowed")

    def bounded(self, result: Number) -> Number:
        """A step of the arithmetic: finite and at most MAX_MAGNITUDE (its operands are, so no
        step can make a number of thousands of digits)."""
        if not abs(result) <= MAX_MAGNITUDE:  # also a NaN or an infinity
            raise self.fail(f"the value {shown(result)} is beyond {MAX_MAGNITUDE:g}, the largest a placeholder"
                            " may compute")
        return result

    def lookup(self, key: str) -> Any:
        if key not in self.values:
            known = ", ".join(self.values) or "nothing"
            raise self.fail(f"'{key}' is not varied (varied: {known})")
        if self.used is not None:
            self.used.add(key)
        return self.values[key]

    def item(self, node: Index) -> Any:
        index = self.value(node.index)
        if isinstance(index, float) and index.is_integer():
            index = int(index)
        if isinstance(index, bool) or not isinstance(index, int):
            raise self.fail(f"an index is a whole number, e.g. [0], not {shown(index)}")
        if isinstance(node.target, Name) and f"{node.target.text}[{index}]" in self.values:
            return self.lookup(f"{node.target.text}[{index}]")  # a varied item of an array: X1.MD34100[0]
        items = self.value(node.target)
        if isinstance(items, str) or not isinstance(items, Sequence):
            raise self.fail(f"[{index}] needs a list, and the value is {shown(items)}")
        if not -len(items) <= index < len(items):
            raise self.fail(f"[{index}] is outside the list {shown(items)}")
        return items[index]

    def number(self, value: Any, symbol: str) -> Number:
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise self.fail(f"'{symbol}' needs numbers, and {shown(value)} is not one")
        if not abs(value) <= MAX_MAGNITUDE:
            raise self.fail(f"'{symbol}' needs numbers within {MAX_MAGNITUDE:g}, and {shown(value)} is not one")
        return value
