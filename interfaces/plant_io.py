"""Plant I/O: what is wired to the PLC's inputs (I) and outputs (Q), declared per machine.

A machine file lists its I/O like an electrical I/O list, address -> function name::

    I0.0: MCP.auto          # machine control panel key
    I2.0: X1.refCam         # reference cam switch of X1
    IB4:  MCP.feedOverride  # feed override switch (binary 0..200 %)
    I9.1: SP1.gearEngaged1  # gear stage 1 engaged sensor of the spindle SP1's gearbox
    Q2.1: SP1.gearShift1    # shift actuator of SP1's gearbox: into gear stage 1
    I6.2: Door.closed       # guard door switch
    Q2.4: SP1.chuckClose    # valve solenoids of SP1's hydraulic chuck: clamp ...
    Q2.5: SP1.chuckRelease  # ... and unclamp

The function names form a fixed vocabulary (``PLANT_FUNCTIONS``), so the plant model and
the PLC programs agree on what each point is without knowing its address.  Safety
contacts (emergency-stop chain, hardware limit switches) are normally closed: the input
reads 1 while healthy and 0 when actuated or when the wire is broken.  A spindle gearbox
has one shift actuator per gear stage (``gearShift1`` .. ``gearShift5``, outputs the PLC
holds on during a shift), one engaged sensor per stage (``gearEngaged1`` ..) and
optionally a neutral sensor (``gearNeutral``).  A spindle's hydraulic chuck has a valve
with two solenoids, outputs the PLC holds on to clamp (``chuckClose``) or to unclamp
(``chuckRelease``), and end-position sensors (``chuckClosed``, optionally ``chuckOpen``).
The guard door switch (``Door.closed``) is the operator's: a person opens and closes the door.
A lathe's tool turret has an indexing drive (``Turret.indexCw``, ``Turret.indexCcw``), a lock pin
pulled by its solenoid (``Turret.unlock``) with end-position sensors (``Turret.locked``,
``Turret.unlocked``) and a binary station code (``Turret.code1``, ``code2``, ``code4`` ..: the
station while the disk stands at one, 0 between).  A mill's tool magazine turns with
``Magazine.rotateCw`` / ``Magazine.rotateCcw`` and reports its pocket as ``Magazine.code1`` ..; its
changer arm swings to the spindle while ``ToolArm.toSpindle`` is on and reports ``ToolArm.home``
and ``ToolArm.atSpindle``.  The coolant pump runs with ``Coolant.pump``; its pressure switch
``Coolant.pressureOk`` closes once the pressure has built up.
"""

from __future__ import annotations

import re
from collections.abc import Iterable, Mapping
from dataclasses import dataclass
from enum import StrEnum

from interfaces.address import Address, AddressError
from interfaces.errors import VcError
from interfaces.signals import Direction, SignalRef, SignalType, UnknownSignalError


class PointOwner(StrEnum):
    """Who drives a plant I/O point."""

    OPERATOR = "operator"  # keys, switches and the emergency-stop button: set by a person (a scenario)
    PLANT = "plant"  # sensors the simulated machine drives: cams, limit switches, drive ready
    PLC = "plc"  # outputs the PLC drives


@dataclass(frozen=True, slots=True)
class PlantFunction:
    pattern: str  # regular expression over the name; (?P<axis>...) captures an axis name
    type: SignalType
    direction: Direction
    owner: PointOwner
    meaning: str


_AXIS = r"(?P<axis>[A-Za-z][A-Za-z0-9_]*)"

