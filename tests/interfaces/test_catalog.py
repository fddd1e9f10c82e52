"""The signal catalogue (interfaces/catalog/*.yaml) as loaded, expanded and used through a process image."""

from __future__ import annotations

import re
from functools import lru_cache
from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from interfaces.address import Address
from interfaces.catalog import load_catalog
from interfaces.image import ProcessImage, Value
from interfaces.signals import (
    FIRST_DB,
    PLACEHOLDER,
    Direction,
    ExpandedCatalog,
    InstanceKind,
    InterfaceLayout,
    Origin,
    SignalInstance,
    SignalType,
    Trigger,
    UnknownSignalError,
    expand,
)

LAYOUT = InterfaceLayout(channels=("CHAN1", "CHAN2"), axes=("X1", "Z1", "SP1"))
SEED_NAME = "shared/seeds/003_95dbb5e1007b236c.txt"
CONTROL_NOTE = (
    "not in the seed; address of the real control (840D sl list manual); symbols chosen by the project"
)
CONTROL_SOURCE = "SINUMERIK 840D sl NC variables and interface signals, list manual (external)"


@lru_cache(maxsize=1)
def expanded() -> ExpandedCatalog:
    return expand(load_catalog(), LAYOUT)


def by_address(text: str) -> SignalInstance:
    item = expanded().signal_at(Address.parse(text))
    assert item is not None, f"{text} is not in the catalogue"
    return item


@lru_cache(maxsize=1)
def seed_lines() -> list[str] | None:
    for base in (Path(__file__).resolve().parents[3], Path("/work")):
        path = base / SEED_NAME
        if path.is_file():
            return path.read_text(encoding="utf-8").split("\n")
    return None


# --------------------------------------------------------------------------------------------
# 1. loading and uniqueness


def test_catalog_loads_with_the_five_kinds() -> None:
    catalog = load_catalog()
    assert {section.kind for section in catalog.sections} == set(InstanceKind)
    for section in catalog.sections:
        assert section.db == FIRST_DB[section.kind]
        assert section.signals, f"DB{section.db} has no signals"
        for signal in section.signals:
            assert signal.address.db == section.db
            assert signal.symbol.startswith(PLACEHOLDER[section.kind] + ".")


def test_sizes_cover_the_highest_signals() -> None:
    catalog = load_catalog()
    minimum = {InstanceKind.NCK: 110, InstanceKind.MODE_GROUP: 8, InstanceKind.HMI: 21,
               InstanceKind.CHANNEL: 378, InstanceKind.AXIS: 104}
    for kind, size in minimum.items():
        assert catalog.section(kind).size >= size


def test_expanded_symbols_and_addresses_are_unique() -> None:
    items = expanded().signals
    symbols = [item.symbol for item in items]
    addresses = [item.address for item in items]
    assert len(set(symbols)) == len(symbols)
    assert len({symbol.casefold() for symbol in symbols}) == len(symbols)
    assert len(set(addresses)) == len(addresses)
    per_kind = {section.kind: len(section.signals) for section in load_catalog().sections}
    expected = (per_kind[InstanceKind.NCK] + per_kind[InstanceKind.MODE_GROUP] + per_kind[InstanceKind.HMI]
                + 2 * per_kind[InstanceKind.CHANNEL] + 3 * per_kind[InstanceKind.AXIS] + per_kind[InstanceKind.ALARMS]
                + per_kind[InstanceKind.PLC_ALARMS])
    assert len(items) == expected


def test_instances_land_in_their_data_blocks() -> None:
    assert expanded().area_sizes.keys() == {"DB2", "DB10", "DB11", "DB19", "DB21", "DB22", "DB31", "DB32",
                                               "DB33", "DB100"}
    assert expanded().resolve("CHAN2.basic.out.reset").address == Address.parse("DB22.DBX7.7")
    assert expanded().resolve("SP1.basic.in.enc1Synchronized").address == Address.parse("DB33.DBX60.4")
    assert expanded().resolve("MODEGROUP.basic.out.jogMode").address == Address.parse("DB11.DBX0.2")
    assert expanded().resolve("NC.basic.out.emergencyStop").address == Address.parse("DB10.DBX56.1")
    assert expanded().resolve("HMI.basic.out.displayWcsValues").address == Address.parse("DB19.DBX0.7")
    assert expanded().resolve("ALARMS.entry[2].in.number").address == Address.parse("DB100.DBD12")
    assert expanded().resolve("PLCALARMS.userArea0.out.alarm700009").address == Address.parse("DB2.DBX181.1")


