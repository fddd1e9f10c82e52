"""A machine configuration, as loaded and checked from a machine YAML file.

Frozen dataclasses: the NC core, the plant and the harness read them and never change
them.  Machine data live in :class:`~vc.config.machine_data.MachineData` per level
instance; what is not machine data of the control (where the simulated machine's cams,
limit switches and zero marks physically are) lives in the ``sim`` and ``plant`` parts.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

from interfaces.links.can.codec import DEFAULT_TIMEOUT_US, CanSettings
from interfaces.plant_io import PlantIoMap
from interfaces.signals import InterfaceLayout
from vc.config.machine_data import MachineData
from vc.config.md_dictionary import DIAMETER_AX_DEF, IPO_SYSCLOCK_TIME_RATIO, SYSCLOCK_CYCLE_TIME


@dataclass(frozen=True, slots=True)
class AxisSimulation:
    """Physical facts of the simulated axis that the control does not know."""

    start_position: float = 0.0  # where the slide stands at power-on (machine coordinates, mm or deg)
    zero_mark_offset: float = 0.0  # measuring system 1: physical position of one zero mark, of the first
    #                                distance-coded mark, or of an absolute encoder's zero
    zero_mark_offset_2: float = 0.0  # the same for measuring system 2
    encoder_serial: int = 0  # serial numbers of the mounted encoders (compared with MD34230)
    encoder_serial_2: int = 0


@dataclass(frozen=True, slots=True)
class GearboxPlant:
    """The load gearbox of a spindle: the PLC shifts it with one actuator per gear stage."""

    stages: int  # gear stages 1..stages (equals MD35090 NUM_GEAR_STEPS)
    shift_time_s: float  # how long the actuator must push while the teeth can mesh (the motor turns)
    engaged_at_power_on: int = 1  # the stage in mesh when the machine is switched on, 0 = neutral


@dataclass(frozen=True, slots=True)
class ChuckPlant:
    """The hydraulic chuck of a spindle: the PLC clamps and opens it with the two solenoids of its valve."""

    travel_time_s: float  # stroke time from open to clamped (and back) with hydraulic pressure
    closed_at_power_on: bool = True  # clamped when the machine is switched on


@dataclass(frozen=True, slots=True)
class AxisPlant:
    """Switches mounted along the axis, in physical machine coordinates, a spindle's gearbox and chuck."""

    ref_cam: tuple[float, float] | None = None  # the axis stands on the cam inside [start, end]
    hw_limit_minus: float | None = None  # the minus limit switch is actuated at or below this position
    hw_limit_plus: float | None = None  # the plus limit switch is actuated at or above this position
    gearbox: GearboxPlant | None = None  # spindles only
    chuck: ChuckPlant | None = None  # spindles only


EXTENDED_STOP = 1  # p0888 = 1, written by ESRS from the part program
EXTENDED_RETRACT = 2  # p0888 = 2, written by ESRR
GENERATOR_OPERATION = 3  # p0888 = 3 (L41708-41712)
DC_LINK_PER_SUPPLY_VOLT = 1.35  # a rectified three-phase supply charges the link to 1.35 x its voltage [control]
PULSE_CANCELLATION_PER_SUPPLY_VOLT = 0.9  # pulses are cancelled below 0.9 x r0208 (L41749-41754)
# a line module's precharge "completed after a period of typically 1 to 2 s" (SINAMICS engineering manual) [INF]
DEFAULT_PRECHARGE_TIME = 1.0
# The generator brakes until its motor runs below p2161, by the hysteresis of the speed comparison
# (SINAMICS p2150, default 2 rev/min) [control]: there r2199.0 (DB31.DBX95.3) comes and it gives no more.
SPEED_HYSTERESIS = 2.0  # rev/min


