"""What the NCK keeps over power-off: machine data it writes itself, and buffered positions.

The control writes some machine data during operation: referencing an absolute encoder
computes MD34090 REFP_MOVE_DIST_CORR and sets MD34210 ENC_REFP_STATE; referencing records
MD34093 REFP_CAM_MARKER_DIST; switching off records MD30250 ACT_POS_ABS.  These values live
here, on top of the machine file, and survive a power cycle like the control's static
memory.  Buffered encoder states let an incremental axis restore its position after
power-on (seed 003 §4.10).  Retract data of a thread aborted by reset or power failure stay
until a program starts (seed 003 §16.12).

The memory is handed from one power-on of the simulated control to the next by the
harness; the core never stores it anywhere itself.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from vc.config.machine_data import MachineData, MdDef, MdScalar, MdValue


@dataclass(frozen=True, slots=True)
class BufferedEncoder:
    """One encoder at switch-off."""

    actual: float  # actual value
    referenced: bool
    restored: bool
    exact_stop_fine: bool  # the axis stood within exact stop fine (automatic referencing needs it)


@dataclass(frozen=True, slots=True)
class RetractData:
    """What a channel keeps when a thread block is aborted, for manual retraction (seed 003 §16.12).

    The control keeps references to the data of the abort, not copies (L35344-35348): tool offset,
    plane, toolholder, transformation and thread data.  This core has no tool offsets, toolholders
    or frames, and a selection starts from where the axes stand (L35655-35656), so what the
    retraction needs of them is the tool axis and the thread's spindle and pitch.
    """

    tool_axis: str  # machine axis of the drilling / thread axis: the retract axis
    spindle: str  # machine axis of the spindle interpolated with it ("" = none)
    spindle_per_mm: float  # thread data: spindle degrees per mm of the tool axis (signed)


@dataclass(slots=True)
class NcMemory:
    written: dict[tuple[str, int], MdValue] = field(default_factory=dict)  # (owner, MD number) -> value
    buffered: dict[tuple[str, int], BufferedEncoder] = field(default_factory=dict)  # (axis, encoder index)
    retract: dict[str, RetractData] = field(default_factory=dict)  # channel -> data of the aborted thread

    def write(self, owner: str, md: MdDef, value: MdScalar, index: int | None, base: MachineData) -> None:
        """The control writes ``md`` (index ``index`` of an array) of ``owner``."""
        current = self.written.get((owner, md.number), base.value(md))
        if isinstance(current, tuple):
            items = list(current)
            items[index or 0] = value
            self.written[(owner, md.number)] = tuple(items)
        else:
            self.written[(owner, md.number)] = value

    def view(self, owner: str, base: MachineData) -> MachineData:
        """``base`` with the values the control wrote for ``owner``."""
        written = {number: value for (name, number), value in self.written.items() if name == owner}
        return base.with_values(written) if written else base
