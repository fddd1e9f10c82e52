"""Stored stroke limits 2 and 3 (G22 / G23): forbidden areas checked before the path enters them.

Seed 000 (GSK 988TD inclined-axis control, L264-291, L414-429) names them with the FANUC
convention it follows: stored stroke limit 2 is switched on by G22 and off by G23, its area set
by parameters or by ``G22 X_ Z_ I_ K_``; stored stroke limit 3 is set by parameters only.  The
seed gives neither parameters nor alarm numbers; the control's conventions [control: FANUC /
GSK] are used and carried as project machine data MD62810-62816 (``md_dictionary``):

* the area of stroke limit 2 is a box of the axes with MD62811 = 1 (parameter 1310 #0 OT2x)
  between MD62813 and MD62812 (1323 / 1322); MD62810 (1300 #0 OUT) = 0: the inside is
  forbidden, 1: the outside.  ``G22 X_ Y_ Z_ I_ J_ K_`` sets the box of the axes it names:
  each axis word and the I / J / K of the same geometry axis are its two corners (either
  order), and the box holds until the next G22 with values or power-on.  G22 alone switches the
  check on, G23 off; power-on state G22 [control: FANUC's group 04 reset state], reset keeps it;
* the area of stroke limit 3 is the inside of the box of the axes with MD62814 = 1 (1310 #1)
  between MD62816 and MD62815 (1325 / 1324), always checked.

An axis takes part once its position is exact (``software_limits_active``).  The box is
checked in *check coordinates*: the machine position, except for the axes of an inclined-axis
control, which are checked in the Cartesian system when AO2 / AO3 (MD62802[1] / [2]) is 1
(``InclinedAxisControl.stroke_point``).

Programs: the path of a block is checked before it moves; where it would enter a forbidden area
the block ends on the boundary (the path decelerates onto it) and the alarm stops the program
there [control: checked in advance like the SINUMERIK's protection zones, which stop the path in
front of the zone; FANUC's default stops just past the boundary].  Alarms 502 / 503 (+ / -,
stroke limit 2) and 504 / 505 (stroke limit 3): FANUC's OT0502-OT0505, the direction being the
motion of the axis whose boundary is reached.  A block that starts inside a forbidden area is
refused before it moves.  JOG stops on the boundary and raises the same alarm when the key is
held against it; after RESET the axis moves away.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass

from vc.config import md_dictionary as MD
from vc.config.machine_data import MdDef
from vc.core.axis.axis import MachineAxis

STROKE_LIMIT_2_PLUS = 502  # FANUC OT0502 + overtravel (soft 2)
STROKE_LIMIT_2_MINUS = 503
STROKE_LIMIT_3_PLUS = 504  # OT0504 + overtravel (soft 3)
STROKE_LIMIT_3_MINUS = 505
BOUNDARY = 1e-9  # mm: a point this close to the boundary is on it, allowed
PATH_SAMPLES = 256  # points a curved path is searched at for its entry, then refined by bisection

Point = Mapping[str, float]  # machine axis -> position (machine or check coordinates)


@dataclass(frozen=True, slots=True)
class StrokeArea:
    """One stored stroke limit: a box of the checked axes, forbidden inside or outside."""

    number: int  # 2 or 3
    bounds: Mapping[str, tuple[float, float]]  # checked machine axis -> (low, high)
    inside_forbidden: bool

    def forbidden(self, point: Point) -> bool:
        if not self.bounds:
            return False
        if self.inside_forbidden:
            return all(low + BOUNDARY < point[axis] < high - BOUNDARY for axis, (low, high) in self.bounds.items())
        return any(point[axis] < low - BOUNDARY or point[axis] > high + BOUNDARY
                   for axis, (low, high) in self.bounds.items())

    def room(self, point: Point, rate: Point) -> tuple[float, float]:
        """How far (minus <= 0 <= plus, in units of ``rate``) the point may travel along
        ``point + t rate`` without entering the forbidden area."""
        low_t, high_t = -math.inf, math.inf
        for axis, (low, high) in self.bounds.items():
            position, speed = point[axis], rate.get(axis, 0.0)
            if abs(speed) < 1e-12:
                if self.inside_forbidden and not low + BOUNDARY < position < high - BOUNDARY:
                    return -math.inf, math.inf  # this axis keeps the point out of the box
                if not self.inside_forbidden and not low - BOUNDARY <= position <= high + BOUNDARY:
                    return 0.0, 0.0
                continue
            begin, end = sorted(((low - position) / speed, (high - position) / speed))
            low_t, high_t = max(low_t, begin), min(high_t, end)
        if not self.inside_forbidden:
            return min(low_t, 0.0), max(high_t, 0.0)
        if low_t >= high_t:
            return -math.inf, math.inf  # the line misses the box
        if low_t >= -BOUNDARY:
            return -math.inf, low_t  # the box lies ahead
        if high_t <= BOUNDARY:
            return high_t, math.inf  # behind
        return 0.0, 0.0  # inside

    def alarm_number(self, direction: float) -> int:
        plus = direction > 0
        if self.number == 2:
            return STROKE_LIMIT_2_PLUS if plus else STROKE_LIMIT_2_MINUS
        return STROKE_LIMIT_3_PLUS if plus else STROKE_LIMIT_3_MINUS

    def reached_axis(self, point: Point, rate: Point) -> tuple[str, float]:
        """The axis whose boundary ``point`` stands on and its direction of motion there."""
        for axis, (low, high) in self.bounds.items():
            speed = rate.get(axis, 0.0)
            if abs(speed) > 1e-12 and min(abs(point[axis] - low), abs(point[axis] - high)) < 1e-6:
                return axis, speed
        axis = max(self.bounds, key=lambda name: abs(rate.get(name, 0.0)))  # inside: the axis moving most
        return axis, rate.get(axis, 0.0) or 1.0


@dataclass(frozen=True, slots=True)
class StrokeStop:
    """Where a path enters a forbidden area: ``fraction`` of it, the alarm number and its axis."""

    fraction: float
    number: int
    axis: str


@dataclass(frozen=True, slots=True)
class StrokeCommand:
    """G22 (``on``) with the box corners it sets, or G23."""

    on: bool
    corners: Mapping[str, tuple[float, float]]  # machine axis -> the two values (axis word, I / J / K)


class StrokeLimitControl:
    """The stored stroke limits 2 and 3 of one channel's axes."""

    def __init__(self, axes: Mapping[str, MachineAxis], inside_forbidden_2: bool):
        self._axes = axes
        self._inside_forbidden_2 = inside_forbidden_2
        self.active_2 = True  # G22 at power-on [control]
        self._bounds_2 = self._bounds(MD.STROKE2_CHECK, MD.STROKE2_LIMIT_MINUS, MD.STROKE2_LIMIT_PLUS)
        self._bounds_3 = self._bounds(MD.STROKE3_CHECK, MD.STROKE3_LIMIT_MINUS, MD.STROKE3_LIMIT_PLUS)

    def _bounds(self, check: MdDef, minus: MdDef, plus: MdDef) -> dict[str, tuple[float, float]]:
        return {name: (axis.config.md.float(minus), axis.config.md.float(plus)) for name, axis in self._axes.items()
                if not axis.is_spindle and axis.config.md.bool(check)}

    def apply(self, command: StrokeCommand) -> None:
        """G22 / G23 of a block: the corners set the box of the axes they name (if checked)."""
        self.active_2 = command.on
        for axis, (first, second) in command.corners.items():
            if axis in self._bounds_2:
                self._bounds_2[axis] = (min(first, second), max(first, second))

    def areas(self) -> list[StrokeArea]:
        """The areas in force: of the axes whose positions are exact."""
        if not (self.active_2 and self._bounds_2) and not self._bounds_3:
            return []
        exact = {name for name, axis in self._axes.items() if axis.software_limits_active}
        areas = []
        if self.active_2:
            bounds = {axis: limits for axis, limits in self._bounds_2.items() if axis in exact}
            if bounds:
                areas.append(StrokeArea(2, bounds, self._inside_forbidden_2))
        bounds = {axis: limits for axis, limits in self._bounds_3.items() if axis in exact}
        if bounds:
            areas.append(StrokeArea(3, bounds, True))
        return areas

    def path_stop(self, at: Callable[[float], dict[str, float]], linear: bool,
                  to_check: Callable[[int, dict[str, float]], dict[str, float]]) -> StrokeStop | None:
        """Where the path ``at(fraction)`` (machine positions) enters a forbidden area first; None
        if it does not.  ``linear``: straight in check coordinates, found exactly; else sampled
        and refined by bisection."""
        stops = []
        for area in self.areas():
            def checked(fraction: float, area: StrokeArea = area) -> dict[str, float]:
                return _completed(to_check(area.number, at(fraction)), self._axes)
            start = checked(0.0)
            if area.forbidden(start):
                stops.append((0.0, area, start, _rate(start, checked(1.0))))
                continue
            fraction = _linear_entry(area, start, checked(1.0)) if linear else _curved_entry(area, checked)
            if fraction is not None:
                before = checked(max(fraction - 1e-6, 0.0))
                stops.append((fraction, area, checked(fraction), _rate(before, checked(min(fraction + 1e-6, 1.0)))))
        if not stops:
            return None
        fraction, area, point, rate = min(stops, key=lambda stop: stop[0])
        axis, direction = area.reached_axis(point, rate)
        return StrokeStop(fraction, area.alarm_number(direction), axis)

    def jog_room(self, travel: Point, to_check: Callable[[int, dict[str, float]], dict[str, float]],
                 ) -> tuple[float, float, int, int, str] | None:
        """How far (minus, plus, in units of the jogged axis's travel; ``travel`` = the machine
        travel of the axes per unit) JOG may go from the setpoints, with the alarm numbers and the
        axis at either end; None without an area in force."""
        areas = self.areas()
        if not areas:
            return None  # most machines, most of the time: nothing to keep JOG from
        setpoints = {name: axis.setpoint for name, axis in self._axes.items()}
        moved = {name: setpoints[name] + travel.get(name, 0.0) for name in setpoints}
        low, high, low_number, high_number, low_axis, high_axis = -math.inf, math.inf, 0, 0, "", ""
        for area in areas:
            point = _completed(to_check(area.number, dict(setpoints)), self._axes)
            rate = _rate(point, _completed(to_check(area.number, moved), self._axes))
            if not any(rate.get(axis, 0.0) for axis in area.bounds):
                continue
            minus, plus = area.room(point, rate)
            if plus < high:
                axis, _ = area.reached_axis({k: v + plus * rate.get(k, 0.0) for k, v in point.items()}, rate)
                high, high_number, high_axis = plus, area.alarm_number(rate[axis]), axis
            if minus > low:
                axis, _ = area.reached_axis({k: v + minus * rate.get(k, 0.0) for k, v in point.items()}, rate)
                low, low_number, low_axis = minus, area.alarm_number(-rate[axis]), axis
        if math.isinf(low) and math.isinf(high):
            return None
        return low, high, low_number, high_number, low_axis or high_axis


def _completed(point: dict[str, float], axes: Mapping[str, MachineAxis]) -> dict[str, float]:
    """``point`` with the setpoints of the axes it does not name."""
    return {**{name: axis.setpoint for name, axis in axes.items()}, **point}


def _rate(start: Point, end: Point) -> dict[str, float]:
    return {axis: end[axis] - start[axis] for axis in start}


def _linear_entry(area: StrokeArea, start: Point, end: Point) -> float | None:
    _, plus = area.room(start, _rate(start, end))
    return plus if plus < 1.0 else None


def _curved_entry(area: StrokeArea, checked: Callable[[float], dict[str, float]]) -> float | None:
    previous = 0.0
    for index in range(1, PATH_SAMPLES + 1):
        fraction = index / PATH_SAMPLES
        if area.forbidden(checked(fraction)):
            allowed, forbidden = previous, fraction
            for _ in range(50):
                middle = (allowed + forbidden) / 2.0
                allowed, forbidden = (allowed, middle) if area.forbidden(checked(middle)) else (middle, forbidden)
            return allowed
        previous = fraction
    return None
