"""YAML with source locations, and the collect-every-problem error model.

Machine files and scenario files are checked completely before anything runs: every
problem is collected with ``file:line:column`` and one :class:`SourceError` reports them
all (in the manner of FMPy's ``validation``).  PyYAML's composer gives nodes with marks;
this module turns them into plain values that remember where they came from, and
reports what PyYAML silently accepts (duplicate keys).
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass
from typing import Any

import yaml


@dataclass(frozen=True, slots=True, order=True)
class Mark:
    file: str
    line: int  # 1-based
    column: int  # 1-based

    def __str__(self) -> str:
        return f"{self.file}:{self.line}:{self.column}"


@dataclass(frozen=True, slots=True, order=True)
class Problem:
    mark: Mark
    message: str

    def __str__(self) -> str:
        return f"{self.mark}: {self.message}"


class SourceError(Exception):
    """One or more problems in input files, each with its location."""

    def __init__(self, problems: list[Problem]):
        self.problems = sorted(problems)
        super().__init__("\n".join(str(problem) for problem in self.problems))


class Problems:
    """Collects problems while a file is checked; ``raise_if_any`` raises them all at once."""

    def __init__(self) -> None:
        self.items: list[Problem] = []

    def add(self, mark: Mark, message: str) -> None:
        self.items.append(Problem(mark, message))

    def extend(self, problems: list[Problem]) -> None:
        self.items.extend(problems)

    def __bool__(self) -> bool:
        return bool(self.items)

    def raise_if_any(self) -> None:
        if self.items:
            raise SourceError(self.items)


class LocatedMap(dict[str, Any]):
    """A mapping that remembers the mark of itself, of each key and of each value."""

    mark: Mark
    key_marks: dict[str, Mark]
    value_marks: dict[str, Mark]

    def mark_of(self, key: str) -> Mark:
        return self.value_marks.get(key, self.mark)

    def mark_of_key(self, key: str) -> Mark:
        return self.key_marks.get(key, self.mark)

    def located_items(self) -> Iterator[tuple[str, Any, Mark]]:
        for key, value in self.items():
            yield key, value, self.value_marks.get(key, self.mark)


class LocatedList(list[Any]):
    """A sequence that remembers its mark and the mark of each item."""

    mark: Mark
    item_marks: list[Mark]

    def mark_of(self, index: int) -> Mark:
        return self.item_marks[index] if index < len(self.item_marks) else self.mark

    def located_items(self) -> Iterator[tuple[int, Any, Mark]]:
        for index, value in enumerate(self):
            yield index, value, self.mark_of(index)


def _mark(file: str, node: yaml.Node) -> Mark:
    return Mark(file, node.start_mark.line + 1, node.start_mark.column + 1)


_CONSTRUCTOR = yaml.SafeLoader(" ")


def _convert(file: str, node: yaml.Node, problems: Problems) -> Any:
    if isinstance(node, yaml.MappingNode):
        result = LocatedMap()
        result.mark = _mark(file, node)
        result.key_marks = {}
        result.value_marks = {}
        _CONSTRUCTOR.flatten_mapping(node)
        for key_node, value_node in node.value:
            key = _convert(file, key_node, problems)
            if not isinstance(key, (str, int, float, bool)) or isinstance(key, bool):
                problems.add(_mark(file, key_node), "a key must be a plain name or address")
                continue
            key_text = str(key)
            if key_text in result:
                problems.add(
                    _mark(file, key_node),
                    f"'{key_text}' appears twice (first at line {result.key_marks[key_text].line})",
                )
                continue
            result[key_text] = _convert(file, value_node, problems)
            result.key_marks[key_text] = _mark(file, key_node)
            result.value_marks[key_text] = _mark(file, value_node)
        return result
    if isinstance(node, yaml.SequenceNode):
        items = LocatedList()
        items.mark = _mark(file, node)
        items.item_marks = []
        for item_node in node.value:
            items.append(_convert(file, item_node, problems))
            items.item_marks.append(_mark(file, item_node))
        return items
    assert isinstance(node, yaml.ScalarNode)
    return _CONSTRUCTOR.construct_scalar(node) if node.tag == "tag:yaml.org,2002:str" else \
        _CONSTRUCTOR.construct_object(node, deep=True)


def load_text(text: str, file: str) -> tuple[Any, list[Problem]]:
    """Parse ``text``; return the located document and the problems found while parsing.

    A syntax error yields ``(None, [problem])`` with the parser's line and column.
    """
    problems = Problems()
    try:
        node = yaml.compose(text, Loader=yaml.SafeLoader)
    except yaml.MarkedYAMLError as error:
        mark = error.problem_mark or error.context_mark
        where = Mark(file, mark.line + 1, mark.column + 1) if mark else Mark(file, 1, 1)
        detail = error.problem or error.context or "not valid YAML"
        return None, [Problem(where, f"YAML syntax error: {detail}")]
    except yaml.YAMLError as error:
        return None, [Problem(Mark(file, 1, 1), f"YAML error: {error}")]
    if node is None:
        return None, [Problem(Mark(file, 1, 1), "the file is empty")]
    return _convert(file, node, problems), problems.items


def load_file(path: str) -> tuple[Any, list[Problem]]:
    """Read and parse a YAML file; an unreadable file is a problem, not an exception."""
    try:
        with open(path, encoding="utf-8") as handle:
            text = handle.read()
    except OSError as error:
        return None, [Problem(Mark(path, 1, 1), f"cannot read the file: {error.strerror}")]
    except UnicodeDecodeError as error:
        return None, [Problem(Mark(path, 1, 1), f"the file is not UTF-8 text ({error.reason})")]
    return load_text(text, path)