PLANT_FUNCTIONS: tuple[PlantFunction, ...] = (
    PlantFunction(r"MCP\.(auto|mda|jog|ref)", SignalType.BOOL, Direction.PLANT_TO_PLC, PointOwner.OPERATOR,
                  "operating mode / machine function key on the machine control panel"),
    PlantFunction(r"MCP\.(ncStart|ncStop|reset|feedStop|feedStart|spindleStop|spindleStart|rapid)",
                  SignalType.BOOL, Direction.PLANT_TO_PLC, PointOwner.OPERATOR, "machine control panel key"),
    PlantFunction(rf"MCP\.(plus|minus)\.{_AXIS}", SignalType.BOOL, Direction.PLANT_TO_PLC, PointOwner.OPERATOR,
                  "traverse key of one axis on the machine control panel"),
    PlantFunction(r"MCP\.optionalStop", SignalType.BOOL, Direction.PLANT_TO_PLC, PointOwner.OPERATOR,
                  "optional stop switch on the machine control panel: 1 = M01 stops the program (the PLC selects"
                  " it with DB21.DBX0.5)"),
    PlantFunction(r"MCP\.gantrySync", SignalType.BOOL, Direction.PLANT_TO_PLC, PointOwner.OPERATOR,
                  "key on the machine control panel: start the gantry synchronization run the NC waits for"
                  " (DB31.DBX101.4; the PLC program gantry gives DB31.DBX29.4)"),
    PlantFunction(r"MCP\.noOrthogonalCompensation", SignalType.BOOL, Direction.PLANT_TO_PLC, PointOwner.OPERATOR,
                  "switch on the machine control panel: move the inclined axis without compensating the "
                  "orthogonal one (NOZAGC of the inclined-axis control)"),
    PlantFunction(r"MCP\.(feedOverride|spindleOverride|rapidOverride)", SignalType.BYTE,
                  Direction.PLANT_TO_PLC, PointOwner.OPERATOR, "override switch, binary coded percent (0..200)"),
    PlantFunction(r"MCP\.handwheel[1-3]", SignalType.BYTE, Direction.PLANT_TO_PLC, PointOwner.OPERATOR,
                  "axis selector of handwheel n on the machine control panel, coded as the HMI's handwheel"
                  " byte DB10.DBB100: bits 0..4 the axis number, bit 7 = 1 machine axis, 0 geometry axis of"
                  " channel 1; 0 = no axis"),
    PlantFunction(r"MCP\.(inc1|inc10|inc100|inc1000|inc10000)", SignalType.BOOL, Direction.PLANT_TO_PLC,
                  PointOwner.OPERATOR,
                  "increment key on the machine control panel (machine function INC1 .. INC10000)"),
    PlantFunction(r"MCP\.(incVar|jogContinuous)", SignalType.BOOL, Direction.PLANT_TO_PLC, PointOwner.OPERATOR,
                  "machine function key on the machine control panel: the variable increment INCvar (SD41010)"
                  " or continuous JOG"),
    PlantFunction(r"MCP\.fixedPoint[1-4]", SignalType.BOOL, Direction.PLANT_TO_PLC, PointOwner.OPERATOR,
                  "JOG to fixed point key on the machine control panel: selects fixed point n of the axes"
                  " (DB31.DBX13.0..13.2); pressed again it withdraws the selection"),
    PlantFunction(r"EStop\.chainOk", SignalType.BOOL, Direction.PLANT_TO_PLC, PointOwner.OPERATOR,
                  "emergency-stop chain, normally closed: 1 = healthy, 0 = pressed or broken"),
    PlantFunction(r"Drives\.ready", SignalType.BOOL, Direction.PLANT_TO_PLC, PointOwner.PLANT,
                  "drive line-up ready (infeed on, no drive fault)"),
    PlantFunction(rf"{_AXIS}\.refCam", SignalType.BOOL, Direction.PLANT_TO_PLC, PointOwner.PLANT,
                  "reference cam switch of the axis: 1 while the axis stands on the cam"),
    PlantFunction(rf"{_AXIS}\.(hwLimitMinus|hwLimitPlus)", SignalType.BOOL, Direction.PLANT_TO_PLC, PointOwner.PLANT,
                  "hardware limit switch, normally closed: 1 = free, 0 = actuated"),
    PlantFunction(rf"{_AXIS}\.gearEngaged[1-5]", SignalType.BOOL, Direction.PLANT_TO_PLC, PointOwner.PLANT,
                  "gear stage n engaged sensor of the spindle's gearbox: 1 while gear stage n is in mesh"),
    PlantFunction(rf"{_AXIS}\.gearNeutral", SignalType.BOOL, Direction.PLANT_TO_PLC, PointOwner.PLANT,
                  "neutral sensor of the spindle's gearbox: 1 while no gear stage is engaged"),
    PlantFunction(rf"{_AXIS}\.chuckClosed", SignalType.BOOL, Direction.PLANT_TO_PLC, PointOwner.PLANT,
                  "end-position sensor of the spindle's chuck: 1 while the chuck is clamped"),
    PlantFunction(rf"{_AXIS}\.chuckOpen", SignalType.BOOL, Direction.PLANT_TO_PLC, PointOwner.PLANT,
                  "end-position sensor of the spindle's chuck: 1 while the chuck is fully open"),
    PlantFunction(r"Door\.closed", SignalType.BOOL, Direction.PLANT_TO_PLC, PointOwner.OPERATOR,
                  "guard door switch of the machining area: 1 = closed, 0 = open"),
    PlantFunction(r"Drives\.on", SignalType.BOOL, Direction.PLC_TO_PLANT, PointOwner.PLC,
                  "main contactor / infeed on command"),
    PlantFunction(r"Lamp\.[A-Za-z0-9_.]+", SignalType.BOOL, Direction.PLC_TO_PLANT, PointOwner.PLC,
                  "indicator lamp on the machine control panel"),
    PlantFunction(rf"{_AXIS}\.gearShift[1-5]", SignalType.BOOL, Direction.PLC_TO_PLANT, PointOwner.PLC,
                  "gear-stage shift actuator (valve) of the spindle's gearbox: 1 = move the gearbox into gear"
                  " stage n; the PLC holds it on until the stage is engaged"),
    PlantFunction(rf"{_AXIS}\.chuckClose", SignalType.BOOL, Direction.PLC_TO_PLANT, PointOwner.PLC,
                  "clamp solenoid of the chuck valve: 1 = the chuck clamps (the PLC holds it on)"),
    PlantFunction(rf"{_AXIS}\.chuckRelease", SignalType.BOOL, Direction.PLC_TO_PLANT, PointOwner.PLC,
                  "unclamp solenoid of the chuck valve: 1 = the chuck opens; neither solenoid on: it holds"),
    PlantFunction(r"(Turret|Magazine)\.code(1|2|4|8|16)", SignalType.BOOL, Direction.PLANT_TO_PLC, PointOwner.PLANT,
                  "bit n of the binary station (pocket) code: the station number while the turret disk (the"
                  " magazine) stands at a station, 0 between two"),
    PlantFunction(r"Turret\.locked", SignalType.BOOL, Direction.PLANT_TO_PLC, PointOwner.PLANT,
                  "lock pin of the turret engaged: the disk is locked at a station"),
    PlantFunction(r"Turret\.unlocked", SignalType.BOOL, Direction.PLANT_TO_PLC, PointOwner.PLANT,
                  "lock pin of the turret fully pulled: the disk may turn"),
    PlantFunction(r"Turret\.(indexCw|indexCcw)", SignalType.BOOL, Direction.PLC_TO_PLANT, PointOwner.PLC,
                  "indexing drive of the turret (contactor): 1 = the disk turns clockwise / counter-clockwise"
                  " (only while the lock pin is pulled)"),
    PlantFunction(r"Turret\.unlock", SignalType.BOOL, Direction.PLC_TO_PLANT, PointOwner.PLC,
                  "lock pin solenoid of the turret: 1 = pull the pin; 0 = the spring engages it (at a station)"),
    PlantFunction(r"Magazine\.(rotateCw|rotateCcw)", SignalType.BOOL, Direction.PLC_TO_PLANT, PointOwner.PLC,
                  "drive of the tool magazine: 1 = it turns clockwise / counter-clockwise"),
    PlantFunction(r"ToolArm\.toSpindle", SignalType.BOOL, Direction.PLC_TO_PLANT, PointOwner.PLC,
                  "valve of the tool changer arm: 1 = swing to the spindle (it takes the tool out and puts the"
                  " magazine's in), 0 = back home"),
    PlantFunction(r"ToolArm\.home", SignalType.BOOL, Direction.PLANT_TO_PLC, PointOwner.PLANT,
                  "tool changer arm in its home position, clear of the spindle"),
    PlantFunction(r"ToolArm\.atSpindle", SignalType.BOOL, Direction.PLANT_TO_PLC, PointOwner.PLANT,
                  "tool changer arm at the spindle: the tools are swapped"),
    PlantFunction(r"Coolant\.pump", SignalType.BOOL, Direction.PLC_TO_PLANT, PointOwner.PLC,
                  "coolant pump contactor: 1 = the pump runs"),
    PlantFunction(r"Lube\.pump", SignalType.BOOL, Direction.PLC_TO_PLANT, PointOwner.PLC,
                  "way lubrication pump of the slides: 1 = it pumps oil to the guideways (a pulse per lubrication)"),
    PlantFunction(r"Coolant\.pressureOk", SignalType.BOOL, Direction.PLANT_TO_PLC, PointOwner.PLANT,
                  "coolant pressure switch: 1 once the running pump has built up the pressure"),
    PlantFunction(r"AxisMagazine\.unlock", SignalType.BOOL, Direction.PLC_TO_PLANT, PointOwner.PLC,
                  "lock pin solenoid of the magazine turned by an NC axis: 1 = pull the pin; 0 = the spring"
                  " engages it (at a pocket)"),
    PlantFunction(r"AxisMagazine\.locked", SignalType.BOOL, Direction.PLANT_TO_PLC, PointOwner.PLANT,
                  "lock pin of the axis magazine engaged: the disk is locked at a pocket"),
    PlantFunction(r"AxisMagazine\.unlocked", SignalType.BOOL, Direction.PLANT_TO_PLC, PointOwner.PLANT,
                  "lock pin of the axis magazine fully pulled: the axis may turn the disk"),
    PlantFunction(r"AxisMagazine\.inPocket", SignalType.BOOL, Direction.PLANT_TO_PLC, PointOwner.PLANT,
                  "pocket sensor of the axis magazine: 1 while a pocket stands within the pin's window"),
    PlantFunction(r"AxisMagazine\.driveReady", SignalType.BOOL, Direction.PLANT_TO_PLC, PointOwner.PLANT,
                  "ready contact of the axis magazine's drive: 0 = the drive reports a fault"),
    PlantFunction(r"Clamp\.close", SignalType.BOOL, Direction.PLC_TO_PLANT, PointOwner.PLC,
                  "clamp valve of an axis (a rotary table): 1 = the clamp closes and holds the axis, 0 = it opens"),
    PlantFunction(r"Clamp\.closed", SignalType.BOOL, Direction.PLANT_TO_PLC, PointOwner.PLANT,
                  "end-position sensor of the axis clamp: 1 while it is closed and holds the axis"),
    PlantFunction(r"Clamp\.opened", SignalType.BOOL, Direction.PLANT_TO_PLC, PointOwner.PLANT,
                  "end-position sensor of the axis clamp: 1 while it is fully open: the axis may move"),
    PlantFunction(r"Tailstock\.retracted", SignalType.BOOL, Direction.PLANT_TO_PLC, PointOwner.PLANT,
                  "tailstock quill's sleeve sensor: 1 while the quill stands retracted, clear of the part"),
    PlantFunction(r"Tailstock\.atPart", SignalType.BOOL, Direction.PLANT_TO_PLC, PointOwner.PLANT,
                  "tailstock quill's sleeve sensor: 1 while its centre presses against the part (the fixed"
                  " stop sensor, DB31.DBX1.2 with MD37040 = 1 / 2)"),
)

