"""What moves in the benchmarks: the MDA programs of ``vc bench``, written from the machine's configuration.

Three loads, each on the first channel of the machine:

* ``idle``: nothing moves; the NC, the plant and the PLC run their cycles with every axis and
  spindle standing in position control (the cost of the machine's size alone).
* ``two axes``: the program of ``vc bench`` since its first version, kept as it was so that its
  figures stay comparable: the first two geometry axes back and forth (G1 and G0 blocks with
  exact stop), the other axes and spindles standing.
* ``everything``: every axis and spindle of the channel moves.  Each spindle turns with M3 at
  half the top speed of its first gear stage (MD35130[1], at most MD35100 and MD32000): the
  gearboxes of the machines in scenarios/machines/ are in stage 1 at power-on, so no gear
  change interrupts the program.  Where the channel has a configured synchronous spindle pair
  (MD21300 COUPLE_AXIS_1 = [FS, LS]) the following spindle does not turn on its own:
  ``COUPDEF(S<fs>,S<ls>,1,1,"NOC","DV")`` and ``COUPON(S<fs>,S<ls>)`` couple it 1:1 to the
  leading one (setpoint coupling, block change at once).  The other axes (geometry axes by
  their geometry names, the rest by their channel names) move incrementally by 20 mm or
  degrees forth and back in every block, all at once, with G1 and G0, and end where they
  started.  Before the timing starts, ``SPOS[n]=0`` takes every spindle to its zero mark once,
  so that the coupled spindles are synchronised with their zero marks (else the NC warns with
  alarm 22040 at every COUPON), and the program runs once: its first run waits for the
  spindles to reach their speeds before the axes move (turn_mill: 2.5 s, SP3 to 5000 rev/min);
  the spindles keep turning over the program end (M30), so each timed run moves everything
  from its first block on.

A plan says what must move (``moving``, machine axis names) and which pair must be coupled
(``pair``): the benchmark checks both, so a figure never stands for motion that did not happen.
"""

from __future__ import annotations

from dataclasses import dataclass
from enum import StrEnum

from vc.config import md_dictionary as MD
from vc.config.model import AxisConfig, ChannelConfig, MachineConfig

# vc bench's program since its first version: never change it (its figures are compared across versions)
TWO_AXES_PROGRAM = """; benchmark: back and forth on two axes
G90 G1 F6000
{a}=40 {b}=-30
{a}=0 {b}=0
G0 {a}=25
G1 {a}=10 {b}=-10 F3000
G0 {a}=0 {b}=0
M30
"""

STROKE = 20  # mm or degrees each axis of the everything load moves per block
SPINDLE_SPEED_SHARE = 0.5  # of the first gear stage's top speed


class Load(StrEnum):
    IDLE = "idle"
    TWO_AXES = "two axes"
    EVERYTHING = "everything"


@dataclass(frozen=True, slots=True)
class CoupledPair:
    following: str  # machine axis names
    leading: str


@dataclass(frozen=True, slots=True)
class MotionPlan:
    """One load on one machine: the programs and what they must move."""

    load: Load
    channel: str
    axes: tuple[str, ...]  # every axis and spindle of the channel, in channel order
    program: str  # the MDA program started again whenever it ended; "" = none (idle)
    setup: str  # an MDA program run once, untimed, before; "" = none
    moving: tuple[str, ...]  # the machine axes and spindles that must move, in channel order
    pair: CoupledPair | None  # the synchronous spindle pair the program couples

    def describe(self) -> str:
        """``two axes (X1, Z1)``, ``everything (X1, ..., SP3; SP2 coupled to SP1)``, ``idle``."""
        if not self.moving:
            return str(self.load)
        coupled = f"; {self.pair.following} coupled to {self.pair.leading}" if self.pair is not None else ""
        return f"{self.load} ({', '.join(self.moving)}{coupled})"


def motion_plan(machine: MachineConfig, load: Load) -> MotionPlan:
    channel = machine.channels[0]
    if load is Load.IDLE:
        return MotionPlan(load, channel.name, channel.axes, "", "", (), None)
    if load is Load.TWO_AXES:
        names = [name for name in channel.geometry_names if channel.axis_for_program_name(name)][:2]
        moving = tuple(axis for name in names if (axis := channel.axis_for_program_name(name)) is not None)
        return MotionPlan(load, channel.name, channel.axes, TWO_AXES_PROGRAM.format(a=names[0], b=names[1]), "",
                          moving, None)
    return _everything(machine, channel)


def _everything(machine: MachineConfig, channel: ChannelConfig) -> MotionPlan:
    spindles = [machine.axis(name) for name in channel.axes if machine.axis(name).is_spindle]
    pair = _configured_pair(machine, channel)
    path_axes = [_program_name(channel, name) for name in channel.axes if not machine.axis(name).is_spindle]
    turning = " ".join(f"M{spindle.spindle_number}=3 S{spindle.spindle_number}={_speed(spindle):g}"
                       for spindle in spindles if pair is None or spindle.name != pair.following)
    lines = ["; benchmark: every axis and spindle moving" + (
        f", {pair.following} coupled to {pair.leading}" if pair is not None else "")]
    if turning:
        lines.append(turning)
    if pair is not None:
        following, leading = (f"S{machine.axis(name).spindle_number}" for name in (pair.following, pair.leading))
        lines += [f'COUPDEF({following},{leading},1,1,"NOC","DV")', f"COUPON({following},{leading})"]
    if path_axes:
        lines += ["G91 G1 F6000", _stroke(path_axes, +1), _stroke(path_axes, -1),
                  "G0 " + _stroke(path_axes, -1), "G1 " + _stroke(path_axes, +1) + " F3000"]
    lines.append("M30")
    setup = " ".join(f"SPOS[{spindle.spindle_number}]=0" for spindle in spindles)
    return MotionPlan(Load.EVERYTHING, channel.name, channel.axes, "\n".join(lines) + "\n",
                      f"{setup}\nM30\n" if setup else "", channel.axes, pair)


def _configured_pair(machine: MachineConfig, channel: ChannelConfig) -> CoupledPair | None:
    """MD21300 COUPLE_AXIS_1 = [FS, LS] as channel axis numbers (MD20070), 0 = none."""
    numbers = [channel.md.int(MD.COUPLE_AXIS_1, index) for index in (0, 1)]
    if not all(numbers) or max(numbers) > len(channel.axes):
        return None
    following, leading = (channel.axes[number - 1] for number in numbers)
    if not (machine.axis(following).is_spindle and machine.axis(leading).is_spindle):
        return None
    return CoupledPair(following, leading)


def _program_name(channel: ChannelConfig, axis: str) -> str:
    """How a part program addresses the machine axis: its geometry name, else its channel name."""
    for geometry_name, geometry_axis in zip(channel.geometry_names, channel.geometry_axes, strict=True):
        if geometry_axis == axis:
            return geometry_name
    return channel.program_names[channel.axes.index(axis)]


def _speed(spindle: AxisConfig) -> float:
    """Half the top speed of the first gear stage, within the chuck limit and the axis's maximum."""
    md = spindle.md
    top = min(md.float(MD.GEAR_STEP_MAX_VELO_LIMIT, 1), md.float(MD.SPIND_VELO_LIMIT), md.float(MD.MAX_AX_VELO))
    return round(top * SPINDLE_SPEED_SHARE)


def _stroke(names: list[str], sign: int) -> str:
    return " ".join(f"{name}{sign * STROKE}" for name in names)
