"""The coverage report: figures that add up, what was never exercised with its meaning and source,
the standalone HTML page, thresholds, and the commands vc run --coverage and vc coverage report."""

from __future__ import annotations

import json
import re
from pathlib import Path

import pytest

from interfaces.links.inprocess import plc_programs
from vc.cli.main import main
from vc.core.alarms import ALARM_TEXTS
from vc.coverage.collector import CoverageCollector
from vc.coverage.data import CoverageData
from vc.coverage.html import report_html
from vc.coverage.report import Report, build_report, check_thresholds, summary_text
from vc.coverage.state_machines import STATE_MACHINES
from vc.harness.targets import simulation_for
from vc.scenario.language.loader import load_scenarios
from vc.scenario.run.runner import run_scenarios

ROOT = Path(__file__).resolve().parents[3]
REFERENCING = ROOT / "scenarios" / "referencing" / "incremental_jog_ref_falling_edge.yaml"


@pytest.fixture(scope="module")
def data() -> CoverageData:
    collector = CoverageCollector()
    run_scenarios(load_scenarios([str(REFERENCING)], plc_programs().keys()), collector.observe(simulation_for))
    return collector.data


@pytest.fixture(scope="module")
def report(data: CoverageData) -> Report:
    return build_report(data)


def test_the_figures_add_up(report: Report) -> None:
    categories = report.categories
    assert report.total.covered == sum(figure.covered for figure in categories.values())
    assert report.total.total == sum(figure.total for figure in categories.values())
    assert categories["signals"].total == sum(figure.total for figure in report.db_kinds) == \
        sum(figure.total for figure in report.instances)
    assert categories["functions"].total == sum(len(m.states) + len(m.transitions) for m in STATE_MACHINES)
    assert categories["alarms"].total == 2 * len(ALARM_TEXTS)
    assert 0 < report.total.percent < 100
    incremental = next(f for f in report.functions if f.machine.name == "referencing.incremental_cam")
    assert incremental.states.covered == 8 and incremental.instances == 3  # X1, Z1, Y1: incremental with a cam


def test_what_was_never_exercised_has_meaning_and_source(report: Report) -> None:
    gaps = {(gap.category, gap.item): gap for gap in report.gaps}
    brake = gaps[("functions", "P2_BRAKE_OFF_CAM")]
    assert brake.missing == "never entered" and brake.meaning == "phase 2: braking off the cam"
    source = (ROOT / "vc/core/referencing/referencing.py").read_text().splitlines()
    line = next(number for number, text in enumerate(source, start=1) if "P2_BRAKE_OFF_CAM = " in text)
    assert brake.source == f"vc/core/referencing/referencing.py:{line}"
    lost = gaps[("signals", "Z1.basic.in.enc1Synchronized")]
    assert lost.address == "DB32.DBX60.4" and lost.missing == "seen 1, rises, falls"
    assert lost.meaning == "Referenced / synchronized, measuring system 1" and "seed 003 L633" in lost.source
    assert lost.group == "turn_mill Z1 (DB32) basic.in"
    alarm = gaps[("alarms", "22010")]
    assert alarm.missing == "never raised" and alarm.meaning == ALARM_TEXTS[22010].text
    assert re.search(r"vc/core/alarms.py:\d+$", alarm.source)
    assert ("signals", "X1.spindle.in.gearChangeoverActive") not in gaps  # not applicable on a linear axis


def test_the_html_page_stands_alone(report: Report) -> None:
    page = report_html(report)
    assert page.startswith("<!DOCTYPE html>") and page.rstrip().endswith("</html>")
    assert "<script" not in page and "http" not in page and "<link" not in page
    assert "P2_BRAKE_OFF_CAM" in page and "phase 2: braking off the cam" in page
    assert "vc/core/referencing/referencing.py:" in page and "Z1.basic.in.enc1Synchronized" in page
    assert "&lt;" not in page.split("<body>")[0]  # nothing escaped in the head


def test_thresholds(report: Report) -> None:
    assert check_thresholds(report, 1, {"referencing.incremental_cam": 40, "mode_group": 10}) == []
    short = check_thresholds(report, 99, {"gear_change": 90, "referencing": 80, "DB31": 95})
    assert short[0].startswith(f"total coverage {report.total.percent:.1f} % is below 99 %")
    assert [line.split(" ")[0] for line in short[1:]] == ["DB31", "gear_change", "referencing"]
    with pytest.raises(KeyError, match="unknown coverage figure nonsense"):
        check_thresholds(report, None, {"nonsense": 5})


