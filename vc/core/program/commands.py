"""The interpreter's output vocabulary: the commands a block gives to the functions of other
packages (spindle, coupling, polygon, drive ESR, retraction), and the coupling parameters a part
program names.

The interpreter (``vc.core.program.interpreter``) writes these; the packages above it (spindle,
retraction, channel) read them.  Keeping them here lets the program package stand below the
functions it commands: it imports none of them.

* COUPDEF's <CouplingType> and <BlockChange>, and the CP keywords of the synchronism thresholds
* ``SpindleCommand``, ``CouplingCommand``, ``PolygonCommand``: what one block asks of a spindle,
  a coupling, the polygon turning
* ``DriveEsrCommand`` (ESRS / ESRR) and the modal retract words ``RetractProgramming``
  (LFON / LFOF, LFTXT / LFWP / LFPOS, DILF, ALF, POLF, POLFMASK / POLFMLIN)
* ``AuxiliaryFunction``: an M, S, T, D, DL, H or F function of a block on its way to the PLC, with
  when it goes out (``OutputTime``)
"""

from __future__ import annotations

from dataclasses import dataclass, field
from enum import Enum, IntEnum

from vc.config import md_dictionary as MD
from vc.config.machine_data import MdDef
from vc.config.model import EXTENDED_RETRACT, EXTENDED_STOP


class Kind(Enum):
    """COUPDEF's <CouplingType> and MD21310 (0 = AV, 1 = DV, 2 = VV [control] coding)."""

    AV = 0
    DV = 1
    VV = 2


class BlockChange(Enum):
    """COUPDEF's <BlockChange> and MD21320 (L22583-22596; 0..3 [control] coding)."""

    NOC = 0  # at once
    FINE = 1  # at synchronism fine
    COARSE = 2  # at synchronism coarse
    IPOSTOP = 3  # at setpoint synchronism


def block_change_of(text: str) -> BlockChange | None:
    """Only the initial letters count: "NOC", "FINE", "COARSE", "IPOSTOP" (L22595-22596)."""
    word = text.strip().upper()
    for criterion, prefix in ((BlockChange.NOC, "NO"), (BlockChange.FINE, "FI"), (BlockChange.COARSE, "CO"),
                              (BlockChange.IPOSTOP, "IP")):
        if word.startswith(prefix):
            return criterion
    return None


def kind_of(text: str) -> Kind | None:
    return {"DV": Kind.DV, "AV": Kind.AV, "VV": Kind.VV}.get(text.strip().upper())


# The CP keywords for the synchronism thresholds of a following spindle (``CPSYNCOP[S2]=0.5``) and
# the machine data whose values they replace (L29655-29726 stage 1, L29810-29846 stage 2,
# L30651-30656: the defaults of the synchronous spindle are these machine data).
SYNCHRONISM_THRESHOLDS: dict[str, MdDef] = {
    "CPSYNCOP": MD.COUPLE_POS_TOL_COARSE, "CPSYNFIP": MD.COUPLE_POS_TOL_FINE,
    "CPSYNCOV": MD.COUPLE_VELO_TOL_COARSE, "CPSYNFIV": MD.COUPLE_VELO_TOL_FINE,
    "CPSYNCOP2": MD.COUPLE_POS_TOL_COARSE_2, "CPSYNFIP2": MD.COUPLE_POS_TOL_FINE_2,
}


@dataclass(slots=True)
class FixedStopWords:
    """FXS / FXST / FXSW of one axis in a block (seed 003 L37132-37160); None: not written."""

    switch: int | None = None  # FXS[ax]=1 selects, =0 deselects
    torque: float | None = None  # FXST[ax]=: the clamping torque, percent of the drive's maximum (SD43510)
    window: float | None = None  # FXSW[ax]=: the monitoring window (SD43520)


@dataclass(slots=True)
class SpindleCommand:
    """What one block asks of one spindle (seed 003 chapter 13)."""

    speed: float | None = None  # S, rev/min
    direction: int | None = None  # M3, M4 or M5
    gear: int | None = None  # M40 .. M45
    position: tuple[str, float] | None = None  # SPOS / SPOSA / M19: (AC|IC|DC|ACP|ACN, degrees)
    wait_for_position: bool = True  # SPOS and M19 hold the block; SPOSA does not
    axis_mode: bool = False  # M70, or the spindle programmed by its axis name
    m_function: int | None = None  # the M function shown in DB31.DBB86


