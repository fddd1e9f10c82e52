"""The file part of the robustness campaign: mutated scenario and machine files through ``vc run``.

Every mutant is derived from a shipped file (``scenarios/**/*.yaml``, ``scenarios/machines/*.yaml``)
by one mutation, chosen with a random generator seeded per mutant (``f"{seed}/{number}"``), so a
seed gives the same mutants in the same order whatever the count:

=====================  ==========================================================================
mutation               what it does
=====================  ==========================================================================
byte_flip              1 to 3 bytes XORed with a random value (may break UTF-8 or the syntax)
truncate               the file cut at a random byte
delete_lines           1 to 3 lines deleted
duplicate_line         a line written twice (duplicate keys, steps twice)
swap_lines             two lines swapped
deep_nesting           a value replaced by 100 to 5,000 nested flow lists or mappings
alias_bomb             a "billion laughs" (nine levels of nine aliases, in lists or ``<<`` merges)
recursive_alias        a value replaced by an alias inside the value it names (``&r [*r]``)
huge_number            a value replaced by a whole number of 25 to 5,000 digits, or ``1.0e+400``
unknown_tag            a value tagged ``!custom``, ``!!python/name:os.system``, ``!!binary`` ...
control_character      a NUL or another control character inserted anywhere
non_finite             a value replaced by ``.inf``, ``-.inf`` or ``.nan``
number_edge            a value replaced by 0, -1, 1e-320, 2^31, 20 digits, ``1e400`` as text
type_confusion         a value replaced by a list, a mapping, null, true or a text
empty_document         the file replaced by nothing, a comment, ``null``, ``~`` or ``---``
long_expression        a condition replaced by 500 nested parentheses or 2,000 ``and`` terms
program_text           an ``mda`` or program ``text`` with a number of 300 to 5,000 digits, a
                       synchronized action of 600 parentheses or 300 terms, or random characters
special_file           the machine file (or a program file) is /dev/zero, /dev/null, a FIFO, ...
false_pass_probe       a scenario of the base's machine and PLC whose only check cannot fail
                       (``.inf`` as expected value, ``"<= 1"`` on a bool, ``min: 0s`` alone ...)
=====================  ==========================================================================

A machine file's mutant is run through a scenario of the library that uses that machine, its
``machine:`` pointed at the mutant.  Each mutant goes the way of ``vc run`` in this process: the
files are loaded and checked (``load_scenarios`` with the registry of PLC programs); a file with
problems is reported by the console report as ``vc run`` reports it (exit 2); a file that loads
is run by the harness with its timeout cut to ``run_seconds`` of simulated time (exit 0 or 1).
A wall-clock bound (``bound_s``) interrupts a mutant that takes longer (SIGALRM; the campaign
must run in the main thread).  Outcomes:

=================  =================================================================================
outcome            when
=================  =================================================================================
problems           refused with located problems, each plausible (below): what bad input must give
passed, failed     it loaded and ran: exit 0 or 1 (a mutation may leave a sound scenario)
crash              an exception escaped the ``vc run`` path (it would end ``vc run`` with a traceback)
traceback          the run printed a traceback (the harness could not build or run the simulation)
hang               the mutant took longer than ``bound_s`` of wall time
false_pass         a ``false_pass_probe`` passed (its check cannot fail, so it must be refused)
wrong_location     a problem names a file the run does not read, a line or column outside the file,
                   a character offset instead of a line, or the report printed its location otherwise
                   than written (an emoji for ``:100:``); or a mutation whose place is known (a
                   control character, a tag, a number, nesting, an alias) got no problem there
=================  =================================================================================
"""

from __future__ import annotations

import contextlib
import dataclasses
import io
import os
import random
import re
import shutil
import signal
import tempfile
import threading
import time
import traceback
from collections import Counter
from collections.abc import Callable, Iterator, Sequence
from dataclasses import dataclass
from pathlib import Path
from types import FrameType

import yaml

from interfaces.links.inprocess import plc_programs
from vc.harness.targets import simulation_for
from vc.located_yaml import Problem, SourceError
from vc.scenario.language.durations import Duration
from vc.scenario.language.loader import load_scenarios
from vc.scenario.outputs.report import ConsoleReport
from vc.scenario.run.runner import run_scenarios