@dataclass(frozen=True, slots=True)
class DriveParameters:
    """Parameters of the axis's drive (SINAMICS) that the NC does not write: extended stop and
    retract in generator operation (seed 003 L41700-41769).  ESRS / ESRR write p0888 and p0892
    from the part program (stop, retract); generator operation is set up in the drive alone."""

    p0888: int = 0  # ESR configuration: 3 = generator operation (Vdc controller)
    p0892: float = 0.0  # s: generator operation may use the motor from the trigger T1 to T2 = T1 + p0892
    p1240: int = 0  # Vdc controller configuration: 2 = at p1248 the motor brakes under ESR to buffer the link
    p1248: float = 0.0  # V: lower DC-link threshold, the Vdc_min controller's setpoint
    p2161: float = 0.0  # rev/min: speed threshold 3, the generator's minimum motor speed (r2199.0), n min
    p0341: float = 0.0  # kg m^2: motor moment of inertia
    p0342: float = 1.0  # ratio of the total moment of inertia (motor and load) to the motor's
    # The drive's messages to the PLC (DB31.DBX94.x / 95.0, docs/fixed_stop_and_drives.md §7): reported
    # where the machine file switches them on, so that the machines without them keep their traces [INF];
    # thresholds and factory settings of SINAMICS [control]
    messages: bool = False
    p0604: float = 120.0  # degC: motor temperature warning threshold (DBX94.0)
    p2155: float = 900.0  # rev/min: speed threshold 2, n x (DBX94.5)
    p2163: float = 90.0  # rev/min: speed threshold 4, the tolerance of n act = n set (DBX94.6, 94.2)
    p2172: float = 800.0  # V: DC-link voltage threshold (DBX95.0)
    p2174: float = 90.0  # percent of the drive's maximum torque [INF: SINAMICS counts Nm]: Mdx (DBX94.3)
    p2176: float = 200.0  # ms: the torque must stand at or above p2174 this long before DBX94.3 falls

    @property
    def generator(self) -> bool:
        return self.p0888 == GENERATOR_OPERATION


@dataclass(frozen=True, slots=True)
class DcLinkConfig:
    """The DC link of the drive line-up, for generator operation (seed 003 L41733-41754)."""

    supply_voltage: float  # V: r0208, rated supply voltage of the power unit (pulses off below 0.9 x r0208)
    capacitance_uf: float  # uF: DC-link capacitance of the line-up
    load_power: float  # W: what the line-up draws from the link with the supply gone (electronics, brakes,
    #                    the other drives holding their axes)
    precharge_time: float = DEFAULT_PRECHARGE_TIME  # s: empty link to charged through the precharge resistors


@dataclass(frozen=True, slots=True)
class IndexDivision:
    """The index positions of an indexing axis (seed 003 chapter 11, MD30500): the positions of its
    table (MD10910 / MD10930, as many as MD10900 / MD10920), position 1 the table's first; or
    equidistant ones (MD30500 = 3): position n at ``offset + (n - 1) x spacing``, ``count`` of them
    in a turn of a modulo axis (MD30502), unbounded on any other axis (``count`` 0)."""

    table: tuple[float, ...] = ()
    offset: float = 0.0  # MD30503 INDEX_AX_OFFSET
    spacing: float = 0.0  # MD30501 / MD30502; on a modulo axis MD30330 / MD30502
    count: int = 0


@dataclass(frozen=True, slots=True)
class AxisConfig:
    name: str  # machine axis name (MD10000), also the interface instance name
    number: int  # machine axis number, 1-based: interface DB(30 + number)
    md: MachineData
    is_rotary: bool  # MD30300 IS_ROT_AX
    spindle_number: int  # MD35000 SPIND_ASSIGN_TO_MACHAX, 0 = not a spindle
    sim: AxisSimulation = field(default_factory=AxisSimulation)
    plant: AxisPlant = field(default_factory=AxisPlant)
    drive: DriveParameters = field(default_factory=DriveParameters)
    indexing: IndexDivision | None = None  # an indexing axis (MD30500 > 0): its index positions

    @property
    def is_spindle(self) -> bool:
        return self.spindle_number > 0

    @property
    def position_unit(self) -> str:
        """The unit of the axis's positions: degrees on a rotary axis or spindle (MD30300), else mm."""
        return "deg" if self.is_rotary else "mm"

    @property
    def velocity_unit(self) -> str:
        """The unit of its velocities as the NC shows them: rev/min on a rotary axis or spindle, else mm/min."""
        return "rev/min" if self.is_rotary else "mm/min"

    @property
    def db(self) -> int:
        return 30 + self.number


