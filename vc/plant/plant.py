"""The machine plant: switches along the axes, spindle gearboxes and chucks and the drive line-up,
wired to the PLC.

The plant sees the true (physical) slide positions and the motor speeds and drives the
plant-owned inputs of the I/O list: reference cams (1 while the slide stands on the cam),
hardware limit switches (normally closed: 0 while actuated), the gear stage sensors of
each spindle gearbox, which the PLC shifts with its actuator outputs (vc/plant/gearbox.py),
the end-position sensors of each spindle chuck, which the PLC clamps and opens with the
solenoids of its valve (vc/plant/chuck.py; the hydraulics have pressure while the drive line-up
is ready) - a part clamped in two chucks ties their spindles together and, twisted, blocks the
counter spindle's drive (vc/plant/workpiece.py, reported by ``blocked_drives``) - and
``Drives.ready``, which follows the PLC's ``Drives.on`` output after the infeed's switch-on
delay while the line supply is there and the DC link (if the machine has one) is precharged
(a mains failure takes it at once).  The machine's devices besides the axes (the machine file's
``plant:``) are driven the same way: a lathe's tool turret (vc/plant/turret.py), a machining
centre's tool magazine and changer arm (vc/plant/tool_changer.py), the coolant pump with its
pressure switch (vc/plant/coolant.py); a machine without them pays nothing for them.  Operator inputs
(panel keys, the emergency-stop button, the guard door switch) are not the plant's: a person (a scenario) sets them.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Protocol

from interfaces.image import ProcessImage
from interfaces.signals import SignalRef
from vc.config.model import AxisConfig, MachineConfig
from vc.plant.axis_magazine import AxisMagazine
from vc.plant.chuck import Chuck
from vc.plant.clamp import AxisClamp
from vc.plant.coolant import Coolant
from vc.plant.gearbox import Gearbox
from vc.plant.holding_brake import HoldingBrake
from vc.plant.tailstock import Tailstock
from vc.plant.tool_changer import ToolChanger
from vc.plant.turret import Turret
from vc.plant.workpiece import ClampedPart

DRIVE_READY_DELAY_S = 0.1  # infeed switch-on to "ready", a typical line module figure
# The operator's side as it stands at power-on: e-stop button released, override switches at 100 %,
# guard door closed.
PANEL_AT_POWER_ON = {"EStop.chainOk": 1, "MCP.feedOverride": 100, "MCP.rapidOverride": 100,
                     "MCP.spindleOverride": 100, "Door.closed": 1}


class Slide(Protocol):
    """Anything with the true position and speed of a slide or spindle (the NC core's machine axis)."""

    physical: float
    velocity: float  # signed, per second: mm/s, or deg/s on a rotary axis and a spindle


@dataclass(slots=True)
class _AxisSwitches:
    cam: tuple[SignalRef, float, float] | None
    limit_minus: tuple[SignalRef, float] | None
    limit_plus: tuple[SignalRef, float] | None
    last_position: float | None = None
    states: int = -1  # cam, minus, plus as last written (bits 0, 1, 2; -1: not yet)


class Device(Protocol):
    """A device of the machine besides its axes: it reads its outputs, moves, writes its sensors."""

    name: str  # its I/O prefix, which clear_faults names

    def step(self, io: ProcessImage) -> bool:
        """One IPO cycle; True while something of it still moves (False: it rests until an output
        changes)."""
    def write_sensors(self, io: ProcessImage) -> None: ...
    def forget_sensors(self) -> None: ...
    def inject(self, kind: str) -> None: ...
    def repair(self) -> None: ...


class ChargedLink(Protocol):
    """The drive line-up's DC link as the infeed's ready signal sees it (vc/core/retraction/dc_link.py)."""

    @property
    def charged(self) -> bool:
        """The precharge is done: the link is on the supply."""


class Plant:
    def __init__(self, machine: MachineConfig, ipo_cycle_us: int, slides: Sequence[Slide],
                 gear_stages: Mapping[str, int] | None = None, chucks_clamped: Mapping[str, bool] | None = None,
                 dc_link: ChargedLink | None = None, turret_station: int | None = None):
        """``gear_stages`` are the stages in mesh at power-on by spindle and ``chucks_clamped``
        the chucks' states, where they differ from the machine file's (a gearbox keeps its stage
        and a chuck its part while the machine is switched off), as is ``turret_station``;
        ``dc_link`` the line-up's link, whose precharge holds ``Drives.ready`` back."""
        self._io = machine.plant_io
        self._slides = list(slides)  # in machine axis order
        self._axes = [self._switches_of(axis) for axis in machine.axes]
        self._switched = list(zip(self._axes, self._slides, strict=True))  # paired once, walked every cycle
        kept = gear_stages or {}
        self._gearboxes = [
            (gearbox, self._slides[index])
            for index, axis in enumerate(machine.axes)
            if (gearbox := Gearbox.of_axis(axis, self._io, ipo_cycle_us, kept.get(axis.name))) is not None
        ]
        clamped = chucks_clamped or {}
        self._chucks = [chuck for axis in machine.axes
                        if (chuck := Chuck.of_axis(axis, self._io, ipo_cycle_us, clamped.get(axis.name))) is not None]
        # a part can sit between the chucks of two spindles: the first chucked spindle is the main
        # spindle, each later one a counter spindle taking the part over from it
        slide_of = {axis.name: slide for axis, slide in zip(machine.axes, self._slides, strict=True)}
        self._parts = [ClampedPart(self._chucks[0], counter, slide_of[self._chucks[0].axis], slide_of[counter.axis])
                       for counter in self._chucks[1:]]
        self.blocked_drives: list[str] = []  # spindles whose drive a twisted part blocked in this cycle
        ready = self._io.by_name("Drives.ready")
        on = self._io.by_name("Drives.on")
        self._drives_ready = ready.ref() if ready else None
        self._drives_on = on.ref() if on else None
        self._ready_delay_cycles = max(1, round(DRIVE_READY_DELAY_S * 1_000_000 / ipo_cycle_us))
        self._on_cycles = 0
        self.supply_on = True  # the line supply of the infeed
        self._dc_link = dc_link
        self._ready: int | None = None
        devices = machine.plant
        self.turret = Turret(devices.turret, self._io, ipo_cycle_us, turret_station) if devices.turret else None
        self.tool_changer = ToolChanger(devices.tool_changer, self._io, ipo_cycle_us) \
            if devices.tool_changer else None
        coolant = Coolant(devices.coolant, self._io, ipo_cycle_us) if devices.coolant else None
        # the tailstock's part is the fixed stop of its quill axis: the composed machine hands it to the axis
        self.tailstock = Tailstock(devices.tailstock, self._io) if devices.tailstock else None
        # a magazine turned by an NC axis: its pocket sensor follows the axis's slide
        self.axis_magazine = AxisMagazine(devices.axis_magazine, self._io, ipo_cycle_us,
                                          slide_of[devices.axis_magazine.axis]) if devices.axis_magazine else None
        # the clamp holds its axis's slide: the composed machine hands it to the axis as well
        self.clamp = AxisClamp(devices.clamp, self._io, ipo_cycle_us) if devices.clamp else None
        # the holding brake holds its axis's slide and follows the drive: the composed machine fits it to the axis
        self.holding_brake = HoldingBrake(devices.holding_brake, ipo_cycle_us) if devices.holding_brake else None
        self._devices: list[Device] = [device for device in (self.turret, self.tool_changer, coolant, self.tailstock,
                                                             self.axis_magazine, self.clamp, self.holding_brake)
                                       if device is not None]
        # the devices rest until the PLC changes an output or one of them still moves
        self._outputs_seen = b""
        self._devices_moving = True

    def _switches_of(self, axis: AxisConfig) -> _AxisSwitches:
        def wired(function: str) -> SignalRef | None:
            point = self._io.by_name(f"{axis.name}.{function}")
            return point.ref() if point else None

        plant = axis.plant
        cam_ref = wired("refCam")
        minus_ref = wired("hwLimitMinus")
        plus_ref = wired("hwLimitPlus")
        return _AxisSwitches(
            cam=(cam_ref, plant.ref_cam[0], plant.ref_cam[1]) if cam_ref and plant.ref_cam else None,
            limit_minus=(minus_ref, plant.hw_limit_minus)
            if minus_ref and plant.hw_limit_minus is not None else None,
            limit_plus=(plus_ref, plant.hw_limit_plus) if plus_ref and plant.hw_limit_plus is not None else None,
        )

    def power_on(self, io: ProcessImage) -> None:
        """The panel's initial state and every plant input for the positions at power-on."""
        for name, value in PANEL_AT_POWER_ON.items():
            point = self._io.by_name(name)
            if point is not None:
                io.write(point.ref(), value)
        self.refresh(io)

    def refresh(self, io: ProcessImage) -> None:
        """Write every plant-owned input anew (e.g. after a force on one of them ended)."""
        for switches in self._axes:
            switches.last_position = None
            switches.states = -1
        self._ready = None
        self._switches(io)
        for gearbox, _ in self._gearboxes:
            gearbox.forget_sensors()
            gearbox.write_sensors(io)
        for chuck in self._chucks:
            chuck.forget_sensors()
            chuck.write_sensors(io)
        for device in self._devices:
            device.forget_sensors()
            device.write_sensors(io)
        self._devices_moving = True
        self._drive_line_up(io)

    def gear_stages(self) -> dict[str, int]:
        """The stage in mesh of every spindle gearbox (0 = neutral), e.g. to keep it over a power cycle."""
        return {gearbox.axis: gearbox.engaged for gearbox, _ in self._gearboxes}

    def chucks_clamped(self) -> dict[str, bool]:
        """Whether each spindle chuck is clamped (a chuck between its end positions counts as open)."""
        return {chuck.axis: chuck.clamped for chuck in self._chucks}

    def step(self, io: ProcessImage) -> None:
        """Update the plant inputs for one IPO cycle."""
        self._switches(io)
        for gearbox, motor in self._gearboxes:
            gearbox.step(io, motor.velocity)
        self._drive_line_up(io)
        # the hydraulic unit runs with the drive line-up; a machine without one always has pressure
        pressure = self._drives_ready is None or self._ready == 1
        for chuck in self._chucks:
            chuck.step(io, pressure)
        if self._parts:
            self._parts_cycle()
        if self._devices:
            self._devices_cycle(io)
        if self.tailstock is not None:
            self.tailstock.write_sensors(io)  # the quill moves with its axis, not with an output
        if self.axis_magazine is not None:
            self.axis_magazine.write_sensors(io)  # the pocket sensor follows the axis
        if self.holding_brake is not None:
            self.holding_brake.cycle()  # the brake follows the drive's order (DB31.DBX20.5), not an output

    def _parts_cycle(self) -> None:
        """The parts held between two chucks; a new list only in the (rare) cycle a drive is blocked."""
        blocked: list[str] | None = None
        for part in self._parts:
            if part.step():
                if blocked is None:
                    blocked = []
                blocked.append(part.counter.axis)
        if blocked is not None:
            self.blocked_drives = blocked
        elif self.blocked_drives:
            self.blocked_drives = []

    def _devices_cycle(self, io: ProcessImage) -> None:
        """The devices' cycle, only when an output changed or one of them still moves: a machine
        standing with its turret locked pays one comparison of its outputs."""
        outputs = io.areas["Q"]
        if not self._devices_moving and outputs == self._outputs_seen:
            return
        self._outputs_seen = bytes(outputs)
        moving = False
        for device in self._devices:
            if device.step(io):
                moving = True
        self._devices_moving = moving

    # ------------------------------------------------------------------ faults of the devices
    def device_names(self) -> list[str]:
        """The devices a fault can be injected into and repaired (their I/O prefixes)."""
        names = [device.name for device in self._devices]
        return [*names, "ToolArm"] if self.tool_changer is not None else names

    def inject(self, device: str, kind: str) -> None:
        """A fault of a device (its FAULTS), until :meth:`repair`."""
        self._device(device).inject(kind)
        self._devices_moving = True

    def repair(self, device: str) -> None:
        self._device(device).repair()
        self._devices_moving = True

    def _device(self, name: str) -> Device:
        wanted = "Magazine" if name == "ToolArm" else name
        for device in self._devices:
            if device.name == wanted:
                return device
        raise KeyError(f"this machine has no {name} (its devices: {', '.join(self.device_names()) or 'none'})")

    def _switches(self, io: ProcessImage) -> None:
        for switches, slide in self._switched:
            position = slide.physical
            if position == switches.last_position:
                continue
            switches.last_position = position
            cam = switches.cam
            minus = switches.limit_minus
            plus = switches.limit_plus
            cam_state = 1 if cam is not None and cam[1] <= position <= cam[2] else 0
            minus_state = 0 if minus is not None and position <= minus[1] else 1
            plus_state = 0 if plus is not None and position >= plus[1] else 1
            states = cam_state | minus_state << 1 | plus_state << 2  # one number: compared without building
            if states == switches.states:
                continue
            switches.states = states
            if cam is not None:
                io.write(cam[0], cam_state)
            if minus is not None:
                io.write(minus[0], minus_state)
            if plus is not None:
                io.write(plus[0], plus_state)

    def _drive_line_up(self, io: ProcessImage) -> None:
        if self._drives_ready is None:
            return
        on = self._drives_on
        switched_on = True if on is None else bool(io.areas["Q"][on.address.byte] >> on.address.bit & 1)
        self._on_cycles = min(self._on_cycles + 1, self._ready_delay_cycles) if switched_on and self.supply_on else 0
        charged = self._dc_link is None or self._dc_link.charged
        ready = 1 if self._on_cycles >= self._ready_delay_cycles and charged else 0
        if ready != self._ready:
            self._ready = ready
            io.write(self._drives_ready, ready)