DEFAULT_BOUND_S = 30.0  # wall seconds a mutant may take before it counts as a hang
DEFAULT_RUN_SECONDS = 2.0  # simulated seconds a mutant that loads may run
MACHINE_SHARE = 0.2  # of the mutants, the share made from machine files
BASES_TRIED = 50  # files a mutation is tried on before another mutation is chosen (few scenarios have an mda)
OUTCOMES = ("problems", "passed", "failed", "crash", "traceback", "hang", "false_pass", "wrong_location")
BAD_OUTCOMES = ("crash", "traceback", "hang", "false_pass", "wrong_location")
FIGURES = ("inputs", "crashes", "hangs", "tracebacks", "false_passes", "wrong_locations", "problems", "passed",
           "failed", "seconds")
_FIGURE_OF = {"crash": "crashes", "hang": "hangs", "traceback": "tracebacks", "false_pass": "false_passes",
              "wrong_location": "wrong_locations", "problems": "problems", "passed": "passed", "failed": "failed"}
_PRINTABLE_CONTROL = "\x00\x01\x02\x07\x08\x0b\x0c\x0e\x1b\x1f\x7f\x80\x9f"  # none of them YAML allows
_OFFSET_MESSAGE = re.compile(r"position \d+|<unicode string>|Traceback")
_LINE_BREAKING = re.compile("[\x00-\x1f\x7f-\x9f\u2028\u2029]")  # a control character or a line break


def default_root() -> Path:
    """The shipped scenarios directory of this checkout."""
    return Path(__file__).resolve().parents[3] / "scenarios"


# ---------------------------------------------------------------------------------- mutants


@dataclass(frozen=True, slots=True)
class Mutant:
    number: int
    kind: str
    base: str  # the shipped file it is made from, relative to the scenarios directory
    target: str  # "scenario" or "machine": which kind of file is mutated
    data: bytes  # the mutated file
    expected_line: int | None = None  # a problem must be reported at this line of the mutated file ...
    expected_lines: tuple[int, int] | None = None  # ... or within these lines
    expected_column: int | None = None  # ... and this column
    must_not_pass: bool = False  # a false-pass probe
    special_path: str = ""  # special_file: the path the mutant names


@dataclass(frozen=True, slots=True)
class _Slot:
    """A scalar value written on one line: where to put a mutation of a value."""

    line: int  # 0-based
    start: int  # column of its first character, 0-based
    end: int  # column after its last character
    tag: str  # the tag PyYAML resolved (int, float, str, bool, null)
    text: str  # the value as written
    key: str  # the key it is the value of (of its list, for an item of a list)


@dataclass(slots=True)
class _Base:
    path: str  # relative to the scenarios directory
    text: str
    slots: list[_Slot]


def _slots(text: str) -> list[_Slot]:
    """Every scalar value of a mapping or list written on one line, without anchor or tag (keys excluded)."""
    root = yaml.compose(text, Loader=yaml.SafeLoader)
    lines = text.split("\n")
    slots: list[_Slot] = []
    pending: list[tuple[yaml.Node, str]] = [(root, "")] if root is not None else []
    while pending:
        node, key = pending.pop()
        if isinstance(node, yaml.MappingNode):
            pending.extend((value, str(name.value)) for name, value in node.value)
        elif isinstance(node, yaml.SequenceNode):
            pending.extend((item, key) for item in node.value)
        elif isinstance(node, yaml.ScalarNode) and node.style in (None, "'", '"'):
            start, end = node.start_mark, node.end_mark
            if start is None or end is None or start.line != end.line or end.column <= start.column:
                continue
            written = lines[start.line][start.column:end.column]
            if not written.startswith(("&", "*", "!")):
                slots.append(_Slot(start.line, start.column, end.column, node.tag.rsplit(":", 1)[-1], written, key))
    return sorted(slots, key=lambda slot: (slot.line, slot.start))


def _replace(text: str, slot: _Slot, value: str) -> str:
    lines = text.split("\n")
    line = lines[slot.line]
    lines[slot.line] = line[:slot.start] + value + line[slot.end:]
    return "\n".join(lines)


@dataclass(frozen=True, slots=True)
class _Made:
    """What a mutation made: the text (or bytes) and where its problem must be."""

    data: bytes
    expected_line: int | None = None
    expected_lines: tuple[int, int] | None = None
    expected_column: int | None = None
    must_not_pass: bool = False
    special_path: str = ""


Mutation = Callable[[random.Random, _Base, str], _Made | None]  # (rng, base, target) -> mutant or None