def test_the_alarm_block_is_a_project_block_behind_every_axis() -> None:
    """DB100 follows the axis blocks in every link's order, so it moves no address of theirs."""
    section = load_catalog().section(InstanceKind.ALARMS)
    assert section.db == 100 and all(signal.origin is Origin.PROJECT for signal in section.signals)
    assert all(signal.direction is Direction.NC_TO_PLC for signal in section.signals)
    assert expanded().byte_ranges(Direction.NC_TO_PLC)[-2] == ("DB100", 0, section.size)


def test_the_software_cam_signals_come_behind_every_block() -> None:
    """DB10.DBB110-117 (the cam signals, catalogued after the links' layout) follow every other
    NC-to-PLC range, DB100 too, so that no address moves; DB10's own range ends before them."""
    ranges = expanded().byte_ranges(Direction.NC_TO_PLC)
    assert ranges[-1] == ("DB10", 110, 118)
    assert ("DB10", 106, 110) in ranges
    cams = [signal for signal in load_catalog().section(InstanceKind.NCK).signals if "swCams" in signal.symbol]
    assert [str(signal.address) for signal in cams[:9]] == [*(f"DB10.DBX110.{bit}" for bit in range(8)),
                                                            "DB10.DBX111.0"]
    assert (cams[31].symbol, str(cams[32].address)) == ("<Nc>.basic.in.swCams[0].minus32", "DB10.DBX114.0")


def test_the_plc_alarm_block_comes_last_in_the_links_order() -> None:
    """DB2 (the PLC's user alarms, added after the links' layout) follows every other PLC-to-NC
    range, so that no address of the other blocks moves; alarm 700000 + n is bit n from DBX180.0."""
    section = load_catalog().section(InstanceKind.PLC_ALARMS)
    assert section.db == 2 and all(signal.direction is Direction.PLC_TO_NC for signal in section.signals)
    assert expanded().byte_ranges(Direction.PLC_TO_NC)[-1] == ("DB2", 180, 188)
    assert [str(signal.address) for signal in section.signals[:9]] == [
        *(f"DB2.DBX180.{bit}" for bit in range(8)), "DB2.DBX181.0"]
    assert section.signals[63].symbol == "<PlcAlarms>.userArea0.out.alarm700063"


# --------------------------------------------------------------------------------------------
# 2. round trips


def test_every_signal_resolves_by_symbol_and_by_address() -> None:
    cat = expanded()
    for item in cat.signals:
        by_symbol = cat.resolve(item.symbol)
        assert by_symbol.address == item.address
        assert by_symbol.signal == item
        assert (by_symbol.type, by_symbol.bits, by_symbol.direction) == (
            item.type, item.definition.bits, item.direction)
        by_text = cat.resolve(str(item.address))
        assert by_text.address == item.address
        assert by_text.signal == item
        assert by_text.direction == item.direction
        if item.type is SignalType.BITS:
            # an absolute bit address names one bit, even where a bits field starts
            assert (by_text.type, by_text.bits) == (SignalType.BOOL, 1)
        else:
            assert (by_text.type, by_text.bits) == (item.type, item.definition.bits)
        assert Address.parse(str(item.address)) == item.address
        assert cat.resolve(item.symbol.lower()).signal == item


def _values(item: SignalInstance) -> st.SearchStrategy[Value]:
    if item.type is SignalType.REAL:
        return st.floats(width=32, allow_nan=False, allow_infinity=False)
    return st.integers(0, (1 << item.definition.bits) - 1)


