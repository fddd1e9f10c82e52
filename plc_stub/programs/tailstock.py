"""tailstock: the turret program plus a lathe's tailstock quill travelling to fixed stop.

Networks after those of ``turret`` (1-13), for the quill's axis (the machine's ``plant: tailstock:``):

14. Tailstock quill (vc/plant/tailstock.py): the part program selects travel to fixed stop with
    ``FXS[W]=1`` and deselects it with ``FXS[W]=0`` (seed 003 chapter 17); the PLC runs the
    handshake of MD37060 = 3 (the motion waits for the enable DB31.DBX3.1, the block change for the
    acknowledgement DB31.DBX1.1), passes the sleeve sensor ``Tailstock.atPart`` to the fixed-stop
    sensor DB31.DBX1.2 (used by the NC with MD37040 = 1 / 2) and watches the clamp::

        IDLE ──DBX62.4 (selected), the main chuck clamped──▶ ADVANCE: DBX3.1 = 1, the quill travels
        IDLE ──DBX62.4 with the main chuck open──▶ FAULT 700032: no enable (the block waits)
        ADVANCE ──DBX62.5 (the NC found the stop) and the sleeve at the part──▶ CLAMPED: DBX1.1 = 1
        ADVANCE ──no stop within approach_timeout──▶ FAULT 700031: DBX3.1 = 0 (the NC aborts: 20094)
        ADVANCE ──DBX62.4 = 0 (not reached 20091, reset)──▶ IDLE: DBX3.1 = 0
        ADVANCE ──the same, with clamp_torque_timeout: and |Md| < Mdx DB31.DBX94.3 fallen──▶ CLAMPED
        ADVANCE ──with clamp_torque_timeout: 94.3 still 1 that long after the stop──▶ FAULT 700033:
                  DBX3.1 = 0 (the clamping torque is not there: the NC aborts, 20094)
        CLAMPED ──DBX62.4 = 0 (FXS[W]=0, or the NC's window alarm 20093)──▶ IDLE: DBX3.1 = DBX1.1 = 0
        CLAMPED ──the sleeve leaves the part (it slipped)──▶ FAULT 700030: DBX3.1 = DBX1.1 = 0, feed
                  disable DB21.DBX6.0 (the slides stand; the part is loose)
        FAULT ──reset key──▶ IDLE

Parameters, besides those of ``turret``::

    plc:
      approach_timeout: 10.0     # s from the enable to the NC's "fixed stop reached"
      clamp_torque_timeout: 0.5  # s: acknowledge only once the drive reports the clamping torque
                                 # (|Md| < Mdx falls: the quill's drive with messages: 1 and p2174
                                 # below FXST); not given: no torque check
"""

from __future__ import annotations

from enum import Enum

from interfaces.plant_io import TAILSTOCK, chuck_closed
from plc_stub.blocks import TON
from plc_stub.io import Bool, PlcIo
from plc_stub.programs.parameters import seconds
from plc_stub.programs.turret import Turret, device_count, spindles

PART_LOST, NO_PART, CHUCK_OPEN, NO_CLAMPING_TORQUE = 700030, 700031, 700032, 700033
APPROACH_TIMEOUT_S = 10.0


class TailstockStep(Enum):
    IDLE = "the quill is free: no travel to fixed stop"
    ADVANCE = "the NC may travel to the stop (DBX3.1): the quill advances with its torque limit"
    CLAMPED = "the NC found the stop, the sleeve is at the part: acknowledged (DBX1.1)"
    FAULT = "stopped with a PLC alarm until the reset key"


