"""YAML with source locations, and the collect-every-problem error model.

Machine files and scenario files are checked completely before anything runs: every
problem is collected with ``file:line:column`` and one :class:`SourceError` reports them
all (in the manner of FMPy's ``validation``).  PyYAML's composer gives nodes with marks;
this module turns them into plain values that remember where they came from, and
reports what PyYAML silently accepts (duplicate keys).

The reader is bounded (:mod:`vc.input_limits`): only regular files up to ``MAX_FILE_BYTES``
are read, collections nest at most ``MAX_NESTING`` deep, aliases may not expand a file
beyond ``MAX_VALUES`` values nor refer to the value they are part of, whole numbers have at
most ``MAX_INTEGER_DIGITS`` digits, and numbers are finite.  Only plain YAML is accepted:
text, numbers, true/false, null, lists and mappings (with ``<<`` merges); any other tag
(``!custom``, ``!!python/...``, ``!!binary``, ``!!set``) is a problem.  Whatever breaks one of
these rules is a problem at its line and column, never an exception.
"""

from __future__ import annotations

import math
import os
import stat
from collections.abc import Iterator
from dataclasses import dataclass
from typing import Any

import yaml

from interfaces.errors import VcError
from vc.escaping import terminal
from vc.input_limits import MAX_FILE_BYTES, MAX_INTEGER_DIGITS, MAX_NESTING, MAX_VALUES


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
        """``file:line:column: message`` on one line, whatever the file's name and the value the
        message echoes hold (a line break of a value would put the rest on a line of its own)."""
        return terminal(f"{self.mark}: {self.message}")


class SourceError(VcError):
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


def mark_at(text: str, position: int, file: str) -> Mark:
    """The mark of the character at ``position`` of ``text``, counting lines as PyYAML does."""
    before = text[:position]
    line = 0
    start = 0
    for index, character in enumerate(before):
        if character in "\n\x85\u2028\u2029" or (character == "\r" and text[index + 1:index + 2] != "\n"):
            line += 1
            start = index + 1
    return Mark(file, line + 1, len(before) - start + 1)


# ---------------------------------------------------------------------------------- composing

_YAML = "tag:yaml.org,2002:"
_STR, _NULL, _BOOL, _INT, _FLOAT = (f"{_YAML}{name}" for name in ("str", "null", "bool", "int", "float"))
_TIMESTAMP = f"{_YAML}timestamp"  # an unquoted date is text to the harness, which has no dates; !!timestamp is refused
_COLLECTION_TAGS = (f"{_YAML}seq", f"{_YAML}map")


class InputLimitError(VcError, yaml.YAMLError):
    """A file beyond a limit of :mod:`vc.input_limits`, or an alias that contains itself, at an event."""

    def __init__(self, message: str, event: yaml.Event):
        super().__init__(message)
        self.message = message
        mark = event.start_mark
        self.line, self.column = (mark.line, mark.column) if mark is not None else (0, 0)


# libyaml's parser where PyYAML was built with it (its wheels are): scanning and parsing are most
# of the time of loading a file, and libyaml does them many times as fast; the composer above it
# stays PyYAML's Python one, so the counting below sees every node.
try:
    from yaml._yaml import CParser

    class _Loader(yaml.composer.Composer, CParser, yaml.resolver.Resolver):
        def __init__(self, text: str):
            CParser.__init__(self, text)
            yaml.composer.Composer.__init__(self)
            yaml.resolver.Resolver.__init__(self)
except ImportError:  # PyYAML without libyaml: its Python reader, scanner and parser
    _Loader = yaml.SafeLoader  # type: ignore[misc, assignment]


class _BoundedLoader(_Loader):
    """PyYAML's composer counting: the nesting depth, and the values of the document with every
    alias expanded (an alias counts as often as it is used, with all it holds).  Composing stops
    at the first limit exceeded, before anything is expanded."""

    def __init__(self, text: str):
        super().__init__(text)
        self.depth = 0
        self.expanded = 0
        self.sizes: dict[int, int] = {}  # id(node) -> values the node stands for, aliases expanded
        self.open_anchors: set[str] = set()  # anchors of the collections being composed
        self.dated: set[int] = set()  # id(node) of the scalars tagged !!timestamp in the file

    def compose_node(self, parent: yaml.Node | None, index: int) -> yaml.Node | None:
        event = self.peek_event()  # the event to compose
        assert isinstance(event, yaml.NodeEvent)  # the composer asks for a node here
        anchor = event.anchor
        if isinstance(event, yaml.AliasEvent):
            if anchor in self.open_anchors:
                raise InputLimitError(f"the alias *{anchor} stands inside the value it names (a value cannot"
                                      " contain itself)", event)
            node = super().compose_node(parent, index)
            size = self.sizes[id(node)]
            self.count(size, event, f" (the alias *{anchor} repeats {size:,} values)")
            return node
        self.depth += 1
        if self.depth > MAX_NESTING:
            raise InputLimitError(f"more than {MAX_NESTING} lists and mappings inside one another", event)
        self.count(1, event, "")
        if anchor is not None:
            self.open_anchors.add(anchor)
        try:
            node = super().compose_node(parent, index)
        finally:
            self.depth -= 1
            if anchor is not None:
                self.open_anchors.discard(anchor)
        if isinstance(event, yaml.ScalarEvent) and event.tag == _TIMESTAMP:
            self.dated.add(id(node))
        children: list[yaml.Node] = []
        if isinstance(node, yaml.SequenceNode):
            children = node.value
        elif isinstance(node, yaml.MappingNode):
            children = [item for pair in node.value for item in pair]
        self.sizes[id(node)] = 1 + sum(self.sizes[id(child)] for child in children)
        return node

    def count(self, values: int, event: yaml.Event, why: str) -> None:
        self.expanded += values
        if self.expanded > MAX_VALUES:
            raise InputLimitError(f"the file holds more than {MAX_VALUES:,} values with its aliases"
                                  f" expanded{why}", event)


