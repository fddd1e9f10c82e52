"""The bounded YAML reader: every input beyond a limit is a problem at its line and column.

Each test here stood for a traceback, a hang or a memory blow-up before the reader was bounded
(RecursionError, ConstructorError, ValueError, MemoryError, a "billion laughs" growing past a
gigabyte), or for a problem reported at the wrong place.
"""

from __future__ import annotations

import os
import time
from pathlib import Path

import pytest

from vc.input_limits import MAX_FILE_BYTES, MAX_INTEGER_DIGITS, MAX_NESTING, MAX_VALUES
from vc.located_yaml import LocatedList, LocatedMap, Mark, load_file, load_text, mark_at


def problems(text: str) -> list[str]:
    document, found = load_text(text, "f.yaml")
    assert document is None, "a refused file yields no document"
    return [str(problem) for problem in found]


def billion_laughs(merge: bool) -> str:
    """Nine levels of nine aliases: 9^9 values once expanded (in lists, or in << merges)."""
    if merge:
        lines = ["a0: &a0 {x: lol}"]
        lines += [f"a{i}: &a{i} {{<<: [{', '.join([f'*a{i - 1}'] * 9)}]}}" for i in range(1, 10)]
    else:
        lines = ["a0: &a0 [lol]"]
        lines += [f"a{i}: &a{i} [{', '.join([f'*a{i - 1}'] * 9)}]" for i in range(1, 10)]
    return "\n".join(lines) + "\n"


@pytest.mark.parametrize("merge", [False, True], ids=["lists", "merges"])
def test_an_alias_bomb_is_refused_at_the_alias_that_crosses_the_limit(merge: bool) -> None:
    began = time.process_time()
    (problem,) = problems(billion_laughs(merge))
    assert problem.startswith("f.yaml:6:")  # a5 is the first level past 100,000 values
    assert f"more than {MAX_VALUES:,} values with its aliases expanded" in problem
    assert time.process_time() - began < 5  # nothing was expanded (a bound, not a timing claim)


def test_aliases_within_the_limit_are_expanded() -> None:
    document, found = load_text("a: &a [1, 2]\nb: *a\nc: {<<: {x: 1}, y: 2}\n", "f.yaml")
    assert found == []
    assert document == {"a": [1, 2], "b": [1, 2], "c": {"x": 1, "y": 2}}


@pytest.mark.parametrize("text, where", [
    ("steps: &s [*s]\n", "1:12"),
    ("a: &m {b: *m}\n", "1:11"),
    ("a: &m {<<: *m}\n", "1:12"),
])
def test_an_alias_inside_the_value_it_names_is_refused(text: str, where: str) -> None:
    (problem,) = problems(text)
    assert problem.startswith(f"f.yaml:{where}: the alias *")
    assert "cannot contain itself" in problem


def test_deep_nesting_is_refused_where_it_crosses_the_limit() -> None:
    (problem,) = problems("a: " + "[" * 500 + "]" * 500 + "\n")
    assert problem == f"f.yaml:1:{3 + MAX_NESTING}: more than {MAX_NESTING} lists and mappings inside one another"
    # deeper than libyaml's own limit (1000 levels): its parser refuses it where it stops, still located
    (problem,) = problems("a: " + "[" * 2000 + "]" * 2000 + "\n")
    assert problem.startswith("f.yaml:1:") and "nesting depth" in problem
    document, found = load_text("a: " + "[" * (MAX_NESTING - 1) + "]" * (MAX_NESTING - 1), "f.yaml")
    assert found == [] and isinstance(document, LocatedMap)


def test_a_mapping_of_many_values_is_refused() -> None:
    text = "a: [" + ", ".join(["1"] * MAX_VALUES) + "]\n"
    (problem,) = problems(text)
    assert problem.startswith("f.yaml:1:") and f"more than {MAX_VALUES:,} values" in problem


@pytest.mark.parametrize("number", ["1" * 5000, "-" + "9" * 21, "0x" + "f" * 30])
def test_whole_numbers_beyond_the_digit_limit_are_refused(number: str) -> None:
    (problem,) = problems(f"name: x\nvalue: {number}\n")
    assert problem.startswith("f.yaml:2:8: ")
    assert f"at most {MAX_INTEGER_DIGITS}" in problem


def test_whole_numbers_within_the_limit_are_read() -> None:
    document, _ = load_text("a: 18446744073709551615\nb: -12_345\nc: 0xff\n", "f.yaml")
    assert document == {"a": 18446744073709551615, "b": -12345, "c": 255}


@pytest.mark.parametrize("value", [".inf", "-.inf", ".nan", ".NaN", "1.0e+400"])
def test_numbers_that_are_not_finite_are_refused(value: str) -> None:
    (problem,) = problems(f"steps:\n  - expect: {{X1.position: {value}}}\n")
    assert problem == f"f.yaml:2:27: '{value}' is not a finite number (the harness reads no infinity and no NaN)"


@pytest.mark.parametrize("tag, shown", [
    ("!custom 1", "!custom"), ("!!python/name:os.system x", "!!python/name:os.system"),
    ("!!python/object/apply:os.system [ls]", "!!python/object/apply:os.system"), ("!!binary aGk=", "!!binary"),
    ("!!set {a}", "!!set"), ("!!omap [a: 1]", "!!omap"), ("!thing {a: 1}", "!thing"),
    ("!!timestamp 2024-01-01", "!!timestamp"),
])
def test_only_plain_yaml_tags_are_accepted(tag: str, shown: str) -> None:
    found = problems(f"name: x\nvalue: {tag}\n")
    assert found[0].startswith(f"f.yaml:2:8: unknown YAML tag {shown} (")


