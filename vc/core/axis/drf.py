"""The DRF offset of one machine axis: a handwheel's travel overlaid on the path in AUTO and MDA
(DB21.DBX0.3; seed 003 §16.13.3, L36409-36506).

With DRF selected, the handwheel's pulses give a distance the axis travels at its DRF velocity
(JOG velocity MD32020 x MD32090), braking to land on its end point, on top of whatever the path
does; the distance travelled is the DRF offset, an offset in the machine coordinate system the
NC does not show (L36423).  It outlives reset and program end (L36426); DRFOF deletes it without
moving the axis (L36470-36490).  Feed stop, feed disable or a drive not ready brake the travel and
drop its rest [control, as the handwheel in JOG].

``DrfOffset`` keeps the offset and its travel; the axis adds each cycle's step to its overlay.
"""

from __future__ import annotations

import math

from vc.core.axis.motion import ramp, stopping_velocity

_TINY = 1e-9


class DrfOffset:
    """The DRF offset of one axis and the distance of it still to travel."""

    def __init__(self, dt: float):
        self._dt = dt
        self.offset = 0.0  # the handwheel's offset in the MCS, overlaid on the path
        self.rest = 0.0  # the distance still to travel
        self.velocity = 0.0

    @property
    def moving(self) -> bool:
        return bool(self.rest or self.velocity)

    def add_travel(self, distance: float) -> None:
        """Handwheel pulses with DRF: the DRF offset grows by ``distance`` (sign = direction)."""
        self.rest += distance

    def step(self, stopped: bool, accel: float, drf_velocity: float) -> float:
        """One IPO cycle of the travel at ``drf_velocity``, ramped with ``accel``: the distance the
        offset moves (``velocity`` is its velocity now); ``stopped`` brakes it and drops the rest."""
        rest = self.rest
        if stopped:
            self.rest = rest = 0.0
        target = math.copysign(min(drf_velocity, stopping_velocity(abs(rest), accel, self._dt)), rest) \
            if rest else 0.0
        velocity = ramp(self.velocity, target, accel, self._dt)
        step = velocity * self._dt
        if rest and (rest - step) * rest <= _TINY * abs(rest):
            step, velocity = rest, 0.0  # land exactly on the end point
        self.rest = rest - step if rest else 0.0
        self.velocity = velocity
        self.offset += step
        return step

    def clear(self) -> None:
        """DRFOF: no offset and nothing left to travel."""
        self.offset = self.rest = 0.0
        self.velocity = 0.0