class Tailstock(Turret):
    PROGRAM = "tailstock"
    PARAMETERS = (*Turret.PARAMETERS, "approach_timeout", "clamp_torque_timeout")

    def __init__(self, io: PlcIo):
        super().__init__(io)
        problems: list[str] = []
        parameters = io.environment.parameters
        approach_timeout = seconds(parameters, "approach_timeout", APPROACH_TIMEOUT_S, problems)
        # the clamping torque checked through the drive's |Md| < Mdx (DB31.DBX94.3) only where it is asked for
        torque_timeout = seconds(parameters, "clamp_torque_timeout", 1.0, problems) \
            if "clamp_torque_timeout" in parameters else None
        if problems:
            raise ValueError("\n".join(problems))
        # Network 14
        db = device_count(io, "tailstock", "axis_db")
        commissioning = io.environment.commissioning
        quill = next((facts.axis for facts in commissioning.axes if facts.db == db), None) \
            if commissioning is not None and db else None
        self.quill = quill
        self.fixed_stop_enable: Bool | None = None
        if quill is not None:
            self.fixed_stop_enable = io.output(f"{quill}.basic.out.fixedStopEnable")
            self.fixed_stop_ack = io.output(f"{quill}.basic.out.fixedStopAckReached")
            self.fixed_stop_sensor = io.output(f"{quill}.basic.out.fixedStopSensor")
            self.fixed_stop_active = io.input(f"{quill}.basic.in.fixedStopRequest")
            self.fixed_stop_reached = io.input(f"{quill}.basic.in.fixedStopReached")
            self.at_part = io.input(f"{TAILSTOCK}.atPart")
            self.torque_below_threshold = io.input(f"{quill}.drive.in.torqueBelowThreshold") \
                if torque_timeout is not None else None
            main = spindles(io)[0]
            self.chuck_clamped = io.input(chuck_closed(main)) if io.is_wired(chuck_closed(main)) else None
        numbers = (PART_LOST, NO_PART, CHUCK_OPEN) + ((NO_CLAMPING_TORQUE,) if torque_timeout is not None else ())
        self.tailstock_alarms = {number: self.plc_alarm(number) for number in numbers} if quill is not None else {}
        self.tailstock_step = TailstockStep.IDLE
        self.tailstock_fault = 0
        self.approach_watchdog = TON(approach_timeout, io.environment.scan_time_s)
        self.torque_watchdog = TON(torque_timeout or 1.0, io.environment.scan_time_s)

    def auxiliary_networks(self) -> None:
        super().auxiliary_networks()
        self.tailstock()

    # Network 14 --------------------------------------------------------------------------
    def tailstock(self) -> None:
        if self.fixed_stop_enable is None:
            return
        selected = self.fixed_stop_active.value
        step = self.tailstock_step
        torque = self.torque_below_threshold  # None: no torque check
        stop_found = step is TailstockStep.ADVANCE and selected and self.fixed_stop_reached.value \
            and self.at_part.value
        if step is TailstockStep.FAULT:
            if self.reset_pressed:
                step, self.tailstock_fault = TailstockStep.IDLE, 0
        elif step is TailstockStep.IDLE and selected:
            chuck_ok = self.chuck_clamped is None or self.chuck_clamped.value
            step, self.tailstock_fault = (TailstockStep.ADVANCE, 0) if chuck_ok else (TailstockStep.FAULT, CHUCK_OPEN)
        elif step is TailstockStep.ADVANCE:
            if not selected:
                step = TailstockStep.IDLE
            elif stop_found and (torque is None or not torque.value):
                step = TailstockStep.CLAMPED
        elif step is TailstockStep.CLAMPED:
            if not selected:
                step = TailstockStep.IDLE
            elif not self.at_part.value:
                step, self.tailstock_fault = TailstockStep.FAULT, PART_LOST
        if self.approach_watchdog(step is TailstockStep.ADVANCE and not self.fixed_stop_reached.value):
            step, self.tailstock_fault = TailstockStep.FAULT, NO_PART
        if self.torque_watchdog(stop_found and step is TailstockStep.ADVANCE):
            step, self.tailstock_fault = TailstockStep.FAULT, NO_CLAMPING_TORQUE
        self.tailstock_step = step
        self.fixed_stop_enable.value = step in (TailstockStep.ADVANCE, TailstockStep.CLAMPED)
        self.fixed_stop_ack.value = step is TailstockStep.CLAMPED
        self.fixed_stop_sensor.value = self.at_part.value
        for number, alarm in self.tailstock_alarms.items():
            alarm.value = step is TailstockStep.FAULT and self.tailstock_fault == number
        self.hold_feed = self.hold_feed or (step is TailstockStep.FAULT and self.tailstock_fault == PART_LOST)
