"""``${...}`` in a scenario: the values of one variant put into its texts before it is checked.

A placeholder holds a varied key (``${X1.MD34050}``, ``${override}``), an item of a varied list
(``${X1.plant.ref_cam[0]}``), or arithmetic of them and numbers: ``+ - * /``, a leading ``-``,
parentheses (``${X1.plant.ref_cam[0] + 7 * side}``).  A text that is only one placeholder takes
the value itself (a number stays a number, a list a list: ``set: {MCP.feedOverride: "${override}"}``);
inside a longer text the value is written out: ``"${X1.plant.ref_cam[0] - 7} +- 0.001"`` becomes
``"273 +- 0.001"``.

The text between the braces is parsed by Python's :mod:`ast` in ``eval`` mode and evaluated by
walking a short list of allowed nodes (numbers, names, attributes, one index, the four
operators): nothing is ever executed.
"""

from __future__ import annotations

import ast
import functools
import re
from collections.abc import Mapping, MutableSet, Sequence
from typing import Any

from interfaces.errors import VcError

PLACEHOLDER = re.compile(r"\$\{([^{}]*)\}")
MARKER = "${"

Number = int | float
_OPERATORS = {ast.Add: "+", ast.Sub: "-", ast.Mult: "*", ast.Div: "/"}


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
    tree = _parsed(source.strip())
    if tree is None:
        raise PlaceholderError(f"{written} is not a varied key or arithmetic of them (+ - * /)", column)
    return _Evaluation(written, values, column, used).value(tree.body)


@functools.lru_cache(maxsize=1024)
def _parsed(source: str) -> ast.Expression | None:
    """Parsed once: every variant of a matrix fills the same placeholders (the tree is only read)."""
    try:
        return ast.parse(source, mode="eval")
    except SyntaxError:
        return None


class _Evaluation:
    def __init__(self, written: str, values: Mapping[str, Any], column: int, used: MutableSet[str] | None):
        self.written = written
        self.values = values
        self.column = column
        self.used = used

    def fail(self, message: str) -> PlaceholderError:
        return PlaceholderError(f"{self.written}: {message}", self.column)

    def value(self, node: ast.expr) -> Any:
        if isinstance(node, ast.Constant) and isinstance(node.value, (int, float)) \
                and not isinstance(node.value, bool):
            return node.value
        if isinstance(node, (ast.Name, ast.Attribute)):
            return self.lookup(self.dotted(node))
        if isinstance(node, ast.Subscript):
            return self.item(node)
        if isinstance(node, ast.UnaryOp) and isinstance(node.op, (ast.USub, ast.UAdd)):
            operand = self.number(self.value(node.operand), "-")
            return -operand if isinstance(node.op, ast.USub) else operand
        if isinstance(node, ast.BinOp) and type(node.op) in _OPERATORS:
            symbol = _OPERATORS[type(node.op)]
            left = self.number(self.value(node.left), symbol)
            right = self.number(self.value(node.right), symbol)
            if symbol == "+":
                return left + right
            if symbol == "-":
                return left - right
            if symbol == "*":
                return left * right
            if right == 0:
                raise self.fail("division by zero")
            return left / right
        raise self.fail("only varied keys, numbers, + - * / and parentheses are allowed")

    def dotted(self, node: ast.expr) -> str:
        if isinstance(node, ast.Name):
            return node.id
        if isinstance(node, ast.Attribute):
            return f"{self.dotted(node.value)}.{node.attr}"
        raise self.fail("a key is a name with dots, e.g. X1.plant.ref_cam")

    def lookup(self, key: str) -> Any:
        if key not in self.values:
            known = ", ".join(self.values) or "nothing"
            raise self.fail(f"'{key}' is not varied (varied: {known})")
        if self.used is not None:
            self.used.add(key)
        return self.values[key]

    def item(self, node: ast.Subscript) -> Any:
        index_node = node.slice
        index = self.value(index_node)
        if isinstance(index, float) and index.is_integer():
            index = int(index)
        if not isinstance(index, int):
            raise self.fail("an index is a whole number, e.g. [0]")
        if isinstance(node.value, (ast.Name, ast.Attribute)):
            key = self.dotted(node.value)
            if f"{key}[{index}]" in self.values:  # a varied item of an array: X1.MD34100[0]
                return self.lookup(f"{key}[{index}]")
            items = self.lookup(key)
        else:
            items = self.value(node.value)
        if isinstance(items, str) or not isinstance(items, Sequence):
            raise self.fail(f"[{index}] needs a list, and the value is {shown(items)}")
        if not -len(items) <= index < len(items):
            raise self.fail(f"[{index}] is outside the list {shown(items)}")
        return items[index]

    def number(self, value: Any, symbol: str) -> Number:
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise self.fail(f"'{symbol}' needs numbers, and {shown(value)} is not one")
        return value
