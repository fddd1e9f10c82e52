"""drive_lineup: the tool_change program plus the drive line-up of an axis with a holding brake.

Networks after those of ``tool_change`` (1-13), for the machine's braked axis (its ``plant:
holding_brake:``, vc/plant/holding_brake.py; the axis found by the commissioning facts):

14. Enables and holding brake in order, a step chain.  Network 4 gives every axis its enables
    with the drive line-up; for the braked axis this network overrides them, so that its drive
    holds the weight whenever the brake does not::

        OFF ──Drives.ready, no emergency stop──▶ PULSES: pulse enable DB31.DBX21.7
        PULSES ──the next scan──▶ ENABLE: controller enable DBX2.1
        ENABLE ──the drive ready DBX92.7──▶ RELEASE: "release holding brake" DBX20.5
        ENABLE ──no DBX92.7 within ready_timeout──▶ FAULT 700052 "drive not ready"
        RELEASE ──"holding brake released" DBX92.5──▶ READY: the axis's feed stop DBX4.3 off
        RELEASE ──no DBX92.5 within brake_timeout──▶ FAULT 700050 "holding brake not released"
        READY ──Drives.ready gone, emergency stop, DBX92.7 gone──▶ ENGAGE: DBX20.5 = 0
        ENGAGE ──DBX92.5 = 0 (the brake holds)──▶ OFF: controller and pulse enable away
        ENGAGE ──DBX92.5 still 1 after brake_timeout──▶ FAULT 700051 "holding brake not engaged"
        FAULT ──reset key──▶ ENGAGE (and from OFF the line-up starts again)

    In every step but READY the axis's feed stop DBX4.3 holds its motion.  The brake engages
    before the enables drop; in FAULT 700051 the enables stay (the drive holds the axis the brake
    cannot), in FAULT 700050 / 700052 the brake stays engaged.  Without the line-up (Drives.ready
    gone) the drive cannot hold the axis any more: its enables drop with it and the brake engages
    as fast as it can.

Parameters, besides those of ``tool_change``::

    plc:
      brake_timeout: 0.3        # s for the brake's contact DBX92.5 to follow DBX20.5
      ready_timeout: 0.1        # s for the drive to report ready (DBX92.7) after its enables
"""

from __future__ import annotations

from enum import Enum

from plc_stub.blocks import TON
from plc_stub.io import Bool, PlcIo
from plc_stub.programs.parameters import seconds
from plc_stub.programs.tool_change import ToolChange
from plc_stub.programs.turret import device_count

BRAKE_NOT_RELEASED, BRAKE_NOT_ENGAGED, DRIVE_NOT_READY = 700050, 700051, 700052
BRAKE_TIMEOUT_S = 0.3
READY_TIMEOUT_S = 0.1


class LineUpStep(Enum):
    OFF = "no enables, the brake holds the axis"
    PULSES = "pulse enable given"
    ENABLE = "controller enable given: waiting for the drive ready DBX92.7"
    RELEASE = "the drive holds the axis: the brake releases (DBX20.5), waiting for DBX92.5"
    READY = "the brake released, the drive holds the axis: it may move"
    ENGAGE = "the brake engages (DBX20.5 = 0), the drive holds the axis until DBX92.5 falls"
    FAULT = "PLC alarm until the reset key"


