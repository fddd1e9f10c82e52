"""The expanded signal map of a machine as CSV, JSON or Markdown (``vc map``).

One row per signal of every DB instance, followed by the machine's plant I/O.  The CSV
columns start with ``symbol,address,direction,type``; links add their own columns later
(Modbus table and address, CAN identifier) without changing these.
"""

from __future__ import annotations

import csv
import io
import json
from collections.abc import Sequence
from dataclasses import asdict, dataclass

from interfaces.plant_io import PlantIoMap
from interfaces.signals import ExpandedCatalog

COLUMNS = ("symbol", "address", "direction", "type", "bits", "trigger", "bp_symbol", "instance", "meaning",
           "source", "origin", "note")


@dataclass(frozen=True, slots=True)
class MapRow:
    symbol: str
    address: str
    direction: str
    type: str
    bits: int
    trigger: str
    bp_symbol: str
    instance: str
    meaning: str
    source: str
    origin: str
    note: str


def map_rows(catalog: ExpandedCatalog, plant_io: PlantIoMap) -> list[MapRow]:
    rows = []
    for item in catalog.signals:
        d = item.definition
        rows.append(MapRow(item.symbol, str(item.address), d.direction.value, d.type.value, d.bits,
                           d.trigger.value, d.bp_symbol, item.instance, d.meaning, d.source, d.origin.value,
                           d.note))
    for point in plant_io.points:
        bits = 1 if point.address.is_bit else 8 * point.address.size
        rows.append(MapRow(point.name, str(point.address), point.direction.value, point.type.value, bits,
                           "level", "-", "PLANT", point.meaning, "machine file plant_io", "project",
                           f"driven by the {point.owner.value}"))
    return rows


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
    shown = ("symbol", "address", "direction", "type", "trigger", "bp_symbol", "meaning")
    lines: list[str] = []
    instance = None
    for row in rows:
        if row.instance != instance:
            instance = row.instance
            title = "Plant I/O" if instance == "PLANT" else f"{instance} ({row.address.split('.')[0]})"
            lines += ["", f"## {title}", "", "| " + " | ".join(shown) + " |", "|" + "---|" * len(shown)]
        cells = [str(getattr(row, column)).replace("|", "\\|").replace("\n", " ") for column in shown]
        lines.append("| " + " | ".join(cells) + " |")
    return "# Signal map" + "\n".join(lines) + "\n"


FORMATTERS = {"csv": to_csv, "json": to_json, "md": to_markdown}