# The machine's devices besides the axes (the machine file's ``plant:``), by their I/O prefix.
TURRET, MAGAZINE, TOOL_ARM, COOLANT, TAILSTOCK = "Turret", "Magazine", "ToolArm", "Coolant", "Tailstock"
AXIS_MAGAZINE = "AxisMagazine"  # a tool magazine turned by an NC axis the PLC positions (FC18)
CLAMP = "Clamp"
HOLDING_BRAKE = "Brake"  # an axis's holding brake: no I/O of its own (the drive's DB31.DBX20.5 / 92.5)
DEVICE_PREFIXES = (TURRET, MAGAZINE, TOOL_ARM, COOLANT, TAILSTOCK, AXIS_MAGAZINE, CLAMP, HOLDING_BRAKE)


def station_code_bits(stations: int) -> tuple[int, ...]:
    """The bit values of a binary station code for ``stations`` stations: 8 stations -> (1, 2, 4, 8)."""
    return tuple(1 << bit for bit in range(stations.bit_length()))

_COMPILED = tuple((re.compile(f"^{f.pattern}$"), f) for f in PLANT_FUNCTIONS)

MAX_GEAR_STAGES = 5  # MD35090 NUM_GEAR_STEPS: at most five gear stages
_GEARBOX_POINT = re.compile(rf"^{_AXIS}\.(?P<kind>gearShift|gearEngaged|gearNeutral)(?P<stage>[1-5]?)$")