def _byte_flip(rng: random.Random, base: _Base, target: str) -> _Made:
    data = bytearray(base.text.encode("utf-8"))
    for _ in range(rng.randint(1, 3)):
        position = rng.randrange(len(data))
        data[position] ^= rng.randint(1, 255)
    return _Made(bytes(data))


def _truncate(rng: random.Random, base: _Base, target: str) -> _Made:
    data = base.text.encode("utf-8")
    return _Made(data[:rng.randrange(len(data))])


def _lines(base: _Base) -> list[str]:
    return base.text.split("\n")


def _delete_lines(rng: random.Random, base: _Base, target: str) -> _Made:
    lines = _lines(base)
    for _ in range(rng.randint(1, 3)):
        if len(lines) > 1:
            del lines[rng.randrange(len(lines))]
    return _Made("\n".join(lines).encode("utf-8"))


def _duplicate_line(rng: random.Random, base: _Base, target: str) -> _Made:
    lines = _lines(base)
    index = rng.randrange(len(lines))
    lines.insert(index, lines[index])
    return _Made("\n".join(lines).encode("utf-8"))


def _swap_lines(rng: random.Random, base: _Base, target: str) -> _Made:
    lines = _lines(base)
    first, second = rng.randrange(len(lines)), rng.randrange(len(lines))
    lines[first], lines[second] = lines[second], lines[first]
    return _Made("\n".join(lines).encode("utf-8"))


def _in_slot(rng: random.Random, base: _Base, value: str, numeric: bool = False, known: bool = True) -> _Made | None:
    """``value`` written over a random value (a number if ``numeric`` and there is one)."""
    slots = [slot for slot in base.slots if slot.tag in ("int", "float")] if numeric else []
    slots = slots or base.slots
    if not slots:
        return None
    slot = rng.choice(slots)
    text = _replace(base.text, slot, value)
    return _Made(text.encode("utf-8"), expected_line=slot.line + 1 if known else None)


def _deep_nesting(rng: random.Random, base: _Base, target: str) -> _Made | None:
    depth = rng.choice((100, 1000, 5000))
    value = "[" * depth + "1" + "]" * depth if rng.random() < 0.5 else "{a: " * depth + "1" + "}" * depth
    return _in_slot(rng, base, value)


def _bomb_lines(rng: random.Random) -> list[str]:
    if rng.random() < 0.5:
        lines = ["lol0: &lol0 [lol]"]
        lines += [f"lol{i}: &lol{i} [{', '.join([f'*lol{i - 1}'] * 9)}]" for i in range(1, 10)]
    else:
        lines = ["lol0: &lol0 {x: lol}"]
        lines += [f"lol{i}: &lol{i} {{<<: [{', '.join([f'*lol{i - 1}'] * 9)}]}}" for i in range(1, 10)]
    return lines


def _alias_bomb(rng: random.Random, base: _Base, target: str) -> _Made:
    bomb = _bomb_lines(rng)
    return _Made("\n".join([*bomb, base.text]).encode("utf-8"), expected_lines=(1, len(bomb)))


def _recursive_alias(rng: random.Random, base: _Base, target: str) -> _Made | None:
    return _in_slot(rng, base, rng.choice(("&r [*r]", "&r {a: *r}", "&r [1, [2, *r]]")))


def _huge_number(rng: random.Random, base: _Base, target: str) -> _Made | None:
    digits = rng.choice((25, 100, 4301, 5000))
    value = rng.choice(("", "-")) + str(rng.randint(1, 9)) + "".join(str(rng.randint(0, 9)) for _ in range(digits - 1))
    return _in_slot(rng, base, rng.choice((value, "1.0e+400", "-1.0e+999")), numeric=True)


def _unknown_tag(rng: random.Random, base: _Base, target: str) -> _Made | None:
    tag = rng.choice(("!custom", "!!python/name:os.system", "!!python/object/apply:os.system", "!!binary",
                      "!!set", "!!timestamp", "!<tag:example.com,2024:x>"))
    slots = base.slots
    if not slots:
        return None
    slot = rng.choice(slots)
    text = _replace(base.text, slot, f"{tag} {slot.text}")
    return _Made(text.encode("utf-8"), expected_line=slot.line + 1)


def _control_character(rng: random.Random, base: _Base, target: str) -> _Made:
    lines = _lines(base)
    index = rng.randrange(len(lines))
    column = rng.randint(0, len(lines[index]))
    lines[index] = lines[index][:column] + rng.choice(_PRINTABLE_CONTROL) + lines[index][column:]
    return _Made("\n".join(lines).encode("utf-8"), expected_line=index + 1, expected_column=column + 1)


