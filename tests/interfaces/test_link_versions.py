"""The link version a PLC reads (Modbus input register 0, the CAN link frames' version) is pinned to
the layout it stands for: the link block, and where every byte of every shipped machine lies in the
tables or frames.  DB100 moved turn_mill's NC-to-PLC table from 325 to 359 registers under the
same version 1, and a PLC built for the old table stopped with "table sizes do not match" instead
of the version check the protocol has for it.

A change of the layout fails here until the link's version is raised and the new layout pinned
under the new number; the versions already given keep their layouts, so no number is given twice.
What each version changed is in docs/modbus.md and docs/can.md (their generators)."""

from __future__ import annotations

import hashlib
import json

from interfaces.catalog import load_catalog
from interfaces.links.can import codec as codec_can
from interfaces.links.can.codec import CanLayout
from interfaces.links.modbus import codec as codec_modbus
from interfaces.links.modbus.codec import RegisterMap, Table
from interfaces.signals import expand
from vc.config.loader import load_machine
from vc.config.machine_files import packaged_machines

# version -> the fingerprint of its layout.  1 was the layout before DB100 (turn_mill 325 / 163
# registers, NC frames to 0x210), never pinned; 2: DB100 at the end of the NC-to-PLC data, over Modbus the
# session key in holding registers 2..5; 3: the channel's auxiliary function area (DB21.DBB58 ff.) and
# DB2, the PLC's user alarms, behind every other block (docs/modbus.md, "Link versions"; docs/can.md); 4: FC18's
# exchange area of every axis, DB31.DBB32-43 (PLC to NC) and DBB104-105 (NC to PLC); 5: the software cams'
# signals DB10.DBB110-117 behind every other block (no address of version 4 moved: backward compatible
# for a PLC that ignores them, the version and the table sizes tell it); 6: the packaged machine gantry_mill and
# DB31.DBX29.4, the gantry's start of the synchronization run (no address of version 5 moved)
MODBUS_LAYOUTS = {
    2: "fffd2c1c55b0696552105b46e4e6152863cf1e343d76537bd4592ebcec3f73f7",
    3: "e1de97c22308d9323762f729d93fdb276ddf82ed16868034bcc93b2f912c0d06",
    4: "934fb304cbcacd0fbc3c6349fc3de513782931a1c03e6e753abacc03f8d14be8",
    5: "2f05c658db7d7dc077bc73acf97da928117f88ce52a07ad868d95b3e158c3241",
    6: "1b0ae20d8a488a9c88d66a983027b2f0b08261ea2b4ff422095cdfb287547930",
}
CAN_LAYOUTS = {
    2: "d7cb80778840f026a9c38e6e6f0299ce63065adfe46ca65be12b8c5b7032003a",
    3: "fdd22d9d3486115be60c64d4d1aaafe98e2f36046120c737bc877c52b46db651",
    4: "cac4454b04b31bc99012e93fdf84b21ea6c9e2575e55dc47720d2c92ee9b8575",
    5: "10545fadf2af467f34875c1d9418d859e436976d490e224215bf2cc3874da68a",
    6: "7e97514e4825df906834743dc65ba3d2641afb75cdd5a37402956740494eff8d",
}


def _fingerprint(layout: object) -> str:
    return hashlib.sha256(json.dumps(layout, sort_keys=True).encode()).hexdigest()


def modbus_layout() -> dict[str, object]:
    """The link block and the segments of both tables of every shipped machine."""
    machines = {}
    for name in packaged_machines():
        machine = load_machine(name)
        register_map = RegisterMap.build(expand(load_catalog(), machine.layout), machine.plant_io.area_sizes())
        machines[name] = {table.value: [[segment.area, segment.start, segment.stop, segment.table_byte]
                                        for segment in register_map.segments[table]] for table in Table}
    return {
        "link_input": {member.name: member.value for member in codec_modbus.LinkInput},
        "link_holding": {member.name: member.value for member in codec_modbus.LinkHolding},
        "link_registers": codec_modbus.LINK_REGISTERS,
        "session_key_registers": codec_modbus.SESSION_KEY_REGISTERS,
        "description_register": codec_modbus.DESCRIPTION_REGISTER,
        "machines": machines,
    }


def can_layout() -> dict[str, object]:
    """The link frames' format and the data frames of every shipped machine."""
    machines = {}
    for name in packaged_machines():
        machine = load_machine(name)
        catalog = expand(load_catalog(), machine.layout)
        layout = CanLayout.build(catalog, machine.plant_io.area_sizes(), machine.can.settings)
        machines[name] = [[slot.can_id, slot.direction.value, slot.area, slot.start, slot.stop, slot.length,
                           slot.checksum, slot.fd] for items in layout.slots.values() for slot in items]
    return {"link_frame": codec_can._LINK.format, "link_frame_bytes": codec_can.LINK_FRAME_BYTES,
            "description_header_bytes": codec_can.DESCRIPTION_HEADER_BYTES, "machines": machines}


def _check(link: str, version: int, pinned: dict[int, str], layout: dict[str, object], where: str) -> None:
    fingerprint = _fingerprint(layout)
    assert version == max(pinned), f"{link} link version {version} is not the latest pinned ({max(pinned)})"
    assert fingerprint == pinned[version], (
        f"the {link} link's layout changed (fingerprint {fingerprint}), and version {version} stands for another"
        f" one: a PLC built for version {version} would read and write the wrong places. Raise LINK_VERSION in"
        f" {where}, pin the new fingerprint here under the new number and say in the docs what changed.")
    assert len(set(pinned.values())) == len(pinned), f"two {link} link versions pinned to one layout"


def test_the_modbus_link_version_stands_for_its_layout() -> None:
    _check("Modbus", codec_modbus.LINK_VERSION, MODBUS_LAYOUTS, modbus_layout(), "interfaces/links/modbus/codec.py")


def test_the_can_link_version_stands_for_its_layout() -> None:
    _check("CAN", codec_can.LINK_VERSION, CAN_LAYOUTS, can_layout(), "interfaces/links/can/codec.py")


def test_a_moved_signal_changes_the_fingerprint() -> None:
    """The check can fail: one byte range a byte longer is another layout."""
    layout = modbus_layout()
    machines = layout["machines"]
    assert isinstance(machines, dict)
    first = machines["turn_mill"]["nc_to_plc"][0]
    first[2] += 1
    assert _fingerprint(layout) != MODBUS_LAYOUTS[codec_modbus.LINK_VERSION]
