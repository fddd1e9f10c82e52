"""The control's handwheels in JOG (seed 003 §16.6.1 / §16.8, L33120-33160, L33395-33415, L33558-33640).

The operator turns an electronic handwheel; its pulses reach the NC directly (not through the
PLC), one pulse per detent (MD11320 HANDWH_IMP_PER_LATCH = 1 [control default]).  The PLC assigns
the handwheels to machine axes with DB31.DBX4.0..4.2 (bit coded: bit n-1 = handwheel n, MD11324 =
0, the default of L33612-33620) and selects the increment with the machine functions INC1 ..
INC10000 (DB31.DBX5.0..5.4).  A detent moves the axis by the increment MD11330 x MD31090
JOG_INCR_WEIGHT (0.001 mm, the control's default, L5484 [control]; negative: the other way, L33591);
without an increment selected the pulses move nothing [control].  The axis travels the distance at
its JOG velocity and acceleration and stops on the end point; an axis its traverse keys move takes
no pulses (L33124).  Spindles take none.

A handwheel may instead be assigned to a geometry axis of the channel (DB21.DBX12.0..2 /
16.0..2 / 20.0..2 for geometry axes 1 / 2 / 3, L33170, L33406-33412) with the increments of the
geometry axis (DB21.DBX13.0..13.4 / 17.x / 21.x [control: the seed prints these machine functions
at DB31.DBX5.x, L33005-33009]): a detent moves the geometry axis in the WCS, through the machine
axis it is; under the inclined-axis transform program Y is the inclined axis's travel x cos(theta),
so a detent moves the inclined axis by the increment / cos(theta) and JOG's Cartesian rule carries
the orthogonal one (NOZAGC = 0, vc/core/transforms/inclined_axis_control.py).  DB21.DBX40.0..2 reports the
handwheel of geometry axis 1 (L34189-34193; the seed prints no such bits for geometry axes 2 and 3).

In a manual retraction (L35590-35598) the pulses are evaluated by priority: the retract (tool)
axis - assigned as machine axis or as the geometry axis it is -, then its spindle, then the axes
not involved; the pulses of a lower handwheel are ignored while a higher one turns, and while the
tool axis is moved by its keys the pulses of the others are ignored.  A handwheel turns while the
operator turns it (a scenario's ``turn`` step).
"""

from __future__ import annotations

from dataclasses import dataclass, field

from interfaces.signal_groups import HandwheelSelection

HANDWHEELS = 3
GEOMETRY_AXES = 3  # geometry axes 1..3 of a channel: DB21 bytes 12, 16, 20
def increment_of(selection: HandwheelSelection, sizes: tuple[float, ...], weight: float) -> float:
    """Travel per detent: the lowest increment the PLC selects of ``sizes`` (MD11330 INC1 ..
    INC10000) x ``weight`` (MD31090 of the axis; negative: the handwheel turns the other way,
    L33591), 0 without one."""
    selected = (selection.inc1, selection.inc10, selection.inc100, selection.inc1000, selection.inc10000)
    for size, on in zip(sizes, selected, strict=True):
        if on:
            return size * weight
    return 0.0


@dataclass(slots=True)
class _Turning:
    detents: int
    cycles: int
    done_cycles: int = 0
    delivered: int = 0


@dataclass(slots=True)
class Handwheels:
    """The pulses of the handwheels, cycle by cycle."""

    _turning: dict[int, _Turning] = field(default_factory=dict)

    def turn(self, number: int, detents: int, cycles: int) -> None:
        """The operator turns handwheel ``number`` by ``detents`` (sign = direction) evenly over ``cycles``."""
        if not 1 <= number <= HANDWHEELS:
            raise ValueError(f"handwheel {number}: the control has handwheels 1..{HANDWHEELS}")
        self._turning[number] = _Turning(detents, max(1, cycles))

    @property
    def any_turning(self) -> bool:
        return bool(self._turning)

    def pulses(self) -> dict[int, int]:
        """The pulses of this IPO cycle of every handwheel that turns (0 when a turning one gives none)."""
        result: dict[int, int] = {}
        for number, turning in list(self._turning.items()):
            turning.done_cycles += 1
            due = turning.detents * turning.done_cycles // turning.cycles if turning.detents >= 0 else \
                -(-turning.detents * turning.done_cycles // turning.cycles)
            result[number] = due - turning.delivered
            turning.delivered = due
            if turning.done_cycles >= turning.cycles:
                del self._turning[number]
        return result