def _non_finite(rng: random.Random, base: _Base, target: str) -> _Made | None:
    return _in_slot(rng, base, rng.choice((".inf", "-.inf", ".nan", ".NaN", "+.Inf")), numeric=True)


def _number_edge(rng: random.Random, base: _Base, target: str) -> _Made | None:
    value = rng.choice(("0", "-1", "1.0e-320", "-0.0", "2147483648", "99999999999999999999", "1e400", "'1e400'",
                        "1e-400", "0x7fffffffffffffff"))
    return _in_slot(rng, base, value, numeric=True, known=False)


def _type_confusion(rng: random.Random, base: _Base, target: str) -> _Made | None:
    return _in_slot(rng, base, rng.choice(("[]", "{}", "null", "true", "'text'", "[1, [2]]", "{a: 1}", "''")),
                    known=False)


def _empty_document(rng: random.Random, base: _Base, target: str) -> _Made:
    text = rng.choice(("", "\n", "# nothing but a comment\n", "null\n", "~\n", "---\n", "--- null\n...\n"))
    return _Made(text.encode("utf-8"), expected_line=1)


_CONDITION_KEYS = ("until", "expect", "invariants")


def _long_expression(rng: random.Random, base: _Base, target: str) -> _Made | None:
    conditions = [slot for slot in base.slots if slot.tag == "str" and slot.key in _CONDITION_KEYS]
    if not conditions:
        return None
    slot = rng.choice(conditions)
    inner = slot.text.strip("\"'") if slot.text[:1] in "\"'" else slot.text
    value = "(" * 500 + inner + ")" * 500 if rng.random() < 0.5 else " and ".join([f"({inner})"] * 2000)
    return _Made(_replace(base.text, slot, '"' + value.replace('"', "'") + '"').encode("utf-8"),
                 expected_line=slot.line + 1)


def _digits(rng: random.Random, count: int) -> str:
    return str(rng.randint(1, 9)) + "".join(str(rng.randint(0, 9)) for _ in range(count - 1))


def _program_text(rng: random.Random, base: _Base, target: str) -> _Made | None:
    programs = [slot for slot in base.slots if slot.tag == "str" and slot.key in ("mda", "text")]
    if not programs:
        return None
    slot = rng.choice(programs)
    written = slot.text.strip("\"'") if slot.text[:1] in "\"'" else slot.text
    damage = rng.choice((
        f"G1 X{_digits(rng, rng.choice((300, 400, 5000)))} F1000",
        f"N{_digits(rng, 5000)} G1 X1",
        f"R1={_digits(rng, 400)}",
        "IDS=1 WHENEVER $AA_IM[X1] > " + "(" * 600 + "1" + ")" * 600 + " DO $AC_ESR_TRIGGER=1",
        "IDS=1 WHENEVER " + " OR ".join(["$AA_IM[X1] > 1"] * 300) + " DO $AC_ESR_TRIGGER=1",
        "".join(rng.choice("GXZFMSNR0123456789.-=()[] $'H") for _ in range(rng.randint(1, 200))),
    ))
    text = f"{written}\\n{damage}" if rng.random() < 0.5 else f"{damage}\\n{written}"
    return _Made(_replace(base.text, slot, '"' + text.replace('"', "'") + '"').encode("utf-8"))


def _special_file(rng: random.Random, base: _Base, target: str) -> _Made | None:
    special = rng.choice(("/dev/zero", "/dev/null", "/dev/urandom", "/proc/self/mem", "{fifo}", "{directory}"))
    if rng.random() < 0.5:
        machines = [slot for slot in base.slots if slot.text.endswith(".yaml")]
        if not machines:
            return None
        slot = machines[0]
        return _Made(_replace(base.text, slot, special).encode("utf-8"), expected_line=slot.line + 1,
                     special_path=special)
    document = yaml.safe_load(base.text)
    document["steps"] = [{"program": {"name": "P", "file": special}}]
    text = yaml.safe_dump(document, sort_keys=False, allow_unicode=True, width=1_000_000)
    line = next(number for number, line in enumerate(text.split("\n"), start=1) if "file: " in line)
    return _Made(text.encode("utf-8"), expected_line=line, special_path=special)


