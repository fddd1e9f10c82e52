"""Part-program text to blocks of words (SINUMERIK syntax, as far as the sequences need it).

A block is one line.  Its items::

    N10                      block number
    G1  X100.5  Z-2  F.5     address words: one letter followed by a number ("X1" is X = 1),
    G1X10.5Z-2               also without blanks between them
    X1=100  DILF=10  M2=3    assignments: a name (letters and digits) '=' a value
    SPOS[2]=IC(-90)          assignment with an index and a value function (AC, IC, DC, ACP, ACN)
    FA[S2]=3600  POLF[X]=10  index by name
    FINEA[X]                 a keyword with an index (no value)
    COUPON(S2,S1,77)         a call with arguments (names, numbers, "strings")
    LFON  STOPRE             a keyword (a name that is not an address word)
    MM_THREAD:               a label
    IF $AC_LIFTFAST GOTOB MM_THREAD
    GOTOF N100               a jump (GOTOB back, GOTOF forward, GOTO / GOTOC forward then back)
                             to a label or block number, with or without a condition (kept as
                             text for vc/core/program/sync_actions.py); a label may stand before it
    IDS=2 WHENEVER $A_IN[1]==1 DO $AC_ESR_TRIGGER=1
                             a synchronized action: kept as condition and action text for
                             vc/core/program/sync_actions.py (ID= modal, IDS= static)
    ; comment                everything after ';' is a comment

Parsing only checks the form; what a word means is the interpreter's business, so a new
NC function adds a handler there and no syntax here.  A malformed block is kept with its
error so that the control raises alarm 12080 when (and only when) execution reaches it.  A
number beyond ``MAX_MAGNITUDE`` (a run of hundreds of digits) is malformed too: as a double it
would be infinite, or overflow the motion's arithmetic.
"""

from __future__ import annotations

import re
from dataclasses import dataclass

from interfaces.errors import VcError
from vc.input_limits import MAX_MAGNITUDE

_WHOLE = r"\d{1,18}(?!\d)"  # a block or action number: longer runs of digits are no number of the control
_NUMBER = r"[+-]?(?:\d+\.?\d*|\.\d+)"
_NAME = r"[A-Z_$][A-Z0-9_$]*"
# Address words, one or several written without blanks: "X100.5", "G1X10.5Z-2", "Y100." (a number
# may end in its decimal point).  Not when the run goes on as a name ("X10ABC", "S1_SPEED") or is
# a name followed by '=', '(', '[' or ':' ("X1=5", "M2=3", "R1[2]").
_ADDRESS_WORD = rf"[A-Z]{_NUMBER}"
_TOKEN = re.compile(
    rf"\s*(?:(?P<words>(?:{_ADDRESS_WORD})+(?![A-Z0-9_$.])(?!\s*[=(\[:]))|(?P<number>{_NUMBER})|(?P<name>{_NAME})"
    r"|(?P<string>\"[^\"]*\")|(?P<symbol>[=\[\](),:]))",
    re.IGNORECASE,
)
_ONE_ADDRESS_WORD = re.compile(rf"([A-Z])({_NUMBER})", re.IGNORECASE)
_BLOCK_NUMBER = re.compile(rf"^\s*N({_WHOLE})", re.IGNORECASE)
_SYNCHRONIZED_ACTION = re.compile(
    rf"^(?:N(?P<block>{_WHOLE})\s+)?(?P<kind>IDS|ID)\s*=\s*(?P<number>{_WHOLE})\s+(?P<mode>WHENEVER|WHEN|EVERY|FROM)\s+"
    r"(?P<condition>.+?)\s+DO\s+(?P<actions>.+)$", re.IGNORECASE)
_JUMP = re.compile(
    rf"^(?:N(?P<block>{_WHOLE})\s+)?(?:(?P<label>[A-Z_][A-Z0-9_]*)\s*:\s*)?(?:IF\s+(?P<condition>.+?)\s+)?"
    r"(?P<direction>GOTOB|GOTOF|GOTOC|GOTO)\s+(?P<target>[A-Z_][A-Z0-9_]*)$", re.IGNORECASE)

Argument = float | str


@dataclass(frozen=True, slots=True)
class ValueFunction:
    """``IC(5)``, ``AC(10)``, ``DC(90)``, ``ACP(0)``, ``ACN(180)`` as a value."""

    name: str
    value: float


Value = float | ValueFunction | str


@dataclass(frozen=True, slots=True)
class Word:
    """``X100``: one-letter address and number."""

    address: str
    value: float


@dataclass(frozen=True, slots=True)
class Assignment:
    """``X1=100``, ``SPOS[2]=IC(-90)``, ``M2=3``."""

    name: str
    index: str  # "" if none, else the index as written ("2", "S2", "X")
    value: Value


@dataclass(frozen=True, slots=True)
class Call:
    """``COUPON(S2,S1,77)``."""

    name: str
    arguments: tuple[Argument, ...]


@dataclass(frozen=True, slots=True)
class Keyword:
    """``LFON``; with an index ``FINEA[X]`` (a word about one axis that takes no value)."""

    name: str
    index: str = ""