@dataclass(frozen=True, slots=True)
class GearboxPoint:
    """What a gearbox I/O name says: whose gearbox, which kind of point, which gear stage."""

    axis: str
    kind: str  # "gearShift" (actuator), "gearEngaged" (stage sensor) or "gearNeutral" (neutral sensor)
    stage: int  # 1..5; 0 for the neutral sensor


def gearbox_point(name: str) -> GearboxPoint | None:
    """The gearbox point a plant I/O name is, or None (also for a malformed one, e.g. gearShift6)."""
    match = _GEARBOX_POINT.match(name)
    if match is None or (match.group("kind") == "gearNeutral") == bool(match.group("stage")):
        return None
    return GearboxPoint(match.group("axis"), match.group("kind"), int(match.group("stage") or 0))


def gear_shift(axis: str, stage: int) -> str:
    """The shift actuator that moves the spindle's gearbox into ``stage``."""
    return f"{axis}.gearShift{stage}"


def gear_engaged(axis: str, stage: int) -> str:
    """The sensor that reads 1 while ``stage`` of the spindle's gearbox is engaged."""
    return f"{axis}.gearEngaged{stage}"


def gear_neutral(axis: str) -> str:
    """The sensor that reads 1 while the spindle's gearbox is in no gear stage."""
    return f"{axis}.gearNeutral"


