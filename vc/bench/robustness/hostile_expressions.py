"""The campaign part "hostile expressions": conditions and ``${...}`` placeholders built to exhaust
the reader, each in a scenario file that ``vc run`` checks in its own process (:mod:`.one_shot`).

:data:`HOSTILE` holds the expressions: 3,000 signs, 50,000 terms, 2,000 parentheses, ``not`` and
``abs`` 2,000 deep, a product of 250 numbers of 20 digits, a number of 5,000 digits divided by 3,
``1e400``, a name of 100,000 characters, an index of 20 digits, calls and lambdas.  Each goes
into a condition (``expect: "..."``, ``wait: {until: ...}``) and, where placeholders can hold
it, into a placeholder of a matrix (``set: {MCP.feedOverride: "${...}"}``).  Every file must be
refused before anything runs: exit 2 with the problem at ``FILE:LINE:COLUMN``.  A file that runs
is a false pass; a traceback, a crash or a run past the bound counts against the part.
"""

from __future__ import annotations

import tempfile
from collections.abc import Collection
from dataclasses import dataclass
from pathlib import Path

from vc.bench.robustness.campaign import CampaignSettings, Row, Say
from vc.bench.robustness.one_shot import Outcome, run_vc, tally
from vc.bench.robustness.processes import ROOT

PART = "Hostile expressions (conditions and ${...}, vc run)"
DEFAULT_BOUND_S = 60.0
MACHINE = ROOT / "scenarios" / "machines" / "turn_mill.yaml"
TWENTY_DIGITS = "12345678901234567890"


@dataclass(frozen=True, slots=True)
class Hostile:
    name: str
    text: str  # "{v}" stands for a name: the varied x in a placeholder, X1.position in a condition
    placeholder: bool = True  # also as a placeholder (varied: x, and the list cam)
    condition: bool = True  # also in conditions: as "(TEXT) > 0", or as it is when ``whole``
    whole: bool = False  # a whole condition (not, abs, and, alarm)


HOSTILE: tuple[Hostile, ...] = (
    Hostile("3,000 unary minus", "-" * 3000 + "{v}"),
    Hostile("3,000 unary plus", "+" * 3000 + "{v}"),
    Hostile("50,000 terms", "+".join(["{v}"] * 50_000)),
    Hostile("5,000 terms", "+".join(["{v}"] * 5_000)),
    Hostile("2,000 parentheses", "(" * 2000 + "{v}" + ")" * 2000),
    Hostile("a product of 250 numbers of 20 digits", "*".join([TWENTY_DIGITS] * 250)),
    Hostile("a product of 12 numbers of 12 digits", "*".join(["123456789012"] * 12)),
    Hostile("5,000 digits divided by 3", "9" * 5000 + "/3"),
    Hostile("400 digits divided by 3", "1" + "0" * 400 + "/3"),
    Hostile("1e400", "1e400"),
    Hostile("1e308 * 1e308", "1e308*1e308"),
    Hostile("a division by 1e-30 twice", "{v}/0.000000000000000000000000000001/0.000000000000000000000000000001",
            condition=False),
    Hostile("a name of 100,000 characters", "{v}" + "a" * 100_000),
    Hostile("a dotted name of 20,000 parts", ".".join(["{v}"] * 20_000)),
    Hostile("an index of 20 digits", f"cam[{TWENTY_DIGITS}]", condition=False),
    Hostile("2,000 nested indexes", "cam[" * 2000 + "0" + "]" * 2000, condition=False),
    Hostile("a call", "__import__('os').system('true')"),
    Hostile("a lambda", "(lambda: 1)()"),
    Hostile("a NUL", "{v}\x00+1"),
    Hostile("4,097 characters", "{v}" + "+0" * 2048),
    Hostile("3,000 not", "not " * 3000 + "{v}", placeholder=False, whole=True),
    Hostile("2,000 abs", "abs(" * 2000 + "{v}" + ")" * 2000 + " > 0", placeholder=False, whole=True),
    Hostile("an element of 20 digits", f"X1.MD34090[{TWENTY_DIGITS}] > 0", placeholder=False, whole=True),
    Hostile("alarm(10^30)", f"alarm({10**30})", placeholder=False, whole=True),
    Hostile("2,000 and", " and ".join(["{v} > 0"] * 2000), placeholder=False, whole=True),
)


def _quoted(text: str) -> str:
    """``text`` inside a double-quoted YAML scalar."""
    return text.replace("\\", "\\\\").replace('"', '\\"').replace("\x00", "\\0")


def _scenario(hostile: Hostile, where: str) -> str:
    """A small scenario with the expression in a condition or in a placeholder."""
    head = f"name: hostile\nmachine: {MACHINE}\nplc: basic_machine\ntimeout: 5s\n"
    if where == "placeholder":
        text = _quoted(hostile.text.replace("{v}", "x"))
        return (head + "vary: {x: [1, 2], cam: [[1, 2]]}\nsteps:\n"
                f'  - set: {{MCP.feedOverride: "${{{text}}}"}}\n  - wait: 10ms\n')
    expression = hostile.text.replace("{v}", "X1.position")
    condition = _quoted(expression if hostile.whole else f"({expression}) > 0")
    if where == "wait":
        return head + f'steps:\n  - wait: {{until: "{condition}", timeout: 10ms}}\n'
    return head + f'steps:\n  - wait: 10ms\n  - expect: "{condition}"\n'


def run_hostile_expressions(settings: CampaignSettings, say: Say, *, only: Collection[str] | None = None,
                            bound_s: float = DEFAULT_BOUND_S) -> Row:
    """Every hostile expression (or those named in ``only``) in every place it fits."""
    outcomes: list[Outcome] = []
    false_passes = violations = 0
    with tempfile.TemporaryDirectory(prefix="vc-hostile-expressions-") as directory:
        for hostile in (item for item in HOSTILE if only is None or item.name in only):
            places = [place for place, fits in (("expect", hostile.condition), ("wait", hostile.condition),
                                                ("placeholder", hostile.placeholder)) if fits]
            for place in places:
                path = Path(directory) / f"hostile_{len(outcomes)}.yaml"
                path.write_text(_scenario(hostile, place), encoding="utf-8")
                outcome = run_vc(f"{hostile.name} ({place})", ["run", str(path), "-j", "1"], bound_s)
                outcomes.append(outcome)
                why = outcome.bad
                if not why and outcome.code != 2:
                    false_passes += 1
                    why = f"exit {outcome.code}: the file ran"
                elif not why and f"{path}:" not in outcome.output:
                    violations += 1
                    why = "refused without FILE:LINE:COLUMN"
                if why:
                    say(f"{outcome.name}: {why}: {outcome.output.strip()[-300:]}")
                path.unlink()
    return tally(PART, outcomes, false_passes=false_passes, violations=violations,
                 notes=f"{len(outcomes)} scenario files, each refused with its location or not; false passes: a"
                       " file that ran; violations: a refusal without FILE:LINE:COLUMN")
