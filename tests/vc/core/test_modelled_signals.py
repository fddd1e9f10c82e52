"""Every catalogued signal is modelled by the NC or says why not (``not_modelled`` in the catalogue).

"Modelled" is what the NC core looks up in the catalogue for any of the packaged machines
(``Nck.signals_used``): the signals it reads (PLC -> NC) and writes (NC -> PLC).  The operator
panel's DB19 requests (``HMI.basic.in.*``) come from the operator, whom the scenarios play.  A
signal marked not modelled must also never change in any golden trace of the scenario library.
"""

from __future__ import annotations

import json
from functools import lru_cache
from pathlib import Path

from interfaces.catalog import load_catalog
from interfaces.signals import PLACEHOLDER, Direction, InstanceKind, SignalDef, expand
from vc.config.loader import load_machine
from vc.config.machine_files import packaged_machines
from vc.core.nck.nck import Nck

GOLDEN = Path(__file__).resolve().parents[2] / "golden"


@lru_cache(maxsize=1)
def used_by_the_nc() -> frozenset[str]:
    catalog = load_catalog()
    return frozenset().union(*(Nck(load_machine(name), catalog).signals_used for name in packaged_machines()))


def _kind_of(signal: SignalDef) -> InstanceKind:
    return next(kind for kind, placeholder in PLACEHOLDER.items() if signal.symbol.startswith(placeholder + "."))


def modelled_by_the_harness(signal: SignalDef) -> bool:
    operator_request = _kind_of(signal) is InstanceKind.HMI and signal.direction is Direction.NC_TO_PLC
    return operator_request or signal.symbol in used_by_the_nc()


def test_the_marks_say_what_the_nc_reads_and_writes() -> None:
    problems = []
    for signal in load_catalog().signals:
        modelled = modelled_by_the_harness(signal)
        if signal.modelled and not modelled:
            verb = "writes" if signal.direction is Direction.NC_TO_PLC else "reads"
            problems.append(f"{signal.address} {signal.symbol}: the NC never {verb} it; mark it not_modelled: <why>")
        elif modelled and not signal.modelled:
            problems.append(f"{signal.address} {signal.symbol}: the NC uses it; drop its not_modelled")
    assert not problems, "\n".join(problems)


def test_a_signal_the_nc_does_not_write_never_changes_in_a_golden_trace() -> None:
    catalog = load_catalog()
    dead = {item.symbol for name in packaged_machines() for item in expand(catalog, load_machine(name).layout).signals
            if item.direction is Direction.NC_TO_PLC and not item.definition.modelled}
    assert "X1.drive.in.rapidStopActive" in dead and "CHAN1.basic.in.handwheelOvrActive" not in dead
    traces = sorted(GOLDEN.rglob("*.json"))
    assert len(traces) > 200
    changing = {(path.relative_to(GOLDEN).as_posix(), name)
                for path in traces for name in json.loads(path.read_text(encoding="utf-8"))["digital"] if name in dead}
    assert not changing, sorted(changing)[:10]


def test_the_not_modelled_marks_give_a_reason_and_the_map_shows_them() -> None:
    from interfaces.signal_map import map_rows

    machine = load_machine("turn_mill")
    rows = {row.symbol: row for row in map_rows(expand(load_catalog(), machine.layout), machine.plant_io)}
    assert rows["X1.drive.in.enabled"].modelled == "yes"
    assert rows["X1.drive.in.holdingBrakeReleased"].modelled == "yes"  # 0 on an axis without a brake
    assert rows["X1.drive.in.rapidStopActive"].modelled.startswith(
        "no: the drive's ramp-function generator and its rapid stop OFF3 are not modelled")
    assert rows["X1.drive.in.autonomousMotionActive"].modelled == "yes"  # the drive's ESR reaction
    assert rows["CHAN1.basic.out.reposModeSelection"].modelled == "no: REPOS is not modelled"
    assert all(len(signal.not_modelled) > 20 for signal in load_catalog().signals if not signal.modelled)