_CHUCK_POINT = re.compile(rf"^{_AXIS}\.(chuckClose|chuckRelease|chuckClosed|chuckOpen)$")


def chuck_axis(name: str) -> str | None:
    """The spindle whose chuck a plant I/O name belongs to, or None (not chuck I/O)."""
    match = _CHUCK_POINT.match(name)
    return match.group("axis") if match else None


def chuck_close(axis: str) -> str:
    """The valve solenoid that clamps the spindle's chuck while it is 1."""
    return f"{axis}.chuckClose"


def chuck_release(axis: str) -> str:
    """The valve solenoid that opens the spindle's chuck while it is 1."""
    return f"{axis}.chuckRelease"


def chuck_closed(axis: str) -> str:
    """The sensor that reads 1 while the spindle's chuck is clamped."""
    return f"{axis}.chuckClosed"


def chuck_open(axis: str) -> str:
    """The sensor that reads 1 while the spindle's chuck is fully open."""
    return f"{axis}.chuckOpen"


_TYPE_WIDTH = {SignalType.BOOL: "X", SignalType.BYTE: "B", SignalType.WORD: "W"}


def plant_function(name: str) -> PlantFunction | None:
    """The vocabulary entry a plant I/O name belongs to, or None."""
    for regex, function in _COMPILED:
        if regex.match(name):
            return function
    return None


@dataclass(frozen=True, slots=True)
class PlantIoPoint:
    address: Address
    name: str
    type: SignalType
    direction: Direction
    owner: PointOwner
    meaning: str

    def ref(self) -> SignalRef:
        bits = 1 if self.type is SignalType.BOOL else 8 * self.address.size
        return SignalRef(self.name, self.address, self.type, bits, self.direction, None)


class PlantIoError(VcError, ValueError):
    """Problems in a plant I/O list; ``problems`` pairs each key with its message."""

    def __init__(self, problems: list[tuple[str, str]]):
        self.problems = problems
        super().__init__("; ".join(f"{key}: {message}" for key, message in problems))