_CONSTRUCTOR = yaml.SafeLoader(" ")


def _shown_tag(tag: str) -> str:
    return f"!!{tag[len(_YAML):]}" if tag.startswith(_YAML) else tag


class _Converter:
    """Turns composed nodes into located values; bad scalars and tags become problems."""

    def __init__(self, file: str, problems: Problems, dated: set[int]):
        self.file = file
        self.problems = problems
        self.dated = dated  # scalars tagged !!timestamp in the file (an unquoted date is text)
        self.refused = False  # a value could not be read: the document is not returned

    def refuse(self, node: yaml.Node, message: str) -> None:
        self.problems.add(_mark(self.file, node), message)
        self.refused = True

    def convert(self, node: yaml.Node) -> Any:
        if isinstance(node, yaml.ScalarNode):
            return self.scalar(node)
        if node.tag not in _COLLECTION_TAGS:
            self.refuse(node, f"unknown YAML tag {_shown_tag(node.tag)} (the harness reads plain lists and mappings)")
        if isinstance(node, yaml.MappingNode):
            return self.mapping(node)
        items = LocatedList()
        items.mark = _mark(self.file, node)
        items.item_marks = []
        for item_node in node.value:
            items.append(self.convert(item_node))
            items.item_marks.append(_mark(self.file, item_node))
        return items

    def mapping(self, node: yaml.MappingNode) -> LocatedMap:
        result = LocatedMap()
        result.mark = _mark(self.file, node)
        result.key_marks = {}
        result.value_marks = {}
        _CONSTRUCTOR.flatten_mapping(node)  # ``<<`` merges; the composer has bounded what they copy
        for key_node, value_node in node.value:
            key = self.convert(key_node)
            if not isinstance(key, (str, int, float, bool)) or isinstance(key, bool):
                self.problems.add(_mark(self.file, key_node), "a key must be a plain name or address")
                continue
            key_text = str(key)
            if key_text in result:
                self.problems.add(
                    _mark(self.file, key_node),
                    f"'{key_text}' appears twice (first at line {result.key_marks[key_text].line})",
                )
                continue
            result[key_text] = self.convert(value_node)
            result.key_marks[key_text] = _mark(self.file, key_node)
            result.value_marks[key_text] = _mark(self.file, value_node)
        return result

    def scalar(self, node: yaml.ScalarNode) -> Any:
        tag, text = node.tag, node.value
        if tag == _STR or (tag == _TIMESTAMP and id(node) not in self.dated):
            return text
        if tag == _NULL:
            return None
        if tag == _BOOL:
            return _CONSTRUCTOR.construct_yaml_bool(node)
        if tag == _INT:
            body = text.lstrip("+-")
            if body[:2].lower() in ("0x", "0o", "0b"):
                body = body[2:]
            digits = sum(character.isalnum() for character in body)  # hex digits; ':' and '_' do not count
            if digits > MAX_INTEGER_DIGITS:
                self.refuse(node, f"a whole number of {digits:,} digits; at most {MAX_INTEGER_DIGITS} are read")
                return None
            number: int = _CONSTRUCTOR.construct_yaml_int(node)
            if len(str(abs(number))) > MAX_INTEGER_DIGITS:
                self.refuse(node, f"{text} has more than {MAX_INTEGER_DIGITS} digits")
                return None
            return number
        if tag == _FLOAT:
            value: float = _CONSTRUCTOR.construct_yaml_float(node)
            if not math.isfinite(value):
                self.refuse(node, f"'{text}' is not a finite number (the harness reads no infinity and no NaN)")
                return None
            return value
        self.refuse(node, f"unknown YAML tag {_shown_tag(tag)} (the harness reads plain text, numbers,"
                          " true/false, lists and mappings)")
        return None