@settings(max_examples=400, deadline=None)
@given(data=st.data())
def test_written_values_read_back_and_touch_nothing_else(data: st.DataObject) -> None:
    cat = expanded()
    item = data.draw(st.sampled_from(cat.signals), label="signal")
    value = data.draw(_values(item), label="value")
    image = ProcessImage(cat.area_sizes)
    key = item.address.area_key
    background = data.draw(st.binary(min_size=len(image.area(key)), max_size=len(image.area(key))))
    image.area(key)[:] = background
    before = image.snapshot()
    ref = cat.resolve(item.symbol)
    image.write(ref, value)
    assert image.read(ref) == value
    if item.type in (SignalType.BOOL, SignalType.BITS):
        mask = ((1 << item.definition.bits) - 1) << item.address.bit
        byte = item.address.byte
        assert image.area(key)[byte] & ~mask & 0xFF == background[byte] & ~mask & 0xFF
    span = set(item.definition.byte_span)
    for change in image.changes_since(before):
        assert change.area == key and change.byte in span, change


@settings(max_examples=200, deadline=None)
@given(data=st.data())
def test_a_bool_write_keeps_the_neighbouring_bits(data: st.DataObject) -> None:
    cat = expanded()
    bools = [item for item in cat.signals if item.type is SignalType.BOOL]
    item = data.draw(st.sampled_from(bools), label="signal")
    start = data.draw(st.integers(0, 255), label="byte before")
    value = data.draw(st.integers(0, 1), label="value")
    image = ProcessImage(cat.area_sizes)
    area = image.area(item.address.area_key)
    area[item.address.byte] = start
    image.write(cat.resolve(str(item.address)), value)
    expected = (start & ~(1 << item.address.bit)) | (value << item.address.bit)
    assert area[item.address.byte] == expected


# --------------------------------------------------------------------------------------------
# 3. seed citations


def _address_pattern(address: Address) -> str:
    if address.is_bit:
        return rf"(?<![\d.])0*{address.byte}\.{address.bit}(?!\d)"
    return rf"DB{address.width}0*{address.byte}(?!\d)"


def test_seed_citations_print_the_entry() -> None:
    lines = seed_lines()
    if lines is None:
        pytest.skip("seed manual not present")
    problems = []
    for signal in load_catalog().signals:
        if signal.origin is not Origin.SEED:
            continue
        cited = [int(n) for n in re.findall(r"\bL(\d+)\b", signal.source)]
        if not cited:
            problems.append(f"{signal.address}: no seed line cited in {signal.source!r}")
            continue
        tail = signal.symbol.split(".", 1)[1]
        pattern = _address_pattern(signal.address)
        if not any(0 < n <= len(lines) and (re.search(pattern, lines[n - 1]) or tail in lines[n - 1])
                   for n in cited):
            problems.append(f"{signal.address} {signal.symbol}: none of {cited} prints it")
    assert not problems, "\n".join(problems)


def test_entries_say_where_they_come_from() -> None:
    for signal in load_catalog().signals:
        if signal.origin is Origin.SEED:
            assert "seed 003 L" in signal.source, signal.address
        elif signal.origin is Origin.CONTROL:
            assert signal.source.startswith(CONTROL_SOURCE), signal.address
            assert signal.note.startswith(CONTROL_NOTE), signal.address  # then what else the entry needs
        assert signal.meaning, signal.address