@dataclass(frozen=True, slots=True)
class CouplingCommand:
    """COUPDEF, COUPON, COUPONC, COUPOF, COUPOFS, COUPDEL, COUPRES or WAITC (seed 003 §14.2)."""

    function: str
    following: str  # machine axis of the FS
    leading: str = ""  # machine axis of the LS ("" where the call names none)
    numerator: float | None = None  # COUPDEF ratio
    denominator: float | None = None
    block_change: str | None = None  # COUPDEF "NOC" / "FINE" / "COARSE" / "IPOSTOP"; WAITC's condition
    kind: str | None = None  # COUPDEF "DV" / "AV" / "VV"
    offset: float | None = None  # COUPON's POSFS


@dataclass(frozen=True, slots=True)
class PolygonCommand:
    """G51.2 P Q R A (start) or G50.2 (cancel), seed 002 L21-51."""

    start: bool
    p: float = 0.0  # master (workpiece) rotation factor = number of tools
    q: float = 0.0  # slave (tool) rotation factor = number of sides, its sign the direction
    r: float = 0.0  # master offset angle before the synchronisation (relative)
    a: float = 0.0  # helix lead per master revolution


MAX_DELAY_S = 20.0  # ESRS: p0892 range 0.00 - 20.00 s (L41932-41940)


@dataclass(frozen=True, slots=True)
class DriveEsrCommand:
    """One axis of ESRS(<axis>, <time>, ...) or ESRR(<axis>, <distance>, <velocity>, ...)."""

    axis: str  # machine axis
    configuration: int  # p0888: 1 = stop (ESRS), 2 = retract (ESRR)
    delay: float  # p0892, s
    velocity: float = 0.0  # ESRR: retract velocity, signed by the distance, per minute (mm/min, deg/min)


def esrs_command(axis: str, delay: float) -> DriveEsrCommand:
    return DriveEsrCommand(axis, EXTENDED_STOP, delay)


def esrr_command(axis: str, distance: float, velocity: float) -> DriveEsrCommand:
    """p0892 = distance / velocity (L41977-41980); the distance's sign gives the direction [INF]."""
    return DriveEsrCommand(axis, EXTENDED_RETRACT, abs(distance) / velocity * 60.0,
                           velocity if distance >= 0 else -velocity)


LFTXT, LFWP, LFPOS = "LFTXT", "LFWP", "LFPOS"  # G group 46: how the retract target is given


@dataclass(slots=True)
class RetractProgramming:
    """The modal retract words of a channel; ``reset()`` gives the reset values (MD20150: LFOF, LFTXT;
    DILF back to MD21200, L8394-8398)."""

    enabled: bool = False  # LFON / LFOF: fast retraction in G33
    target_mode: str = LFTXT  # LFTXT / LFWP / LFPOS
    distance: float | None = None  # DILF; None = MD21200
    direction: int = 1  # ALF
    positions: dict[str, tuple[float, bool]] = field(default_factory=dict)  # POLF: machine axis -> (value, IC)
    axial: tuple[str, ...] = ()  # POLFMASK: machine axes retracting each on its own
    linear: tuple[str, ...] = ()  # POLFMLIN: machine axes retracting together on a line

    def reset(self) -> None:
        self.enabled = False
        self.target_mode = LFTXT
        self.distance = None
        self.direction = 1
        self.positions = {}
        self.axial = ()
        self.linear = ()

    def position_targets(self, axes: list[str], where: dict[str, float]) -> dict[str, float]:
        """The POLF end points of ``axes`` (those with a POLF value), from the positions at the trigger."""
        targets = {}
        for name in axes:
            if name in self.positions:
                value, incremental = self.positions[name]
                targets[name] = where[name] + value if incremental else value
        return targets


class OutputTime(IntEnum):
    """When an auxiliary function goes to the PLC: MD22200 .. MD22252 (the coding of the control)."""

    BEFORE_MOTION = 0  # the block's motion starts once the functions are acknowledged
    DURING_MOTION = 1  # with the motion; the block ends once they are acknowledged
    AT_BLOCK_END = 2  # after the motion; the block change follows their acknowledgement
    NOT_OUTPUT = 3  # the PLC never sees it


@dataclass(frozen=True, slots=True)
class AuxiliaryFunction:
    """One auxiliary function of a block as the PLC gets it (seed 003 L16391, L20662-20680): its
    type, extended address and value, whether it is quick (QU: the block does not wait for the
    PLC) and when it goes out."""

    kind: str  # "M", "S", "T", "D", "DL", "H" or "F"
    extension: int  # the extended address: M2=5 -> 2; a spindle function's spindle number
    value: float  # M, T, D: a whole number; S, H, F, DL: a real
    time: OutputTime = OutputTime.DURING_MOTION
    quick: bool = False

    def __str__(self) -> str:
        value = f"{self.value:g}"
        return f"{self.kind}{self.extension}={value}" if self.extension else f"{self.kind}{value}"
