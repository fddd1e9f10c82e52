"""coolant: the spindle program plus the coolant pump with its pressure supervision.

Networks after those of ``spindle`` (1-9) and the reading of the auxiliary functions (network 10,
plc_stub/programs/auxiliary.py), for the first channel:

11. Coolant pump, a step chain::

        OFF ──M8──▶ BUILDING: Coolant.pump on, 6.1 = 1 (the next block waits for the coolant)
        BUILDING ──Coolant.pressureOk──▶ ON: 6.1 = 0
        BUILDING, ON ──M9, program end M2/M30 (DB21.DBX33.5), reset key, emergency stop──▶ OFF: pump off
        BUILDING ──no pressure within pressure_timeout──▶ FAULT
        ON ──pressure gone for pressure_loss_delay──▶ FAULT
        FAULT: pump off, PLC alarm 700010, feed disable 6.0 = 1 (the slides stand) and 6.1 = 1
        FAULT ──reset key──▶ OFF: alarm gone, 6.0 / 6.1 free

    The reset key ends a program (network 3 gives the channel reset), so the coolant goes with it:
    what the program switched on, the end of the program switches off.

Parameters (the machine file's ``plc:`` section), besides those of ``spindle``::

    plc:
      pressure_timeout: 1.0        # s from M8 to the pressure switch before the PLC gives up
      pressure_loss_delay: 0.1     # s the switch may open while the pump runs (a pressure dip)
"""

from __future__ import annotations

from enum import Enum

from plc_stub.blocks import TON
from plc_stub.io import PlcIo
from plc_stub.programs.auxiliary import AuxiliaryMachine
from plc_stub.programs.parameters import seconds

COOLANT_ON, COOLANT_OFF = 8, 9
PROGRAM_ENDS = (2, 30)
COOLANT_PRESSURE_ALARM = 700010
PRESSURE_TIMEOUT_S = 1.0
PRESSURE_LOSS_DELAY_S = 0.1


class CoolantStep(Enum):
    OFF = "pump off"
    BUILDING = "pump on, waiting for the pressure (the program waits)"
    ON = "pump on, pressure there"
    FAULT = "no pressure: pump off, slides and program held until the reset key"


class Coolant(AuxiliaryMachine):
    PROGRAM = "coolant"
    PARAMETERS = (*AuxiliaryMachine.PARAMETERS, "pressure_timeout", "pressure_loss_delay")

    def __init__(self, io: PlcIo):
        super().__init__(io)
        problems: list[str] = []
        parameters = io.environment.parameters
        timeout = seconds(parameters, "pressure_timeout", PRESSURE_TIMEOUT_S, problems)
        delay = seconds(parameters, "pressure_loss_delay", PRESSURE_LOSS_DELAY_S, problems)
        if problems:
            raise ValueError("\n".join(problems))
        scan = io.environment.scan_time_s
        # Network 11
        self.pump = io.output("Coolant.pump") if io.is_wired("Coolant.pump") else None
        self.pressure = io.input("Coolant.pressureOk") if io.is_wired("Coolant.pressureOk") else None
        self.coolant_alarm = self.plc_alarm(COOLANT_PRESSURE_ALARM)
        self.coolant_step = CoolantStep.OFF
        self.build_up = TON(timeout, scan)
        self.pressure_loss = TON(delay, scan)

    def auxiliary_networks(self) -> None:
        super().auxiliary_networks()
        self.coolant()

    # Network 11 --------------------------------------------------------------------------
    def coolant(self) -> None:
        if self.pump is None:
            return
        step = self.coolant_step
        pressure = self.pressure.value if self.pressure is not None else True
        ended = self.program_ended.value or any(self.m_function(code) for code in PROGRAM_ENDS)
        switched_off = self.m_function(COOLANT_OFF) or ended or self.reset_pressed or self.emergency_stop_active.value
        if step is CoolantStep.FAULT:
            if self.reset_pressed:
                step = CoolantStep.OFF  # acknowledged: the operator has seen to the coolant
        elif switched_off:
            step = CoolantStep.OFF
        elif self.m_function(COOLANT_ON) and step is CoolantStep.OFF:
            step = CoolantStep.BUILDING
        if step is CoolantStep.BUILDING and pressure:
            step = CoolantStep.ON
        if self.build_up(step is CoolantStep.BUILDING) or self.pressure_loss(step is CoolantStep.ON and not pressure):
            step = CoolantStep.FAULT  # the filter is clogged, the tank dry: no machining without coolant
        self.coolant_step = step
        self.pump.value = step in (CoolantStep.BUILDING, CoolantStep.ON)
        self.coolant_alarm.value = step is CoolantStep.FAULT
        self.hold_read_in = self.hold_read_in or step in (CoolantStep.BUILDING, CoolantStep.FAULT)
        self.hold_feed = self.hold_feed or step is CoolantStep.FAULT
