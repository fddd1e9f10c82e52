"""``vc map --format s7`` and ``--format awlsim``: symbol tables of STEP 7 classic and awlsim (pure).

Both name the tags in the process image view of :mod:`interfaces.exports.tags` (table byte t is
``IB(base + t)`` / ``QB(base + t)``) with the short names of at most 24 characters the two tools
allow, and the map's symbol and S7 address as the comment (at most 80 characters).

* ``s7``: STEP 7's ASCII symbol table (``*.asc``, the format of the symbol editor's export and
  import): one line per symbol, ``126,`` then the symbol in 24 columns, the address in 12, the
  data type in 10 and the comment in 80, 130 characters, CR LF.  English mnemonics (I, Q).
* ``awlsim``: awlsim's symbol table (``*.csv``): ``symbol;address;type;comment`` per line, CR LF,
  fields with a ``;`` or ``"`` quoted; awlsim's project and ``awlsim-symtab`` read it (and ``*.asc``).
"""

from __future__ import annotations

import csv
import io
from collections.abc import Sequence

from interfaces.exports.context import ExportContext
from interfaces.exports.tags import S7_SYMBOL_LENGTH, PlcTag, ascii_text, plc_tags, short_names
from interfaces.signal_map import MapRow

ASC_ADDRESS_COLUMNS = 12
ASC_TYPE_COLUMNS = 10
COMMENT_LENGTH = 80


def symbols(rows: Sequence[MapRow]) -> list[tuple[str, PlcTag]]:
    """(short name, tag) of every tag, in the map's order."""
    tags = plc_tags(rows)
    names = short_names([tag.symbol for tag in tags])
    return [(names[tag.symbol], tag) for tag in tags]


def comment(tag: PlcTag) -> str:
    where = "" if tag.address == "-" else f" {tag.address}"
    return ascii_text(f"{tag.symbol}{where}", COMMENT_LENGTH)


def step7_asc(rows: Sequence[MapRow], context: ExportContext) -> str:
    lines = []
    for name, tag in symbols(rows):
        address = tag.image_address(context.io_base)
        lines.append("126," + name.ljust(S7_SYMBOL_LENGTH) + address.ljust(ASC_ADDRESS_COLUMNS)
                     + tag.data_type.value.ljust(ASC_TYPE_COLUMNS) + comment(tag).ljust(COMMENT_LENGTH))
    return "".join(line + "\r\n" for line in lines)


def awlsim_csv(rows: Sequence[MapRow], context: ExportContext) -> str:
    buffer = io.StringIO()
    writer = csv.writer(buffer, delimiter=";", quotechar='"', lineterminator="\r\n", quoting=csv.QUOTE_MINIMAL)
    for name, tag in symbols(rows):
        writer.writerow((name, tag.image_address(context.io_base), tag.data_type.value, comment(tag)))
    return buffer.getvalue()
