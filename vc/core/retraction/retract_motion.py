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

A retraction runs at the axes' maximum dynamics (MD32000 / MD32300 / MD32431, L8340-8349): each
group of axes is a straight line from standstill to standstill with a jerk-limited (S-curve)
velocity profile, owned by the retraction (``Owner.RETRACT``), so neither feed stop nor the
single-axis stop signal holds it (L11394-11396).
"""

from __future__ import annotations

import math
from collections.abc import Collection
from dataclasses import dataclass
from typing import Protocol

from vc.core.axis.axis import MachineAxis
from vc.core.axis.owner import Owner
from vc.core.program.commands import RetractProgramming

# The plane's first and second axis (geometry axis names): ALF=1 points along the first, ALF=3 along the second.
PLANE_AXES = {"G17": ("X", "Y"), "G18": ("Z", "X"), "G19": ("Y", "Z")}


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


@dataclass(frozen=True, slots=True)
class SCurve:
    """A rest-to-rest motion over ``length`` at velocity, acceleration and jerk limits: jerk +J, (hold
    the acceleration), -J up to the velocity, cruise, and the mirror image down to standstill.

    Closed form, sampled at the IPO cycles: ``peak_accel`` = min(A, sqrt(V J)); the acceleration
    phase lasts ``ramp_time`` = V / A + A / J (2 sqrt(V / J) without a constant-acceleration part)
    and covers V x ramp_time / 2; a line too short for the velocity limit lowers V until both
    ramps fit (no cruise)."""

    length: float
    velocity: float  # the cruise velocity reached
    peak_accel: float
    jerk: float
    ramp_time: float
    cruise_time: float

    @classmethod
    def plan(cls, length: float, velocity: float, accel: float, jerk: float) -> SCurve:
        def ramp_time(v: float) -> float:
            return v / accel + accel / jerk if v * jerk >= accel * accel else 2.0 * math.sqrt(v / jerk)

        if length <= 0.0:
            return cls(0.0, 0.0, 0.0, jerk, 0.0, 0.0)
        if velocity * ramp_time(velocity) > length:  # both ramps at V are longer than the line
            low, high = 0.0, velocity
            for _ in range(100):  # the ramps' length V x ramp_time(V) grows with V
                middle = 0.5 * (low + high)
                low, high = (middle, high) if middle * ramp_time(middle) <= length else (low, middle)
            velocity = low
        ramp = ramp_time(velocity)
        return cls(length, velocity, min(accel, math.sqrt(velocity * jerk)), jerk, ramp,
                   (length - velocity * ramp) / velocity if velocity > 0.0 else 0.0)

    @property
    def duration(self) -> float:
        return 2.0 * self.ramp_time + self.cruise_time

    def at(self, t: float) -> tuple[float, float]:
        """Path position and velocity ``t`` seconds after the start."""
        if t >= self.duration:
            return self.length, 0.0
        if t > self.ramp_time + self.cruise_time:  # braking: the acceleration mirrored in time
            s, v = self._ramp(self.duration - t)
            return self.length - s, v
        if t > self.ramp_time:
            ramp_length = self.velocity * self.ramp_time / 2.0
            return ramp_length + self.velocity * (t - self.ramp_time), self.velocity
        return self._ramp(t)

    def _ramp(self, t: float) -> tuple[float, float]:
        """Position and velocity ``t`` into the acceleration phase."""
        jerk, peak = self.jerk, self.peak_accel
        jerk_time = peak / jerk
        if t <= jerk_time:
            return jerk * t ** 3 / 6.0, jerk * t * t / 2.0
        rest = self.ramp_time - t
        if rest <= jerk_time:  # jerk -J up to the velocity: the first phase mirrored
            return self.velocity * self.ramp_time / 2.0 - (self.velocity * rest - jerk * rest ** 3 / 6.0), \
                self.velocity - jerk * rest * rest / 2.0
        held = t - jerk_time
        start_velocity = jerk * jerk_time * jerk_time / 2.0
        return jerk * jerk_time ** 3 / 6.0 + start_velocity * held + peak * held * held / 2.0, \
            start_velocity + peak * held


@dataclass(slots=True)
class RetractSegment:
    """One group of retract axes on the straight line from where they stand to their end points."""

    axes: list[MachineAxis]
    starts: list[float]
    ends: list[float]
    profile: SCurve
    time: float = 0.0

    @classmethod
    def plan(cls, axes: list[MachineAxis], ends: list[float]) -> RetractSegment:
        starts = [axis.setpoint for axis in axes]
        deltas = [end - start for start, end in zip(starts, ends, strict=True)]
        length = math.sqrt(sum(d * d for d in deltas))
        units = [abs(d) / length for d in deltas] if length > 0.0 else []

        def limit(value_of: str) -> float:
            return min((getattr(axis.dyn, value_of) / unit for axis, unit in zip(axes, units, strict=False) if unit),
                       default=math.inf)

        return cls(axes, starts, ends, SCurve.plan(length, limit("max_velocity"), limit("max_accel"),
                                                  limit("max_jerk")))

    @property
    def finished(self) -> bool:
        """At the end point and standing: the cycle after the one that arrived."""
        return self.time > self.profile.duration

    def cycle(self, dt: float) -> None:
        """Advance one IPO cycle and hand each axis its position setpoint."""
        self.time += dt
        s, v = self.profile.at(self.time)
        length = self.profile.length
        for axis, start, end in zip(self.axes, self.starts, self.ends, strict=True):
            share = (end - start) / length if length > 0.0 else 0.0
            axis.set_path_setpoint(end if s >= length else start + share * s, share * v)


class RetractMotion:
    """Retract moves running at maximum dynamics: one jerk-limited straight line per group of axes."""

    def __init__(self, groups: list[dict[MachineAxis, float]]):
        self.segments: list[RetractSegment] = []
        for group in groups:
            self.add(group)

    def add(self, group: dict[MachineAxis, float]) -> None:
        """One more group: it starts from where its axes stand; the running groups go on unchanged."""
        axes = list(group)
        if not axes:
            return
        for axis in axes:
            axis.take(Owner.RETRACT)
        self.segments.append(RetractSegment.plan(axes, [group[axis] for axis in axes]))

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
            segment.cycle(dt)
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
