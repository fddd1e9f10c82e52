"""The coupling parameters a part program names: COUPDEF's <CouplingType> and <BlockChange>, and the
CP keywords of the synchronism thresholds."""

from __future__ import annotations

from enum import Enum

from vc.config import md_dictionary as MD
from vc.config.machine_data import MdDef


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
