"""Five-axis program words and their modal state (Syntec, seed 001).

The words (spec 8.4, seed 001 L42-46, L54-60):

* ``G43.4 [H_]``: tool centre point control (RTCP type 1): the programmed X Y Z are the tool
  tip in workpiece coordinates, A / C (the rotary axes) the attitude; ``G43.4 L2 [E_] [R_]``
  (smooth tool orientation, STO) is refused with alarm 12550, this control has no STO;
  ``G43.4 L0`` (STO off) is accepted;
* ``G43 [H_]``: tool length compensation along the tool (used after G53.1, L59-60);
* ``G49``: cancels G43.4 and G43;
* ``G68.2 X_ Y_ Z_ I_ J_ K_``: the tilted working plane, origin X Y Z and Euler angles I J K
  (Z-X'-Z''); ``G69`` cancels it;
* ``G53.1 [P_]``: turns the rotary axes so that the tool stands along the plane's Z axis.

The interpreter collects the words of a block into :class:`FiveAxisWords`; the channel's
five-axis control (``vc.core.transforms.five_axis_control``) checks them against the machine and applies them
to :class:`FiveAxisModal`, the part of the channel's modal state these words set.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from vc.core.kinematics.tilted_plane import Frame

TOOL_CENTER_POINT = 43.4
LENGTH_COMPENSATION = 43.0
LENGTH_CANCEL = 49.0
TILTED_PLANE = 68.2
TILTED_PLANE_CANCEL = 69.0
ALIGN_TOOL = 53.1
FIVE_AXIS_G_CODES = frozenset({TOOL_CENTER_POINT, LENGTH_COMPENSATION, LENGTH_CANCEL, TILTED_PLANE,
                               TILTED_PLANE_CANCEL, ALIGN_TOOL})
# Addresses that are arguments in a five-axis block (H tool offset, L STO on/off, E tolerance,
# R ball radius, P solution choice, I J K Euler angles); elsewhere they are no words of this control.
FIVE_AXIS_ADDRESSES = frozenset("HLERPIJK")



@dataclass(slots=True)
class FiveAxisWords:
    """The five-axis words of one block, as written."""

    codes: list[float] = field(default_factory=list)  # the five-axis G codes, in block order
    arguments: dict[str, float] = field(default_factory=dict)  # H L E R P I J K
    origin: dict[str, float] = field(default_factory=dict)  # G68.2: geometry axis name -> origin coordinate
    incremental_axes: bool = False  # an axis of the block is written incrementally (G91 or IC)


@dataclass(slots=True)
class FiveAxisModal:
    """What the five-axis words leave in force until they are cancelled or the channel is reset.

    Reset and program end cancel all of it: G43.4 / G43 -> G49 [control: the SINUMERIK
    deselects a transformation on reset with MD20110 / MD20140 at their defaults; seed 001
    is silent], G68.2 -> G69 (Pr3014 = 0, "not kept on reset", seed 001 L18; Pr3014 is not
    carried).
    """

    tool_center_point: bool = False  # G43.4 until G49
    length_compensation: bool = False  # G43 until G49
    length_offset: int = 0  # H: the tool offset number whose length applies
    plane: Frame | None = None  # G68.2 until G69

    @property
    def transformed(self) -> bool:
        """Program positions are not machine positions: tool tip, tool length or tilted plane."""
        return self.tool_center_point or self.length_compensation or self.plane is not None

    @property
    def tool_length_active(self) -> bool:
        return self.tool_center_point or self.length_compensation

    def reset(self) -> None:
        self.tool_center_point = False
        self.length_compensation = False
        self.length_offset = 0
        self.plane = None

