"""Exports of the signal map for PLC tools (``vc map --format codesys|openplc|tia|s7|awlsim``).

One module per tool, all pure (text or bytes from the map's rows, no I/O), all built on
:mod:`interfaces.exports.tags`; docs/plc_tools.md describes each format and what the tools accept.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass

from interfaces.exports.codesys import codesys_gvl
from interfaces.exports.context import ExportContext
from interfaces.exports.openplc import openplc_variables
from interfaces.exports.symbol_tables import awlsim_csv, step7_asc
from interfaces.exports.tia import tia_workbook
from interfaces.signal_map import MapRow


@dataclass(frozen=True, slots=True)
class Export:
    name: str
    write: Callable[[Sequence[MapRow], ExportContext], str | bytes]
    suffix: str  # the file name extension the tool expects
    binary: bool = False  # bytes, written to a file (-o), not to a terminal
    uses_io_base: bool = False  # the process image view: --io-base applies


EXPORTS = {
    export.name: export for export in (
        Export("codesys", codesys_gvl, ".st"),
        Export("openplc", openplc_variables, ".st"),
        Export("tia", tia_workbook, ".xlsx", binary=True, uses_io_base=True),
        Export("s7", step7_asc, ".asc", uses_io_base=True),
        Export("awlsim", awlsim_csv, ".csv", uses_io_base=True),
    )
}

__all__ = ["EXPORTS", "Export", "ExportContext"]