_PROBES: tuple[object, ...] = (
    {"expect": {"X1.position": float("inf")}},
    {"expect": {"X1.position": float("-inf")}},
    {"expect": {"X1.position": float("nan")}},
    {"expect": {"X1.position": "1e308"}},
    {"expect": {"X1.position": "0 +- 1e400"}},
    {"expect": {"X1.position": "0 +- 1e15"}},
    {"expect": {"X1.position": "< 1e400"}},
    {"expect": {"X1.position": "> -1e400"}},
    {"expect": {"X1.position": "!= 1e400"}},
    {"expect": {"X1.position": 1e300}},
    {"expect": {"X1.basic.in.posFineReached": "<= 1"}},
    {"expect": {"X1.basic.in.posFineReached": ">= 0"}},
    {"expect": {"X1.basic.in.posFineReached": "!= 2"}},
    {"expect": {"X1.basic.in.posFineReached": "0.5 +- 0.5"}},
    {"expect": {"X1.MD34210": ">= 0"}},
    {"expect": "X1.position < 1e400"},
    {"expect": "X1.position > -1e999 or X1.position == 0"},
    {"expect": "1 == 1"},
    {"expect": "(((((((((((((((((((((((((((((((((((((X1.position > -1e16)))))))))))))))))))))))))))))))))))))"},
    {"expect_timing": {"from": "when time >= 0", "to": "when time >= 0.05", "min": "0s"}},
    {"expect_timing": {"from": "when time >= 0", "to": "when time >= 0.05", "max": "1000s"}},
    {"expect_timing": {"from": "when time >= 0", "to": "when time >= 0.05", "max": "1e400s"}},
    {"expect_timing": {"from": "when time >= 0", "to": "when time >= 0.05", "max": float("inf")}},
)


def _false_pass_probe(rng: random.Random, base: _Base, target: str) -> _Made | None:
    document = yaml.safe_load(base.text)
    if not isinstance(document, dict):
        return None
    kept = {key: document[key] for key in ("name", "machine", "plc", "link", "machine_data", "plc_parameters")
            if key in document}
    probe = {**kept, "timeout": "10s", "steps": [{"wait": "100ms"}, rng.choice(_PROBES)]}
    text = yaml.safe_dump(probe, sort_keys=False, allow_unicode=True, width=1_000_000)
    return _Made(text.encode("utf-8"), must_not_pass=True)


MUTATIONS: dict[str, Mutation] = {
    "byte_flip": _byte_flip, "truncate": _truncate, "delete_lines": _delete_lines,
    "duplicate_line": _duplicate_line, "swap_lines": _swap_lines, "deep_nesting": _deep_nesting,
    "alias_bomb": _alias_bomb, "recursive_alias": _recursive_alias, "huge_number": _huge_number,
    "unknown_tag": _unknown_tag, "control_character": _control_character, "non_finite": _non_finite,
    "number_edge": _number_edge, "type_confusion": _type_confusion, "empty_document": _empty_document,
    "long_expression": _long_expression, "program_text": _program_text, "special_file": _special_file,
    "false_pass_probe": _false_pass_probe,
}
SCENARIO_ONLY = ("long_expression", "program_text", "special_file", "false_pass_probe")


class Shipped:
    """The shipped files to mutate, each parsed once, and the scenario that drives each machine."""

    def __init__(self, root: Path):
        self.root = root
        scenario_paths = sorted(path for path in root.rglob("*.yaml") if "machines" not in path.relative_to(root).parts)
        self.scenarios = [self._base(path) for path in scenario_paths]
        self.machines = [self._base(path) for path in sorted((root / "machines").glob("*.yaml"))]
        self.drivers: dict[str, _Base] = {}
        for machine in self.machines:
            name = Path(machine.path).name
            self.drivers[machine.path] = next(scenario for scenario in self.scenarios
                                              if re.search(rf"^machine: .*\b{re.escape(name)}\s*$", scenario.text,
                                                           re.MULTILINE))

    def _base(self, path: Path) -> _Base:
        text = path.read_text(encoding="utf-8")
        return _Base(str(path.relative_to(self.root)), text, _slots(text))

    def mutant(self, seed: int, number: int) -> Mutant:
        """Mutant ``number`` of ``seed``: the same whatever the count of the campaign."""
        rng = random.Random(f"{seed}/{number}")
        target = "machine" if rng.random() < MACHINE_SHARE else "scenario"
        bases = self.machines if target == "machine" else self.scenarios
        kinds = [kind for kind in MUTATIONS if target == "scenario" or kind not in SCENARIO_ONLY]
        while True:  # a mutation that finds nothing to change in its base tries other bases, then another kind
            kind = rng.choice(kinds)
            for _ in range(BASES_TRIED):
                base = rng.choice(bases)
                made = MUTATIONS[kind](rng, base, target)
                if made is not None:
                    return Mutant(number, kind, base.path, target, made.data, made.expected_line,
                                  made.expected_lines, made.expected_column, made.must_not_pass, made.special_path)