@dataclass(frozen=True, slots=True)
class ChannelConfig:
    name: str
    number: int  # 1-based: interface DB(20 + number)
    md: MachineData
    axes: tuple[str, ...]  # machine axes of the channel (MD20070), in channel axis order
    program_names: tuple[str, ...]  # channel axis names used in part programs (MD20080), same order
    geometry_names: tuple[str, ...]  # names of the geometry axes (MD20060), e.g. ("X", "Y", "Z")
    geometry_axes: tuple[str, ...]  # machine axis serving each geometry axis (MD20050), "" = none

    @property
    def db(self) -> int:
        return 20 + self.number

    def axis_for_program_name(self, name: str) -> str | None:
        """The machine axis a part program means by ``name`` (geometry, channel or machine axis name)."""
        for geometry_name, machine_axis in zip(self.geometry_names, self.geometry_axes, strict=True):
            if name == geometry_name and machine_axis:
                return machine_axis
        for program_name, machine_axis in zip(self.program_names, self.axes, strict=True):
            if name == program_name:
                return machine_axis
        return name if name in self.axes else None

    def transverse_axis(self) -> str | None:
        """The machine axis of the transverse axis (MD20100 DIAMETER_AX_DEF names a geometry axis), or
        None: diameter programming and G96 / G961 take it (seed 003 §8, L10268-10645)."""
        name = self.md.str(DIAMETER_AX_DEF)
        return self.axis_for_program_name(name) if name and name in self.geometry_names else None


PERIOD_PLC = "plc"  # with every PLC scan
PERIOD_IPO = "ipo"  # every IPO cycle
DEFAULT_TIMEOUT_S = DEFAULT_TIMEOUT_US / 1_000_000
# [INF] SocketCAN restarts a bus-off controller only when told (restart-ms 0); a harness that stayed
# bus-off until the next power-on would hide every later reaction, so it restarts after 100 ms.
DEFAULT_RESTART_S = 0.1


@dataclass(frozen=True, slots=True)
class CanConfig:
    """The machine file's ``can:`` section (vc/config/can_config.py reads and checks it)."""

    settings: CanSettings = field(default_factory=CanSettings)  # what the PLC must agree on
    period: str | float = PERIOD_PLC  # PERIOD_PLC, PERIOD_IPO or seconds
    timeout_s: float = DEFAULT_TIMEOUT_S
    restart_s: float = DEFAULT_RESTART_S  # 0: no automatic restart after bus-off

    def period_cycles(self, ipo_cycle_us: int, plc_cycle_ipo: int) -> int:
        """IPO cycles between two transmissions of the NC-to-PLC frames (checked whole by the loader)."""
        if self.period == PERIOD_PLC:
            return plc_cycle_ipo
        if self.period == PERIOD_IPO:
            return 1
        return max(1, round(float(self.period) * 1_000_000 / ipo_cycle_us))

    def timeout_cycles(self, ipo_cycle_us: int) -> int:
        return max(1, round(self.timeout_s * 1_000_000 / ipo_cycle_us))

    @property
    def timeout_us(self) -> int:
        return round(self.timeout_s * 1_000_000)

    def restart_cycles(self, ipo_cycle_us: int) -> int:
        """IPO cycles from bus-off to the controller's restart; 0: none."""
        return 0 if self.restart_s == 0 else max(1, round(self.restart_s * 1_000_000 / ipo_cycle_us))


# The PLC's user alarms of DB2 user area 0 (DB2.DBX180.0 .. 187.7): the numbers the machine's PLC
# program may raise, whose texts ``plc_alarms:`` gives (vc/core/nck/plc_alarms.py).
PLC_USER_ALARMS = range(700000, 700064)


@dataclass(frozen=True, slots=True)
class TailstockPlant:
    """A tailstock quill on a machine axis that presses a part against the main spindle: the part's
    face is the fixed stop the quill travels to (seed 003 chapter 17, vc/plant/tailstock.py)."""

    axis: str  # the machine axis of the quill
    stop: float  # where the quill's tip touches the part, on the axis (physical mm)
    stiffness: float  # N/mm of the part and the centre: the quill goes force / stiffness further
    max_force: float  # N the drive pushes with at 100 % torque
    force_limit: float  # N the part takes; above them it slips away: the stop is lost
    retracted: float  # the sleeve sensor "retracted" reads 1 at or behind this position


@dataclass(frozen=True, slots=True)
class AxisMagazinePlant:
    """A tool magazine turned by a modulo NC axis that the PLC positions with FC18 (seed 003 §9.7):
    its lock pin and pocket sensor (vc/plant/axis_magazine.py)."""

    axis: str  # the machine axis that turns the disk
    pockets: int  # pocket p stands at the pin at (p - 1) x 360 / pockets degrees
    lock_time_s: float  # the lock pin's stroke
    window: float  # degrees either side of a pocket in which the pin engages and inPocket reads 1


