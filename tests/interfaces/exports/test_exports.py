"""The exports for PLC tools (``vc map --format codesys|openplc|tia|s7|awlsim``), each parsed back and
checked against the map's own Modbus columns, and the symbol tables loaded into awlsim."""

from __future__ import annotations

import csv
import io
import re
from pathlib import Path

import pytest

from interfaces.catalog import load_catalog
from interfaces.exports import EXPORTS, ExportContext
from interfaces.exports.client_setups import codesys_channels, codesys_word
from interfaces.exports.codesys import codesys_gvl
from interfaces.exports.openplc import openplc_variables
from interfaces.exports.symbol_tables import awlsim_csv, step7_asc
from interfaces.exports.tags import S7_SYMBOL_LENGTH, PlcTag, plc_tags, short_name, short_names
from interfaces.exports.tia import COLUMNS, SHEET, tia_workbook
from interfaces.links.modbus.codec import RegisterMap, Table
from interfaces.signal_map import MapRow, map_rows
from interfaces.signals import expand
from vc.cli.main import main
from vc.config.loader import load_machine

ROOT = Path(__file__).resolve().parents[3]
MACHINES = ("turn_mill", "mill_3axis", "mill_5axis", "gantry_mill")


def _rows_and_context(machine_name: str, io_base: int = 0) -> tuple[list[MapRow], ExportContext]:
    machine = load_machine(str(ROOT / "scenarios" / "machines" / f"{machine_name}.yaml"))
    catalog = expand(load_catalog(), machine.layout)
    register_map = RegisterMap.build(catalog, machine.plant_io.area_sizes())
    return map_rows(catalog, machine.plant_io, machine.can.settings), ExportContext(machine.name, register_map,
                                                                                     io_base)


@pytest.fixture(scope="module")
def turn_mill() -> tuple[list[MapRow], ExportContext]:
    return _rows_and_context("turn_mill")


def _by_symbol(rows: list[MapRow]) -> dict[str, MapRow]:
    return {row.symbol: row for row in rows}


def _register_and_bit(row: MapRow) -> tuple[int, int]:
    """Where the map says a bool row lies: its register and the bit in it."""
    assert isinstance(row.register, int) and isinstance(row.register_bit, int)
    return row.register, row.register_bit


# ---------------------------------------------------------------------------------------- tags


def test_every_row_with_a_table_place_becomes_tags_and_bits_fields_a_bool_per_bit(turn_mill) -> None:
    rows, _ = turn_mill
    tags = plc_tags(rows)
    symbols = {tag.symbol for tag in tags}
    for row in rows:
        if row.type == "text":
            assert row.symbol not in symbols
        elif row.type == "bits":
            assert {f"{row.symbol}.bit{k}" for k in range(row.bits)} <= symbols
        else:
            assert row.symbol in symbols
    gear = [tag for tag in tags if tag.symbol.startswith("SP1.spindle.out.gearStageSelection.")]
    assert [(tag.table_byte, tag.bit) for tag in gear] == [(gear[0].table_byte, k) for k in range(3)]


@pytest.mark.parametrize("machine", MACHINES)
def test_short_names_fit_24_characters_and_are_unique_regardless_of_case(machine: str) -> None:
    rows, _ = _rows_and_context(machine)
    symbols = [tag.symbol for tag in plc_tags(rows)]
    names = short_names(symbols)
    assert all(len(name) <= S7_SYMBOL_LENGTH for name in names.values())
    assert len({name.lower() for name in names.values()}) == len(symbols)
    assert short_names(symbols) == names  # deterministic


def test_short_names_drop_the_default_group_and_the_direction_and_keep_a_field_bit() -> None:
    assert short_name("X1.basic.in.enc1Synchronized") == "X1_enc1Synchronized"
    assert short_name("NC.basic.out.emergencyStopAck") == "NC_emergencyStopAck"
    assert short_name("MCP.plus.X1") == "MCP_plus_X1"
    long = short_name("SP1.coupling.in.egSpeedThresholdReached")
    assert len(long) <= S7_SYMBOL_LENGTH and long.startswith("SP1_")
    assert short_name("SP1.spindle.in.requestedGearStageNumber.bit2").endswith("_2")
    clashing = short_names(["A.xxxxxxxxxxxxxxxxxxxxxxxxxxxx1", "A.xxxxxxxxxxxxxxxxxxxxxxxxxxxx2"])
    assert len(set(clashing.values())) == 2 and all(len(name) == S7_SYMBOL_LENGTH for name in clashing.values())