# ---------------------------------------------------------------------------------- checking


class _Hang(BaseException):
    """Raised by the wall-clock bound (not an Exception: nothing in the harness may catch it)."""


_RE_ALARM_S = 0.01


@contextlib.contextmanager
def _wall_bound(seconds: float) -> Iterator[None]:
    """Interrupt the block after ``seconds`` of wall time (SIGALRM; the main thread only).  A timer
    already running (a test's time-out) keeps its deadline and its handler."""
    if threading.current_thread() is not threading.main_thread():
        raise RuntimeError("the file campaign bounds each mutant with SIGALRM: run it in the main thread")
    began = time.monotonic()
    outer_delay, outer_interval = signal.getitimer(signal.ITIMER_REAL)
    outer_deadline = began + outer_delay if outer_delay else None

    def interrupt(signum: int, frame: FrameType | None) -> None:
        if outer_deadline is not None and time.monotonic() >= outer_deadline and callable(previous):
            previous(signum, frame)
        raise _Hang()

    previous = signal.signal(signal.SIGALRM, interrupt)
    # again every 10 ms until the block is left: a _Hang raised while the interpreter runs a
    # finalizer is printed as "Exception ignored" and swallowed, and the run went on to pass
    signal.setitimer(signal.ITIMER_REAL, min(seconds, outer_delay) if outer_delay else seconds, _RE_ALARM_S)
    try:
        yield
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, previous)
        if outer_deadline is not None:
            signal.setitimer(signal.ITIMER_REAL, max(outer_deadline - time.monotonic(), 0.001), outer_interval)


@dataclass(frozen=True, slots=True)
class Outcome:
    mutant: Mutant
    outcome: str  # one of OUTCOMES
    detail: str = ""


class Workspace:
    """A copy of the scenarios directory where mutants are written next to the files they replace."""

    def __init__(self, root: Path, directory: Path):
        self.root = directory / "scenarios"
        shutil.copytree(root, self.root)
        self.fifo = directory / "fifo.yaml"
        os.mkfifo(self.fifo)

    def write(self, mutant: Mutant, shipped: Shipped) -> tuple[str, set[str]]:
        """Write the mutant (and, for a machine, its driving scenario); the scenario to run and the
        files whose problems the run may report."""
        data = mutant.data.replace(b"{fifo}", str(self.fifo).encode()).replace(b"{directory}", str(self.root).encode())
        base = self.root / mutant.base
        written = base.with_name(f"mutant_{mutant.number}.yaml")
        written.write_bytes(data)
        files = {str(written)}
        if mutant.target == "scenario":
            return str(written), files | self._referenced(written)
        driver = shipped.drivers[mutant.base]
        driver_path = (self.root / driver.path).with_name(f"mutant_{mutant.number}_driver.yaml")
        text = re.sub(r"^machine: .*$", f"machine: {os.path.relpath(written, driver_path.parent)}", driver.text,
                      count=1, flags=re.MULTILINE)
        driver_path.write_text(text, encoding="utf-8")
        return str(driver_path), files | {str(driver_path)} | self._referenced(driver_path)

    def _referenced(self, scenario: Path) -> set[str]:
        """Files a scenario may name: any file of the workspace, and the special files of the mutations."""
        return {"/dev/zero", "/dev/null", "/dev/urandom", "/proc/self/mem", str(self.fifo), str(self.root)}

    def remove(self, mutant: Mutant, shipped: Shipped) -> None:
        for path in self.root.rglob(f"mutant_{mutant.number}*.yaml"):
            path.unlink()


