"""Part programs for the NC: ``mda`` (blocks into the MDA buffer) and ``program`` (a part
program selected for AUTOMATIC, written in the scenario or read from its file).
"""

from __future__ import annotations

import os
from typing import Any

from vc.located_yaml import LocatedMap, Mark, read_source
from vc.scenario.language.model import LoadMda, SelectProgram, Step
from vc.scenario.language.steps.common import StepChecker, StepKind, StepRun, built, kind_of_value, looked_for

# -- checking ------------------------------------------------------------------------------


def check_mda(checker: StepChecker, index: int, mark: Mark, value: Any, value_mark: Mark) -> Step | None:
    channel = checker.first_channel()
    text = value
    text_mark = value_mark
    if isinstance(value, LocatedMap):
        if not checker.check_keys(value, ("channel", "text"), ("text",), "mda"):
            return None
        channel = checker.channel(value, channel)
        text, text_mark = value["text"], value.mark_of("text")
    if not isinstance(text, str) or not text.strip():
        checker.add(text_mark, f"mda takes the block(s) to run as a text, not {kind_of_value(text)}")
        return None
    return LoadMda(index, "mda", mark, channel, text) if channel is not None else None


def check_program(checker: StepChecker, index: int, mark: Mark, value: Any, value_mark: Mark) -> Step | None:
    if not isinstance(value, LocatedMap):
        checker.add(value_mark, "program takes a mapping: {name: PART1, text: ...}"
                    " or {name: PART1, file: ...}")
        return None
    if not checker.check_keys(value, ("name", "text", "file", "channel"), ("name",), "program"):
        return None
    name = checker.text(value, "name")
    channel = checker.channel(value, checker.first_channel())
    if ("text" in value) == ("file" in value):
        checker.add(value.mark, "program needs either 'text' (the program itself) or 'file' (where it is)")
        return None
    if "text" in value:
        text = checker.text(value, "text")
    else:
        file = checker.text(value, "file")
        if not file:
            return None
        location = os.path.normpath(os.path.join(checker.directory, file))
        checker.sources.append(location)
        read, problems = read_source(location, f"program file '{file}'")
        if read is None:  # reported at the scenario's line, with where in the program file
            where = problems[0].mark
            inside = f" at line {where.line}, column {where.column}" if (where.line, where.column) != (1, 1) else ""
            checker.add(value.mark_of("file"), f"{problems[0].message}{inside}{looked_for(file, location)}")
            return None
        text = read
    if not name or not text or channel is None:
        return None
    return SelectProgram(index, "program", mark, channel, name, text)


# -- running -------------------------------------------------------------------------------


def run_mda(run: StepRun, step: Step) -> None:
    mda = built(step, LoadMda)
    run.target.load_mda(mda.channel, mda.text)


def run_program(run: StepRun, step: Step) -> None:
    program = built(step, SelectProgram)
    run.target.select_program(program.channel, program.name, program.text)


# -- the kinds -----------------------------------------------------------------------------

MDA = StepKind("mda", 'mda: "G1 X100 F2000"', (LoadMda,), check_mda, run_mda)
PROGRAM = StepKind("program", "program: {name: PART1, file: programs/part1.mpf}", (SelectProgram,), check_program,
                   run_program)
