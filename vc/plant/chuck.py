"""The hydraulic chuck of a spindle: a valve from the PLC, end-position sensors to the PLC.

The chuck cylinder hangs on a closed-centre valve with two solenoids, outputs Q the PLC
holds on: ``<spindle>.chuckClose`` clamps, ``<spindle>.chuckRelease`` opens.  With neither
solenoid on (or, pushed both ways, with both) the valve blocks the cylinder and the chuck
holds where it stands.  A stroke takes ``travel_time``; the plant reports the end positions
on ``<spindle>.chuckClosed`` (clamped) and ``<spindle>.chuckOpen`` (fully open), inputs I
written only where wired.  Between the end positions both sensors read 0.

The cylinder moves only with hydraulic pressure.  The hydraulic unit runs with the drive
line-up (``Drives.ready``; a machine without that input has pressure all the time), and
without pressure the cylinder's check valves hold the piston where it stands: a part stays
clamped through a power failure, while the PLC starts up with its outputs at 0 and under a
PLC program that does not know the chucks::

    CLAMPED ──chuckRelease alone, pressure──▶ UNCLAMPING ──travel_time──▶ OPEN
    OPEN ──chuckClose alone, pressure──▶ CLAMPING ──travel_time──▶ CLAMPED
    CLAMPING / UNCLAMPING ──the other solenoid alone──▶ back from where the piston stands
    any ──neither or both solenoids, or no pressure──▶ the piston stands

Time is counted in IPO cycles, so the model is deterministic; it does no I/O.
"""

from __future__ import annotations

from dataclasses import dataclass

from interfaces.image import ProcessImage
from interfaces.plant_io import PlantIoMap, chuck_close, chuck_closed, chuck_open, chuck_release
from interfaces.signals import SignalRef
from vc.config.model import AxisConfig


@dataclass(slots=True)
class Chuck:
    """One spindle's chuck: its I/O, its stroke time in IPO cycles and where the piston stands."""

    axis: str
    clamp_solenoid: tuple[int, int]  # (Q byte, bit mask) of chuckClose
    release_solenoid: tuple[int, int]  # (Q byte, bit mask) of chuckRelease
    closed_sensor: SignalRef | None
    open_sensor: SignalRef | None
    travel_cycles: int  # IPO cycles of a full stroke
    stroke: int  # 0 = fully open .. travel_cycles = clamped
    _sensors_written_for: int = -1  # clamped (bit 0) and open (bit 1) as last written (-1: not yet)

    @classmethod
    def of_axis(cls, axis: AxisConfig, io_map: PlantIoMap, ipo_cycle_us: int,
                clamped: bool | None = None) -> Chuck | None:
        """The chuck of ``axis`` (None without one); ``clamped`` overrides the power-on state."""
        config = axis.plant.chuck
        clamp = io_map.by_name(chuck_close(axis.name))
        release = io_map.by_name(chuck_release(axis.name))
        if config is None or clamp is None or release is None:
            return None

        def wired(name: str) -> SignalRef | None:
            point = io_map.by_name(name)
            return point.ref() if point else None

        travel_cycles = max(1, round(config.travel_time_s * 1_000_000 / ipo_cycle_us))
        closed = config.closed_at_power_on if clamped is None else clamped
        return cls(
            axis=axis.name,
            clamp_solenoid=(clamp.address.byte, 1 << clamp.address.bit),
            release_solenoid=(release.address.byte, 1 << release.address.bit),
            closed_sensor=wired(chuck_closed(axis.name)),
            open_sensor=wired(chuck_open(axis.name)),
            travel_cycles=travel_cycles,
            stroke=travel_cycles if closed else 0,
        )

    @property
    def clamped(self) -> bool:
        return self.stroke == self.travel_cycles

    @property
    def open(self) -> bool:
        return self.stroke == 0

    def step(self, io: ProcessImage, pressure: bool) -> None:
        """One IPO cycle: read the solenoids, move the piston, write the sensors."""
        if pressure:
            outputs = io.areas["Q"]
            clamp = bool(outputs[self.clamp_solenoid[0]] & self.clamp_solenoid[1])
            release = bool(outputs[self.release_solenoid[0]] & self.release_solenoid[1])
            if clamp and not release:
                self.stroke = min(self.stroke + 1, self.travel_cycles)
            elif release and not clamp:
                self.stroke = max(self.stroke - 1, 0)
        self.write_sensors(io)

    def write_sensors(self, io: ProcessImage) -> None:
        """The end-position sensors for where the piston stands (only those wired)."""
        state = self.clamped | self.open << 1  # one number: compared without building anything
        if state == self._sensors_written_for:
            return
        self._sensors_written_for = state
        if self.closed_sensor is not None:
            io.write(self.closed_sensor, 1 if self.clamped else 0)
        if self.open_sensor is not None:
            io.write(self.open_sensor, 1 if self.open else 0)

    def forget_sensors(self) -> None:
        """Write the sensors anew at the next :meth:`write_sensors` (after a force on one ended)."""
        self._sensors_written_for = -1