@dataclass(frozen=True, slots=True)
class ClampPlant:
    """The clamp of an axis (a rotary table's), closed by the PLC once the axis stands
    (vc/plant/clamp.py); DB31.DBX2.3 tells the NC (its clamping monitor)."""

    axis: str  # the machine axis it clamps
    travel_time_s: float  # s from open to closed and back
    load: float  # mm/min or deg/min the machining load pushes the axis with once the clamp gives way


@dataclass(frozen=True, slots=True)
class HoldingBrakePlant:
    """The holding brake of an axis's motor (a vertical axis's), released by the drive on the PLC's
    DB31.DBX20.5 (vc/plant/holding_brake.py); its feedback is DB31.DBX92.5."""

    axis: str  # the machine axis whose motor it brakes
    switch_time_s: float  # s the brake takes to release and to engage
    sag: float  # mm/min (deg/min), signed: how the weight moves the slide while the brake is open without torque


@dataclass(frozen=True, slots=True)
class TurretPlant:
    """A tool turret indexed by the PLC: a disk with its stations, an indexing drive, a lock pin."""

    stations: int  # tool stations on the disk, 1..stations
    index_time_s: float  # s the disk needs from one station to the next
    lock_time_s: float  # s the lock pin needs to engage or to retract
    station_at_power_on: int = 1


@dataclass(frozen=True, slots=True)
class CoolantPlant:
    """A coolant pump with a pressure switch."""

    pressure_time_s: float  # s from the pump on to the pressure switch closing


@dataclass(frozen=True, slots=True)
class ToolChangerPlant:
    """A mill's simple tool changer: a tool magazine indexed by the PLC and a changer arm."""

    pockets: int  # magazine pockets, 1..pockets
    index_time_s: float  # s the magazine needs from one pocket to the next
    arm_time_s: float  # s the arm needs from its home position to the spindle (and back)
    pocket_at_power_on: int = 1


@dataclass(frozen=True, slots=True)
class MachinePlant:
    """The machine's devices besides its axes (the machine file's ``plant:``), None where it has none."""

    turret: TurretPlant | None = None
    coolant: CoolantPlant | None = None
    tool_changer: ToolChangerPlant | None = None
    tailstock: TailstockPlant | None = None
    axis_magazine: AxisMagazinePlant | None = None
    clamp: ClampPlant | None = None
    holding_brake: HoldingBrakePlant | None = None


@dataclass(frozen=True, slots=True)
class MachineConfig:
    name: str
    source: str  # the file it was loaded from
    nck: MachineData
    channels: tuple[ChannelConfig, ...]
    axes: tuple[AxisConfig, ...]
    plant_io: PlantIoMap
    plc_cycle_ipo: int  # OB1 period in IPO cycles
    plc_parameters: Mapping[str, Any] = field(default_factory=dict)  # ``plc:``, for the PLC program to check
    dc_link: DcLinkConfig | None = None  # ``dc_link:``; None: the drive line-up's link is not modelled
    can: CanConfig = field(default_factory=CanConfig)  # ``can:``, checked against the machine by the loader
    plant: MachinePlant = field(default_factory=MachinePlant)  # ``plant:``: turret, coolant, tool changer
    plc_alarms: Mapping[int, str] = field(default_factory=dict)  # ``plc_alarms:``: texts of the PLC user alarms

    @property
    def layout(self) -> InterfaceLayout:
        return InterfaceLayout(
            channels=tuple(channel.name for channel in self.channels),
            axes=tuple(axis.name for axis in self.axes),
        )

    def axis(self, name: str) -> AxisConfig:
        for axis in self.axes:
            if axis.name == name:
                return axis
        raise KeyError(name)

    def channel(self, name: str) -> ChannelConfig:
        for channel in self.channels:
            if channel.name == name:
                return channel
        raise KeyError(name)


def machine_ipo_cycle_us(config: MachineConfig) -> int:
    """The IPO cycle in microseconds: MD10050 SYSCLOCK_CYCLE_TIME x MD10070 IPO_SYSCLOCK_TIME_RATIO.

    The loader has checked that it is a whole number of microseconds.
    """
    seconds = config.nck.float(SYSCLOCK_CYCLE_TIME) * config.nck.int(IPO_SYSCLOCK_TIME_RATIO)
    return round(seconds * 1_000_000)
