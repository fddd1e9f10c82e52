"""NC, plant and PLC in virtual lockstep: the simulation a scenario runs against.

Images and who writes them::

    nck.image   the NC's data blocks: it writes NC->PLC bytes at the end of each IPO cycle
    interface   the wire between NC and PLC: the PLC (or a scenario acting as PLC)
                writes PLC->NC bytes; NC->PLC bytes are copied in before every PLC scan
    plant_io    plant inputs I (plant, operator) and outputs Q (PLC)

One IPO cycle: NC step (reads ``interface``) -> plant step (reads physical positions and
Q, writes I) -> every ``plc_cycle_ipo`` cycles a PLC scan.  Forces are applied where
their owner writes, so a forced value is what the reader sees.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Protocol

from interfaces.catalog import load_catalog
from interfaces.image import ProcessImage, RangeCopy, Value
from interfaces.links.errors import LinkError
from interfaces.links.inprocess import InProcessConnector
from interfaces.plant_io import PointOwner
from interfaces.plc import CyclicPlc, PlcConnector, PlcEnvironment, SoftPlc
from interfaces.signals import NCK_INSTANCE, Direction, SignalRef
from vc.config.machine_data import MachineData
from vc.config.md_dictionary import BY_NUMBER
from vc.config.model import MachineConfig, machine_ipo_cycle_us
from vc.core.alarms import Alarm
from vc.core.channel.channel import Channel
from vc.core.nc_memory import NcMemory
from vc.core.nck.nck import Nck
from vc.plant.plant import Plant
from vc.simulation.commissioning import commissioning_of
from vc.simulation.link_faults import FaultInjectable, LinkFault, LinkFaultKind
from vc.simulation.observables import (
    AXIS_QUANTITIES,
    CHANNEL_QUANTITIES,
    COUPLING_QUANTITY_MEANINGS,
    DEVICE_FAULTS,
    FAULTS,
    MAINS,
    NCK_QUANTITIES,
    StepRefused,
)
from vc.simulation.published import AlarmList, NcFunction, StateView


class Pacer(Protocol):
    def wait_next_cycle(self) -> None:
        """Return when the next IPO cycle may start (real time); the links are served meanwhile."""


class Simulation:
    def __init__(self, machine: MachineConfig, plc: str | None = "basic_machine",
                 connector: PlcConnector | None = None, pacer: Pacer | None = None):
        """``plc`` names the PLC program (None: the scenario acts as the PLC); ``connector`` says
        where it runs (default: in this process, in lockstep); ``pacer`` ties the IPO cycles to
        the wall clock (default: as fast as possible)."""
        self._catalog = load_catalog()
        self.machine = machine
        self.plant_io = machine.plant_io
        self.plc_name = plc
        self.plc_period = machine.plc_cycle_ipo
        self.connector: PlcConnector = connector or InProcessConnector()
        self.pacer = pacer
        self._cycles_before = 0  # IPO cycles of earlier power-ons and of the time switched off
        self._forces: dict[SignalRef, Value] = {}
        self._underlying: dict[SignalRef, Value] = {}  # what the owner wrote while a force held
        self._forces_by_direction: dict[Direction, list[tuple[SignalRef, Value]]] = {d: [] for d in Direction}
        self.plant_image = ProcessImage(machine.plant_io.area_sizes())
        ready = machine.plant_io.by_name("Drives.ready")
        self._drives_ready = ready.ref() if ready is not None else None
        self._power_on(NcMemory(), None, None, None, first=True)

    def _power_on(self, memory: NcMemory, physical: dict[str, float] | None,
                  gear_stages: dict[str, int] | None, chucks_clamped: dict[str, bool] | None, first: bool,
                  turret_station: int | None = None) -> None:
        """The control, the PLC and the plant start: a fresh NC with the kept memory, a PLC
        restart, the slides where they stand, the gearboxes in the stages they are in, the
        chucks as they hold, the turret at its station, the panel as the operator left it."""
        machine = self.machine
        self.nck = Nck(machine, self._catalog, memory, physical)
        self.catalog = self.nck.catalog
        self.interface = ProcessImage(self.catalog.area_sizes)
        self._nc_outputs = RangeCopy(self.interface, self.nck.image, self.nck.nc_to_plc_ranges)
        self.plant = Plant(machine, self.nck.cycle_us, self.nck.axes, gear_stages, chucks_clamped, self.nck.dc_link,
                           turret_station)
        tailstock = self.plant.tailstock
        if tailstock is not None:
            self.nck.axes_by_name[tailstock.axis].obstacle = tailstock  # the part is the quill's fixed stop
        clamp = self.plant.clamp
        if clamp is not None:
            self.nck.axes_by_name[clamp.axis].obstacle = clamp  # closed, it holds the slide
        brake = self.plant.holding_brake
        if brake is not None:
            braked = self.nck.axes_by_name[brake.axis]
            brake.fit(braked, braked.fit_holding_brake(brake))  # engaged, it holds the slide; the drive switches it
        self.plc: SoftPlc | None = None
        if self.plc_name is not None:
            scan_time = self.plc_period * self.nck.cycle_us / 1_000_000
            environment = PlcEnvironment(self.catalog, machine.plant_io, scan_time, machine.plc_parameters,
                                         machine.name, self.nck.cycle_us, self.plc_period,
                                         commissioning_of(machine, self.catalog))
            self.plc = self.connector.connect(environment, self.plc_name)
        self._cyclic: CyclicPlc | None = self.plc if isinstance(self.plc, CyclicPlc) else None
        self._observed = ProcessImage({**self.catalog.area_sizes, **machine.plant_io.area_sizes()})
        self._observed_cycle = -1
        if first:
            self.plant.power_on(self.plant_image)
        else:
            self.plant_image.areas["Q"][:] = bytes(len(self.plant_image.areas["Q"]))  # outputs dropped
            self.plant.refresh(self.plant_image)
        for ref, value in self._forces.items():
            if ref.direction is not Direction.NC_TO_PLC:
                self._image_of(ref).write(ref, value)
        self._line_up_ready = -1  # what the NC was last told of the plant's Drives.ready
        self._line_up_seen_version = -1  # the plant image's version when it was last looked at
        self._tell_line_up()
        self._plc_cycle()

    def power_cycle(self, off_seconds: float = 1.0) -> None:
        """Switch the machine off and on again after ``off_seconds``: what the NC keeps (machine
        data it wrote, buffered positions) survives, the PLC restarts, the slides stay, and so
        do the gearboxes (a shift the PLC had not finished ends in neutral) and the chucks (a
        stroke the hydraulics had not finished counts as open)."""
        memory = self.nck.power_off()
        physical = self.nck.physical_positions()
        gear_stages = self.plant.gear_stages()
        chucks_clamped = self.plant.chucks_clamped()
        turret = self.plant.turret.station or None if self.plant.turret is not None else None
        self._cycles_before += self.nck.cycle + round(off_seconds * 1_000_000 / self.nck.cycle_us)
        self._power_on(memory, physical, gear_stages, chucks_clamped, first=False, turret_station=turret)

    # ------------------------------------------------------------------ time
    @property
    def cycle(self) -> int:
        return self._cycles_before + self.nck.cycle

    @property
    def ipo_cycle_us(self) -> int:
        return self.nck.cycle_us

    @property
    def ipo_cycle_s(self) -> float:
        return self.nck.cycle_us / 1_000_000

    @staticmethod
    def ipo_seconds(machine: MachineConfig) -> float:
        return machine_ipo_cycle_us(machine) / 1_000_000

    @property
    def time_s(self) -> float:
        return self.cycle * self.nck.cycle_us / 1_000_000

    def step(self, cycles: int = 1) -> None:
        nck, plant, interface, plant_image = self.nck, self.plant, self.interface, self.plant_image
        plant_forces = self._forces_by_direction[Direction.PLANT_TO_PLC]
        pacer, cyclic, plc_period = self.pacer, self._cyclic, self.plc_period
        for _ in range(cycles):
            if pacer is not None:
                pacer.wait_next_cycle()
            nck.step(interface)
            plant.step(plant_image)
            if plant.blocked_drives:
                for axis in plant.blocked_drives:
                    nck.drive_blocked(axis)
            if plant_forces:
                self._apply(plant_forces, plant_image)
            if plant_image.version != self._line_up_seen_version:
                self._tell_line_up()
            if nck.cycle % plc_period == 0:
                self._plc_cycle()
            elif cyclic is not None:
                self._link_cycle(cyclic)

    def _tell_line_up(self) -> None:
        """The drives learn whether their line-up is ready (DB31.DBX92.7) from the plant input
        ``Drives.ready`` as the plant (or a force) sets it; without that input it is always ready.
        Both write through ProcessImage.write: while the plant image's version stands, so does the
        input (``step`` asks only then)."""
        self._line_up_seen_version = self.plant_image.version
        ready = self._drives_ready
        state = 1 if ready is None else self.plant_image.areas["I"][ready.address.byte] >> ready.address.bit & 1
        if state != self._line_up_ready:
            self._line_up_ready = state
            self.nck.drive_line_up(bool(state))

    def _plc_cycle(self) -> None:
        """Interface update and one PLC scan (or, without a PLC, just the interface update), which
        the NC counts for the handshake of its auxiliary functions: every scan with a new sign of
        life (in lockstep each one; in real time those the PLC finished since the last exchange)."""
        self._refresh_plc_inputs()
        if self.plc is not None:
            life = self.plc.sign_of_life
            self.plc.scan(self.interface, self.plant_image)
            self.nck.plc_sign_of_life(self.plc.sign_of_life)
            self._apply_plc_forces()
            if self.plc.sign_of_life == life:
                return  # real time: the PLC has not finished a scan since the last exchange
        self.nck.plc_cycle_done()

    def _link_cycle(self, link: CyclicPlc) -> None:
        """An IPO cycle between two scans of a PLC whose link works every cycle (CAN): the NC's
        signals go out when the link's period is due, the PLC's arrive when they arrive."""
        cycle = self.nck.cycle
        if link.sends_at(cycle):
            self._refresh_plc_inputs()
        if link.ipo_cycle(cycle, self.interface, self.plant_image):
            self._apply_plc_forces()

    def _refresh_plc_inputs(self) -> None:
        """The NC-to-PLC bytes of the wire from the NC, forces applied."""
        self._nc_outputs.run()
        self._apply(self._forces_by_direction[Direction.NC_TO_PLC], self.interface)

    def _apply_plc_forces(self) -> None:
        self._apply(self._forces_by_direction[Direction.PLC_TO_NC], self.interface)
        self._apply(self._forces_by_direction[Direction.PLC_TO_PLANT], self.plant_image)

    # ------------------------------------------------------------------ signals
    def _image_of(self, ref: SignalRef) -> ProcessImage:
        return self.plant_image if ref.address.area in ("I", "Q") else self.interface

    def image_of(self, ref: SignalRef) -> ProcessImage:
        """The image that holds ``ref``'s value: the NC's for NC->PLC signals, the wire for
        PLC->NC signals, the plant's for I and Q.  Reading or writing there directly bypasses
        the forces (for a host that forces nothing and exchanges everything every step)."""
        return self.nck.image if ref.direction is Direction.NC_TO_PLC else self._image_of(ref)

    def read(self, ref: SignalRef) -> Value:
        if ref.direction is Direction.NC_TO_PLC:
            # most runs force nothing: no hash of the reference then
            forced = self._forces.get(ref) if self._forces else None
            return forced if forced is not None else self.nck.image.read(ref)
        return self._image_of(ref).read(ref)

    def write(self, ref: SignalRef, value: Value) -> None:
        if self._forces and ref in self._forces:
            self._underlying[ref] = value  # the force wins; the value applies when it is released
            return
        self.image_of(ref).write(ref, value)  # NC->PLC: a request of the operator panel (DB19)
        self._observed_cycle = -1

    def force(self, ref: SignalRef, value: Value) -> None:
        if ref not in self._forces and ref.direction is not Direction.NC_TO_PLC:
            self._underlying[ref] = self._image_of(ref).read(ref)
        self._forces[ref] = value
        self._rebuild_forces()
        if ref.direction is not Direction.NC_TO_PLC:
            self._image_of(ref).write(ref, value)
        self._observed_cycle = -1

    def release(self, ref: SignalRef) -> None:
        """End a force: the owner's value applies again (the plant's, the operator's, the PLC's)."""
        if self._forces.pop(ref, None) is None:
            return
        self._rebuild_forces()
        self._observed_cycle = -1
        underlying = self._underlying.pop(ref, None)
        point = self.plant_io.by_name(ref.name) if ref.direction is Direction.PLANT_TO_PLC else None
        if point is not None and point.owner is PointOwner.PLANT:
            self.plant.refresh(self.plant_image)
        elif underlying is not None:
            self._image_of(ref).write(ref, underlying)

    def forced(self) -> dict[SignalRef, Value]:
        """The signals forced now and their forced values (a copy: the operator page shows them)."""
        return dict(self._forces)

    def _rebuild_forces(self) -> None:
        for items in self._forces_by_direction.values():
            items.clear()
        for ref, value in self._forces.items():
            self._forces_by_direction[ref.direction].append((ref, value))

    @staticmethod
    def _apply(forces: list[tuple[SignalRef, Value]], image: ProcessImage) -> None:
        for ref, value in forces:
            image.write(ref, value)

    def image_areas(self) -> dict[str, bytearray]:
        """The interface as ``read`` shows it, byte by byte, for trace recording.

        NC->PLC bytes come from the NC (forces applied), PLC->NC bytes from the wire, I and Q
        from the plant image.  Composed once per cycle, only when someone asks.
        """
        observed = self._observed
        if self._observed_cycle != self.nck.cycle:
            self._observed_cycle = self.nck.cycle
            observed.copy_from(self.nck.image, self.nck.nc_to_plc_ranges)
            observed.copy_from(self.interface, self.nck.plc_to_nc_ranges)
            self._apply(self._forces_by_direction[Direction.NC_TO_PLC], observed)
            for key in ("I", "Q"):
                observed.areas[key][:] = self.plant_image.areas[key]
        return observed.areas

    # ------------------------------------------------------------------ axes, alarms, HMI
    def axis_quantity(self, axis: str, quantity: str) -> float:
        """``X1.position`` and the like; a channel's quantities (``CHAN1.toolTipX``) and the NCK's
        (``NC.dcLinkVoltage``) come this way too."""
        if axis == NCK_INSTANCE and quantity in NCK_QUANTITIES:
            dc_link = self.nck.dc_link
            return dc_link.voltage if dc_link is not None else 0.0
        channel = self.nck.channels_by_name.get(axis)
        if channel is not None:
            return self._channel_quantity(channel, quantity)
        item = self.nck.axes_by_name.get(axis)
        if item is None:
            raise KeyError(f"'{axis}' is neither an axis nor a channel of this machine")
        if quantity == "position":
            return item.shown(item.actual)
        if quantity == "setpoint":
            return item.shown(item.setpoint)
        if quantity == "velocity":
            return item.display_velocity
        if quantity == "followingError":
            return item.following_error
        if quantity == "physical":
            return item.physical
        if quantity == "programPosition":
            return self.nck.program_position(axis)
        if quantity == "drfOffset":
            return item.drf_offset
        if quantity in COUPLING_QUANTITY_MEANINGS:
            return self.nck.couplings.quantity(axis, quantity)
        raise KeyError(f"unknown axis quantity '{quantity}' (known: {', '.join(AXIS_QUANTITIES)})")

    @staticmethod
    def _channel_quantity(channel: Channel, quantity: str) -> float:
        if quantity == "liftfast":
            if channel.esr is not None:
                return channel.esr.liftfast
        elif quantity in ("tool", "toolPreselected", "toolOffset"):
            tools = channel.tools
            numbers = {"tool": tools.tool, "toolPreselected": tools.preselected, "toolOffset": tools.offset}
            return float(numbers[quantity])
        elif quantity in CHANNEL_QUANTITIES:  # CHAN1.toolTipX: the five-axis tool
            return channel.five_axis.quantity(quantity, channel.modal.five_axis)
        raise KeyError(f"unknown channel quantity '{quantity}' (known: {', '.join(CHANNEL_QUANTITIES)})")

    def alarms(self) -> Sequence[Alarm]:
        return list(self.nck.alarms.present)

    # ------------------------------------------------------------------ for observers (vc.simulation.published)
    def state_view(self) -> StateView:
        """The states of the NC's state machines (of the present power-on)."""
        return self.nck.state_view()

    @property
    def alarm_list(self) -> AlarmList:
        return self.nck.alarms

    def functions_of(self, instance: str) -> frozenset[NcFunction]:
        """The functions of those only some have that the axis or channel ``instance`` has now."""
        axis = self.nck.axes_by_name.get(instance)
        if axis is not None:
            return frozenset({NcFunction.SPINDLE} if axis.is_spindle else ())
        channel = self.nck.channels_by_name.get(instance)
        if channel is None:
            return frozenset()
        return frozenset(function for function, present in (
            (NcFunction.INCLINED_AXIS, channel.inclined is not None),
            (NcFunction.FIVE_AXIS, channel.five_axis.kinematics is not None)) if present)

    def alarm_history(self) -> Sequence[Alarm]:
        return list(self.nck.alarms.history)

    def machine_datum(self, instance: str, number: int, index: int | None = None) -> float:
        """A machine datum as the control has it now (with what it wrote itself, e.g. MD34090)."""
        md = BY_NUMBER[number]
        base = self._machine_data_of(instance)
        value = self.nck.memory.view(instance, base).value(md)
        if isinstance(value, tuple):
            value = value[index or 0]
        return float(value)

    def _machine_data_of(self, instance: str) -> MachineData:
        if instance == "NC":
            return self.machine.nck
        for channel in self.machine.channels:
            if channel.name == instance:
                return channel.md
        return self.machine.axis(instance).md

    # ------------------------------------------------------------------ faults of the machine, manual motion
    def inject_fault(self, axis: str, kind: str, start: float = 0.0, end: float = 0.0, amount: float = 0.0,
                     encoder: int = 1) -> None:
        """A fault of the simulated machine (see FAULTS)."""
        if kind == "mains_failure":
            self._supply(False)
            return
        if kind in DEVICE_FAULTS:
            self.plant.inject(DEVICE_FAULTS[kind], kind)
            if self.plant.clamp is not None and DEVICE_FAULTS[kind] == self.plant.clamp.name:
                self.nck.axes_by_name[self.plant.clamp.axis].resting = False  # the load acts on a standing axis
            if self.plant.holding_brake is not None and DEVICE_FAULTS[kind] == self.plant.holding_brake.name:
                self.nck.axes_by_name[self.plant.holding_brake.axis].resting = False  # the brake acts on the slide
            return
        item = self.nck.axes_by_name[axis]
        measuring_system = item.encoders[encoder - 1]
        if kind == "zero_marks_missing":
            measuring_system.zero_marks_visible = False
        elif kind == "reference_marks_missing":
            measuring_system.missing_marks.append((min(start, end), max(start, end)))
        elif kind == "encoder_slip":
            self.nck.encoder_slip(axis, encoder - 1, amount)
        elif kind == "load_disturbance":
            item.disturbance_velocity = amount / item.dyn.display_velocity_factor
            item.resting = False
        elif kind == "motor_temperature":
            if not self.nck.motor_temperature(axis, end):
                raise StepRefused(f"motor_temperature: the drive of {axis} reports no messages (drive: messages: 1)")
        elif kind == "workpiece_clamp":
            if not self.nck.couplings.clamp(axis, amount):
                raise StepRefused(f"workpiece_clamp: {axis} is not the following spindle of a coupling now")
        else:
            raise KeyError(f"unknown fault '{kind}' (known: {', '.join(FAULTS)})")

    def link_quantity(self, name: str) -> float:
        """A counter or state of the CAN link the PLC sits behind (see LINK_QUANTITIES)."""
        return self._faulty_link().quantity(name)

    def _faulty_link(self) -> FaultInjectable:
        if not isinstance(self.plc, FaultInjectable):
            where = "no PLC" if self.plc is None else "a PLC without a bus (in process, Modbus TCP)"
            raise LinkError(f"a link fault or quantity needs the PLC behind the CAN link; this simulation has {where}")
        return self.plc

    def inject_link_fault(self, kind: str, duration_us: int, directions: Sequence[str] = ("nc_to_plc", "plc_to_nc"),
                          areas: Sequence[str] = (), delay_us: int = 0, every: int = 1) -> None:
        """A fault of the bus between NC and PLC from now on for ``duration_us`` (see LINK_FAULTS);
        only a PLC behind a link with a bus (CAN) takes it."""
        link = self._faulty_link()
        cycle_us = self.nck.cycle_us
        start = self.nck.cycle
        link.inject_fault(LinkFault(
            LinkFaultKind(kind), start, start + -(-duration_us // cycle_us),
            frozenset(Direction(direction) for direction in directions), frozenset(areas),
            -(-delay_us // cycle_us), every))

    def _supply(self, on: bool) -> None:
        self.plant.supply_on = on
        self.nck.supply(on)

    def acknowledge_alarms(self) -> None:
        self.nck.acknowledge()

    def clear_faults(self, axis: str) -> None:
        """Repair: an axis's faults, the mains (``mains``) or a device's (``Turret``, ``Coolant`` ..)."""
        if axis == MAINS:
            self._supply(True)
            return
        if axis in self.plant.device_names():
            self.plant.repair(axis)
            return
        item = self.nck.axes_by_name[axis]
        item.disturbance_velocity = 0.0
        item.clamp = None
        self.nck.motor_temperature(axis, None)
        item.resting = False
        for measuring_system in item.encoders:
            measuring_system.zero_marks_visible = True
            measuring_system.missing_marks.clear()

    def move_by_hand(self, axis: str, velocity: float) -> None:
        """Someone moves the slide from outside at ``velocity`` (mm/min or rev/min; 0 stops).

        Only a slide without position control moves (servo off, follow-up or hold); a
        position-controlled axis holds its position against it."""
        item = self.nck.axes_by_name[axis]
        item.external_velocity = velocity / item.dyn.display_velocity_factor
        item.resting = False

    def turn_handwheel(self, number: int, detents: int, cycles: int) -> None:
        """The operator turns handwheel ``number`` by ``detents`` evenly over ``cycles`` IPO cycles."""
        self.nck.turn_handwheel(number, detents, cycles)

    def load_mda(self, channel: str, text: str) -> None:
        self.nck.load_mda(channel, text)

    def select_program(self, channel: str, name: str, text: str) -> None:
        self.nck.select_program(channel, name, text)
