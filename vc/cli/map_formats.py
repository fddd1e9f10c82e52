"""The formats of ``vc map`` for people and spreadsheets: Markdown, CSV and JSON of the signal map.

The rows come from :func:`interfaces.signal_map.map_rows`; the exports for PLC tools (TIA,
CODESYS, OpenPLC, symbol tables) are in :mod:`interfaces.exports`, the DBC file in
:mod:`interfaces.links.can.dbc`.
"""

from __future__ import annotations

import csv
import io
import json
from collections.abc import Sequence
from dataclasses import asdict

from interfaces.signal_map import COLUMNS, COMMISSIONING_INSTANCE, MapRow


def to_csv(rows: Sequence[MapRow]) -> str:
    buffer = io.StringIO()
    writer = csv.writer(buffer, lineterminator="\n")
    writer.writerow(COLUMNS)
    for row in rows:
        writer.writerow(getattr(row, column) for column in COLUMNS)
    return buffer.getvalue()


def to_json(rows: Sequence[MapRow]) -> str:
    return json.dumps([asdict(row) for row in rows], indent=1, ensure_ascii=False) + "\n"


def to_markdown(rows: Sequence[MapRow]) -> str:
    shown = ("symbol", "address", "direction", "type", "modbus_table", "modbus_address", "bit", "register",
             "register_bit", "can_id", "can_start_bit", "trigger", "meaning", "modelled")
    facts = [row for row in rows if row.instance == COMMISSIONING_INSTANCE]
    lines: list[str] = []
    if facts:
        lines += ["", "## Commissioning", "", "How each axis is referenced, where its cam and limit switches are"
                  " wired on the slide (physical machine coordinates), the order of channel-specific referencing,"
                  " and what the plant needs from the PLC:", "", "| name | addresses | fact |", "|---|---|---|"]
        lines += [f"| {_cell(row.symbol)} | {_cell(row.address)} | {_cell(row.meaning)} |" for row in facts]
    instance = None
    for row in rows:
        if row.instance == COMMISSIONING_INSTANCE:
            continue
        if row.instance != instance:
            instance = row.instance
            title = {"PLANT": "Plant I/O", "LINK": "Modbus link block"}.get(
                instance, f"{instance} ({row.address.split('.')[0]})")
            lines += ["", f"## {title}", "", "| " + " | ".join(shown) + " |", "|" + "---|" * len(shown)]
        cells = [_cell(getattr(row, column)) for column in shown]
        lines.append("| " + " | ".join(cells) + " |")
    convention = ("\n\nModbus: bit signals are coils (PLC writes) or discrete inputs (PLC reads) with number"
                  " = table byte x 8 + bit, and the same bit in its holding or input register (S7 byte order:"
                  " an even table byte is the high byte). The convention: interfaces/links/modbus/codec.py;"
                  " connecting a PLC: docs/modbus.md. CAN: the data frame's identifier and the signal's start"
                  " bit as in the DBC file (vc map --format dbc; docs/can.md).\n")
    return "# Signal map" + convention + "\n".join(lines) + "\n"


def _cell(value: object) -> str:
    return str(value).replace("|", "\\|").replace("\n", " ")


FORMATTERS = {"csv": to_csv, "json": to_json, "md": to_markdown}