def test_the_process_image_view_puts_table_byte_t_at_byte_base_plus_t(turn_mill) -> None:
    rows, _ = turn_mill
    tags = {tag.symbol: tag for tag in plc_tags(rows)}
    # DB31.DBX60.4 is discrete input 3092 (docs/modbus.md): table byte 386, bit 4
    assert tags["X1.basic.in.enc1Synchronized"].image_address() == "I 386.4"
    assert tags["X1.basic.in.enc1Synchronized"].image_address(1000) == "I 1386.4"
    assert tags["LINK.session"].image_address() == "IW 2"
    assert tags["LINK.ncCycle"].image_address() == "ID 8"
    assert tags["LINK.scanDone"].image_address() == "QW 0"
    assert tags["MCP.feedOverride"].image_address() == "IB 35"  # IB3: low byte of IR 17


# ---------------------------------------------------------------------------------------- CODESYS

_GVL_LINE = re.compile(r"^\t(\w+) AT %([IQ])([XBW])(\d+)(?:\.(\d))? : (\w+); \(\* (\S+) ")


def test_the_codesys_gvl_locates_every_tag_at_its_channel_word(turn_mill) -> None:
    rows, context = turn_mill
    by_symbol = _by_symbol(rows)
    text = codesys_gvl(rows, context)
    assert "*)\nVAR_GLOBAL\n" in text and text.rstrip().endswith("END_VAR")
    declared = [_GVL_LINE.match(line) for line in text.splitlines() if line.startswith("\t")]
    assert declared and all(declared)
    names = [match.group(1) for match in declared if match]
    assert len(names) == len(set(names))
    channels = codesys_channels(context.register_map)
    inputs = sum(c.length for c in channels if c.table is Table.NC_TO_PLC)
    for match in declared:
        assert match is not None
        name, area, size, number, bit, type_name, symbol = match.groups()
        table = Table.NC_TO_PLC if area == "I" else Table.PLC_TO_NC
        row = by_symbol[symbol.rsplit(".bit", 1)[0] if ".bit" in symbol else symbol]
        if size == "X":  # little-endian: byte 2w + 1 holds register bits 8..15
            word, register_bit = divmod(8 * int(number) + int(bit), 16)
            register, expected_bit = (row.register, row.register_bit) if row.type == "bool" else \
                divmod(int(row.modbus_address) + int(symbol.rsplit("bit", 1)[1]), 16)
            if row.type == "bits":  # coil 16r + k is register bit (k + 8) mod 16
                expected_bit = (expected_bit + 8) % 16
            assert (word, register_bit) == (codesys_word(context.register_map, table, register), expected_bit), symbol
            assert type_name == "BOOL"
        elif size == "B":
            word, high = divmod(int(number), 2)
            assert word == codesys_word(context.register_map, table, int(row.modbus_address))
            assert (8 if high else 0) == row.bit, symbol
        else:
            register = int(row.modbus_address) + name.endswith("_LO")
            assert int(number) == codesys_word(context.register_map, table, register), symbol
    assert codesys_word(context.register_map, Table.NC_TO_PLC, 193) == 193  # link block first: word = register
    # Link out comes last: after the data registers 16.. of the PLC-to-NC table
    outputs = context.register_map.registers(Table.PLC_TO_NC)
    assert codesys_word(context.register_map, Table.PLC_TO_NC, 0) == outputs - 16
    assert inputs == context.register_map.registers(Table.NC_TO_PLC)
    assert "X1_basic_in_enc1Synchronized AT %IX387.4 : BOOL;" in text  # IR 193 bit 12


# ---------------------------------------------------------------------------------------- OpenPLC