def test_control_entries_are_the_agreed_ones() -> None:
    control = {str(s.address) for s in load_catalog().signals if s.origin is Origin.CONTROL}
    assert control == {
        "DB10.DBB1", "DB10.DBX56.2", "DB10.DBX106.1", "DB10.DBX108.7", "DB10.DBX109.0",
        "DB11.DBX0.0", "DB11.DBX6.0", "DB11.DBX6.1", "DB11.DBX7.2",
        "DB21.DBX1.7", *(f"DB21.DBX35.{bit}" for bit in range(7)), "DB21.DBX36.6", "DB21.DBX36.7",
        # the geometry axes' machine functions INC1 .. INC10000 (the seed prints them at DB31 DBX5.x)
        *(f"DB21.DBX{byte}.{bit}" for byte in (13, 17, 21) for bit in range(5)), "DB21.DBX13.5",
        # program control: activate M01, M00/M01 active, M02/M30 active
        "DB21.DBX0.5", "DB21.DBX32.5", "DB21.DBX33.5",
        # auxiliary function output (Basic Functions H2): change and quick signals ...
        *(f"DB21.DBX58.{bit}" for bit in range(5)), *(f"DB21.DBX60.{bit}" for bit in (0, 1, 2, 4, 5, 6)),
        "DB21.DBX61.0", "DB21.DBX61.4", *(f"DB21.DBX62.{bit}" for bit in (0, 1, 4, 5)),
        *(f"DB21.DBX64.{bit}" for bit in (0, 1, 2, 4, 5, 6)), "DB21.DBX65.0",
        *(f"DB21.DBX66.{bit}" for bit in range(5)),
        # ... the values behind the seed's DBW68 (M 1), the S, T, D, DL and H functions ...
        "DB21.DBD70", *(f"DB21.DB{kind}{byte}" for byte in (74, 80, 86, 92) for kind, byte in (("W", byte),
                                                                                              ("D", byte + 2))),
        *(f"DB21.DB{kind}{byte}" for byte in (98, 104, 110, 116, 140, 146, 152)
          for kind, byte in (("W", byte), ("D", byte + 2))),
        "DB21.DBW122", "DB21.DBW124", "DB21.DBW126", "DB21.DBD128",
        # ... the decoded M signals besides the seed's m64Decoded (DBX202.0)
        *(f"DB21.DBX{194 + m // 8}.{m % 8}" for m in range(100) if m != 64),
        # the PLC's user alarms 700000 .. 700063 (the basic program's DB2, user area 0)
        *(f"DB2.DBX{180 + n // 8}.{n % 8}" for n in range(64)),
        # the drive's messages the seed's §18.2 does not print: motor temperature, |n act| < n x, Vdc
        "DB31.DBX94.0", "DB31.DBX94.5", "DB31.DBX95.0",
        # the software cams 2 .. 31 inside the seed's fields DBX110.0..113.7 and DBX114.0..117.7
        *(f"DB10.DBX{base + (n - 1) // 8}.{(n - 1) % 8}" for base in (110, 114) for n in range(2, 32)),
    }


def test_symbols_are_well_formed_and_match_the_direction() -> None:
    form = re.compile(r"^<(Nc|ModeGroup|Hmi|Chan|Axis|Alarms|PlcAlarms)>(\.[A-Za-z][A-Za-z0-9]*(\[\d+\])?)+$")
    for signal in load_catalog().signals:
        assert form.match(signal.symbol), signal.symbol
        expected = Direction.PLC_TO_NC if ".out." in signal.symbol else Direction.NC_TO_PLC
        assert signal.direction is expected, signal.symbol
        if signal.trigger is Trigger.EDGE:
            assert signal.direction is Direction.PLC_TO_NC and signal.type is SignalType.BOOL, signal.symbol


# --------------------------------------------------------------------------------------------
# 4. spot checks