@dataclass(frozen=True, slots=True)
class PlantIoMap:
    points: tuple[PlantIoPoint, ...]

    @classmethod
    def from_mapping(cls, entries: Mapping[str, str], axes: Iterable[str]) -> PlantIoMap:
        """Build the map from ``{address text: function name}``; collects every problem."""
        axis_names = set(axes)
        problems: list[tuple[str, str]] = []
        points: list[PlantIoPoint] = []
        names: dict[str, str] = {}
        occupied: dict[tuple[str, int, int], str] = {}
        for address_text, name in entries.items():
            key = str(address_text)
            try:
                address = Address.parse(key)
            except AddressError as error:
                problems.append((key, str(error)))
                continue
            if address.area not in ("I", "Q"):
                problems.append((key, "plant I/O lives in I (inputs) or Q (outputs), not in a data block"))
                continue
            name = str(name)
            function = plant_function(name)
            if function is None:
                problems.append((key, f"'{name}' is not a plant function (see interfaces/plant_io.py)"))
                continue
            axis = re.match(f"^{function.pattern}$", name)
            if axis is not None and "axis" in axis.groupdict() and axis.group("axis") not in axis_names:
                problems.append((key, f"'{name}' names axis {axis.group('axis')}, which the machine lacks"))
                continue
            expected_area = "I" if function.direction is Direction.PLANT_TO_PLC else "Q"
            if address.area != expected_area:
                problems.append((key, f"'{name}' is an {'input' if expected_area == 'I' else 'output'};"
                                      f" wire it to {expected_area}, not {address.area}"))
                continue
            if address.width != _TYPE_WIDTH[function.type]:
                problems.append((key, f"'{name}' is a {function.type.value}; it needs a"
                                      f" {'bit' if function.type is SignalType.BOOL else 'byte'} address"))
                continue
            if name in names:
                problems.append((key, f"'{name}' is already wired to {names[name]}"))
                continue
            clash = _first_clash(address, occupied)
            if clash is not None:
                problems.append((key, f"overlaps {clash}"))
                continue
            names[name] = key
            for location in _bits_of(address):
                occupied[location] = f"{address} ({name})"
            points.append(PlantIoPoint(address, name, function.type, function.direction, function.owner,
                                       function.meaning))
        if problems:
            raise PlantIoError(problems)
        return cls(tuple(points))

    def area_sizes(self) -> dict[str, int]:
        """Bytes of the I and Q areas (at least 1 each)."""
        sizes = {"I": 1, "Q": 1}
        for point in self.points:
            end = point.address.byte + point.address.size
            sizes[point.address.area] = max(sizes[point.address.area], end)
        return sizes

    def by_name(self, name: str) -> PlantIoPoint | None:
        for point in self.points:
            if point.name == name:
                return point
        return None

    def resolve(self, name: str) -> SignalRef:
        """Resolve a function name (``MCP.jog``) or an I/Q address (``I0.2``) that is wired."""
        point = self.by_name(name.strip())
        if point is not None:
            return point.ref()
        try:
            address = Address.parse(name)
        except AddressError:
            raise UnknownSignalError(f"unknown plant I/O '{name}'") from None
        for point in self.points:
            if point.address == address:
                return point.ref()
            if address.is_bit and point.address.area == address.area and point.type is not SignalType.BOOL \
                    and point.address.byte <= address.byte < point.address.byte + point.address.size:
                return SignalRef(str(address), address, SignalType.BOOL, 1, point.direction, None)
        raise UnknownSignalError(f"{address} is not wired on this machine")


def _bits_of(address: Address) -> list[tuple[str, int, int]]:
    if address.is_bit:
        return [(address.area, address.byte, address.bit)]
    return [(address.area, byte, bit) for byte in range(address.byte, address.byte + address.size)
            for bit in range(8)]


def _first_clash(address: Address, occupied: Mapping[tuple[str, int, int], str]) -> str | None:
    for location in _bits_of(address):
        if location in occupied:
            return occupied[location]
    return None