def test_every_bad_value_of_a_file_is_reported() -> None:
    assert problems("a: !x 1\nb: .nan\nc: " + "1" * 30 + "\n") == [
        "f.yaml:1:4: unknown YAML tag !x (the harness reads plain text, numbers, true/false, lists and mappings)",
        "f.yaml:2:4: '.nan' is not a finite number (the harness reads no infinity and no NaN)",
        f"f.yaml:3:4: a whole number of 30 digits; at most {MAX_INTEGER_DIGITS} are read",
    ]


def test_plain_tags_and_unquoted_dates_are_read() -> None:
    document, found = load_text("a: !!str 5\nb: !!int '7'\nc: 2024-13-45\nd: !!float 1\n", "f.yaml")
    assert found == []
    assert document == {"a": "5", "b": 7, "c": "2024-13-45", "d": 1.0}


@pytest.mark.parametrize("text, where, code", [
    ("name: x\x00\n", "1:8", "U+0000"),
    ("name: x\nmachine: m\n\nplc: \x01none\n", "4:6", "U+0001"),
    ("a: 1\r\nb: 2\r\nc: \x1b\n", "3:4", "U+001B"),
    ("a: 1\rb: \x7f\n", "2:4", "U+007F"),
])
def test_control_characters_are_reported_at_their_line_and_column(text: str, where: str, code: str) -> None:
    (problem,) = problems(text)
    assert problem == f"f.yaml:{where}: a control character ({code}) that YAML does not allow"


def test_mark_at_counts_lines_as_the_parser_does() -> None:
    assert mark_at("ab\r\ncd\ref\x85gh", 11, "f") == Mark("f", 4, 2)


@pytest.mark.parametrize("text, message", [
    ("", "f.yaml:1:1: the file is empty"),
    ("# only a comment\n", "f.yaml:1:1: the file is empty"),
    ("null\n", "f.yaml:1:1: the document is empty (it holds only 'null')"),
    ("~\n", "f.yaml:1:1: the document is empty (it holds only '~')"),
    ("---\n", "f.yaml:1:1: the document is empty"),
])
def test_an_empty_document_is_a_problem(text: str, message: str) -> None:
    assert problems(text) == [message]


def test_a_device_is_refused_without_reading_it() -> None:
    if not os.path.exists("/dev/zero"):
        pytest.skip("no /dev/zero here")
    document, found = load_file("/dev/zero")
    assert document is None
    assert [str(problem) for problem in found] == [
        "/dev/zero:1:1: cannot read the file: it is a device, FIFO or socket, not a regular file"]


def test_a_fifo_is_refused_without_waiting_for_a_writer(tmp_path: Path) -> None:
    fifo = tmp_path / "pipe.yaml"
    os.mkfifo(fifo)
    document, found = load_file(str(fifo))
    assert document is None and "a device, FIFO or socket, not a regular file" in found[0].message


def test_a_directory_is_refused(tmp_path: Path) -> None:
    _, found = load_file(str(tmp_path))
    assert found[0].message == "cannot read the file: it is a directory, not a regular file"


def test_a_file_over_the_size_limit_is_refused(tmp_path: Path) -> None:
    path = tmp_path / "big.yaml"
    path.write_bytes(b"# " + b"x" * MAX_FILE_BYTES + b"\n")
    _, found = load_file(str(path))
    assert [problem.message for problem in found] == [
        f"the file is larger than {MAX_FILE_BYTES:,} bytes, the most the harness reads"]


def test_text_that_is_not_utf8_is_reported_at_its_line(tmp_path: Path) -> None:
    path = tmp_path / "latin1.yaml"
    path.write_bytes("name: x\ndescription: Fräse\n".encode("latin-1"))
    _, found = load_file(str(path))
    assert [str(problem) for problem in found] == [
        f"{path}:2:16: the file is not UTF-8 text (invalid continuation byte)"]


def test_line_ends_of_every_kind_read_alike(tmp_path: Path) -> None:
    path = tmp_path / "crlf.yaml"
    path.write_bytes(b"a: |\r\n  one\r\n  two\r\nb: [1,\r\n  2]\r\n")
    document, found = load_file(str(path))
    assert found == []
    assert document == {"a": "one\ntwo\n", "b": [1, 2]}
    assert isinstance(document["b"], LocatedList) and document.mark_of("b") == Mark(str(path), 4, 4)


@pytest.mark.parametrize("text, where", [
    ("steps:\n\t- wait: 1s\n", "f.yaml:2:1"),
    ("a:\n  b: 1\n\tc: 2\n", "f.yaml:3:1"),
], ids=["list", "mapping"])
def test_a_tab_that_indents_is_named_at_its_place(text: str, where: str) -> None:
    assert problems(text) == [f"{where}: YAML syntax error: a tab character here: YAML indents with spaces,"
                              " never with tabs"]


@pytest.mark.parametrize("text, where", [
    ("name: x\nsteps:\n  - wait: [1s\n", "f.yaml:3:14"),  # the file ends with its line break
    ("name: x\nsteps: {wait: 1s,\n", "f.yaml:2:18"),
    ("name: x\nsteps:\n  - wait: [1s", "f.yaml:3:14"),  # ... and without one
], ids=["list", "mapping", "no-line-break"])
def test_the_end_of_a_file_is_marked_on_its_last_line(text: str, where: str) -> None:
    (problem,) = problems(text)
    assert problem.startswith(f"{where}: YAML syntax error: ")


def test_a_problem_is_one_line_whatever_the_value_it_echoes_holds() -> None:
    from vc.located_yaml import Problem

    problem = Problem(Mark("a\nb.yaml", 2, 10), "no machine file 'turn\nmill' (\x1b[2K\rPASS)")
    assert str(problem) == "a\\nb.yaml:2:10: no machine file 'turn\\nmill' (\\x1b[2K\\rPASS)"