def _location_problem(problem: Problem, involved: set[str], workspace: Path) -> str:
    """Why the location of ``problem`` is not plausible ("" if it is)."""
    mark = problem.mark
    if _OFFSET_MESSAGE.search(problem.message):
        return f"a character offset or a traceback instead of a location: {problem}"
    if _LINE_BREAKING.search(str(problem)):  # the rest of the message would stand on a line of its own
        return f"printed over more than one line: {str(problem)!r}"
    path = os.path.normpath(mark.file)
    inside = path.startswith(str(workspace) + os.sep)
    if path not in involved and not inside:
        return f"a file the run does not read: {problem}"
    if not os.path.isfile(path) or not inside:
        return "" if (mark.line, mark.column) == (1, 1) else f"a line and column in a file that is none: {problem}"
    text = Path(path).read_bytes().decode("utf-8", errors="replace").replace("\r\n", "\n")
    lines = text.split("\n")
    if text.endswith("\n"):  # the line break ends the last line; nothing follows it
        lines.pop()
    if not 1 <= mark.line <= max(len(lines), 1):
        return f"line {mark.line} of a file of {len(lines)} lines: {problem}"
    width = len(lines[mark.line - 1]) if mark.line <= len(lines) else 0
    if not 1 <= mark.column <= width + 2:
        return f"column {mark.column} of a line of {width} characters: {problem}"
    return ""


def _judge_problems(mutant: Mutant, error: SourceError, printed: str, mutated: str, involved: set[str],
                    workspace: Path) -> Outcome:
    for problem in error.problems:
        reason = _location_problem(problem, involved, workspace)
        if reason:
            return Outcome(mutant, "wrong_location", reason)
        if str(problem) not in printed:
            return Outcome(mutant, "wrong_location", f"printed otherwise than written: {problem}")
    # the problem of a special file that is a regular file to the kernel but cannot be read (/proc/self/mem)
    # is reported at the file itself
    if mutant.special_path and any(problem.mark.file == mutant.special_path for problem in error.problems):
        return Outcome(mutant, "problems", str(error.problems[0]))
    at = [problem for problem in error.problems if os.path.normpath(problem.mark.file) == os.path.normpath(mutated)]
    expected = _expected_lines(mutant)
    if expected is not None and not any(expected[0] <= problem.mark.line <= expected[1] and (
            mutant.expected_column is None or problem.mark.column == mutant.expected_column) for problem in at):
        column = f", column {mutant.expected_column}" if mutant.expected_column is not None else ""
        shown = "; ".join(str(problem) for problem in error.problems[:3])
        return Outcome(mutant, "wrong_location", f"expected a problem at line {expected[0]}{column} of the mutant,"
                                                 f" got: {shown}")
    return Outcome(mutant, "problems", str(error.problems[0]))


def _expected_lines(mutant: Mutant) -> tuple[int, int] | None:
    """The lines where a problem of the mutant must be (None: no line is known, it may even load)."""
    if mutant.expected_lines is not None:
        return mutant.expected_lines
    return (mutant.expected_line, mutant.expected_line) if mutant.expected_line is not None else None


def check_mutant(mutant: Mutant, shipped: Shipped, workspace: Workspace, bound_s: float,
                 run_seconds: float) -> Outcome:
    """One mutant the way of ``vc run``: load and check, report, run what loads."""
    scenario_path, involved = workspace.write(mutant, shipped)
    mutated = scenario_path if mutant.target == "scenario" else str(
        (workspace.root / mutant.base).with_name(f"mutant_{mutant.number}.yaml"))
    involved = {os.path.normpath(path) for path in involved}
    report = ConsoleReport()
    printed = io.StringIO()
    report.console.file = printed
    try:
        with _wall_bound(bound_s):
            try:
                scenarios = load_scenarios([scenario_path], plc_programs())
            except SourceError as error:
                report.print_problems(error)
                return _judge_problems(mutant, error, printed.getvalue(), mutated, involved, workspace.root)
            limit = Duration(round(run_seconds * 1_000_000))
            capped = [dataclasses.replace(scenario, timeout=min(scenario.timeout, limit)) for scenario in scenarios]
            results = run_scenarios(capped, simulation_for)
            for result in results:
                report.print_result(result)
            report.print_summary(results)
    except _Hang:
        return Outcome(mutant, "hang", f"longer than {bound_s:g} s of wall time")
    except Exception as error:  # anything escaping the vc run path would end vc run with a traceback
        return Outcome(mutant, "crash", "".join(traceback.format_exception_only(error)).strip()[-500:])
    finally:
        workspace.remove(mutant, shipped)
    errors = [result for result in results if result.error]
    if errors:
        return Outcome(mutant, "traceback", errors[0].error.strip().splitlines()[-1][-500:])
    expected = _expected_lines(mutant)
    if expected is not None:
        return Outcome(mutant, "wrong_location", f"expected a problem at line {expected[0]} of the mutant; it loaded")
    if all(result.passed for result in results):
        if mutant.must_not_pass:
            return Outcome(mutant, "false_pass", "a check that cannot fail was accepted and passed")
        return Outcome(mutant, "passed")
    return Outcome(mutant, "failed")


