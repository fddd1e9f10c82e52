"""The campaign's parts and its table: what a part returns, how the rows are printed.

A part is a function ``run(settings, say) -> Row``; ``bench/robustness.py`` lists them (its
``PARTS``) and prints the table.  Counts that a part cannot have are None and print as ``-``
(a link part has no verdicts that could pass falsely, a file part no requests that could be lost).
"""

from __future__ import annotations

from collections.abc import Callable, Iterable
from dataclasses import dataclass, fields

Say = Callable[[str], None]


@dataclass(frozen=True, slots=True)
class CampaignSettings:
    """How much of each part: the full campaign by default; the test suite runs a few hundred."""

    modbus_frames: int = 100_000
    s7_requests: int = 2_000
    can_inputs: int = 20_000
    flood_seconds: float = 30.0
    flood_connections: int = 50
    soak_minutes: float = 10.0
    file_mutations: int = 2_000
    seed: int = 19


@dataclass(slots=True)
class Row:
    """One part's result; the columns of the table."""

    part: str
    inputs: int = 0  # frames, requests, datagrams, files, cycles tried
    crashes: int = 0  # a process of the harness ended by itself
    hangs: int = 0  # no answer within the part's time-out where one was due
    tracebacks: int = 0  # Python tracebacks in the harness's output
    false_passes: int | None = None  # verdicts that passed where they must fail
    lost_requests: int | None = None  # requests never answered
    violations: int = 0  # answers against the documented rules (a foreign write taken, a wrong code)
    rss_growth_pct: float | None = None  # resident memory of the harness's processes, end against start
    overruns: str = "-"  # real-time cycles more than a period late, of all (those caused by the links)
    notes: str = ""

    @property
    def clean(self) -> bool:
        """Nothing went wrong: no crash, hang, traceback, false pass, lost request or violation."""
        return not (self.crashes or self.hangs or self.tracebacks or self.false_passes or self.lost_requests
                    or self.violations)


@dataclass(frozen=True, slots=True)
class Part:
    name: str
    run: Callable[[CampaignSettings, Say], Row]


COLUMNS = ("part", "inputs tried", "crashes", "hangs", "tracebacks", "false passes", "lost requests",
           "rule violations", "RSS growth", "overruns", "notes")


def _cell(value: object) -> str:
    if value is None:
        return "-"
    if isinstance(value, float):
        return f"{value:+.2f} %"
    return str(value)


def table(rows: Iterable[Row]) -> str:
    """The rows as a Markdown table, one line a part."""
    lines = ["| " + " | ".join(COLUMNS) + " |", "|" + "---|" * len(COLUMNS)]
    for row in rows:
        values = [getattr(row, column.name) for column in fields(Row)]
        lines.append("| " + " | ".join(_cell(value) for value in values) + " |")
    return "\n".join(lines)


def failed_row(part: str, error: Exception) -> Row:
    """A part that could not run at all counts as a crash of the campaign, with its reason."""
    return Row(part, crashes=1, notes=f"did not run: {error}")
