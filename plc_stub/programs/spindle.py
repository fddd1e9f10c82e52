"""spindle: referencing plus the spindle networks of a machine with shiftable gearboxes.

Networks after those of ``referencing`` (1-4 basic machine, 5 referencing), for every spindle
whose gearbox is wired (``<spindle>.gearShift1..n`` and ``<spindle>.gearEngaged1..n`` in the
I/O list; n = the stages wired):

6. Gear change handshake with the NC (seed 003 L18364-18410, example t1..t4 L19384-19451).
   Step chain, one per gearbox::

       IDLE ──82.3 = 1 (set gear in 82.0-2)──▶ WAIT_STANDSTILL
       WAIT_STANDSTILL ──61.4 = 1──▶ SHIFTING: 18.5 = 1, actuator gearShift<set gear> on
       SHIFTING ──gearEngaged<set gear> = 1──▶ DONE: actuator off, 18.5 = 0, 16.0-2 = set gear, 16.3 = 1
       SHIFTING ──watchdog gear_shift_timeout──▶ DONE: actuator off, 18.5 = 0, 16.0-2 = sensed gear, 16.3 = 1
       DONE ──82.3 = 0──▶ IDLE: 16.3 = 0
       WAIT_STANDSTILL, SHIFTING ──82.3 = 0 (an NC reset ends the change)──▶ IDLE

7. Gear report outside a change (L18597-18625): in IDLE the PLC writes the gear the sensors
   show (0 = neutral) into 16.0-2 all the time and never 16.3; the NC takes it over in reset
   state and acknowledges it in 82.0-2.
8. Oscillation by the PLC (L19328-19364), for the spindles in ``oscillation_by_plc``: while
   SHIFTING the PLC sets 18.4 with 18.5 and turns the motor CW (18.6) for
   ``oscillation_time_cw``, then CCW (18.7) for ``oscillation_time_ccw``, and so on until
   the gear is engaged.  The other gearbox spindles are oscillated by the NC (MD35400 ..).

And once for the machine:

9. Spindle keys and override: the spindle stop key latches the spindle stop DB31.DBX4.3 of
   the master spindle, the spindle start key releases it (the stop key wins while both are
   pressed); the spindle override switch goes to DB31.DBB19 of every axis the NC reports as
   a spindle (DB31.DBX60.0).  The override enable DB31.DBX1.7, the servo enables and the
   measuring system are network 4's, for every axis.

Parameters (the machine file's ``plc:`` section, a scenario's ``plc_parameters``), besides
those of ``referencing``::

    plc:
      gear_shift_timeout: 5.0        # s from the actuator on to "gear engaged" before the PLC gives up
      oscillation_by_plc: [SP1]      # spindles the PLC oscillates (default: none, the NC does)
      oscillation_time_cw: 0.2       # s clockwise (18.6) ...
      oscillation_time_ccw: 0.15     # ... and counter-clockwise (18.7) per oscillation
      master_spindle: SP1            # the spindle of the panel's spindle keys (default: the first
                                     # spindle with a gearbox wired)
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from enum import Enum
from typing import Any

from interfaces.plant_io import MAX_GEAR_STAGES, gear_engaged, gear_shift
from plc_stub.blocks import SR, TON
from plc_stub.io import BitField, Bool, Byte, PlcIo
from plc_stub.programs.basic_machine import pressed
from plc_stub.programs.parameters import seconds
from plc_stub.programs.referencing import Referencing

GEAR_SHIFT_TIMEOUT_S = 5.0
OSCILLATION_TIME_CW_S = 0.2
OSCILLATION_TIME_CCW_S = 0.15
OVERRIDE_WITHOUT_SWITCH = 100  # percent: a panel without a spindle override switch runs at 100 %


class GearStep(Enum):
    IDLE = "idle"  # no change requested: network 7 reports the sensed gear
    WAIT_STANDSTILL = "wait standstill"  # requested: the NC brakes the spindle (seed L18372-18374)
    SHIFTING = "shifting"  # standing: oscillation enabled, the actuator pushes until the gear is in
    DONE = "done"  # reported with 16.3; waits for the NC to withdraw 82.3


@dataclass(slots=True)
class _GearboxSpindle:
    name: str
    actuators: list[Bool]  # gearShift1 .. gearShift<n>, stage k at index k - 1
    sensors: list[Bool]  # gearEngaged1 .. gearEngaged<n>
    change_requested: Bool  # DB31.DBX82.3
    requested_stage: BitField  # DB31.DBX82.0-82.2
    stationary: Bool  # DB31.DBX61.4
    actual_stage: BitField  # DB31.DBX16.0-16.2
    change_done: Bool  # DB31.DBX16.3
    oscillation_request: Bool  # DB31.DBX18.4: oscillation by the PLC
    oscillation_enable: Bool  # DB31.DBX18.5
    direction_cw: Bool  # DB31.DBX18.6
    direction_ccw: Bool  # DB31.DBX18.7
    oscillated_by_plc: bool
    watchdog: TON
    cw_time: TON
    ccw_time: TON
    step: GearStep = GearStep.IDLE
    set_stage: int = 0  # the gear the NC asked for, latched with its request
    turning_ccw: bool = False  # the PLC's oscillation: False = CW phase, True = CCW phase

    def sensed_stage(self) -> int:
        """The gear the sensors show, 0 when none is engaged (neutral)."""
        for stage, sensor in enumerate(self.sensors, start=1):
            if sensor.value:
                return stage
        return 0


@dataclass(slots=True)
class _SpindleOverride:
    is_spindle: Bool  # DB31.DBX60.0 spindle / no axis
    override: Byte  # DB31.DBB19


@dataclass(frozen=True, slots=True)
class _Parameters:
    gear_shift_timeout_s: float
    oscillated_by_plc: frozenset[str]
    oscillation_time_cw_s: float
    oscillation_time_ccw_s: float
    master_spindle: str | None


class Spindle(Referencing):
    PROGRAM = "spindle"  # the name the harness knows the program by (unknown-parameter messages)
    PARAMETERS = (*Referencing.PARAMETERS, "gear_shift_timeout", "oscillation_by_plc", "oscillation_time_cw",
                  "oscillation_time_ccw", "master_spindle")

    def __init__(self, io: PlcIo):
        super().__init__(io)
        scan = io.environment.scan_time_s
        axes = io.environment.catalog.layout.axes
        stages = {axis: _wired_stages(io, axis) for axis in axes}
        gearbox_axes = [axis for axis in axes if stages[axis]]
        parameters = _parameters(io.environment.parameters, self.PROGRAM, self.PARAMETERS, axes, gearbox_axes,
                                 keys_wired=io.is_wired("MCP.spindleStop") or io.is_wired("MCP.spindleStart"))
        # Networks 6 to 8
        self.gearboxes = [
            _GearboxSpindle(
                name=axis,
                actuators=[io.output(gear_shift(axis, stage)) for stage in range(1, stages[axis] + 1)],
                sensors=[io.input(gear_engaged(axis, stage)) for stage in range(1, stages[axis] + 1)],
                change_requested=io.input(f"{axis}.spindle.in.gearChangeoverRequested"),
                requested_stage=io.input_field(f"{axis}.spindle.in.requestedGearStageNumber"),
                stationary=io.input(f"{axis}.basic.in.isStationary"),
                actual_stage=io.output_field(f"{axis}.spindle.out.gearStageSelection"),
                change_done=io.output(f"{axis}.spindle.out.gearChangeoverDone"),
                oscillation_request=io.output(f"{axis}.spindle.out.oscillRequest"),
                oscillation_enable=io.output(f"{axis}.spindle.out.oscillEnable"),
                direction_cw=io.output(f"{axis}.spindle.out.oscillSetDirCw"),
                direction_ccw=io.output(f"{axis}.spindle.out.oscillSetDirCcw"),
                oscillated_by_plc=axis in parameters.oscillated_by_plc,
                watchdog=TON(parameters.gear_shift_timeout_s, scan),
                cw_time=TON(parameters.oscillation_time_cw_s, scan),
                ccw_time=TON(parameters.oscillation_time_ccw_s, scan),
            )
            for axis in gearbox_axes
        ]
        # Network 9
        self.key_spindle_stop = io.input("MCP.spindleStop") if io.is_wired("MCP.spindleStop") else None
        self.key_spindle_start = io.input("MCP.spindleStart") if io.is_wired("MCP.spindleStart") else None
        self.spindle_switch = io.input_byte("MCP.spindleOverride") if io.is_wired("MCP.spindleOverride") else None
        self.spindle_stop_latch = SR()
        master = parameters.master_spindle
        self.master_spindle_stop = io.output(f"{master}.basic.out.feedStopSpindleStop") if master else None
        self.spindle_overrides = [_SpindleOverride(io.input(f"{axis}.basic.in.spindleModeActive"),
                                                   io.output_byte(f"{axis}.spindle.out.ovrFactor")) for axis in axes]

    def ob1(self) -> None:
        super().ob1()
        for spindle in self.gearboxes:
            self.gear_change(spindle)
            self.gear_report(spindle)
            self.oscillation_by_plc(spindle)
        self.spindle_keys_and_override()

    # Network 6 ---------------------------------------------------------------------------
    def gear_change(self, spindle: _GearboxSpindle) -> None:
        requested = spindle.change_requested.value
        if not requested and spindle.step is not GearStep.IDLE:
            # DONE: the NC withdrew 82.3 after our 16.3, which tells the PLC to reset 16.3 (seed 003
            # L18392-18397).  Before 16.3: an NC reset ended the change and the NC takes the gear
            # of 16.0-2 (L18694-18699), so stop pushing; network 7 reports what the sensors show.
            spindle.step = GearStep.IDLE
        if spindle.step is GearStep.IDLE and requested:
            spindle.set_stage = spindle.requested_stage.value  # 82.0-2 come with 82.3 (L18366-18371)
            spindle.step = GearStep.WAIT_STANDSTILL
        if spindle.step is GearStep.WAIT_STANDSTILL and spindle.stationary.value:
            # The NC brakes by itself, no 4.3 needed (L19456-19460); the oscillation enable must be
            # set at the latest at standstill (L18375-18379, L19401-19407).
            spindle.step = GearStep.SHIFTING
        shifting = spindle.step is GearStep.SHIFTING
        gave_up = spindle.watchdog(shifting)
        in_gear = 1 <= spindle.set_stage <= len(spindle.sensors) and spindle.sensors[spindle.set_stage - 1].value
        if shifting and (in_gear or gave_up):
            # t3 (L19411-19422): actual gear in 16.0-2 with 16.3, oscillation enable off.  A gear
            # that did not engage within gear_shift_timeout is reported as the sensors show it (0 in
            # neutral): a real PLC would rather raise an operator message and leave the NC waiting,
            # but the harness's PLC has no message channel the scenarios could assert, so it ends
            # the change and lets the NC raise alarm 22010, actual gear != set gear (L18401-18405).
            spindle.actual_stage.value = spindle.sensed_stage()
            spindle.step = GearStep.DONE
            shifting = False
        for stage, actuator in enumerate(spindle.actuators, start=1):
            # held on during the whole shift: released early, the gearbox stays in neutral
            actuator.value = shifting and stage == spindle.set_stage
        spindle.oscillation_enable.value = shifting  # the teeth mesh while the spindle oscillates
        spindle.change_done.value = spindle.step is GearStep.DONE

    # Network 7 ---------------------------------------------------------------------------
    def gear_report(self, spindle: _GearboxSpindle) -> None:
        # Outside a change the sensed gear goes to 16.0-2, stable while nothing moves, without
        # 16.3 (L18610-18622); at power-on this tells the NC the gear the machine is in, 0 when
        # the gearbox is disengaged (L18808-18843).  During a change network 6 owns 16.0-2.
        if spindle.step is GearStep.IDLE:
            spindle.actual_stage.value = spindle.sensed_stage()

    # Network 8 ---------------------------------------------------------------------------
    def oscillation_by_plc(self, spindle: _GearboxSpindle) -> None:
        # 18.4 with 18.5 asks the NC for oscillation by the PLC; 18.6 / 18.7 turn the motor CW / CCW
        # at MD35400 (L19332-19359); "the oscillation times and the reversals are the PLC
        # program's" (L19363).  Every oscillation starts clockwise.
        oscillating = spindle.oscillated_by_plc and spindle.step is GearStep.SHIFTING
        if not oscillating:
            spindle.turning_ccw = False
        running, waiting = ((spindle.ccw_time, spindle.cw_time) if spindle.turning_ccw
                            else (spindle.cw_time, spindle.ccw_time))
        reverse = running(oscillating)
        # the other direction's time starts in the scan of the reversal: each lasts exactly its time
        waiting(reverse)
        if reverse:
            spindle.turning_ccw = not spindle.turning_ccw
        spindle.oscillation_request.value = oscillating
        spindle.direction_cw.value = oscillating and not spindle.turning_ccw
        spindle.direction_ccw.value = oscillating and spindle.turning_ccw

    # Network 9 ---------------------------------------------------------------------------
    def spindle_keys_and_override(self) -> None:
        # DB31.DBX4.3 is "feed stop / spindle stop": on a spindle it brakes the spindle along its
        # ramp (seed 003 L8960-8964, L19487).
        stopped = self.spindle_stop_latch(pressed(self.key_spindle_stop), pressed(self.key_spindle_start))
        if self.master_spindle_stop is not None:
            self.master_spindle_stop.value = stopped
        # Every spindle has its own override byte next to the enable (L9170-9176).
        percent = self.spindle_switch.value if self.spindle_switch is not None else OVERRIDE_WITHOUT_SWITCH
        for axis in self.spindle_overrides:
            if axis.is_spindle.value:
                axis.override.value = percent


def _wired_stages(io: PlcIo, axis: str) -> int:
    """The gear stages of ``axis`` whose actuator and sensor are both wired, counted from stage 1."""
    stages = 0
    while (stages < MAX_GEAR_STAGES and io.is_wired(gear_shift(axis, stages + 1))
           and io.is_wired(gear_engaged(axis, stages + 1))):
        stages += 1
    return stages


def _parameters(parameters: Mapping[str, Any], program: str, known: Sequence[str], axes: Sequence[str],
                gearbox_axes: Sequence[str], keys_wired: bool) -> _Parameters:
    """Check the program's parameters; every mistake is reported at once when the PLC starts."""
    problems = [f"plc: unknown parameter '{name}'; the program {program} takes {', '.join(known)}"
                for name in parameters if name not in known]

    timeout = seconds(parameters, "gear_shift_timeout", GEAR_SHIFT_TIMEOUT_S, problems)
    oscillated = parameters.get("oscillation_by_plc", [])
    if not isinstance(oscillated, list) or not all(isinstance(name, str) for name in oscillated):
        problems.append(f"plc: oscillation_by_plc is a list of spindles, e.g. [SP1], got {oscillated!r}")
        oscillated = []
    for name in oscillated:
        if name not in axes:
            problems.append(f"plc: oscillation_by_plc names {name}, which the machine lacks")
        elif name not in gearbox_axes:
            problems.append(f"plc: oscillation_by_plc names {name}, which has no gearbox wired"
                            f" ({gear_shift(name, 1)}, {gear_engaged(name, 1)} ...)")
    time_cw = seconds(parameters, "oscillation_time_cw", OSCILLATION_TIME_CW_S, problems)
    time_ccw = seconds(parameters, "oscillation_time_ccw", OSCILLATION_TIME_CCW_S, problems)
    master = parameters.get("master_spindle", gearbox_axes[0] if gearbox_axes else None)
    if "master_spindle" in parameters and not isinstance(master, str):
        problems.append(f"plc: master_spindle is the name of a spindle, e.g. SP1, got {master!r}")
        master = None
    elif master is not None and master not in axes:
        problems.append(f"plc: master_spindle names {master}, which the machine lacks")
        master = None
    elif master is None and keys_wired:
        problems.append("plc: master_spindle: no spindle has a gearbox wired; name the spindle the panel's"
                        " spindle keys act on")
    if problems:
        raise ValueError("\n".join(problems))
    return _Parameters(timeout, frozenset(oscillated), time_cw, time_ccw, master)