def load_text(text: str, file: str) -> tuple[Any, list[Problem]]:
    """Parse ``text``; return the located document and the problems found while parsing.

    A syntax error or an input beyond a limit yields ``(None, [problem])`` with its line and
    column; bad values (unknown tags, numbers too long or not finite) yield ``None`` and a
    problem for each.  Duplicate keys are problems beside the document.
    """
    problems = Problems()
    loader = _BoundedLoader(text) if _printable(text, file, problems) else None
    if loader is None:
        return None, problems.items
    try:
        node = loader.get_single_node()
    except InputLimitError as error:
        return None, [Problem(Mark(file, error.line + 1, error.column + 1), error.message)]
    except yaml.MarkedYAMLError as error:
        mark = error.problem_mark or error.context_mark
        where = _within(text, Mark(file, mark.line + 1, mark.column + 1)) if mark else Mark(file, 1, 1)
        detail = error.problem or error.context or "not valid YAML"
        if _character_at(text, where) == "\t":
            detail = "a tab character here: YAML indents with spaces, never with tabs"
        return None, [Problem(where, f"YAML syntax error: {detail}")]
    except yaml.YAMLError as error:
        return None, [Problem(Mark(file, 1, 1), f"YAML error: {error}")]
    finally:
        loader.dispose()
    if node is None:
        return None, [Problem(Mark(file, 1, 1), "the file is empty")]
    converter = _Converter(file, problems, loader.dated)
    try:
        document = converter.convert(node)
    except yaml.MarkedYAMLError as error:  # a << merge of something that is not a mapping
        mark = error.problem_mark or error.context_mark
        where = Mark(file, mark.line + 1, mark.column + 1) if mark is not None else _mark(file, node)
        return None, [*problems.items, Problem(where, str(error.problem or error.context))]
    if converter.refused:
        return None, problems.items
    if document is None:  # ``null``, ``~`` or a bare ``---``
        if node.value:
            return None, [Problem(_mark(file, node), f"the document is empty (it holds only '{node.value}')")]
        return None, [Problem(Mark(file, 1, 1), "the document is empty")]
    return document, problems.items


def _within(text: str, mark: Mark) -> Mark:
    """``mark``, or where the text ends when the mark lies beyond it: the parser marks the end of a
    file that ends with a line break at the start of a line that is not there."""
    lines = text.split("\n")
    if text.endswith("\n"):
        lines.pop()
    if mark.line <= max(len(lines), 1):
        return mark
    return Mark(mark.file, len(lines), len(lines[-1]) + 1)


def _character_at(text: str, mark: Mark) -> str:
    lines = text.split("\n")
    line = lines[mark.line - 1] if mark.line <= len(lines) else ""
    return line[mark.column - 1:mark.column]


def _printable(text: str, file: str, problems: Problems) -> bool:
    """Whether ``text`` holds only characters YAML allows; else a problem at the first other one."""
    match = yaml.reader.Reader.NON_PRINTABLE.search(text)
    if match is None:
        return True
    code = ord(match.group())
    problems.add(mark_at(text, match.start(), file), f"a control character (U+{code:04X}) that YAML does not allow")
    return False


def read_source(path: str, what: str = "file") -> tuple[str | None, list[Problem]]:
    """The text of the regular file ``path`` (UTF-8, lines ending in ``\\n``), or a problem
    whose message names the file as ``the {what}``.

    Devices, FIFOs and directories are refused without reading from them (``/dev/zero`` never
    ends), as is a file over ``MAX_FILE_BYTES``.
    """
    where = Mark(path, 1, 1)
    try:
        # O_NONBLOCK: opening a FIFO for reading would otherwise wait for a writer
        descriptor = os.open(path, os.O_RDONLY | getattr(os, "O_NONBLOCK", 0))
    except OSError as error:
        return None, [Problem(where, f"cannot read the {what} ({error.strerror})")]
    mode = os.fstat(descriptor).st_mode
    if not stat.S_ISREG(mode):
        os.close(descriptor)
        kind = "a directory" if stat.S_ISDIR(mode) else "a device, FIFO or socket"
        return None, [Problem(where, f"cannot read the {what}: it is {kind}, not a regular file")]
    try:
        with os.fdopen(descriptor, "rb") as handle:
            data = handle.read(MAX_FILE_BYTES + 1)
    except OSError as error:  # a regular file the kernel will not read (/proc/self/mem)
        return None, [Problem(where, f"cannot read the {what} ({error.strerror})")]
    if len(data) > MAX_FILE_BYTES:
        return None, [Problem(where, f"the {what} is larger than {MAX_FILE_BYTES:,} bytes, the most the harness reads")]
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError as error:
        line_start = data.rfind(b"\n", 0, error.start) + 1
        column = len(data[line_start:error.start].decode("utf-8", errors="replace")) + 1
        mark = Mark(path, data.count(b"\n", 0, error.start) + 1, column)
        return None, [Problem(mark, f"the {what} is not UTF-8 text ({error.reason})")]
    return text.replace("\r\n", "\n").replace("\r", "\n"), []


def load_file(path: str) -> tuple[Any, list[Problem]]:
    """Read and parse a YAML file; an unreadable file is a problem, not an exception."""
    text, problems = read_source(path)
    if text is None:
        return None, problems
    return load_text(text, path)
