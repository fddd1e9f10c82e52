"""The load gearbox of a spindle: shift actuators from the PLC, stage sensors to the PLC.

The gearbox sits between the spindle motor and the spindle.  The PLC moves it into gear
stage n by holding the shift actuator ``<spindle>.gearShift<n>`` (a valve, output Q) on; the
plant reports the stage in mesh on ``<spindle>.gearEngaged<n>`` and "no stage in mesh" on
``<spindle>.gearNeutral`` (inputs I, written only where wired).

The teeth of the new stage find their gaps only while the motor turns: that is why the NC
oscillates the spindle during a gear change (seed 003 L19259-19325, "the load gearbox may
now be disengaged ... oscillation by NC or PLC").  The harness's rule for it::

    ENGAGED(k) ──actuator N (N != k) on alone──▶ SHIFTING(N) in neutral at once
    SHIFTING(N) ──motor turned for shift_time──▶ ENGAGED(N)
    SHIFTING(N) ──motor stands──▶ SHIFTING(N): tooth on tooth, no progress
    SHIFTING(N) ──two or more actuators on──▶ SHIFTING(N): the fork is pushed both ways, stalls
    SHIFTING(N) ──actuator released──▶ NEUTRAL: the turning time counted so far is lost
    SHIFTING(N) ──actuator M (M != N) on alone──▶ SHIFTING(M), counting from the start
    ENGAGED(k) / NEUTRAL ──no actuator on──▶ unchanged

"The motor turns" means |speed| >= 1 rev/min.  Time is counted in IPO cycles, so the model
is deterministic; it does no I/O.
"""

from __future__ import annotations

from dataclasses import dataclass

from interfaces.image import ProcessImage
from interfaces.plant_io import PlantIoMap, gear_engaged, gear_neutral, gear_shift
from interfaces.signals import SignalRef
from vc.config.model import AxisConfig

# 1 rev/min = 6 deg/s: slower than that the teeth of the new stage do not find their gaps.
MESHING_SPEED_DEG_S = 6.0


@dataclass(slots=True)
class Gearbox:
    """One spindle's gearbox: its I/O, its shift time in IPO cycles and its mechanical state."""

    axis: str
    actuators: tuple[tuple[int, int, int], ...]  # (stage, Q byte, bit mask) of each wired gearShift<stage>
    engaged_sensors: tuple[SignalRef | None, ...]  # gearEngaged1 .. gearEngaged<stages>
    neutral_sensor: SignalRef | None
    shift_cycles: int  # IPO cycles the motor must turn while the actuator pushes
    engaged: int  # the stage in mesh, 0 = neutral
    target: int = 0  # the stage a shift in progress moves to, 0 = no shift in progress
    meshing_cycles: int = 0  # IPO cycles turned so far towards ``target``
    _sensors_written_for: int | None = None  # the stage the sensors were last written for

    @classmethod
    def of_axis(cls, axis: AxisConfig, io_map: PlantIoMap, ipo_cycle_us: int,
                engaged: int | None = None) -> Gearbox | None:
        """The gearbox of ``axis`` (None without one); ``engaged`` overrides the power-on stage."""
        config = axis.plant.gearbox
        if config is None:
            return None

        def wired(name: str) -> SignalRef | None:
            point = io_map.by_name(name)
            return point.ref() if point else None

        stages = range(1, config.stages + 1)
        actuators = [(stage, wired(gear_shift(axis.name, stage))) for stage in stages]
        return cls(
            axis=axis.name,
            actuators=tuple((stage, ref.address.byte, 1 << ref.address.bit) for stage, ref in actuators if ref),
            engaged_sensors=tuple(wired(gear_engaged(axis.name, stage)) for stage in stages),
            neutral_sensor=wired(gear_neutral(axis.name)),
            shift_cycles=max(1, round(config.shift_time_s * 1_000_000 / ipo_cycle_us)),
            engaged=config.engaged_at_power_on if engaged is None else engaged,
        )

    def step(self, io: ProcessImage, motor_velocity: float) -> None:
        """One IPO cycle: read the actuators, move the sliding gear, write the sensors."""
        outputs = io.areas["Q"]
        pushed = [stage for stage, byte, mask in self.actuators if outputs[byte] & mask]
        if not pushed and not self.target:
            return  # no actuator and no shift in progress: the stage stays, and so do the sensors
        self._shift(pushed, abs(motor_velocity) >= MESHING_SPEED_DEG_S)
        self.write_sensors(io)

    def _shift(self, pushed: list[int], motor_turns: bool) -> None:
        if len(pushed) > 1:
            return  # pushed into two stages at once: the shift fork does not move
        if not pushed:
            self.target = 0  # released: an unfinished shift stays in neutral, its meshing is lost
            self.meshing_cycles = 0
            return
        (stage,) = pushed
        if stage == self.engaged:
            return
        if stage != self.target:
            self.engaged = 0  # the sliding gear leaves its stage at once
            self.target = stage
            self.meshing_cycles = 0
        if not motor_turns:
            return  # tooth on tooth: the teeth find no gap while the motor stands
        self.meshing_cycles += 1
        if self.meshing_cycles >= self.shift_cycles:
            self.engaged = stage
            self.target = 0
            self.meshing_cycles = 0

    def write_sensors(self, io: ProcessImage) -> None:
        """The stage sensors and the neutral sensor for the stage in mesh (only those wired)."""
        if self._sensors_written_for == self.engaged:
            return
        self._sensors_written_for = self.engaged
        for stage, sensor in enumerate(self.engaged_sensors, start=1):
            if sensor is not None:
                io.write(sensor, 1 if stage == self.engaged else 0)
        if self.neutral_sensor is not None:
            io.write(self.neutral_sensor, 1 if self.engaged == 0 else 0)

    def forget_sensors(self) -> None:
        """Write every sensor anew at the next :meth:`write_sensors` (after a force on one ended)."""
        self._sensors_written_for = None