def test_the_summary_names_every_data_block_and_state_machine(report: Report) -> None:
    text = summary_text(report)
    for line in ("DB10 NCK", "DB31 axes", "turn_mill DB34 SP1", "gear_change", "referencing.follow_up", "total"):
        assert line in text


def test_vc_run_coverage_and_vc_coverage_report(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    coverage = tmp_path / "coverage.json"
    assert main(["run", str(REFERENCING), "--coverage", str(coverage)]) == 0
    out = capsys.readouterr().out
    assert re.search(rf"interface coverage \d+\.\d % \(\d+ of \d+ points\) written to {re.escape(str(coverage))}", out)
    html, report_json = tmp_path / "coverage.html", tmp_path / "report.json"
    assert main(["coverage", "report", str(coverage), str(coverage), "--html", str(html), "--json",
                 str(report_json), "--fail-under", "5", "--fail-under-function", "channel=10"]) == 0
    summary = capsys.readouterr().out
    assert "Interface coverage of 2 scenario runs" in summary  # the same file twice: merged
    figures = json.loads(report_json.read_text())
    assert figures["scenarios"] == 2 and figures["gaps"] and html.read_text().startswith("<!DOCTYPE html>")

    assert main(["coverage", "report", str(coverage), "--fail-under", "99"]) == 1
    assert "FAIL total coverage" in capsys.readouterr().err
    assert main(["coverage", "report", str(coverage), "--fail-under-function", "gear_change=90"]) == 1
    assert "FAIL gear_change coverage" in capsys.readouterr().err
    assert main(["coverage", "report", str(coverage), "--fail-under-function", "gearbox=90"]) == 2
    assert "unknown coverage figure gearbox" in capsys.readouterr().err
    assert main(["coverage", "report", str(coverage), "--fail-under-function", "gear_change"]) == 2
    assert "write NAME=PERCENT" in capsys.readouterr().err
    broken = tmp_path / "broken.json"
    broken.write_text('{"format": "vc-coverage",', encoding="utf-8")
    assert main(["coverage", "report", str(coverage), str(broken)]) == 2
    err = capsys.readouterr().err
    assert f"{broken}:1:26: not a coverage file" in err and "Traceback" not in err


def test_the_alarm_list_db100_is_a_data_block_of_its_own_with_meaning_and_address(report: Report) -> None:
    """DB100's rows were counted as axis signals, with empty address, meaning and source."""
    assert [figure.name for figure in report.db_kinds][-1] == "DB100" and report.db_kinds[-1].total > 0
    entries = [gap for gap in report.gaps if gap.item.startswith("ALARMS.")]
    assert entries and all(gap.address.startswith("DB100.") and gap.meaning and gap.source for gap in entries)
    second = next(gap for gap in entries if gap.item == "ALARMS.entry[2].in.number")
    assert second.address == "DB100.DBD12" and second.meaning == "Number of the 2nd alarm present (0: none)"


def test_signals_the_nc_does_not_model_are_listed_apart_and_counted_nowhere(
        data: CoverageData, report: Report) -> None:
    """They were counted as "never exercised": no scenario can exercise them."""
    from vc.coverage.names import definitions, kind_of_db

    catalogue = definitions()
    not_modelled = {item.symbol for item in catalogue.values() if not item.modelled}
    assert report.not_modelled and {gap.item for gap in report.not_modelled} <= not_modelled
    assert all(gap.missing for gap in report.not_modelled)  # why: the catalogue's not_modelled
    for gap in (gap for gap in report.gaps if gap.category == "signals"):
        kind = kind_of_db(int(gap.address.split(".")[0][2:]))
        assert kind is not None and catalogue[(kind, gap.item.split(".", 1)[1])].modelled, gap
    page, text = report_html(report), summary_text(report)
    assert f"Not modelled by the NC ({len(report.not_modelled)})" in page
    assert f"{len(report.not_modelled)} catalogue signals the NC does not model are left out" in text
    assert build_report(data).to_json()["not_modelled"]
