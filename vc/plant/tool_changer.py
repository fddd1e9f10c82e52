"""A machining centre's simple tool changer: a tool magazine and a changer arm, wired to the PLC.

The magazine turns with ``Magazine.rotateCw`` / ``Magazine.rotateCcw`` (clockwise = towards higher
pockets) and reports the pocket at the change position as a binary code ``Magazine.code1``,
``code2`` .. (0 between two pockets).  The arm swings to the spindle while ``ToolArm.toSpindle`` is
on and back home when it drops; at the spindle it has swapped the spindle's tool with the one of
the pocket at the change position (a double gripper)::

    HOME ──toSpindle on──▶ SWINGING ──arm_time──▶ AT_SPINDLE (the tools swapped)
    AT_SPINDLE ──toSpindle off──▶ SWINGING ──arm_time──▶ HOME

The plant keeps which tool is where (``tools``: pocket -> tool, tool k in pocket k at power-on;
``spindle_tool``), so that a scenario can check that the PLC changed the right one.

Faults (``fault: {kind: ...}``, repaired with ``clear_faults: Magazine`` / ``ToolArm``):
``magazine_stalled`` (the drive runs, the magazine does not turn) and ``tool_arm_stuck`` (the arm
does not move).

Time is counted in IPO cycles, so the model is deterministic; it does no I/O.
"""

from __future__ import annotations

from interfaces.image import ProcessImage
from interfaces.plant_io import MAGAZINE, TOOL_ARM, PlantIoMap
from vc.config.model import ToolChangerPlant
from vc.plant.indexing import Cylinder, IndexingDisk, Output, Sensors, code_names, code_values, cycles_of

FAULTS = ("magazine_stalled", "tool_arm_stuck")


class ToolChanger:
    name = MAGAZINE  # faults of the arm are repaired under its own name too (clear_faults: ToolArm)

    def __init__(self, config: ToolChangerPlant, io: PlantIoMap, ipo_cycle_us: int):
        self.magazine = IndexingDisk.at_station(config.pockets, cycles_of(config.index_time_s, ipo_cycle_us),
                                                config.pocket_at_power_on)
        self.arm = Cylinder(cycles_of(config.arm_time_s, ipo_cycle_us), 0)
        self.tools = {pocket: pocket for pocket in range(1, config.pockets + 1)}  # pocket -> tool, 0 = empty
        self.spindle_tool = 0
        self._cw = Output(io, f"{MAGAZINE}.rotateCw")
        self._ccw = Output(io, f"{MAGAZINE}.rotateCcw")
        self._swing = Output(io, f"{TOOL_ARM}.toSpindle")
        self._sensors = Sensors(io, (f"{TOOL_ARM}.home", f"{TOOL_ARM}.atSpindle",
                                     *code_names(MAGAZINE, config.pockets)))
        self._swapped = False  # the arm swapped the tools on this visit to the spindle
        self._commands: tuple[bool, bool, bool] | None = None
        self._settled = False

    def step(self, io: ProcessImage) -> bool:
        """One IPO cycle: read the outputs, move magazine and arm, write the sensors; True while one
        of them moves."""
        outputs = io.areas["Q"]
        commands = (self._cw.on(outputs), self._ccw.on(outputs), self._swing.on(outputs))
        if self._settled and commands == self._commands:
            return False
        self._commands = commands
        cw, ccw, swing = commands
        arm, magazine = self.arm, self.magazine
        stroke, position = arm.stroke, magazine.position
        if cw != ccw and arm.back:
            magazine.turn(1 if cw else -1)  # the magazine turns only while the arm is clear of it
        elif not arm.back:
            magazine.centre()  # the gripper centres the pocket it takes
        arm.step(swing)
        if arm.out and not self._swapped and magazine.station:
            pocket = magazine.station
            self.tools[pocket], self.spindle_tool = self.spindle_tool, self.tools[pocket]
            self._swapped = True
        elif arm.back:
            self._swapped = False
        self._settled = arm.stroke == stroke and magazine.position == position
        self.write_sensors(io)
        return not self._settled

    def write_sensors(self, io: ProcessImage) -> None:
        self._sensors.write(io, (int(self.arm.back), int(self.arm.out),
                                 *code_values(self.magazine.station, self.magazine.stations)))

    def forget_sensors(self) -> None:
        self._sensors.forget()
        self._settled = False

    def inject(self, kind: str) -> None:
        if kind == "magazine_stalled":
            self.magazine.stalled = True
        else:
            self.arm.jammed = True
        self._settled = False

    def repair(self) -> None:
        self.magazine.stalled = self.arm.jammed = False
        self._settled = False