@pytest.mark.parametrize(
    ("address", "symbol", "direction", "signal_type", "bits", "trigger"),
    [
        ("DB31.DBX60.4", "<Axis>.basic.in.enc1Synchronized", "nc_to_plc", "bool", 1, "level"),
        ("DB21.DBX36.2", "<Chan>.basic.in.allAxesReferenced", "nc_to_plc", "bool", 1, "level"),
        ("DB31.DBX12.7", "<Axis>.basic.out.refPointApproachCam", "plc_to_nc", "bool", 1, "level"),
        ("DB31.DBB19", "<Axis>.spindle.out.ovrFactor", "plc_to_nc", "byte", 8, "level"),
        ("DB31.DBD88", "<Axis>.spindle.in.sFuncValue", "nc_to_plc", "real", 32, "level"),
        ("DB31.DBX16.0", "<Axis>.spindle.out.gearStageSelection", "plc_to_nc", "bits", 3, "level"),
        ("DB11.DBX0.2", "<ModeGroup>.basic.out.jogMode", "plc_to_nc", "bool", 1, "level"),
        ("DB21.DBX7.7", "<Chan>.basic.out.reset", "plc_to_nc", "bool", 1, "edge"),
        ("DB21.DBX7.1", "<Chan>.basic.out.ncStart", "plc_to_nc", "bool", 1, "edge"),
        ("DB21.DBX1.0", "<Chan>.basic.out.refPointApproach", "plc_to_nc", "bool", 1, "edge"),
        ("DB31.DBX31.4", "<Axis>.coupling.out.syncSpindleResync", "plc_to_nc", "bool", 1, "edge"),
        ("DB31.DBX31.7", "<Axis>.coupling.out.syncResetCorrection", "plc_to_nc", "bool", 1, "edge"),
        ("DB31.DBX16.4", "<Axis>.spindle.out.resyncEnc1", "plc_to_nc", "bool", 1, "edge"),
        ("DB31.DBX2.4", "<Axis>.basic.out.refPointSelection", "plc_to_nc", "bits", 4, "level"),
        ("DB31.DBX82.0", "<Axis>.spindle.in.requestedGearStageNumber", "nc_to_plc", "bits", 3, "level"),
        ("DB31.DBX68.0", "<Axis>.plcCtrl.in.assignedChanNumber", "nc_to_plc", "bits", 4, "level"),
        ("DB31.DBB0", "<Axis>.basic.out.feedrateOvrFactor", "plc_to_nc", "byte", 8, "level"),
        ("DB21.DBB4", "<Chan>.basic.out.pathFeedrateOvrFactor", "plc_to_nc", "byte", 8, "level"),
        ("DB21.DBW68", "<Chan>.auxMFuncs[1].in.extendedAddress", "nc_to_plc", "word", 16, "level"),
        ("DB31.DBD78", "<Axis>.basic.in.posAxisFeedrateValue", "nc_to_plc", "real", 32, "level"),
        ("DB31.DBB86", "<Axis>.spindle.in.mFuncNumber", "nc_to_plc", "byte", 8, "level"),
        ("DB31.DBX99.0", "<Axis>.coupling.in.leadingSpindleActive", "nc_to_plc", "bool", 1, "level"),
        ("DB31.DBX95.1", "<Axis>.drive.in.esrDcVoltageAlarmActive", "nc_to_plc", "bool", 1, "level"),
        ("DB31.DBX28.7", "<Axis>.plcCtrl.out.requestPlcCtrl", "plc_to_nc", "bool", 1, "level"),
        ("DB21.DBX7.0", "<Chan>.basic.out.disableNcStart", "plc_to_nc", "bool", 1, "level"),
        ("DB21.DBX33.0", "<Chan>.basic.in.refActive", "nc_to_plc", "bool", 1, "level"),
        ("DB10.DBX56.1", "<Nc>.basic.out.emergencyStop", "plc_to_nc", "bool", 1, "level"),
        ("DB19.DBX0.7", "<Hmi>.basic.out.displayWcsValues", "plc_to_nc", "bool", 1, "level"),
        ("DB19.DBX20.7", "<Hmi>.basic.in.mcsWcsSwitched", "nc_to_plc", "bool", 1, "level"),
    ],
)
def test_spot_checks(address: str, symbol: str, direction: str, signal_type: str, bits: int,
                     trigger: str) -> None:
    item = by_address(address)
    definition = item.definition
    assert definition.symbol == symbol
    assert definition.direction is Direction(direction)
    assert definition.type is SignalType(signal_type)
    assert definition.bits == bits
    assert definition.trigger is Trigger(trigger)


