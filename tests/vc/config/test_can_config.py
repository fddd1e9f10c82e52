"""The ``can:`` section of a machine file: defaults, every key, and every mistake reported with
its file, line and column."""

from __future__ import annotations

from pathlib import Path

import pytest

from interfaces.links.can.codec import CanSettings
from vc.config.can_config import read_can_section
from vc.config.loader import load_machine
from vc.config.model import CanConfig
from vc.located_yaml import LocatedMap, Problems, SourceError, load_text

ROOT = Path(__file__).resolve().parents[3]
TURN_MILL = ROOT / "scenarios" / "machines" / "turn_mill.yaml"


def section(text: str) -> tuple[CanConfig, list[str]]:
    document, problems = load_text(text, "m.yaml")
    assert not problems and isinstance(document, LocatedMap)
    collected = Problems()
    config = read_can_section(document["can"], document.mark_of("can"), collected).config
    return config, [str(problem) for problem in sorted(collected.items)]


def test_defaults_without_a_section_and_with_an_empty_one() -> None:
    assert section("can:\n")[0] == CanConfig()
    assert CanConfig().settings == CanSettings(0x100, 0x200, 0x400, True, True)
    assert (CanConfig().period, CanConfig().timeout_s, CanConfig().restart_s) == ("plc", 0.05, 0.1)


def test_every_key() -> None:
    config, problems = section("can:\n  ids: {link: 0x80, nc_to_plc: 0x300, plc_to_nc: 0x500}\n  fd: false\n"
                               "  checksum: false\n  period: 0.004\n  timeout: 0.1\n  restart: 0\n")
    assert problems == []
    assert config.settings == CanSettings(0x80, 0x300, 0x500, False, False)
    assert (config.period, config.timeout_s) == (0.004, 0.1)
    assert config.period_cycles(2000, 5) == 2 and config.timeout_cycles(2000) == 50
    assert config.restart_cycles(2000) == 0 and CanConfig().restart_cycles(2000) == 50
    assert section("can: {period: ipo}\n")[0].period_cycles(2000, 5) == 1
    assert section("can: {period: plc}\n")[0].period_cycles(2000, 5) == 5


def test_every_mistake_with_its_place() -> None:
    _, problems = section("can:\n  ids: {link: 0x800, nc_to_plc: two, data: 5}\n  fd: yes please\n"
                          "  checksum: 1\n  period: fast\n  timeout: -1\n  bitrate: 500000\n  restart: -0.1\n")
    assert problems == [
        "m.yaml:2:15: can.ids.link: expected an 11-bit identifier 0..0x7FF (e.g. 0x200), got 2048",
        "m.yaml:2:33: can.ids.nc_to_plc: expected an 11-bit identifier 0..0x7FF (e.g. 0x200), got 'two'",
        "m.yaml:2:38: unknown key 'data' in can.ids; allowed: link, nc_to_plc, plc_to_nc",
        "m.yaml:3:7: can.fd: expected true or false, got 'yes please'",
        "m.yaml:4:13: can.checksum: expected true or false, got 1",
        "m.yaml:5:11: can.period: expected plc, ipo or seconds greater than 0 (e.g. 0.004), got 'fast'",
        "m.yaml:6:12: can.timeout: expected seconds greater than 0 (e.g. 0.05), got -1",
        "m.yaml:7:3: unknown key 'bitrate' in can; allowed: ids, fd, checksum, period, timeout, restart",
        "m.yaml:8:12: can.restart: expected seconds, 0 or more (e.g. 0.1; 0: no automatic restart after bus-off),"
        " got -0.1",
    ]
    _, problems = section("can: [0x100]\n")
    assert problems == ["m.yaml:1:6: can: expected a mapping with ids, fd, checksum, period, timeout, restart,"
                        " got a list"]


def machine_file_with(tmp_path: Path, text: str) -> Path:
    """turn_mill's file with a ``can:`` section appended."""
    path = tmp_path / "turn_mill_can.yaml"
    path.write_text(TURN_MILL.read_text(encoding="utf-8") + text, encoding="utf-8")
    return path


def test_the_loader_keeps_the_section_in_the_machine(tmp_path: Path) -> None:
    assert load_machine(str(TURN_MILL)).can == CanConfig()
    config = load_machine(str(machine_file_with(tmp_path, "can:\n  ids: {nc_to_plc: 0x180}\n  period: 0.004\n"))).can
    assert config.settings.nc_to_plc_id == 0x180 and config.period == 0.004


def test_the_loader_checks_what_only_the_machine_can_tell(tmp_path: Path) -> None:
    path = machine_file_with(tmp_path, "can:\n  ids: {nc_to_plc: 0x101}\n  period: 0.003\n")
    with pytest.raises(SourceError) as caught:
        load_machine(str(path))
    lines = len(TURN_MILL.read_text(encoding="utf-8").splitlines())
    assert [str(problem) for problem in caught.value.problems] == [
        f"{path}:{lines + 2}:8: can.ids: the link frames (0x100..0x102) overlap the NC-to-PLC data frames"
        f" (0x101..0x114)",
        f"{path}:{lines + 3}:11: can.period = 0.003 s is not a whole number of IPO cycles (2 ms)",
    ]


def test_a_scenario_that_changes_the_ipo_cycle_gets_the_period_checked_again(tmp_path: Path) -> None:
    """The period is checked against the IPO cycle after the scenario's machine data: 4 ms are two
    cycles of 2 ms but not a whole number of 3 ms cycles."""
    path = machine_file_with(tmp_path, "can:\n  period: 0.004\n")
    assert load_machine(str(path)).can.period_cycles(2000, 5) == 2
    overrides, problems = load_text("NC: {MD10050 SYSCLOCK_CYCLE_TIME: 0.003}\n", "s.yaml")
    assert not problems and isinstance(overrides, LocatedMap)
    with pytest.raises(SourceError) as caught:
        load_machine(str(path), overrides, "s.yaml")
    lines = len(TURN_MILL.read_text(encoding="utf-8").splitlines())
    assert [str(problem) for problem in caught.value.problems] == [
        f"{path}:{lines + 2}:11: can.period = 0.004 s is not a whole number of IPO cycles (3 ms)"]
