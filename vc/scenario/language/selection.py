"""Which of a run's scenarios and variants run: ``vc run -k EXPRESSION`` and ``--shard I/N``.

``-k`` works as pytest's: the expression's words are matched, case-insensitively, as parts of a
scenario's id (its file as given and its name; a variant's name carries its arguments in brackets,
``ref_cam[X1.MD34050=1]``), combined with ``and``, ``or``, ``not`` and parentheses::

    vc run scenarios/ -k "referencing and not abort"
    vc run campaigns/ref_cam.yaml -k "MD34050=1"

``--shard I/N`` runs the I-th of N parts of what is selected (I from 1): every N-th scenario from
the I-th on, in the run's order, so that the N parts are alike whatever the files hold and a CI
matrix of N machines runs each scenario exactly once, without a cluster.
"""

from __future__ import annotations

import re
from collections.abc import Callable, Sequence
from dataclasses import dataclass

from interfaces.errors import VcError
from vc.scenario.language.model import Scenario

_TOKEN = re.compile(r"\s*(\(|\)|[^\s()]+)")
_OPERATORS = ("and", "or", "not")

Match = Callable[[str], bool]  # the scenario's id, lower case -> selected


class SelectionError(VcError, ValueError):
    """A ``-k`` expression or a ``--shard`` that cannot be read; the message says where."""


class _Parser:
    """Recursive descent over the tokens: or-expression := and-expression ("or" and-expression)*,
    and-expression := not-expression ("and" not-expression)*, not-expression := "not" not-expression
    | "(" or-expression ")" | word."""

    def __init__(self, expression: str):
        self.expression = expression
        self.tokens = _TOKEN.findall(expression)
        self.position = 0

    def parse(self) -> Match:
        if not self.tokens:
            raise SelectionError(f"-k {self.expression!r}: the expression is empty")
        match = self._or()
        if self.position < len(self.tokens):
            raise self._unexpected()
        return match

    def _peek(self) -> str | None:
        return self.tokens[self.position] if self.position < len(self.tokens) else None

    def _take(self) -> str:
        token = self._peek()
        if token is None:
            raise SelectionError(f"-k {self.expression!r}: the expression ends where a word or '(' is missing")
        self.position += 1
        return token

    def _unexpected(self) -> SelectionError:
        return SelectionError(f"-k {self.expression!r}: unexpected {self.tokens[self.position]!r} at word"
                              f" {self.position + 1}")

    def _or(self) -> Match:
        parts = [self._and()]
        while self._peek() == "or":
            self.position += 1
            parts.append(self._and())
        return parts[0] if len(parts) == 1 else (lambda text: any(part(text) for part in parts))

    def _and(self) -> Match:
        parts = [self._not()]
        while self._peek() == "and":
            self.position += 1
            parts.append(self._not())
        return parts[0] if len(parts) == 1 else (lambda text: all(part(text) for part in parts))

    def _not(self) -> Match:
        token = self._take()
        if token == "not":
            inner = self._not()
            return lambda text: not inner(text)
        if token == "(":
            inner = self._or()
            if self._peek() != ")":
                raise SelectionError(f"-k {self.expression!r}: a '(' is not closed")
            self.position += 1
            return inner
        if token in (")", "and", "or"):
            self.position -= 1
            raise self._unexpected()
        word = token.lower()
        return lambda text: word in text


def keyword_match(expression: str) -> Match:
    """The test of ``-k expression`` (module docstring); :class:`SelectionError` if it cannot be read."""
    return _Parser(expression).parse()


@dataclass(frozen=True, slots=True)
class Shard:
    """Part ``index`` (from 1) of ``count``."""

    index: int
    count: int

    @classmethod
    def parse(cls, text: str) -> Shard:
        found = re.fullmatch(r"\s*(\d+)\s*/\s*(\d+)\s*", text)
        if found is None:
            raise SelectionError(f"--shard {text!r}: give I/N, the I-th of N parts (e.g. 2/4)")
        index, count = int(found.group(1)), int(found.group(2))
        if not 1 <= index <= count <= 10_000:
            raise SelectionError(f"--shard {text!r}: I must be 1 .. N and N at most 10,000")
        return cls(index, count)

    def __str__(self) -> str:
        return f"{self.index}/{self.count}"


@dataclass(frozen=True, slots=True)
class Selection:
    """``-k`` and ``--shard`` together: the keyword test first, then the shard of what it kept."""

    keyword: str | None = None
    shard: Shard | None = None

    def __post_init__(self) -> None:
        if self.keyword is not None:
            keyword_match(self.keyword)  # an expression that cannot be read is refused before anything runs

    def apply(self, scenarios: Sequence[Scenario]) -> list[Scenario]:
        chosen = list(scenarios)
        if self.keyword is not None:
            match = keyword_match(self.keyword)
            chosen = [scenario for scenario in chosen if match(scenario_id(scenario))]
        if self.shard is not None:
            chosen = chosen[self.shard.index - 1::self.shard.count]
        return chosen

    def describe(self) -> str:
        parts = ([f"-k {self.keyword!r}"] if self.keyword is not None else []) + \
            ([f"--shard {self.shard}"] if self.shard is not None else [])
        return " ".join(parts)


def scenario_id(scenario: Scenario) -> str:
    """What ``-k`` reads: the file as given and the name (with a variant's arguments), lower case."""
    origin = scenario.variant.origin if scenario.variant is not None else scenario.path
    return f"{origin} {scenario.path} {scenario.name}".lower()