class DriveLineup(ToolChange):
    PROGRAM = "drive_lineup"
    PARAMETERS = (*ToolChange.PARAMETERS, "brake_timeout", "ready_timeout")

    def __init__(self, io: PlcIo):
        super().__init__(io)
        parameters = io.environment.parameters
        problems: list[str] = []
        brake_timeout = seconds(parameters, "brake_timeout", BRAKE_TIMEOUT_S, problems)
        ready_timeout = seconds(parameters, "ready_timeout", READY_TIMEOUT_S, problems)
        if problems:
            raise ValueError("\n".join(problems))
        scan = io.environment.scan_time_s
        # Network 14
        db = device_count(io, "holding_brake", "axis_db")
        commissioning = io.environment.commissioning
        braked = next((facts.axis for facts in commissioning.axes if facts.db == db), None) \
            if commissioning is not None and db else None
        self.braked_axis = braked
        self.brake_release: Bool | None = None
        if braked is not None:
            self.brake_release = io.output(f"{braked}.drive.out.releaseHoldingBrake")
            self.brake_released = io.input(f"{braked}.drive.in.holdingBrakeReleased")
            self.braked_controller_enable = io.output(f"{braked}.basic.out.enableCtrl")
            self.braked_pulse_enable = io.output(f"{braked}.drive.out.enablePulses")
            self.braked_feed_stop = io.output(f"{braked}.basic.out.feedStopSpindleStop")
            self.braked_drive_ready = io.input(f"{braked}.drive.in.enabled")
        self.line_up_alarms = {number: self.plc_alarm(number)
                               for number in (BRAKE_NOT_RELEASED, BRAKE_NOT_ENGAGED, DRIVE_NOT_READY)} \
            if braked is not None else {}
        self.line_up_step = LineUpStep.OFF
        self.line_up_fault = 0
        self.brake_watchdog = TON(brake_timeout, scan)
        self.brake_watchdog_engage = TON(brake_timeout, scan)
        self.ready_watchdog = TON(ready_timeout, scan)

    def auxiliary_networks(self) -> None:
        super().auxiliary_networks()
        self.drive_line_up()

    # Network 14 --------------------------------------------------------------------------
    def drive_line_up(self) -> None:
        if self.brake_release is None:
            return
        line_up = self.drives_ready.value if self.drives_ready is not None else True
        chain_ok = self.chain_ok.value if self.chain_ok is not None else True
        wanted = line_up and chain_ok
        drive_ready = self.braked_drive_ready.value
        released = self.brake_released.value
        step = self.line_up_step
        if step is LineUpStep.FAULT:
            if self.reset_pressed:
                step, self.line_up_fault = LineUpStep.ENGAGE, 0
        elif step is LineUpStep.OFF and wanted:
            step = LineUpStep.PULSES
        elif step is LineUpStep.PULSES:
            step = LineUpStep.ENABLE if wanted else LineUpStep.OFF
        elif step is LineUpStep.ENABLE:
            step = LineUpStep.OFF if not wanted else LineUpStep.RELEASE if drive_ready else step
        elif step is LineUpStep.RELEASE:
            step = LineUpStep.ENGAGE if not wanted or not drive_ready else LineUpStep.READY if released else step
        elif step is LineUpStep.READY and (not wanted or not drive_ready or not released):
            step = LineUpStep.ENGAGE
        elif step is LineUpStep.ENGAGE and not released:
            step = LineUpStep.OFF
        if self.ready_watchdog(step is LineUpStep.ENABLE and not drive_ready):
            step, self.line_up_fault = LineUpStep.FAULT, DRIVE_NOT_READY
        if self.brake_watchdog(step is LineUpStep.RELEASE and not released):
            step, self.line_up_fault = LineUpStep.FAULT, BRAKE_NOT_RELEASED
        if self.brake_watchdog_engage(step is LineUpStep.ENGAGE and released):
            step, self.line_up_fault = LineUpStep.FAULT, BRAKE_NOT_ENGAGED
        self.line_up_step = step
        holding = step is LineUpStep.FAULT and self.line_up_fault == BRAKE_NOT_ENGAGED
        enabled = line_up and (holding or step in (LineUpStep.ENABLE, LineUpStep.RELEASE, LineUpStep.READY,
                                                   LineUpStep.ENGAGE))
        self.braked_pulse_enable.value = enabled or (line_up and step is LineUpStep.PULSES)
        self.braked_controller_enable.value = enabled
        self.brake_release.value = step in (LineUpStep.RELEASE, LineUpStep.READY)
        self.braked_feed_stop.value = step is not LineUpStep.READY
        for number, alarm in self.line_up_alarms.items():
            alarm.value = step is LineUpStep.FAULT and self.line_up_fault == number
