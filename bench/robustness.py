"""The robustness campaign: ``python bench/robustness.py [--soak [--soak-minutes 60]]``.

Each part starts the harness as a user would (``vc serve``, ``python -m plc_stub``), abuses it and
gives one row of a table: inputs tried, crashes, hangs, tracebacks, false passes, lost requests,
rule violations, RSS growth, overruns (the parts are in vc/bench/robustness/; bench/README.md
says what each does).  Not a test: it takes minutes (the soak ten by default, an hour with
``--soak-minutes 60``); the test suite runs a short version of each part
(tests/vc/bench/test_robustness.py).

Prints each part's progress, the table, and as its last line the rows as one JSON object.  Exit
code 1 when a row is not clean (a crash, hang, traceback, false pass, lost request or violation).
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import sys
from collections.abc import Sequence

from vc.bench.robustness.campaign import CampaignSettings, Part, Row, Say, failed_row, table
from vc.bench.robustness.campaign_size import run_campaign_size
from vc.bench.robustness.can_noise import run_can_noise
from vc.bench.robustness.control_characters import run_control_characters
from vc.bench.robustness.files import run_file_mutations
from vc.bench.robustness.flood import run_flood
from vc.bench.robustness.hostile_expressions import run_hostile_expressions
from vc.bench.robustness.hostile_recordings import run_hostile_recordings
from vc.bench.robustness.isolation import run_isolation
from vc.bench.robustness.modbus_fuzz import run_modbus_fuzz
from vc.bench.robustness.non_reading import run_non_reading
from vc.bench.robustness.s7_probe import run_s7_probe
from vc.bench.robustness.soak import run_soak
from vc.bench.robustness.takeover import run_session_takeover


def _file_part(settings: CampaignSettings, say: Say) -> Row:
    """The row of the file part from its figures (``run_file_mutations(count, seed, say)``)."""
    figures = run_file_mutations(settings.file_mutations, settings.seed, say)
    return Row("Mutated scenario and machine files (vc run)", inputs=figures.get("inputs", 0),
               crashes=figures.get("crashes", 0), hangs=figures.get("hangs", 0),
               tracebacks=figures.get("tracebacks", 0), false_passes=figures.get("false_passes", 0),
               violations=figures.get("wrong_locations", 0),
               notes=f"{figures.get('problems', 0)} located problems, {figures.get('passed', 0)} passed,"
                     f" {figures.get('failed', 0)} failed; violations: problems at a wrong location")


PARTS: list[Part] = [
    Part("modbus", run_modbus_fuzz),
    Part("flood", run_flood),
    Part("s7", run_s7_probe),
    Part("can", run_can_noise),
    Part("files", _file_part),  # the scenario and machine files (vc/bench/robustness/files.py)
    Part("control", run_control_characters),  # control characters in names through vc run's outputs
    Part("recordings", run_hostile_recordings),  # vc replay on hostile recordings
    Part("expressions", run_hostile_expressions),  # conditions and ${...} built to exhaust the reader
    Part("campaign_size", run_campaign_size),  # matrices and campaigns beyond the ceiling, and a large allowed one
    Part("soak", run_soak),  # only with --soak
    Part("takeover", run_session_takeover),  # a lost PLC's session (vc/bench/robustness/takeover.py)
    Part("non-reading", run_non_reading),  # clients that never take their answers (non_reading.py)
    Part("isolation", run_isolation),  # busy processes beside the real-time NC: --cpu, --fifo (isolation.py)
]


def _arguments(argv: Sequence[str] | None) -> argparse.Namespace:
    defaults = CampaignSettings()
    parser = argparse.ArgumentParser(prog="python bench/robustness.py",
                                     description="The links and the real-time NC under abuse (bench/README.md)")
    parser.add_argument("--parts", default=",".join(part.name for part in PARTS if part.name != "soak"),
                        help="the parts to run, comma-separated (default: all but the soak)")
    parser.add_argument("--soak", action="store_true", help="run the soak as well")
    parser.add_argument("--soak-minutes", type=float, metavar="MIN",
                        help=f"the soak's length (default {defaults.soak_minutes:g}); implies --soak")
    parser.add_argument("--modbus-frames", type=int, default=defaults.modbus_frames, metavar="N")
    parser.add_argument("--s7-requests", type=int, default=defaults.s7_requests, metavar="N")
    parser.add_argument("--can-inputs", type=int, default=defaults.can_inputs, metavar="N")
    parser.add_argument("--flood-seconds", type=float, default=defaults.flood_seconds, metavar="S")
    parser.add_argument("--flood-connections", type=int, default=defaults.flood_connections, metavar="N")
    parser.add_argument("--file-mutations", type=int, default=defaults.file_mutations, metavar="N")
    parser.add_argument("--seed", type=int, default=defaults.seed)
    return parser.parse_args(argv)


def main(argv: Sequence[str] | None = None) -> int:
    arguments = _arguments(argv)
    settings = CampaignSettings(
        modbus_frames=arguments.modbus_frames, s7_requests=arguments.s7_requests, can_inputs=arguments.can_inputs,
        flood_seconds=arguments.flood_seconds, flood_connections=arguments.flood_connections,
        soak_minutes=arguments.soak_minutes or CampaignSettings().soak_minutes,
        file_mutations=arguments.file_mutations, seed=arguments.seed)
    wanted = {name.strip() for name in arguments.parts.split(",") if name.strip()}
    if arguments.soak or arguments.soak_minutes:
        wanted.add("soak")
    unknown = wanted - {part.name for part in PARTS}
    if unknown:
        print(f"no part {', '.join(sorted(unknown))} (parts: {', '.join(part.name for part in PARTS)})",
              file=sys.stderr)
        return 2
    rows = []
    for part in PARTS:
        if part.name not in wanted:
            continue
        print(f"{part.name}:", flush=True)
        try:
            rows.append(part.run(settings, lambda text: print(text, flush=True)))
        except Exception as error:  # the campaign goes on with the next part and reports this one
            rows.append(failed_row(part.name, error))
    print(table(rows))
    print(json.dumps([dataclasses.asdict(row) for row in rows]))
    return 0 if all(row.clean for row in rows) else 1


if __name__ == "__main__":
    sys.exit(main())
