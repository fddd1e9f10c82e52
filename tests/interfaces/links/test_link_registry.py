"""The registry of link kinds (interfaces/links/__init__.py) is what every place that chooses a link
reads: ``vc run --link``, a scenario's ``link:``, ``python -m plc_stub`` and ``vc serve``."""

from __future__ import annotations

import pytest

from interfaces.links import INPROCESS, LINKS, UnknownLink, in_process_links, link_kind, load
from plc_stub.__main__ import main as plc_stub_main


def test_an_unknown_link_names_the_known_ones() -> None:
    with pytest.raises(UnknownLink, match="no link 'profinet' \\(known: modbus, can\\)"):
        link_kind("profinet")


def test_a_row_names_what_it_loads_by_module_and_name() -> None:
    from vc.harness.external_plc import CanPlcProcess

    assert load(LINKS["can"].plc_process) == CanPlcProcess.for_run
    with pytest.raises(AttributeError):
        load("interfaces.links.can.plc_end:nonesuch")


def test_vc_run_offers_in_process_and_every_link_of_the_registry(capsys: pytest.CaptureFixture[str]) -> None:
    from vc.cli.main import main as vc_main

    with pytest.raises(SystemExit):
        vc_main(["run", "--link", "profinet", "scenarios"])
    assert f"choose from {', '.join(repr(name) for name in (INPROCESS, *LINKS))}" in capsys.readouterr().err


def test_python_m_plc_stub_has_an_option_per_link(capsys: pytest.CaptureFixture[str]) -> None:
    with pytest.raises(SystemExit):
        plc_stub_main(["--help"])
    shown = " ".join(capsys.readouterr().out.split())
    assert [name for name, kind in LINKS.items() if f"--{name} {kind.address}" not in shown] == []


def test_a_malformed_address_is_a_usage_error_before_anything_runs(capsys: pytest.CaptureFixture[str]) -> None:
    with pytest.raises(SystemExit) as caught:
        plc_stub_main(["--modbus", "localhost"])
    assert caught.value.code == 2
    assert "argument --modbus: 'localhost' is not HOST:PORT (e.g. 127.0.0.1:5020)" in capsys.readouterr().err


def test_a_scenario_may_put_its_plc_behind_each_link_that_runs_in_process() -> None:
    from vc.scenario.language.loader import LINKS as SCENARIO_LINKS

    assert SCENARIO_LINKS == in_process_links() == ("can",)


def test_vc_serve_chooses_its_link_by_the_registry_name_of_its_options() -> None:
    from interfaces.links.can.bus import BusSpec
    from vc.harness.serve import ServeOptions

    assert ServeOptions("turn_mill").link == "modbus"
    assert ServeOptions("turn_mill", can=BusSpec.parse("virtual")).link == "can"
    assert load(link_kind("can").harness).__module__ == "vc.harness.links.can"
