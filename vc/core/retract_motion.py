"""Retract programming (LFON / LFOF, DILF, LFTXT / LFWP / LFPOS, ALF, POLF, POLFMASK, POLFMLIN)
and the retract motion it describes (seed 003 §7.2.3.5 L8211-8399, §22.4 L42197-42360).

Two ways to say where the tool goes:

* distance and direction (LFTXT / LFWP with DILF and ALF): DILF (default MD21200) in the
  direction ALF of the retract plane.  ALF = n points (n - 1) x 45 degrees from the plane's first
  axis towards its second: G17 (X, Y), G18 (Z, X), G19 (Y, Z); the seed confirms 1, 3 and 7
  (L8288-8301, L8365-8372), the other steps are the control's 45-degree grid [control];
* positions (LFPOS): the axes of POLFMASK move each on its own (axial) to their POLF position,
  those of POLFMLIN together on a straight line; POLF on a geometry axis is a WCS value, on a
  machine axis an MCS value, IC() incremental from where the axis stands at the trigger (L8314-8333).
  The harness has no frames, so WCS = MCS.

With a transformation active (the inclined Y slide of seed 000) the geometry axes of the
transformation are program (Cartesian) axes: their POLF and DILF / ALF end points are program
positions, and the transformation's machine axes move together on the straight program line to
the machine end points of those positions (``TransformGroup``).  A geometry axis of the group
without a retract target keeps its program position at the trigger [control].

A retraction runs at the axes' maximum dynamics (MD32000 / MD32300, L8340-8349; the jerk limit
MD32431 is not modelled): each group of axes is a rapid linear segment, owned by the retraction
(``Owner.RETRACT``), so neither feed stop nor the single-axis stop signal holds it (L11394-11396).
"""

from __future__ import annotations

import math
from collections.abc import Collection
from dataclasses import dataclass, field
from typing import Protocol

from vc.core.axis import MachineAxis, Owner
from vc.core.path import PathSegment

LFTXT, LFWP, LFPOS = "LFTXT", "LFWP", "LFPOS"  # G group 46: how the retract target is given
# The plane's first and second axis (geometry axis names): ALF=1 points along the first, ALF=3 along the second.
PLANE_AXES = {"G17": ("X", "Y"), "G18": ("Z", "X"), "G19": ("Y", "Z")}


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


def direction_targets(direction: int, distance: float, plane: str, machine_axis_of: dict[str, str],
                      where: dict[str, float]) -> dict[str, float]:
    """DILF / ALF: the end points of the plane's axes ``distance`` away in direction ``direction``."""
    angle = math.radians((direction - 1) * 45.0)
    first, second = PLANE_AXES[plane]
    targets = {}
    for geometry, component in ((first, math.cos(angle)), (second, math.sin(angle))):
        machine_axis = machine_axis_of.get(geometry)
        if machine_axis is not None and abs(component) > 1e-12:
            targets[machine_axis] = where[machine_axis] + distance * component
    return targets


class TransformGroup(Protocol):
    """The machine axes of an active transformation and their program (Cartesian) positions."""

    @property
    def machine_axes(self) -> Collection[str]: ...

    def program_positions(self) -> dict[str, float]:
        """Program positions of the group's axes, keyed by their machine axis names."""
        ...

    def machine_targets(self, program_targets: dict[str, float]) -> dict[str, float]:
        """Machine end points of every axis of the group for program end points of some of them."""
        ...


def retract_positions(axes: dict[str, MachineAxis], transform: TransformGroup | None) -> dict[str, float]:
    """Where the axes stand at the trigger, as the retract programming counts: the program positions
    of a transformation's axes, else the machine setpoints."""
    where = {name: axis.setpoint for name, axis in axes.items()}
    if transform is not None:
        where.update(transform.program_positions())
    return where


def through_transform(groups: list[dict[str, float]], transform: TransformGroup | None) -> list[dict[str, float]]:
    """The groups with program end points of a transformation's axes turned into machine end points:
    the groups that hold an axis of the transformation become one group with all its axes, so the
    tool leaves on the straight program line [control]."""
    if transform is None:
        return groups
    members = set(transform.machine_axes)
    touching = [group for group in groups if members & set(group)]
    if not touching:
        return groups
    merged = {name: target for group in touching for name, target in group.items()}
    merged.update(transform.machine_targets({name: merged[name] for name in members if name in merged}))
    return [group for group in groups if not members & set(group)] + [merged]


class RetractMotion:
    """Retract moves running at maximum dynamics: one rapid linear segment per group of axes."""

    def __init__(self, groups: list[dict[MachineAxis, float]]):
        self.segments: list[PathSegment] = []
        for group in groups:
            self.add(group)

    def add(self, group: dict[MachineAxis, float]) -> None:
        """One more group: it starts from where its axes stand; the running groups go on unchanged."""
        axes = list(group)
        if not axes:
            return
        for axis in axes:
            axis.take(Owner.RETRACT)
        self.segments.append(PathSegment.plan(axes, [group[axis] for axis in axes], [True] * len(axes), 0.0, True))

    @property
    def axes(self) -> list[MachineAxis]:
        return [axis for segment in self.segments for axis in segment.axes]

    @property
    def finished(self) -> bool:
        return not self.segments

    def cycle(self, dt: float) -> None:
        """One IPO cycle of every segment; a segment whose axis was taken away (rapid stop) ends."""
        running = []
        for segment in self.segments:
            if any(axis.owner is not Owner.RETRACT for axis in segment.axes):
                continue
            segment.cycle(1.0, False, dt)
            if segment.finished:
                for axis in segment.axes:
                    axis.release()
            else:
                running.append(segment)
        self.segments = running


def retract_groups(programming: RetractProgramming, axes: dict[str, MachineAxis], candidates: list[str],
                   transform: TransformGroup | None = None) -> list[dict[MachineAxis, float]]:
    """LFPOS: the POLFMLIN axes as one group, every POLFMASK axis as a group of its own, restricted
    to ``candidates`` (the axes allowed to retract) that have a POLF position."""
    where = retract_positions(axes, transform)
    linear = [name for name in programming.linear if name in candidates]
    groups = [programming.position_targets(linear, where)]
    for name in programming.axial:
        if name in candidates and name not in linear:
            groups.append(programming.position_targets([name], where))
    return machine_groups(through_transform([group for group in groups if group], transform), axes)


def machine_groups(groups: list[dict[str, float]], axes: dict[str, MachineAxis]) -> list[dict[MachineAxis, float]]:
    return [{axes[name]: target for name, target in group.items()} for group in groups]