@dataclass(frozen=True, slots=True)
class Label:
    name: str


@dataclass(frozen=True, slots=True)
class SynchronizedAction:
    """``IDS=2 WHENEVER <condition> DO <actions>``: the words after the identifier as written."""

    number: int  # the ID / IDS number
    static: bool  # IDS: stays active beyond the program (reset, program end)
    mode: str  # WHENEVER, WHEN, EVERY or FROM
    condition: str
    actions: str


@dataclass(frozen=True, slots=True)
class Jump:
    """``IF <condition> GOTOB <label>``, ``GOTOF N100``: a program jump, conditional or not."""

    direction: str  # GOTOB, GOTOF, GOTO or GOTOC
    target: str  # a label, or N and a block number
    condition: str = ""  # "" = always


Item = Word | Assignment | Call | Keyword | Label | SynchronizedAction | Jump


@dataclass(frozen=True, slots=True)
class Block:
    line: int  # 1-based line in the program text
    text: str  # the line as written, for alarms
    number: int | None  # N number
    items: tuple[Item, ...]
    error: str = ""  # syntax error: execution of this block raises alarm 12080

    @property
    def label(self) -> str:
        """Block number as the control shows it in alarms (N10, or the line)."""
        return f"N{self.number}" if self.number is not None else f"line {self.line}"


class _SyntaxError(VcError):
    pass


def jump_target(blocks: tuple[Block, ...], current: int, jump: Jump) -> int | None:
    """Index of the block ``jump`` (at ``current``) goes to, or None: GOTOB searches back towards the
    program start, GOTOF forward to its end, GOTO and GOTOC forward first, then back [control].
    Searching back starts at the jump's own block, whose label stands before the jump: ``MM: IF
    $A_IN[1]==0 GOTOB MM`` waits in its block [control]."""
    def is_target(block: Block) -> bool:
        if jump.target.startswith("N") and jump.target[1:].isdigit():
            return block.number == int(jump.target[1:])
        return any(isinstance(item, Label) and item.name == jump.target for item in block.items)

    backward = range(current, -1, -1)
    forward = range(current + 1, len(blocks))
    searched = {"GOTOB": (backward,), "GOTOF": (forward,)}.get(jump.direction, (forward, backward))
    for indices in searched:
        for index in indices:
            if is_target(blocks[index]):
                return index
    return None


def parse_program(text: str) -> tuple[Block, ...]:
    """Every non-empty line becomes a block; comments and blank lines are dropped."""
    blocks = []
    for line_number, raw in enumerate(text.splitlines(), start=1):
        code = raw.split(";", 1)[0].strip()
        if not code:
            continue
        action = _SYNCHRONIZED_ACTION.match(code)
        if action is not None:
            number = int(action.group("block")) if action.group("block") else None
            blocks.append(Block(line_number, raw.strip(), number, (SynchronizedAction(
                int(action.group("number")), action.group("kind").upper() == "IDS", action.group("mode").upper(),
                action.group("condition").strip(), action.group("actions").strip()),)))
            continue
        jump = _JUMP.match(code)
        if jump is not None:
            number = int(jump.group("block")) if jump.group("block") else None
            label = (Label(jump.group("label").upper()),) if jump.group("label") else ()
            blocks.append(Block(line_number, raw.strip(), number, (*label, Jump(
                jump.group("direction").upper(), jump.group("target").upper(),
                (jump.group("condition") or "").strip()))))
            continue
        try:
            number, items = _parse_line(code)
            blocks.append(Block(line_number, raw.strip(), number, items))
        except _SyntaxError as error:
            # The block keeps its number, so alarm 12080 names it as the control does.
            number_match = _BLOCK_NUMBER.match(code)
            number = int(number_match.group(1)) if number_match else None
            blocks.append(Block(line_number, raw.strip(), number, (), str(error)))
    return tuple(blocks)


def tokenize(pattern: re.Pattern[str], code: str, error: type[Exception]) -> list[tuple[str, str]]:
    """(group name, text) for each match of ``pattern`` (named alternatives) between blanks;
    ``error`` with the rest of the text where nothing matches."""
    tokens: list[tuple[str, str]] = []
    position = 0
    while position < len(code):
        if code[position].isspace():
            position += 1
            continue
        match = pattern.match(code, position)
        if match is None or match.end() == position:
            raise error(code[position:])
        kind = match.lastgroup
        assert kind is not None
        tokens.append((kind, match.group(kind)))
        position = match.end()
    return tokens


def _tokens(code: str) -> list[tuple[str, str]]:
    return tokenize(_TOKEN, code, _SyntaxError)


def _number(text: str) -> float:
    return number(text, _SyntaxError)


def number(text: str, error: type[Exception]) -> float:
    """The number ``text`` of a block; ``error`` for one beyond MAX_MAGNITUDE."""
    value = float(text)
    if not abs(value) <= MAX_MAGNITUDE:
        shown = text if len(text) <= 24 else f"{text[:20]}... ({len(text)} digits)"
        raise error(f"{shown}: beyond {MAX_MAGNITUDE:g}")
    return value