def test_the_openplc_list_names_register_r_at_word_100_plus_r_with_each_signals_mask(turn_mill) -> None:
    rows, context = turn_mill
    text = openplc_variables(rows, context)
    words = re.findall(r"^\t(IR|HR)(\d+) AT %([IQ])W(\d+) : WORD;$", text, re.MULTILINE)
    assert words and all(int(located) == 100 + int(register) and (kind == "IR") == (area == "I")
                         for kind, register, area, located in words)
    for row in rows:
        if row.type != "bool":
            continue
        register, bit = _register_and_bit(row)
        word = f"{'IR' if row.modbus_table == 'discrete_input' else 'HR'}{register}"
        assert f"(* {row.symbol} {row.address} BOOL: ({word} AND 16#{1 << bit:04X}) <> 0 *)" in text, row.symbol
    assert "IR193 AT %IW293 : WORD;" in text


# ---------------------------------------------------------------------------------------- STEP 7, awlsim


def _expected_byte_and_bit(row: MapRow, symbol: str) -> tuple[int, int | None]:
    """The table byte (and bit) of a row from its Modbus columns alone."""
    number = int(row.modbus_address)
    if row.type in ("bool", "bits"):
        number += int(symbol.rsplit("bit", 1)[1]) if row.type == "bits" else 0
        return number // 8, number % 8
    return 2 * number + (1 if row.type == "byte" and row.bit == 0 else 0), None


def _parse_with_awlsim(text: str):  # type: ignore[no-untyped-def]
    pytest.importorskip("awlsim")
    import awlsim_loader.core  # noqa: F401 - awlsim's modules must be loaded through its loader
    from awlsim.common.cpuconfig import S7CPUConfig
    from awlsim.core.symbolparser import SymTabParser

    return SymTabParser.parseText(text, autodetectFormat=True, mnemonics=S7CPUConfig.MNEMONICS_EN)


@pytest.mark.parametrize("export", [step7_asc, awlsim_csv], ids=["s7", "awlsim"])
def test_awlsim_reads_the_symbol_table_with_every_address_where_the_map_says(turn_mill, export) -> None:
    rows, _ = turn_mill
    rows_and_context = _rows_and_context("turn_mill", io_base=100)
    text = export(rows_and_context[0], rows_and_context[1])
    table = _parse_with_awlsim(text)
    tags: dict[str, PlcTag] = {tag.symbol: tag for tag in plc_tags(rows)}
    assert len(table) == len(tags)
    by_symbol = _by_symbol(rows)
    for symbol in table:
        long = symbol.getComment().split(" ")[0]
        row = by_symbol[long.rsplit(".bit", 1)[0] if ".bit" in long else long]
        byte, bit = _expected_byte_and_bit(row, long)
        offset = symbol.getOperator().offset
        assert (offset.byteOffset, offset.bitOffset if bit is not None else None) == (100 + byte, bit), long
        assert str(symbol.getType()).upper() == tags[long].data_type.value
    assert table.findByName("X1_enc1Synchronized").getComment() == "X1.basic.in.enc1Synchronized DB31.DBX60.4"


def test_the_step7_ascii_table_has_the_fixed_columns(turn_mill) -> None:
    rows, context = turn_mill
    lines = step7_asc(rows, context).split("\r\n")
    assert lines[-1] == "" and all(len(line) == 130 and line.startswith("126,") for line in lines[:-1])
    line = next(line for line in lines if line[4:28].rstrip() == "X1_enc1Synchronized")
    assert (line[28:40].rstrip(), line[40:50].rstrip()) == ("I 386.4", "BOOL")
    assert all(line.isascii() for line in lines)


