"""docs/plc_examples/turn_mill.st against the map: every signal it uses must be a signal of ``vc map
--format codesys`` for turn_mill, written only if the PLC writes it, and every located address it
declares must be the map's.  (No IEC 61131-3 compiler is packaged here; the program runs on a test
bench against vc serve in tests/plc_examples/test_turn_mill_st.py.)"""

from __future__ import annotations

import re
from pathlib import Path

from interfaces.catalog import load_catalog
from interfaces.exports.codesys import codesys_gvl
from interfaces.exports.context import ExportContext
from interfaces.links.modbus.codec import RegisterMap
from interfaces.signal_map import map_rows
from interfaces.signals import expand
from vc.config.loader import load_machine

ROOT = Path(__file__).resolve().parents[1]
PROGRAM = ROOT / "docs" / "plc_examples" / "turn_mill.st"
# a name that starts like one of turn_mill's instances is meant as a signal
SIGNAL_LIKE = re.compile(r"\b(?:NC|MODEGROUP|HMI|CHAN\d+|X1|Z1|Y1|SP\d|MCP|EStop|Drives|Door|Lamp|LINK)_\w+")


def _gvl() -> dict[str, tuple[str, str]]:
    """name -> (location, area I or Q) of the CODESYS list."""
    machine = load_machine(str(ROOT / "scenarios" / "machines" / "turn_mill.yaml"))
    catalog = expand(load_catalog(), machine.layout)
    text = codesys_gvl(map_rows(catalog, machine.plant_io),
                       ExportContext(machine.name, RegisterMap.build(catalog, machine.plant_io.area_sizes())))
    return {name: (location, location[1]) for name, location in re.findall(r"^\t(\w+) AT (%\S+) :", text, re.MULTILINE)}


def _code() -> str:
    return re.sub(r"\(\*.*?\*\)", " ", PROGRAM.read_text(), flags=re.DOTALL)


def test_every_signal_the_program_uses_is_a_signal_of_the_map() -> None:
    gvl = _gvl()
    used = set(SIGNAL_LIKE.findall(_code()))
    assert len(used) > 100
    assert sorted(used - set(gvl)) == []


def test_the_program_writes_only_what_the_plc_writes() -> None:
    gvl = _gvl()
    written = set(re.findall(r"\b(\w+)\s*:=", _code()))
    signals = written & set(gvl)
    assert {"NC_basic_out_emergencyStopAck", "SP1_spindle_out_oscillEnable", "X1_basic_out_refPointApproachCam",
            "SP1_gearShift2", "Drives_on", "LINK_sessionReady", "LINK_scanDone"} <= signals
    assert sorted(name for name in signals if gvl[name][1] != "Q") == []


def test_located_addresses_in_the_program_are_the_maps() -> None:
    gvl = _gvl()
    for name, location in re.findall(r"\b(\w+)\s+AT\s+(%[IQM][XBWD]?[\d.]+)", _code()):
        assert gvl.get(name, ("", ""))[0] == location, name