def _split_address_words(tokens: list[tuple[str, str]]) -> list[tuple[str, str]]:
    """Split a run of address words (``G1X10.5``) into address and number tokens.

    Inside brackets it is a name (``FA[S2]``, ``COUPON(S2,S1)``); ``SP1`` (two letters) and
    ``X1=5`` (an assignment) are names to the tokenizer already.  ``X -10``: a single letter
    followed by a number is an address word too.
    """
    result: list[tuple[str, str]] = []
    depth = 0  # inside (...) or [...] names are arguments or indices: S2 stays S2
    index = 0
    while index < len(tokens):
        kind, text = tokens[index]
        if text in ("(", "["):
            depth += 1
        elif text in (")", "]"):
            depth -= 1
        following = tokens[index + 1] if index + 1 < len(tokens) else ("", "")
        if kind == "words":
            if depth:
                result.append(("name", text.upper()))
            else:
                for letter, number in _ONE_ADDRESS_WORD.findall(text):
                    result.extend((("address", letter.upper()), ("number", number)))
            index += 1
            continue
        if kind == "name" and depth == 0 and len(text) == 1 and following[0] == "number":
            result.append(("address", text.upper()))
            index += 1
            continue
        result.append((kind, text.upper() if kind == "name" else text))
        index += 1
    return result


def _parse_line(code: str) -> tuple[int | None, tuple[Item, ...]]:
    tokens = _split_address_words(_tokens(code))
    items: list[Item] = []
    number: int | None = None
    index = 0
    while index < len(tokens):
        kind, text = tokens[index]
        if kind == "address":
            value_kind, value_text = tokens[index + 1] if index + 1 < len(tokens) else ("", "")
            if value_kind != "number":
                raise _SyntaxError(f"{text}{value_text}")
            if text == "N" and not items and number is None:
                number = int(_number(value_text))
            else:
                items.append(Word(text, _number(value_text)))
            index += 2
            continue
        if kind != "name":
            raise _SyntaxError(text)
        following = tokens[index + 1][1] if index + 1 < len(tokens) else ""
        if following == ":":
            items.append(Label(text))
            index += 2
        elif following == "(":
            arguments, index = _arguments(tokens, index + 2)
            items.append(Call(text, tuple(arguments)))
        elif following in ("=", "["):
            item, index = _assignment(tokens, index)
            items.append(item)
        elif len(text) == 1:
            raise _SyntaxError(f"{text}: a value is missing")  # every single letter is an address
        else:
            items.append(Keyword(text))
            index += 1
    return number, tuple(items)


def _arguments(tokens: list[tuple[str, str]], index: int) -> tuple[list[Argument], int]:
    """Arguments up to the closing ')'; empty arguments (``WAITC(S2, ,S4)``) read as ''."""
    arguments: list[Argument] = []
    expect_value = True
    while index < len(tokens):
        kind, text = tokens[index]
        if text == ")":
            if expect_value and arguments:
                arguments.append("")  # a trailing empty argument: f(a, )
            return arguments, index + 1
        if text == ",":
            if expect_value:
                arguments.append("")
            expect_value = True
        elif not expect_value:
            raise _SyntaxError(text)
        elif kind == "number":
            arguments.append(_number(text))
            expect_value = False
        elif kind == "string":
            arguments.append(text[1:-1])
            expect_value = False
        elif kind in ("name", "address"):
            arguments.append(text.upper())
            expect_value = False
        else:
            raise _SyntaxError(text)
        index += 1
    raise _SyntaxError("missing ')'")


def _assignment(tokens: list[tuple[str, str]], index: int) -> tuple[Assignment | Keyword, int]:
    name = tokens[index][1]
    index += 1
    subscript = ""
    if tokens[index][1] == "[":
        if index + 2 >= len(tokens) or tokens[index + 2][1] != "]":
            raise _SyntaxError(f"{name}[")
        subscript = tokens[index + 1][1].upper()
        index += 3
        if index >= len(tokens) or tokens[index][1] != "=":
            return Keyword(name, subscript), index  # FINEA[X]: an indexed word without a value
    if index >= len(tokens) or tokens[index][1] != "=":
        raise _SyntaxError(f"{name}: '=' expected")
    index += 1
    if index >= len(tokens):
        raise _SyntaxError(f"{name}=: a value is missing")
    kind, text = tokens[index]
    if kind == "number":
        return Assignment(name, subscript, _number(text)), index + 1
    if kind == "string":
        return Assignment(name, subscript, text[1:-1]), index + 1
    if kind in ("name", "address") and index + 1 < len(tokens) and tokens[index + 1][1] == "(":
        arguments, end = _arguments(tokens, index + 2)
        if len(arguments) != 1 or not isinstance(arguments[0], float):
            raise _SyntaxError(f"{name}={text}(...)")
        return Assignment(name, subscript, ValueFunction(text.upper(), arguments[0])), end
    if kind in ("name", "address"):
        return Assignment(name, subscript, text.upper()), index + 1
    raise _SyntaxError(f"{name}={text}")