# ---------------------------------------------------------------------------------- campaign


def run_file_mutations(count: int, seed: int, say: Callable[[str], None], *, bound_s: float = DEFAULT_BOUND_S,
                       run_seconds: float = DEFAULT_RUN_SECONDS, root: Path | None = None,
                       keep: Path | None = None) -> dict[str, int]:
    """Make ``count`` mutants of the shipped files with ``seed`` and put each through ``vc run``.

    ``say`` is told about every bad outcome (and progress every 250 mutants); with ``keep`` the
    bad mutants are also written there.  Returns the figures: ``inputs``, ``crashes``, ``hangs``,
    ``tracebacks``, ``false_passes``, ``wrong_locations`` (all bad), ``problems`` (refused with
    located problems), ``passed``, ``failed`` (loaded and ran), ``seconds`` (wall, whole), and
    ``outcome/kind`` counts per mutation kind.
    """
    began = time.perf_counter()
    shipped = Shipped(root or default_root())
    counts: Counter[str] = Counter()
    with tempfile.TemporaryDirectory(prefix="vc-mutants-") as directory:
        workspace = Workspace(shipped.root, Path(directory))
        for number in range(count):
            mutant = shipped.mutant(seed, number)
            outcome = check_mutant(mutant, shipped, workspace, bound_s, run_seconds)
            counts[outcome.outcome] += 1
            counts[f"{outcome.outcome}/{mutant.kind}"] += 1
            if outcome.outcome in BAD_OUTCOMES:
                say(f"{outcome.outcome}: mutant {number} ({mutant.kind} of {mutant.target} {mutant.base}):"
                    f" {outcome.detail}")
                if keep is not None:
                    keep.mkdir(parents=True, exist_ok=True)
                    (keep / f"mutant_{number}_{mutant.kind}.yaml").write_bytes(mutant.data)
            if (number + 1) % 250 == 0:
                say(f"{number + 1} of {count} mutants, {time.perf_counter() - began:.0f} s")
    figures = {"inputs": count, **{_FIGURE_OF[outcome]: counts[outcome] for outcome in OUTCOMES},
               "seconds": round(time.perf_counter() - began)}
    figures.update({key: value for key, value in sorted(counts.items()) if "/" in key})
    return figures


def table(figures: dict[str, int]) -> str:
    """The figures as a table: the totals, then the outcomes of each mutation kind."""
    lines = [f"{'figure':<16} {'count':>7}"]
    lines += [f"{name:<16} {figures.get(name, 0):>7}" for name in FIGURES]
    kinds = sorted({key.split("/")[1] for key in figures if "/" in key})
    if kinds:
        lines += ["", f"{'mutation':<18} " + " ".join(f"{outcome:>9.9}" for outcome in OUTCOMES)]
        for kind in kinds:
            lines.append(f"{kind:<18} " + " ".join(f"{figures.get(f'{outcome}/{kind}', 0):>9}"
                                                   for outcome in OUTCOMES))
    return "\n".join(lines)


def main(argv: Sequence[str] | None = None) -> int:
    import argparse
    import json

    parser = argparse.ArgumentParser(description="Mutated scenario and machine files through vc run")
    parser.add_argument("--count", type=int, default=2000, help="mutants to make (default 2000)")
    parser.add_argument("--seed", type=int, default=1, help="seed of the mutations (default 1)")
    parser.add_argument("--bound", type=float, default=DEFAULT_BOUND_S, metavar="S",
                        help=f"wall seconds a mutant may take before it counts as a hang (default {DEFAULT_BOUND_S:g})")
    parser.add_argument("--run-seconds", type=float, default=DEFAULT_RUN_SECONDS, metavar="S",
                        help="simulated seconds a mutant that loads may run (default"
                             f" {DEFAULT_RUN_SECONDS:g})")
    parser.add_argument("--keep", metavar="DIR", help="write the mutants with a bad outcome into DIR")
    arguments = parser.parse_args(argv)
    figures = run_file_mutations(arguments.count, arguments.seed, lambda text: print(text, flush=True),
                                 bound_s=arguments.bound, run_seconds=arguments.run_seconds,
                                 keep=Path(arguments.keep) if arguments.keep else None)
    print(table(figures))
    print(json.dumps({name: figures[name] for name in FIGURES}))
    return 0 if not any(figures[_FIGURE_OF[outcome]] for outcome in BAD_OUTCOMES) else 1
