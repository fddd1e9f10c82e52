"""Console report, lazy progress bar, JUnit XML, and the `vc run` entry point's exit codes."""

from __future__ import annotations

import io
import xml.etree.ElementTree as ElementTree
from pathlib import Path

from rich.console import Console
from scenario_fakes import KNOWN_PROGRAMS, FakeTarget, SimpleNc, machine, scenario, write_scenario

from vc.scenario.command import EXIT_FAILED, EXIT_PASSED, EXIT_PROBLEMS, run_command
from vc.scenario.language.model import Scenario
from vc.scenario.outputs.report import ConsoleReport, failure_text, write_junit
from vc.scenario.run.runner import ScenarioResult, run_scenario, run_scenarios

HEAD = "machine: machines/mini.yaml\nplc: none\n"
PASSING = "name: moves to 10\n" + HEAD + """\
steps:
  - mda: "G1 X10 F6000"
  - pulse: {signal: CHAN1.basic.out.ncStart, for: 20ms}
  - wait: {until: "X1.basic.in.posFineReached == 1", timeout: 1s}
"""
FAILING = "name: expects too much\n" + HEAD + """\
steps:
  - mda: "G1 X10 F6000"
  - pulse: {signal: CHAN1.basic.out.ncStart, for: 20ms}
  - wait: 30ms
  - expect: {X1.position: "10 +- 0.001"}
"""


def make_target(loaded: Scenario) -> FakeTarget:
    return FakeTarget(loaded.machine, SimpleNc())


def results(tmp_path: Path) -> list[ScenarioResult]:
    loaded = [scenario(tmp_path, PASSING, "pass.yaml"), scenario(tmp_path, FAILING, "fail.yaml")]
    return run_scenarios(loaded, make_target)


def console() -> tuple[Console, io.StringIO]:
    output = io.StringIO()
    return Console(file=output, width=200, color_system=None, force_terminal=False), output


def test_console_lines(tmp_path: Path) -> None:
    shown, output = console()
    report = ConsoleReport(shown)
    for result in results(tmp_path):
        report.print_result(result)
    text = output.getvalue()
    lines = text.splitlines()
    assert lines[0].startswith(f"PASS  moves to 10  {tmp_path}/pass.yaml  0.102 s simulated, ")
    assert lines[1].startswith(f"FAIL  expects too much  {tmp_path}/fail.yaml  0.05 s simulated, ")
    assert lines[2] == f"      step 4 (expect) at {tmp_path}/fail.yaml:8:5"
    assert lines[3] == "      expected X1.position = 10 ± 0.001, found 5 mm"
    assert lines[4] == "      history before the failure at 0.050 s:"
    assert lines[5].split() == ["signal", "address", "time", "value"]
    assert lines[6].split() == ["X1.position", "0.032", "s", "3.2", "mm"]
    assert lines[-1].split() == ["0.050", "s", "5", "mm"]
    assert lines[-1].startswith("      ") and len(lines) == 16


def test_failure_text(tmp_path: Path) -> None:
    failed = results(tmp_path)[1]
    text = failure_text(failed)
    assert text.splitlines()[0] == (f"step 4 (expect) at {tmp_path}/fail.yaml:8:5:"
                                    " expected X1.position = 10 ± 0.001, found 5 mm")
    assert text.splitlines()[2].startswith("  X1.position: 0.032 s = 3.2 mm, 0.034 s = 3.4 mm,")


def test_progress_appears_only_after_a_second(tmp_path: Path) -> None:
    now = [0.0]
    shown = Console(file=io.StringIO(), width=200, force_terminal=True)  # a terminal: the bar is for people
    report = ConsoleReport(shown, clock=lambda: now[0])
    loaded = scenario(tmp_path, PASSING)
    report.scenario_started(loaded, 0, 2)
    report.scenario_progress(loaded, 0.5)
    assert report.progress is None
    now[0] = 1.5
    report.scenario_progress(loaded, 1.0)
    assert report.progress is not None and report.task is not None
    task = report.progress.tasks[0]
    assert task.total == 2 and "moves to 10" in task.description and "1 s simulated" in task.description
    report.close()
    assert report.progress is None


def test_no_progress_bar_into_a_file_or_pipe(tmp_path: Path) -> None:
    """Off a terminal the report is the same however long the run takes (no transient bar line)."""
    now = [0.0]
    shown, _ = console()
    report = ConsoleReport(shown, clock=lambda: now[0])
    loaded = scenario(tmp_path, PASSING)
    report.scenario_started(loaded, 0, 1)
    now[0] = 5.0
    report.scenario_progress(loaded, 1.0)
    assert report.progress is None


