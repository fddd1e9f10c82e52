"""``vc map --format tia``: a PLC tag table for TIA Portal as an Excel workbook (pure, no I/O).

TIA Portal exports a tag table to ``*.xlsx`` and imports one from it (*PLC tags*, *Import*): a sheet
``PLC Tags`` with the columns ``Name, Path, Data Type, Logical Address, Comment, Hmi Visible, Hmi
Accessible, Hmi Writeable, Typeobject ID, Version ID``, one tag a row.  The tags are those of the
process image view (:mod:`interfaces.exports.tags`): ``%I386.4``, ``%IB33``, ``%IW0``, ``%ID8`` and the
``%Q`` counterparts, from the ``io_base`` given; names are the map's symbols as identifiers (TIA
allows 128 characters), the comment the symbol, the S7 address and the meaning.  The tags land in
the tag table named in ``Path`` (``VC <machine>``).  The HMI may write the PLC's outputs only.

openpyxl writes the workbook (the ``tia`` extra); the document properties and the archive's entries
carry a fixed date, so the same map gives the same file.
"""

from __future__ import annotations

import datetime
import io
import zipfile
from collections.abc import Sequence

from interfaces.errors import VcError
from interfaces.exports.context import ExportContext
from interfaces.exports.tags import DataType, PlcTag, plc_tags
from interfaces.signal_map import MapRow

SHEET = "PLC Tags"
COLUMNS = ("Name", "Path", "Data Type", "Logical Address", "Comment", "Hmi Visible", "Hmi Accessible",
           "Hmi Writeable", "Typeobject ID", "Version ID")
TIA_TYPES = {DataType.BOOL: "Bool", DataType.BYTE: "Byte", DataType.WORD: "Word", DataType.DWORD: "DWord",
             DataType.REAL: "Real"}
FIXED_DATE = datetime.datetime(2000, 1, 1)  # a constant, not the clock


class MissingExtra(VcError, RuntimeError):
    """openpyxl is not installed."""


def logical_address(tag: PlcTag, base: int) -> str:
    return "%" + tag.image_address(base).replace(" ", "")


def tag_rows(rows: Sequence[MapRow], context: ExportContext) -> list[tuple[str, ...]]:
    """The sheet's rows after the header."""
    table = f"VC {context.machine}"
    result: list[tuple[str, ...]] = []
    for tag in plc_tags(rows):
        where = "" if tag.address == "-" else f" {tag.address}"
        result.append((tag.identifier, table, TIA_TYPES[tag.data_type], logical_address(tag, context.io_base),
                       f"{tag.symbol}{where}: {tag.meaning}", "True", "True", "False" if tag.is_input else "True",
                       "", ""))
    return result


def tia_workbook(rows: Sequence[MapRow], context: ExportContext) -> bytes:
    try:
        from openpyxl import Workbook
        from openpyxl.writer.excel import ExcelWriter
    except ImportError:
        raise MissingExtra("the tia format needs openpyxl: pip install 'vc-harness[tia]'") from None
    workbook = Workbook()
    sheet = workbook.active
    sheet.title = SHEET
    sheet.append(COLUMNS)
    for row in tag_rows(rows, context):
        sheet.append(row)
    workbook.properties.created = workbook.properties.modified = FIXED_DATE
    workbook.properties.creator = "vc map"
    buffer = io.BytesIO()
    # ExcelWriter, not Workbook.save: save stamps the document's "modified" with the clock
    ExcelWriter(workbook, zipfile.ZipFile(buffer, "w", zipfile.ZIP_DEFLATED)).save()
    return _without_clock(buffer.getvalue())


def _without_clock(workbook: bytes) -> bytes:
    """The same archive with every member stamped with a fixed date: openpyxl stamps the zip entries
    with the time of the save, so two saves in different seconds differed."""
    packed = io.BytesIO()
    with zipfile.ZipFile(io.BytesIO(workbook)) as source, zipfile.ZipFile(packed, "w") as target:
        for member in source.infolist():
            stamped = zipfile.ZipInfo(member.filename, date_time=FIXED_DATE.timetuple()[:6])
            stamped.compress_type = member.compress_type
            stamped.external_attr = member.external_attr
            target.writestr(stamped, source.read(member.filename))
    return packed.getvalue()