def test_signals_that_must_not_be_catalogued() -> None:
    catalog = load_catalog()
    symbols = {signal.symbol for signal in catalog.signals}
    assert not any(s.startswith(("<HmiChan>", "<HmiModeGroup>")) for s in symbols)
    # DBX29.4 is the gantry's start of the synchronization run (§12.4, §12.6), not the channel's
    # "ptpTravers" §12.3.1 also prints at that address
    assert {signal.symbol for signal in catalog.signals if str(signal.address) == "DB31.DBX29.4"} == {
        "<Axis>.coupling.out.gantryStartSyncRun"}
    # the channel's NC start disable lives in DB21; DB31.DBX7.0 is the axis's handwheel inversion, whose
    # symbol the seed misprints as it (L33287, L33404)
    assert by_address("DB31.DBX7.0").definition.symbol == "<Axis>.basic.out.handwheelInvertDir"
    assert not any(signal.address.db == 31 and signal.address.byte >= 132 for signal in catalog.signals)


# --------------------------------------------------------------------------------------------
# 5. resolve errors


@pytest.mark.parametrize(
    ("name", "message"),
    [
        ("Y9.basic.in.enc1Synchronized",
         "unknown signal 'Y9.basic.in.enc1Synchronized': 'Y9' is not an instance of this machine"
         " (known: ALARMS, CHAN1, CHAN2, HMI, MODEGROUP, NC, PLCALARMS, SP1, X1, Z1)"),
        ("X1.basic.in.enc1Synchronised",
         "unknown signal 'X1.basic.in.enc1Synchronised'; did you mean X1.basic.in.enc1Synchronized"
         " or X1.basic.in.enc2Synchronized?"),
        ("X1.nothing.like.this", "unknown signal 'X1.nothing.like.this'"),
        ("DB31.DBX50.0", "DB31.DBX50.0 is not a signal of the catalogue"),
        ("DB34.DBX60.4", "DB34.DBX60.4: this machine has no DB34"),
        ("DB23.DBX7.7", "DB23.DBX7.7: this machine has no DB23"),
        ("DB31.DBW45", "DB31.DBW45 covers bytes that hold no catalogue signal"),
        ("I0.3", "I0.3: plant I/O is not part of the NC/PLC interface"),
    ],
)
def test_resolve_error_messages(name: str, message: str) -> None:
    with pytest.raises(UnknownSignalError) as caught:
        expanded().resolve(name)
    assert str(caught.value) == message


def test_raw_addresses_inside_signals_resolve() -> None:
    cat = expanded()
    gear_b = cat.resolve("DB32.DBX16.1")
    assert gear_b.signal == cat.by_symbol("Z1.spindle.out.gearStageSelection")
    assert (gear_b.type, gear_b.bits, gear_b.direction) == (SignalType.BOOL, 1, Direction.PLC_TO_NC)
    override_bit = cat.resolve("DB31.DBX19.3")
    assert override_bit.signal == cat.by_symbol("X1.spindle.out.ovrFactor")
    status = cat.resolve("DB31.DBW60")
    assert (status.type, status.bits, status.direction, status.signal) == (
        SignalType.WORD, 16, Direction.NC_TO_PLC, None)


# --------------------------------------------------------------------------------------------
# 6. direction ranges


def test_direction_ranges_are_disjoint_and_cover_every_signal_byte() -> None:
    """Ranges may span bytes that hold no signal (fewer, longer copies), never a byte of the other way."""
    cat = expanded()
    covered: dict[Direction, set[tuple[str, int]]] = {}
    for direction in (Direction.PLC_TO_NC, Direction.NC_TO_PLC):
        bytes_of_direction: set[tuple[str, int]] = set()
        for key, start, stop in cat.byte_ranges(direction):
            assert 0 <= start < stop <= cat.area_sizes[key]
            span = {(key, byte) for byte in range(start, stop)}
            assert not span & bytes_of_direction, (key, start, stop)
            bytes_of_direction |= span
        covered[direction] = bytes_of_direction
    assert not covered[Direction.PLC_TO_NC] & covered[Direction.NC_TO_PLC]
    for item in cat.signals:
        for byte in item.definition.byte_span:
            assert (item.address.area_key, byte) in covered[item.direction], (item.symbol, byte)
    for direction, bytes_of_direction in covered.items():
        for key, byte in bytes_of_direction:
            assert cat.byte_direction(key, byte) in (direction, None), (direction, key, byte)