def test_junit(tmp_path: Path) -> None:
    path = tmp_path / "junit.xml"
    write_junit(results(tmp_path), path)
    root = ElementTree.parse(path).getroot()
    assert root.tag == "testsuites"
    suite = root.find("testsuite")
    assert suite is not None
    assert (suite.get("tests"), suite.get("failures"), suite.get("errors")) == ("2", "1", "0")
    cases = suite.findall("testcase")
    assert [(case.get("classname"), case.get("name")) for case in cases] == [
        (f"{tmp_path}/pass.yaml", "moves to 10"), (f"{tmp_path}/fail.yaml", "expects too much")]
    assert cases[0].find("failure") is None
    failure = cases[1].find("failure")
    assert failure is not None
    assert failure.get("message") == (f"step 4 (expect) at {tmp_path}/fail.yaml:8:5:"
                                      " expected X1.position = 10 ± 0.001, found 5 mm")
    assert failure.get("type") == "step"
    assert failure.text is not None and "X1.position: 0.032 s = 3.2" in failure.text


def test_junit_error(tmp_path: Path) -> None:
    loaded = scenario(tmp_path, PASSING)

    def broken(_: Scenario) -> FakeTarget:
        raise RuntimeError("no simulation today")

    path = tmp_path / "junit.xml"
    write_junit(run_scenarios([loaded], broken), path)
    error = ElementTree.parse(path).getroot().find("testsuite/testcase/error")
    assert error is not None and error.get("message") == "RuntimeError: no simulation today"


def test_exit_codes(tmp_path: Path) -> None:
    write_scenario(tmp_path, PASSING, "pass.yaml")
    shown, output = console()
    code = run_command([str(tmp_path / "pass.yaml")], make_target, KNOWN_PROGRAMS, console=shown)
    assert code == EXIT_PASSED
    assert output.getvalue().splitlines()[-1].startswith("1 passed, 0 failed, 0 errors of 1 scenarios")

    write_scenario(tmp_path, FAILING, "fail.yaml")
    junit, traces = tmp_path / "out" / "junit.xml", tmp_path / "out" / "traces"
    shown, output = console()
    code = run_command([str(tmp_path)], make_target, KNOWN_PROGRAMS, junit=junit, trace_dir=traces,
                       console=shown)
    assert code == EXIT_FAILED
    assert ElementTree.parse(junit).getroot().find("testsuite").get("failures") == "1"  # type: ignore[union-attr]
    assert sorted(path.name for path in traces.iterdir()) == [
        "fail.csv", "fail.gtkw", "fail.vcd", "pass.csv", "pass.gtkw", "pass.vcd"]

    write_scenario(tmp_path, PASSING.replace("plc: none", "plc: basic_machin"), "bad.yaml")
    shown, output = console()
    made: list[Scenario] = []
    assert run_command([str(tmp_path)], lambda s: made.append(s) or make_target(s), KNOWN_PROGRAMS,
                       console=shown) == EXIT_PROBLEMS
    assert not made  # nothing ran
    assert output.getvalue().splitlines() == [
        f"{tmp_path}/bad.yaml:3:6: unknown PLC program 'basic_machin'; did you mean basic_machine?"
        " (known: basic_machine, referencing, none)",
        "1 problem in 1 file; nothing ran.",
    ]
    shown, output = console()
    code = run_command([str(tmp_path / "nothing_here")], make_target, KNOWN_PROGRAMS, console=shown)
    assert code == EXIT_PROBLEMS
    assert output.getvalue().startswith(f"{tmp_path}/nothing_here:1:1: no such scenario file or directory")


def test_run_scenario_with_own_recorder(tmp_path: Path) -> None:
    from vc.scenario.run.trace import Recorder

    target = FakeTarget(machine(), SimpleNc())
    recorder = Recorder(target, record_all=False)
    result = run_scenario(scenario(tmp_path, PASSING), target, recorder)
    assert result.passed and result.recorder is recorder
    assert sorted(history.quantity.name for history in recorder.histories) == [
        "CHAN1.basic.out.ncStart", "X1.basic.in.posFineReached"]


def test_locations_and_names_print_as_written(tmp_path: Path) -> None:
    """Rich turned ``:100:`` into an emoji (file💯12) and would read ``[dim]`` in a name as a style."""
    shown, output = console()  # emoji and markup on, as a Console has them by default
    path = write_scenario(tmp_path, "name: \"[dim]x :1234: y\"\n" + HEAD + "# \n" * 95 + "steps:\n  - wiat: 1s\n")
    code = run_command([str(path)], make_target, KNOWN_PROGRAMS, console=shown)
    assert code == EXIT_PROBLEMS
    assert output.getvalue().splitlines()[0] == f"{path}:100:5: unknown step 'wiat'; did you mean wait?"
    report = ConsoleReport(shown)
    loaded = scenario(tmp_path, PASSING.replace("moves to 10", "\"[dim]moves :100: to :1234: 10\""))
    report.print_result(run_scenario(loaded, make_target(loaded)))
    assert output.getvalue().splitlines()[-1].startswith("PASS  [dim]moves :100: to :1234: 10  ")


def test_the_default_console_reads_no_emoji_and_no_markup() -> None:
    default = ConsoleReport().console
    with default.capture() as captured:
        default.print("x.yaml:100:12: [b]y[/b]")
    assert captured.get() == "x.yaml:100:12: [b]y[/b]\n"
