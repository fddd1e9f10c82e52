"""The README's Quickstart: exactly two commands, and .ci/run runs the second one; the figures the
README states of the layout (its import contracts) are those of pyproject.toml."""

from __future__ import annotations

import re
import tomllib
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def quickstart_commands() -> list[str]:
    text = (ROOT / "README.md").read_text(encoding="utf-8")
    section = text.split("## Quickstart", 1)[1].split("\n## ", 1)[0]
    blocks = re.findall(r"```sh\n(.*?)```", section, flags=re.DOTALL)
    return [line for block in blocks for line in block.splitlines() if line.strip()]


def test_quickstart_has_exactly_two_commands() -> None:
    commands = quickstart_commands()
    assert len(commands) == 2
    assert commands[0].endswith("vc run scenarios/")
    assert "'.[test]'" in commands[1] and commands[1].endswith("pytest")


def test_ci_runs_the_readme_test_command() -> None:
    ci = (ROOT / ".ci" / "run").read_text(encoding="utf-8")
    assert f'TEST_COMMAND="{quickstart_commands()[1]}"' in ci
    assert 'bash -c "$TEST_COMMAND"' in ci


def test_the_modbus_example_reads_the_address_vc_map_gives() -> None:
    """"`SYMBOL` (ADDRESS) is discrete input N, display number D (`mbpoll ... -t 1 -r R ...`)"
    must be what the map of the default machine says, in every number."""
    from interfaces.catalog import load_catalog
    from interfaces.signal_map import map_rows
    from interfaces.signals import expand
    from vc.config.loader import load_machine
    from vc.config.machine_files import DEFAULT_MACHINE

    text = " ".join((ROOT / "README.md").read_text(encoding="utf-8").split())
    example = re.search(r"`(?P<symbol>[\w.]+)` \((?P<address>DB[\w.]+)\) is discrete input (?P<number>\d+), display"
                        r" number (?P<display>\d+) \(`mbpoll -m tcp -p 5020 -t 1 -r (?P<reference>\d+) -c 1", text)
    assert example is not None, "the README's Modbus example is gone or reworded"
    machine = load_machine(DEFAULT_MACHINE)
    rows = {row.symbol: row for row in map_rows(expand(load_catalog(), machine.layout), machine.plant_io)}
    row = rows[example["symbol"]]
    assert (row.address, row.modbus_table) == (example["address"], "discrete_input")
    assert int(example["number"]) == row.modbus_address
    assert example["display"] == row.modbus_number
    assert int(example["reference"]) == int(example["number"]) + 1  # mbpoll's -r counts from 1


def test_the_test_run_lists_its_skips_with_their_reasons() -> None:
    """The README explains the skips the test command reports: pytest must list them (``-r`` with
    ``s``), and the failures and errors as its default ``-r fE`` does (``-r`` replaces it)."""
    import tomllib

    options = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))["tool"]["pytest"]["ini_options"]
    report = [option[2:] for option in options["addopts"].split() if option.startswith("-r")]
    assert report and set("fEs") <= set(report[0])
    text = " ".join((ROOT / "README.md").read_text(encoding="utf-8").split())
    assert f"`-r{report[0]}` in `pyproject.toml`" in text


def test_the_readme_counts_the_import_contracts_of_pyproject() -> None:
    said = re.search(r"`lint-imports`, (\d+) contracts in `pyproject.toml`", (ROOT / "README.md").read_text())
    contracts = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))["tool"]["importlinter"]
    assert said is not None and int(said.group(1)) == len(contracts["contracts"])