def test_an_awlsim_program_builds_against_the_exported_symbols(turn_mill) -> None:
    pytest.importorskip("awlsim")
    # the bridge's view of awlsim loads its modules in the order they need (the CPU core first)
    from plc_awlsim.awlsim_api import AwlParser, AwlSim, AwlSource, S7CPUConfig

    rows, context = turn_mill
    sim = AwlSim()
    sim.cpu.getConf().setConfiguredMnemonics(S7CPUConfig.MNEMONICS_EN)
    sim.cpu.getSpecs().setNrInputs(context.register_map.table_bytes[Table.NC_TO_PLC])
    sim.cpu.getSpecs().setNrOutputs(context.register_map.table_bytes[Table.PLC_TO_NC])
    sim.loadSymbolTable(_parse_with_awlsim(awlsim_csv(rows, context)))
    program = ('ORGANIZATION_BLOCK OB 1\nBEGIN\n\tA\t"X1_enc1Synchronized"\n\t=\t"X1_enableCtrl"\n'
               '\tL\t"LINK_ncCycle"\n\tT\tMD 0\nEND_ORGANIZATION_BLOCK\n')
    parser = AwlParser()
    parser.parseSource(AwlSource(name="test", sourceBytes=program.encode()))
    sim.load(parser.getParseTree())
    sim.startup()  # builds: every symbol resolved
    sim.cpu.storeInputRange(386, bytearray([0x10]))  # I 386.4
    sim.runCycle()
    q_byte = 2 * 69  # X1.basic.out.enableCtrl = DB31.DBX2.1 = HR 69 bit 9: table byte 138, bit 1
    assert sim.cpu.fetchOutputRange(q_byte, 1)[0] & 0x02


# ---------------------------------------------------------------------------------------- TIA Portal


def test_the_tia_workbook_has_the_plc_tags_sheet_with_every_tag(turn_mill) -> None:
    openpyxl = pytest.importorskip("openpyxl")
    rows, context = turn_mill
    data = tia_workbook(rows, context)
    assert data == tia_workbook(rows, context)  # deterministic
    sheet = openpyxl.load_workbook(io.BytesIO(data))[SHEET]
    table = [tuple("" if cell is None else str(cell) for cell in row) for row in sheet.iter_rows(values_only=True)]
    assert table[0] == COLUMNS
    tags = plc_tags(rows)
    assert len(table) == len(tags) + 1
    by_name = {row[0]: row for row in table[1:]}
    assert by_name["X1_basic_in_enc1Synchronized"][1:5] == (
        "VC turn_mill", "Bool", "%I386.4", "X1.basic.in.enc1Synchronized DB31.DBX60.4: " +
        next(r.meaning for r in rows if r.symbol == "X1.basic.in.enc1Synchronized"))
    assert by_name["LINK_ncCycle"][2:4] == ("DWord", "%ID8")
    assert by_name["X1_basic_out_enableCtrl"][7] == "True" and by_name["X1_basic_in_enc1Synchronized"][7] == "False"
    assert all(len(name) <= 128 and re.fullmatch(r"[A-Za-z][A-Za-z0-9_]*", name) for name in by_name)


# ---------------------------------------------------------------------------------------- vc map


def test_vc_map_writes_each_export_and_refuses_what_does_not_apply(tmp_path: Path,
                                                                   capsys: pytest.CaptureFixture[str]) -> None:
    machine = str(ROOT / "scenarios" / "machines" / "turn_mill.yaml")
    for name, export in EXPORTS.items():
        if export.binary and name == "tia":
            pytest.importorskip("openpyxl")
        target = tmp_path / f"turn_mill{export.suffix}"
        assert main(["map", "--machine", machine, "--format", name, "-o", str(target)]) == 0
        assert target.stat().st_size > 10_000
    assert (tmp_path / "turn_mill.asc").read_bytes().count(b"\r\n") == len(
        (tmp_path / "turn_mill.asc").read_bytes().splitlines())
    capsys.readouterr()
    assert main(["map", "--machine", machine, "--format", "tia"]) == 2
    assert "-o FILE.xlsx" in capsys.readouterr().err
    assert main(["map", "--machine", machine, "--format", "codesys", "--io-base", "4"]) == 2
    assert "does not apply" in capsys.readouterr().err
    assert main(["map", "--machine", machine, "--format", "csv", "--io-base", "4"]) == 2
    assert main(["map", "--machine", machine, "--format", "awlsim", "--io-base", "4"]) == 0
    first = next(csv.reader(io.StringIO(capsys.readouterr().out), delimiter=";"))
    assert first[1] == "QB 41"  # NC.basic.out.setDigitalInputs DB10.DBB1: table byte 37 (behind QB0..2), + 4
